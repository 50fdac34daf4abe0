"""The per-step neural surrogate of the UVLM: one wing's instantaneous loads from the kinematics and the body's motion.

Network. A multilayer perceptron (tanh hidden layers, linear output) for the LEFT wing:

- inputs (:func:`input_names`): the seven kinematic parameters (SI, :data:`hawksim.insect.kinematics.PARAM_NAMES`),
  the wingbeat phase as sin and cos of 2 pi f t (t from the flight's start, the phase of Eq. 1), the body's
  velocity relative to the air v (3) [m/s] and its angular velocity omega (3) [rad/s] in body axes (x head, y left,
  z dorsal), and for each lag in ``lags`` (in wingbeat periods T) the same six at time t - lag T, each in the body
  axes of its own time (the wake's memory; which lags it needs is an ablation, docs/surrogate.md);
  and, for a network with ``age_beats`` > 0, last, the wake's age :data:`AGE_INPUT`: min(f (t - t_launch),
  age_beats), the wingbeats since the flight's launch from no wake, saturating (:func:`wake_age`; the UVLM's wake
  starts from none at a launch and develops over its first beats, docs/surrogate.md, "Launch from no wake");
- outputs (:data:`OUTPUTS`): the wing's aerodynamic force [N] and moment about its hinge [N m] in its own wing
  axes (the wing body's frame in MuJoCo), six numbers.

The right wing is the left one's mirror image across the body's x-z plane (``M = diag(1, -1, 1)``, the right wing's
frame is M R_left M): the right wing's loads are the network's at mirrored inputs (v -> M v, omega -> -M omega)
with F -> M F and the moment, a pseudovector, -> -M M (:func:`mirror_inputs`, :data:`MIRROR_F`, :data:`MIRROR_M`;
exact for the UVLM, checked on its symmetric flights in tests/hawksim/test_step_surrogate.py).

Files. safetensors with tensors ``W0, b0, ..., W{L-1}, b{L-1}`` (``W_k`` (n_out_k, n_in_k)), ``x_mean, x_std``
(n_in,) and ``y_mean, y_std`` (6,) (standardisation of the training data; the network maps standardised inputs
to standardised outputs), weights float32, standardisation float64; JSON metadata: ``format`` (:data:`FORMAT`),
``inputs`` (names, lags, and ``age_beats`` where > 0; a file without it, every file before the age input, has
none), ``outputs`` and ``meta`` (provenance: command, seed, data hash, scores). No pickle. A file of another
format, with other tensor names or shapes, other input names than its lags and age imply, or non-finite values is
refused with :class:`StepNetworkFileError`.

Inference (:meth:`StepNetwork.folded`): the input standardisation is folded into the first layer and the output
scaling into the last, so a flight evaluates ``tanh(x W0' + b0') ... W' + b'`` on SI inputs in float32 numpy,
both wings in one (2, n_in) batch.
"""

from __future__ import annotations

import json
from dataclasses import dataclass, field
from pathlib import Path

import numpy as np

from hawksim.insect.kinematics import PARAM_NAMES

FORMAT = "hawksim-step-surrogate-1"
OUTPUTS = ("Fx", "Fy", "Fz", "Mx", "My", "Mz")
"""Outputs: force [N] and moment about the hinge [N m] of the (left) wing in its wing axes."""
STATE_NAMES = ("vx", "vy", "vz", "wx", "wy", "wz")
"""The body's velocity [m/s] and angular velocity [rad/s] in body axes."""
MIRROR_V = np.array([1.0, -1.0, 1.0])
MIRROR_W = np.array([-1.0, 1.0, -1.0])
MIRROR_F = MIRROR_V
"""Right-wing force in its wing axes = MIRROR_F * (network force at mirrored inputs)."""
MIRROR_M = MIRROR_W
"""Right-wing moment in its wing axes = MIRROR_M * (network moment at mirrored inputs)."""
SHIPPED_NAME = "uvlm_step.safetensors"
AGE_INPUT = "wake_age_beats"
"""Name of the wake-age input (wingbeats since the launch, saturating at the network's ``age_beats``)."""


class StepNetworkFileError(ValueError):
    """A per-step surrogate file that cannot be used: missing, not safetensors, another format or shapes."""


def input_names(lags: tuple[float, ...] = (), age_beats: float = 0.0) -> tuple[str, ...]:
    """Names of the network inputs for history lags (in periods), and the wake-age input last when ``age_beats``
    > 0."""
    names = [*PARAM_NAMES, "sin_phase", "cos_phase", *STATE_NAMES]
    for lag in lags:
        names += [f"{n}@-{lag:g}T" for n in STATE_NAMES]
    if age_beats > 0:
        names.append(AGE_INPUT)
    return tuple(names)


def wake_age(t: np.ndarray | float, f: float, age_beats: float, t_launch: float = 0.0) -> np.ndarray | float:
    """The wake-age input: min(f (t - t_launch), age_beats) [wingbeats] at time(s) t [s] of a flight launched
    from no wake at t_launch [s] with flapping frequency f [Hz] (t_launch = -inf: a developed wake, the saturated
    value). One formula for the training rows and both inference paths."""
    return np.minimum(f * (np.asarray(t, dtype=np.float64) - t_launch), age_beats)


def mirror_inputs(x: np.ndarray) -> np.ndarray:
    """Inputs (..., n_in) of the right wing mapped to the left wing's network: every (v, omega) block mirrored
    (a wake-age input, one column after them, is the same for both wings)."""
    x = np.array(x, dtype=x.dtype, copy=True)
    n_state = (x.shape[-1] - len(PARAM_NAMES) - 2) // 6
    s = np.concatenate([MIRROR_V, MIRROR_W])
    for k in range(n_state):
        j = len(PARAM_NAMES) + 2 + 6 * k
        x[..., j:j + 6] *= s
    return x


@dataclass(frozen=True)
class StepNetwork:
    """A trained per-step network (module docstring). ``weights``: ((W0, b0), ..., (W_L, b_L)) float32, W (out, in);
    ``lags``: history lags [periods]; ``age_beats``: saturation of the wake-age input [wingbeats] (0: the network
    has none); ``meta``: provenance and scores."""

    weights: tuple[tuple[np.ndarray, np.ndarray], ...]
    x_mean: np.ndarray
    x_std: np.ndarray
    y_mean: np.ndarray
    y_std: np.ndarray
    lags: tuple[float, ...] = ()
    meta: dict = field(default_factory=dict, compare=False)
    age_beats: float = 0.0

    @property
    def n_in(self) -> int:
        return len(input_names(self.lags, self.age_beats))

    def folded(self) -> tuple[tuple[np.ndarray, np.ndarray], ...]:
        """((W0'^T, b0'), ..., (W_L'^T, b_L')) float32 acting on SI inputs and giving SI outputs: the input
        standardisation folded into the first layer, the output scaling into the last; W' transposed (in, out)."""
        Ws = [np.asarray(W, np.float64) for W, _ in self.weights]
        bs = [np.asarray(b, np.float64) for _, b in self.weights]
        W0 = Ws[0] / self.x_std[None, :]
        bs[0] = bs[0] - W0 @ self.x_mean
        Ws[0] = W0
        Ws[-1] = Ws[-1] * self.y_std[:, None]
        bs[-1] = bs[-1] * self.y_std + self.y_mean
        return tuple((np.ascontiguousarray(W.T, np.float32), np.ascontiguousarray(b, np.float32))
                     for W, b in zip(Ws, bs))

    def predict(self, x: np.ndarray) -> np.ndarray:
        """Outputs (n, 6) SI of the left-wing network at SI inputs x (n, n_in) (float64, unfolded reference)."""
        x = np.atleast_2d(np.asarray(x, dtype=np.float64))
        if x.shape[-1] != self.n_in:
            raise ValueError(f"inputs must have shape (n, {self.n_in}), got {x.shape}")
        h = (x - self.x_mean) / self.x_std
        for k, (W, b) in enumerate(self.weights):
            h = h @ np.asarray(W, np.float64).T + b
            if k < len(self.weights) - 1:
                h = np.tanh(h)
        return h * self.y_std + self.y_mean

    # ---------------------------------------------------------------------------------------------- files

    def save(self, path: str | Path) -> Path:
        from safetensors.numpy import save

        from hawksim.atomic import write_bytes

        path = Path(path)
        tensors = {}
        for k, (W, b) in enumerate(self.weights):
            tensors[f"W{k}"] = np.ascontiguousarray(W, np.float32)
            tensors[f"b{k}"] = np.ascontiguousarray(b, np.float32)
        for k in ("x_mean", "x_std", "y_mean", "y_std"):
            tensors[k] = np.ascontiguousarray(getattr(self, k), np.float64)
        inputs = {"names": list(input_names(self.lags, self.age_beats)), "lags": list(self.lags)}
        if self.age_beats > 0:  # absent otherwise: a network without the age input is written as before
            inputs["age_beats"] = float(self.age_beats)
        md = {"format": FORMAT, "inputs": json.dumps(inputs),
              "outputs": json.dumps(list(OUTPUTS)), "meta": json.dumps(self.meta)}
        # all or nothing, a link's target replaced, a device refused (hawksim.atomic)
        return write_bytes(path, save(tensors, metadata=md), "per-step surrogate")


def load(path: str | Path) -> StepNetwork:
    """Read and check a per-step surrogate file (format, inputs, outputs, tensor names, shapes, finiteness)."""
    from safetensors import SafetensorError, safe_open

    from hawksim.inputfile import check_regular_file, metadata_object, strict_json

    path = check_regular_file(path, "per-step surrogate file", StepNetworkFileError)  # FIFO, directory, device: named
    try:
        with safe_open(str(path), framework="numpy") as fh:
            md = fh.metadata() or {}
            arrays = {k: fh.get_tensor(k) for k in fh.keys()}
    except (SafetensorError, OSError, ValueError) as exc:
        raise StepNetworkFileError(f"{str(path)!r} is not a safetensors file: {exc}") from None
    if md.get("format") != FORMAT:
        raise StepNetworkFileError(f"{str(path)!r} is not a {FORMAT} file (format {md.get('format')!r}; a cycle-mean "
                                   "network is used by --aero surrogate-mean)")
    try:
        inp = strict_json(md["inputs"])
        lags = tuple(float(v) for v in inp["lags"])
        age = float(inp.get("age_beats", 0.0))
        names = tuple(inp["names"])
        outputs = tuple(strict_json(md["outputs"]))
        meta = metadata_object(md.get("meta"), "meta")
    except (KeyError, TypeError, ValueError) as exc:
        raise StepNetworkFileError(f"{str(path)!r} has unreadable metadata: {exc}") from None
    if not (np.isfinite(age) and age >= 0):
        raise StepNetworkFileError(f"{str(path)!r} has age_beats {age!r}; expected a finite number >= 0")
    if names != input_names(lags, age):
        raise StepNetworkFileError(f"{str(path)!r} has inputs {list(names)}, not this hawksim's "
                                   f"{list(input_names(lags, age))}")
    if outputs != OUTPUTS:
        raise StepNetworkFileError(f"{str(path)!r} predicts {list(outputs)}, not {list(OUTPUTS)}")
    n_layers = sum(1 for k in arrays if k.startswith("W"))
    need = {f"{p}{k}" for k in range(n_layers) for p in "Wb"} | {"x_mean", "x_std", "y_mean", "y_std"}
    if n_layers < 1 or set(arrays) != need:
        raise StepNetworkFileError(f"{str(path)!r} holds tensors {sorted(arrays)}, expected {sorted(need)}")
    n_in = len(names)
    weights = []
    for k in range(n_layers):
        W, b = arrays[f"W{k}"], arrays[f"b{k}"]
        n_out = len(OUTPUTS) if k == n_layers - 1 else (W.shape[0] if W.ndim == 2 else -1)
        if W.shape != (n_out, n_in) or b.shape != (n_out,):
            raise StepNetworkFileError(f"{str(path)!r}: layer {k} has W {W.shape}, b {b.shape}, expected "
                                       f"({n_out}, {n_in}) and ({n_out},)")
        weights.append((W.astype(np.float32), b.astype(np.float32)))
        n_in = n_out
    for k, n in (("x_mean", len(names)), ("x_std", len(names)), ("y_mean", len(OUTPUTS)), ("y_std", len(OUTPUTS))):
        if arrays[k].shape != (n,):
            raise StepNetworkFileError(f"{str(path)!r}: tensor {k} has shape {arrays[k].shape}, expected ({n},)")
    if not all(np.all(np.isfinite(a)) for a in arrays.values()) or np.any(arrays["x_std"] <= 0) \
            or np.any(arrays["y_std"] <= 0):
        raise StepNetworkFileError(f"{str(path)!r} holds non-finite weights or non-positive scales")
    return StepNetwork(tuple(weights), *(arrays[k].astype(np.float64) for k in ("x_mean", "x_std", "y_mean", "y_std")),
                       lags=lags, meta=meta, age_beats=age)


def network_sha256(path: str | Path | None = None) -> str | None:
    """SHA-256 of a network file's bytes (default: the shipped one; None if absent): what a table solved with it
    (the surrogate's orbit table) records."""
    import hashlib

    p = Path(path) if path is not None else shipped_path()
    return hashlib.sha256(p.read_bytes()).hexdigest() if p.is_file() else None


def shipped_path() -> Path:
    """Package-data path of the shipped per-step network (the default insect's, :func:`hawksim.backends.network.
    shipped_network`)."""
    from hawksim.backends.network import shipped_network

    return shipped_network(SHIPPED_NAME)
