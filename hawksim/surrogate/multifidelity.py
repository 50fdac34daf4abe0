"""Multi-fidelity surrogate of the reference UVLM: a network of cheap labels plus a correction network.

The shipped cycle-mean networks (:mod:`hawksim.backends.network`) fit labels of the coarse training lattice
(:data:`hawksim.backends.resolution.TRAINING`, 4 x 8 rings, 30 steps per beat), which sit several per cent from
`hawksim aero`'s default lattice (:data:`hawksim.backends.resolution.REFERENCE`). A correction network, of the same
kind (one hidden layer of logistic sigmoids, linear outputs) but small, is trained by the same Levenberg-Marquardt
(:func:`hawksim.surrogate.train.train`) on the difference between reference-lattice labels and the base network's
prediction at the same kinematics (:func:`correction_targets`), so that base + correction approximates the
reference UVLM: the correction carries the lattice's bias and whatever of the base's own fitting error is smooth
enough to learn from the few reference samples. (Kennedy & O'Hagan 2000's additive discrepancy; Meng &
Karniadakis 2020, J. Comput. Phys. 401, for neural multi-fidelity surrogates.)

Both networks have one hidden layer on the same normalised inputs, so their sum is itself such a network, with
the two hidden layers side by side (:func:`fold`): the result is an ordinary ``hawksim-surrogate-1`` file, read,
evaluated and used by the trim exactly as the shipped networks are.
"""

from __future__ import annotations

import numpy as np

from hawksim.backends.network import Surrogate


def correction_targets(base: Surrogate, x: np.ndarray, y: np.ndarray) -> np.ndarray:
    """Targets of the correction network: reference labels minus the base network's prediction.

    Parameters
    ----------
    base : Surrogate
        The cheap-label network (per-speed or speed-input).
    x : (n, n_in) array
        Network inputs in SI: the seven kinematic parameters (f [Hz], angles [rad]), plus the ascent speed [m/s]
        as an eighth column for a speed-input ``base``.
    y : (n, 4) array
        Reference labels L+, D+, M+, P+ (paper Eq. 2, dimensionless).

    Returns
    -------
    (n, 4) array
        y - base(x), dimensionless.
    """
    x = np.asarray(x, dtype=float)
    if x.ndim != 2 or x.shape[1] != base.inputs.n_in:
        raise ValueError(f"inputs must have shape (n, {base.inputs.n_in}) for this base network, got {x.shape}")
    speed = x[:, 7] if base.inputs.speed is None else None
    return np.asarray(y, dtype=float) - base.predict(x[:, :7], speed)


def fold(base: Surrogate, correction: Surrogate, meta: dict | None = None) -> Surrogate:
    """The network base + correction as one network (exact in real arithmetic).

    Hidden layers stacked (``W1``: (H_b + H_c, n_in)); output weights side by side, the correction's rescaled to
    the base's output scaling: with s_b, m_b and s_c, m_c the output scales and means,
    out = s_b (h_b W2_b + b2_b) + m_b + s_c (h_c W2_c + b2_c) + m_c
        = s_b ([h_b, h_c] [W2_b, W2_c s_c / s_b] + b2_b + (s_c b2_c + m_c) / s_b) + m_b.

    Parameters
    ----------
    base, correction : Surrogate
        Networks on the same :class:`hawksim.backends.network.InputDefinition` (ValueError otherwise).
    meta : dict, optional
        Metadata of the folded network (default: the correction's).

    Returns
    -------
    Surrogate
        Hidden units H_b + H_c; y_mean, y_std the base's.
    """
    if base.inputs != correction.inputs:
        raise ValueError(f"the correction's inputs {correction.inputs.to_json()} are not the base network's "
                         f"{base.inputs.to_json()}")
    s = base.y_std
    ratio = correction.y_std / s
    W1 = np.vstack([base.W1, correction.W1])
    b1 = np.concatenate([base.b1, correction.b1])
    W2 = np.hstack([base.W2, correction.W2 * ratio[:, None]])
    b2 = base.b2 + (correction.b2 * correction.y_std + correction.y_mean) / s
    return Surrogate(base.inputs, W1, b1, W2, b2, base.y_mean.copy(), s.copy(),
                     meta=dict(correction.meta if meta is None else meta))
