"""Levenberg-Marquardt training of the surrogate (Nguyen et al. 2020, Sec. 2.4: MATLAB's ``trainlm``).

The loss is the sum of squared residuals of the four standardised outputs over the training samples. Each
iteration forms the Jacobian J of the residuals with respect to all weights, the Gauss-Newton matrix J^T J and
gradient J^T r (float64; :func:`gauss_newton`), and solves
(J^T J + mu I) dw = -J^T r by Cholesky; a step that lowers the loss is taken and mu divided by ``mu_dec``,
otherwise mu is multiplied by ``mu_inc`` and the step retried (the ``trainlm`` rule, its defaults mu = 1e-3,
mu_dec = 0.1, mu_inc = 10). Early stopping as ``trainlm``: training stops when the validation error has not
improved for ``max_fail`` = 6 iterations, and the weights of the best validation error are kept.

Cost. The Jacobian with respect to the hidden layer's weights (W1, b1) is the Jacobian with respect to the
hidden pre-activations, from ``torch.func`` (``vmap`` of ``jacrev``), times the inputs (chain rule). The output
layer is linear, so output k's residuals depend on W2[k], b2[k] only, with derivatives the hidden activations
[s, 1] (the same for every k): :func:`gauss_newton` assembles those blocks of J^T J from the activations
instead of multiplying the (mostly zero) full Jacobian, which halves the work of an iteration (for 7-500-4 and
2400 samples: 0.31 instead of 0.69 TFLOP). ``tests`` hold it equal to J^T J of the full ``torch.func`` Jacobian.

Splits. The samples (ordered by speed and index) are shuffled by ``seed``; ``test_fraction`` is held out (never
seen in training, used for the scores), ``val_fraction`` is the early-stopping set, the rest trains. Weight
initialisation is seeded too: same data and seed, same network, bit for bit on one machine (torch
deterministic algorithms, float64).
"""

from __future__ import annotations

import time
from dataclasses import dataclass

import numpy as np

from hawksim.backends.network import OUTPUTS, InputDefinition, Surrogate


@dataclass(frozen=True)
class TrainConfig:
    """hidden: sigmoid units (paper: 500); max_iter: LM iterations; mu*: the damping rule (trainlm defaults);
    max_fail: early-stopping patience; fractions of the samples held out for test and validation; time_limit_s:
    stop (keeping the best weights) after this wall time."""

    hidden: int = 500
    max_iter: int = 300
    mu: float = 1e-3
    mu_dec: float = 0.1
    mu_inc: float = 10.0
    mu_max: float = 1e10
    max_fail: int = 6
    test_fraction: float = 0.1
    val_fraction: float = 0.1
    time_limit_s: float = 3600.0


@dataclass(frozen=True)
class Scores:
    """Held-out scores per output: RMSE (output units) and coefficient of determination R^2."""

    rmse: dict
    r2: dict


@dataclass(frozen=True)
class TrainResult:
    surrogate: Surrogate
    n_train: int
    n_val: int
    n_test: int
    test_scores: Scores
    iterations: int
    history: tuple  # (iteration, train mse, val mse, mu) in standardised units
    wall_time_s: float
    test_x: np.ndarray  # (n_test, n_in) SI, for validation plots
    test_y: np.ndarray  # (n_test, 4) UVLM


def scores(y_true: np.ndarray, y_pred: np.ndarray) -> Scores:
    err = y_pred - y_true
    rmse = np.sqrt(np.mean(err**2, axis=0))
    ss_tot = np.sum((y_true - y_true.mean(axis=0)) ** 2, axis=0)
    r2 = 1.0 - np.sum(err**2, axis=0) / ss_tot
    return Scores({k: float(v) for k, v in zip(OUTPUTS, rmse)}, {k: float(v) for k, v in zip(OUTPUTS, r2)})


def split_groups(groups: np.ndarray, seed: int, cfg: TrainConfig) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """:func:`split` within each group (e.g. each ascent speed), concatenated: the speed-input network holds out
    exactly the samples each per-speed network holds out (same data order and seed), so both are scored on the
    same unseen samples."""
    parts = []
    for g in np.unique(groups):
        idx = np.flatnonzero(groups == g)
        parts.append([idx[s] for s in split(len(idx), seed, cfg)])
    return tuple(np.concatenate([p[k] for p in parts]) for k in range(3))


def split(n: int, seed: int, cfg: TrainConfig) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """Seeded permutation of range(n) into (train, validation, test) index arrays."""
    perm = np.random.default_rng([int(seed), 7]).permutation(n)
    n_test = max(1, int(round(cfg.test_fraction * n)))
    n_val = max(1, int(round(cfg.val_fraction * n)))
    if n - n_test - n_val < 2:
        raise ValueError(f"{n} samples are too few to train (need test, validation and >= 2 training samples)")
    return perm[n_test + n_val:], perm[n_test:n_test + n_val], perm[:n_test]


def held_out(meta: dict, n: int) -> np.ndarray:
    """Test indices that the per-speed network with metadata ``meta`` (`train`'s) held out of its n samples (the
    same data order: `hawksim.surrogate.dataset.read_samples` of that speed)."""
    cfg = TrainConfig(**{k: meta["train_config"][k] for k in ("test_fraction", "val_fraction")})
    return split(n, meta["seed"], cfg)[2]


def held_out_samples(net: Surrogate, path, speed: float):
    """The samples of data-set file ``path`` at ``speed`` and the indices into them of the test split that the
    per-speed network ``net`` held out (never seen in training or early stopping): ``(Table, (n_test,) int)``.
    Raises ValueError when ``net`` was not trained on this file's rows at this speed (its recorded
    ``data_sha256`` differs), since a split of other data would mix training samples into the test set."""
    from hawksim.surrogate.dataset import file_sha256, read_samples

    want = net.meta.get("data_sha256")
    if want != file_sha256(path, speed, net.meta.get("data_seed")):
        raise ValueError(f"{path}: the network ({net.meta.get('command', '?')}) was trained on other data at "
                         f"{speed:g} m/s (data_sha256 differs), so its held-out split does not apply")
    t = read_samples(path, speed=speed, seed=net.meta.get("data_seed"))
    return t, held_out(net.meta, len(t.y))


def shipped_held_out(path) -> list:
    """[(speed, network, Table, test indices)] for each shipped per-speed network (`hawksim.backends.network`'s
    SHIPPED_SPEEDS) on data-set file ``path``, by :func:`held_out_samples` (ValueError if a network was not
    trained on that file)."""
    from hawksim.backends.network import SHIPPED_SPEEDS, load, shipped_path

    out = []
    for v in SHIPPED_SPEEDS:
        net = load(shipped_path(v))
        out.append((v, net, *held_out_samples(net, path, v)))
    return out


def _unpack(w, n_in: int, H: int, n_out: int):
    """Flat weights (H n_in + H + n_out H + n_out,) -> W1 (H, n_in), b1 (H,), W2 (n_out, H), b2 (n_out,)."""
    p = H * n_in
    return (w[:p].reshape(H, n_in), w[p:p + H], w[p + H:p + H + n_out * H].reshape(n_out, H),
            w[p + H + n_out * H:])


def _net_batch(w, zz, n_in: int, H: int, n_out: int):
    import torch

    W1, b1, W2, b2 = _unpack(w, n_in, H, n_out)
    return torch.sigmoid(zz @ W1.T + b1) @ W2.T + b2


def gauss_newton(w, zz, yy, n_in: int, H: int, n_out: int, *, rows_per_block: int = 1024, on_block=None):
    """J^T J (n_par, n_par) and J^T r (n_par,) of the residuals r = net(z) - y, (n, n_out) flattened sample-major,
    for flat weights w (float64 torch tensors; zz (n, n_in) normalised inputs, yy (n, n_out) standardised
    outputs). The Jacobian of the outputs with respect to the hidden pre-activations is ``torch.func``'s (``vmap``
    of ``jacrev``), carried to W1 and b1 by the chain rule; the output layer's blocks are assembled from the
    activations (see the module docstring). Processed in blocks of ``rows_per_block`` samples (bounded memory);
    ``on_block(k, n_blocks)`` is called before block k (from 1).
    """
    import torch
    from torch.func import jacrev, vmap

    W1, b1, W2, b2 = _unpack(w, n_in, H, n_out)
    P = H * (n_in + 1)  # hidden-layer weights W1, b1: the first P entries of w
    n_par = P + n_out * (H + 1)

    def output_of_preactivation(a):  # (H,) hidden pre-activations of one sample -> (n_out,)
        return W2 @ torch.sigmoid(a) + b2

    jac_a = vmap(jacrev(output_of_preactivation))  # (m, H) -> (m, n_out, H)
    A = torch.zeros((n_par, n_par), dtype=w.dtype)
    Ahh = torch.zeros((P, P), dtype=w.dtype)
    g = torch.zeros(n_par, dtype=w.dtype)
    hh = torch.zeros((P, n_out, H + 1), dtype=w.dtype)  # Jh_k^T [s, 1] per output k
    ss = torch.zeros((H + 1, H + 1), dtype=w.dtype)  # [s, 1]^T [s, 1]
    n_blocks = -(-zz.shape[0] // rows_per_block)
    for s in range(0, zz.shape[0], rows_per_block):
        if on_block is not None:
            on_block(s // rows_per_block + 1, n_blocks)
        z, y = zz[s:s + rows_per_block], yy[s:s + rows_per_block]
        a = z @ W1.T + b1
        Ja = jac_a(a)  # d output / d pre-activation; chain rule to W1 (times z) and b1 (times 1):
        Jh = torch.cat([(Ja[..., None] * z[:, None, None, :]).reshape(z.shape[0], n_out, H * n_in), Ja], dim=2)
        S1 = torch.cat([torch.sigmoid(a), torch.ones((z.shape[0], 1), dtype=w.dtype)], dim=1)
        r = S1[:, :H] @ W2.T + b2 - y  # (m, n_out)
        Jf = Jh.reshape(-1, P)
        Ahh.addmm_(Jf.T, Jf)
        g[:P].addmv_(Jf.T, r.reshape(-1))
        hh += torch.einsum("mkp,mq->pkq", Jh, S1)
        ss.addmm_(S1.T, S1)
        for k in range(n_out):
            g[P + k * H:P + (k + 1) * H] += S1[:, :H].T @ r[:, k]
            g[P + n_out * H + k] += r[:, k].sum()
    A[:P, :P] = Ahh
    for k in range(n_out):
        cols = torch.cat([torch.arange(P + k * H, P + (k + 1) * H), torch.tensor([P + n_out * H + k])])
        A[:P, cols] = hh[:, k, :]
        A[cols[:, None], cols[None, :]] = ss
    A[P:, :P] = A[:P, P:].T
    return A, g


def _deterministic(torch) -> None:
    """torch's deterministic algorithms on. ``torch.use_deterministic_algorithms`` also sets the flag of the
    torch.compile back end, and importing that (torch._inductor) took 2.5-3.1 s of the ~5 s before the first LM
    iteration (measured on two loaded cores, torch 2.13); this trainer runs eager only, so the eager flag alone is
    set where torch has it."""
    setter = getattr(torch._C, "_set_deterministic_algorithms", None)
    if setter is None:
        torch.use_deterministic_algorithms(True)
    else:
        setter(True, warn_only=False)


def train(x: np.ndarray, y: np.ndarray, inputs: InputDefinition, *, seed: int = 0,
          cfg: TrainConfig = TrainConfig(), meta: dict | None = None, progress=None,
          groups: np.ndarray | None = None, status=None) -> TrainResult:
    """Train a network on inputs x (n, n_in) SI (kinematics, plus speed for the speed-input network) and UVLM
    outputs y (n, 4). groups (n,): split within each group (:func:`split_groups`), e.g. the speed of each sample.
    progress(iteration, max_iter, train_mse, val_mse) is called each iteration; status(text) as each stage starts
    (importing torch, normalising, and within each LM iteration each block of the Gauss-Newton matrix and each
    damped Cholesky solve: for 7-500-4 on 2300 samples on two loaded cores the first iteration took 24-34 s, J^T J
    ~55 % of it, the damped Cholesky solves of 6004 x 6004, 3 tries at 3-6 s each, the rest)."""
    def note(text: str) -> None:
        if status is not None:
            status(text)

    note("importing torch")
    import torch

    t0 = time.perf_counter()
    x = np.asarray(x, dtype=float)
    y = np.asarray(y, dtype=float)
    if x.ndim != 2 or x.shape[1] != inputs.n_in or y.shape != (x.shape[0], len(OUTPUTS)):
        raise ValueError(f"training data shapes {x.shape}, {y.shape} do not fit {inputs.n_in} inputs, 4 outputs")
    if not (np.all(np.isfinite(x)) and np.all(np.isfinite(y))):
        raise ValueError("training data hold non-finite values")
    note(f"normalising {x.shape[0]} samples")
    tr, va, te = split(x.shape[0], seed, cfg) if groups is None else split_groups(np.asarray(groups), seed, cfg)
    y_mean, y_std = y[tr].mean(axis=0), y[tr].std(axis=0)
    y_std = np.where(y_std > 0, y_std, 1.0)
    z = inputs.normalise(x)
    yn = (y - y_mean) / y_std

    _deterministic(torch)
    dt = torch.float64
    Z = {k: torch.from_numpy(z[idx]).to(dt) for k, idx in (("tr", tr), ("va", va))}
    Y = {k: torch.from_numpy(yn[idx]).to(dt) for k, idx in (("tr", tr), ("va", va))}
    n_in, H, n_out = inputs.n_in, cfg.hidden, len(OUTPUTS)

    g = torch.Generator().manual_seed(int(seed))
    w0 = torch.cat([torch.randn(H * n_in, generator=g, dtype=dt) * (2.0 / np.sqrt(n_in)),
                    torch.randn(H, generator=g, dtype=dt),
                    torch.randn(n_out * H, generator=g, dtype=dt) * (1.0 / np.sqrt(H)),
                    torch.zeros(n_out, dtype=dt)])

    def net_batch(w, zz):
        return _net_batch(w, zz, n_in, H, n_out)

    def mse(w, key):
        return float(torch.mean((net_batch(w, Z[key]) - Y[key]) ** 2))

    w = w0.clone()
    mu = cfg.mu
    best_w, best_val, fails = w.clone(), mse(w, "va"), 0
    history = [(0, mse(w, "tr"), best_val, mu)]
    it = 0
    stopped_by = "max_iter"
    for it in range(1, cfg.max_iter + 1):
        A, gvec = gauss_newton(w, Z["tr"], Y["tr"], n_in, H, n_out, on_block=lambda k, nb, it=it: note(
            f"LM iteration {it}: J^T J block {k}/{nb}"))
        loss = mse(w, "tr")
        while True:
            note(f"LM iteration {it}: Cholesky, mu {mu:.0e}")
            damped = A.clone()
            damped.diagonal().add_(mu)  # A + mu I, bit for bit, without two more n_par^2 temporaries
            L = torch.linalg.cholesky_ex(damped)
            if L.info == 0:
                dw = torch.cholesky_solve(-gvec[:, None], L.L)[:, 0]
                w_new = w + dw
                new_loss = mse(w_new, "tr")
                if new_loss < loss:
                    w, mu = w_new, max(mu * cfg.mu_dec, 1e-20)
                    break
            mu *= cfg.mu_inc
            if mu > cfg.mu_max:
                break
        val = mse(w, "va")
        history.append((it, mse(w, "tr"), val, mu))
        if progress:
            progress(it, cfg.max_iter, history[-1][1], val)
        if val < best_val:
            best_w, best_val, fails = w.clone(), val, 0
        else:
            fails += 1
        if fails >= cfg.max_fail:
            stopped_by = "early_stopping"
        elif mu > cfg.mu_max:
            stopped_by = "mu_max"
        elif time.perf_counter() - t0 > cfg.time_limit_s:
            stopped_by = "time_limit"
        else:
            continue
        break

    note("scoring the held-out samples")
    W1, b1, W2, b2 = (a.numpy().copy() for a in _unpack(best_w, n_in, H, n_out))
    sur = Surrogate(inputs, W1, b1, W2, b2, y_mean, y_std, meta=dict(meta or {}))
    pred = sur.predict(x[te, :7], x[te, 7] if inputs.speed is None else None)
    sc = scores(y[te], pred)
    full_meta = dict(meta or {}, seed=int(seed), hidden=H, n_train=len(tr), n_val=len(va), n_test=len(te),
                     iterations=it, stopped_by=stopped_by, best_val_mse=best_val, test_rmse=sc.rmse, test_r2=sc.r2,
                     train_config={k: getattr(cfg, k) for k in cfg.__dataclass_fields__})
    sur = Surrogate(inputs, W1, b1, W2, b2, y_mean, y_std, meta=full_meta)
    return TrainResult(sur, len(tr), len(va), len(te), sc, it, tuple(history), time.perf_counter() - t0,
                       x[te], y[te])
