"""Training and scoring of the per-step surrogate (:mod:`hawksim.backends.step_network`) on UVLM flights
(:mod:`hawksim.surrogate.flights`).

Split by FLIGHT (seeded): held-out flights are never seen in training or early stopping. Rows of the first
:data:`hawksim.surrogate.flights.WARM_BEATS` wingbeats (the wake's start from none) are left out of the training
of a network without the wake-age input (``TrainConfig.age_beats`` 0, the shipped one's) and kept, with that input
(:func:`hawksim.backends.step_network.wake_age`, the flight's launch at t = 0), by one with it; the scores are
those of the rows past the warm-up either way. A
symmetric flight contributes its left wing (the right one is its exact mirror image); a lateral flight both, the
right mapped to the left network by mirror symmetry.

Training: torch, Adam (``torch.optim.Adam``) on the mean squared error of the standardised outputs, mini-batches,
the learning rate reduced on validation plateaus (``ReduceLROnPlateau``), the best validation epoch kept.

Scores (:func:`score`): per-step R^2 of each of the six outputs on the held-out rows, and per held-out wingbeat
the cycle means L+, D+, M+, P+ (Eq. 2, :mod:`hawksim.backends.averages`) of the network's loads along the recorded
flight against the UVLM's: lift along world z, drag opposite to the body's horizontal heading, the nose-up pitching
moment about the body's centre of mass; P+ from the recorded joint power with the UVLM's aerodynamic power
replaced by the network's, P_aero = -sum_wings (omega_wing - omega_body) . M_hinge (exact for a rigid wing hinged
on the body).
"""

from __future__ import annotations

import functools
import math
import time
from dataclasses import dataclass

import numpy as np

from hawksim.backends.step_network import (
    MIRROR_F,
    MIRROR_M,
    MIRROR_V,
    MIRROR_W,
    OUTPUTS,
    StepNetwork,
    input_names,
    mirror_inputs,
    wake_age,
)
from hawksim.insect.kinematics import Kinematics
from hawksim.insect.folder import default_insect
from hawksim.surrogate.flights import COLUMNS, WARM_BEATS, StoredFlight

UPDATES_PER_BEAT = 40
"""UVLM updates per wingbeat in the flights (FLY_UVLM.steps_per_cycle): the rows' cadence, T / 40."""

COLUMN_INDEX: dict[str, int] = {n: i for i, n in enumerate(COLUMNS)}
"""The column of each recorded quantity in a flight's rows (:data:`hawksim.surrogate.flights.COLUMNS`)."""


def column_indices(*names: str) -> list[int]:
    """The row columns of the named quantities (:data:`COLUMN_INDEX`), in the order given."""
    return [COLUMN_INDEX[n] for n in names]


@dataclass(frozen=True)
class Rows:
    """Network rows of a set of flights. x (n, n_in) SI inputs, y (n, 6) SI targets (left-wing frame), flight (n,)
    flight indices, wing (n,) 0 left / 1 right (mirrored)."""

    x: np.ndarray
    y: np.ndarray
    flight: np.ndarray
    wing: np.ndarray


def flight_inputs(fl: StoredFlight, lags: tuple[float, ...], age_beats: float = 0.0) -> tuple[np.ndarray,
                                                                                              np.ndarray]:
    """(left-wing inputs (n, n_in), mask (n,) of rows past the warm-up) for every row of a flight; with
    ``age_beats`` > 0 the last input is the wake's age (:func:`wake_age`: the flight was launched from no wake at
    t = 0)."""
    r = fl.rows
    n = r.shape[0]
    f = fl.kinematics[0]
    ph = 2 * math.pi * f * r[:, COLUMN_INDEX["t"]]
    state = r[:, column_indices(*("vx", "vy", "vz", "wx", "wy", "wz"))]
    parts = [np.broadcast_to(fl.kinematics, (n, 7)), np.sin(ph)[:, None], np.cos(ph)[:, None], state]
    for lag in lags:
        k = int(round(lag * UPDATES_PER_BEAT))
        idx = np.clip(np.arange(n) - k, 0, None)
        parts.append(state[idx])
    if age_beats > 0:
        parts.append(wake_age(r[:, COLUMN_INDEX["t"]], f, age_beats)[:, None])
    x = np.concatenate(parts, axis=1)
    return x, r[:, COLUMN_INDEX["t"]] >= WARM_BEATS / f - 1e-9


def rows_of(flights: list[StoredFlight], lags: tuple[float, ...], age_beats: float = 0.0) -> Rows:
    """Training rows (module docstring) of ``flights``: past the warm-up, or every row with the wake-age input
    (``age_beats`` > 0)."""
    xs, ys, fid, wid = [], [], [], []
    for j, fl in enumerate(flights):
        x, keep = flight_inputs(fl, lags, age_beats)
        if age_beats > 0:
            keep = np.ones_like(keep)
        r = fl.rows[keep]
        x = x[keep]
        yl = np.concatenate([r[:, column_indices("FLx", "FLy", "FLz")], r[:, column_indices("MLx", "MLy", "MLz")]],
                            axis=1)
        xs.append(x)
        ys.append(yl)
        fid.append(np.full(len(x), j))
        wid.append(np.zeros(len(x), int))
        if not fl.symmetric:
            yr = np.concatenate([r[:, column_indices("FRx", "FRy", "FRz")] * MIRROR_F,
                                 r[:, column_indices("MRx", "MRy", "MRz")] * MIRROR_M], axis=1)
            xs.append(mirror_inputs(x))
            ys.append(yr)
            fid.append(np.full(len(x), j))
            wid.append(np.ones(len(x), int))
    return Rows(np.concatenate(xs), np.concatenate(ys), np.concatenate(fid), np.concatenate(wid))


def split_flights(n: int, seed: int, test: float = 0.15, val: float = 0.1) -> tuple[np.ndarray, np.ndarray,
                                                                                     np.ndarray]:
    """(train, val, test) flight indices: a seeded permutation of range(n)."""
    p = np.random.default_rng([int(seed), 2121]).permutation(n)
    n_test, n_val = max(1, int(round(test * n))), max(1, int(round(val * n)))
    return np.sort(p[n_test + n_val:]), np.sort(p[n_test:n_test + n_val]), np.sort(p[:n_test])


@dataclass(frozen=True)
class TrainConfig:
    """hidden: widths of the tanh hidden layers; lags: history lags [periods]; epochs: most epochs; batch: rows per
    step; lr: Adam's initial learning rate; patience: epochs without validation gain before the rate is halved;
    stop: epochs without gain before training stops; max_seconds: wall-time cap [s]; seed; weight_decay: AdamW's
    decoupled weight decay (0: Adam); ensemble: members trained from different initial weights and folded into one
    network (:func:`fold_ensemble`); age_beats: saturation of the wake-age input [wingbeats] (0: no such input, the
    warm-up rows left out; module docstring)."""

    hidden: tuple[int, ...] = (128, 128, 128)
    lags: tuple[float, ...] = ()
    epochs: int = 300
    batch: int = 256
    lr: float = 2e-3
    patience: int = 10
    stop: int = 40
    max_seconds: float = 1800.0
    seed: int = 0
    weight_decay: float = 0.0
    ensemble: int = 1
    age_beats: float = 0.0


def train(train_rows: Rows, val_rows: Rows, cfg: TrainConfig, log=None) -> tuple[StepNetwork, dict]:
    """Fit the network (module docstring; ``cfg.ensemble`` members from seeds cfg.seed, cfg.seed + 1, ..., folded
    into one network); returns it and a history {epochs, best_epoch, val_mse, wall_s} (lists for an ensemble)."""
    import torch

    x_mean, x_std = train_rows.x.mean(0), train_rows.x.std(0)
    x_std = np.where(x_std > 1e-12 * np.maximum(1.0, np.abs(x_mean)), x_std, 1.0)  # constant inputs pass through
    y_mean, y_std = train_rows.y.mean(0), train_rows.y.std(0)

    def t(a):
        return torch.as_tensor(a, dtype=torch.float32)

    X, Y = t((train_rows.x - x_mean) / x_std), t((train_rows.y - y_mean) / y_std)
    Xv, Yv = t((val_rows.x - x_mean) / x_std), t((val_rows.y - y_mean) / y_std)
    members, hists = [], []
    for k in range(cfg.ensemble):
        w, h = _train_member(X, Y, Xv, Yv, cfg, cfg.seed + k, log)
        members.append(w)
        hists.append(h)
    weights = members[0] if len(members) == 1 else fold_ensemble(members)
    sn = StepNetwork(weights, x_mean, x_std, y_mean, y_std, lags=tuple(cfg.lags), age_beats=cfg.age_beats)
    if len(hists) == 1:
        return sn, hists[0]
    if log:
        with torch.no_grad():
            ys = StepNetwork(weights, np.zeros(X.shape[1]), np.ones(X.shape[1]), np.zeros(6), np.ones(6),
                             lags=tuple(cfg.lags), age_beats=cfg.age_beats).predict(Xv.numpy())
        log(f"ensemble of {len(members)}: val mse {float(np.mean((ys - Yv.numpy()) ** 2)):.3e}")
    return sn, {k: [h[k] for h in hists] for k in hists[0]}


def fold_ensemble(members: list[tuple[tuple[np.ndarray, np.ndarray], ...]]) -> tuple[tuple[np.ndarray, np.ndarray],
                                                                                        ...]:
    """The mean of K tanh MLPs of the same shape as ONE MLP: hidden layers side by side (the first layer's weights
    stacked, the middle ones block-diagonal), the output layer averaging them. Exact."""
    import scipy.linalg

    K, L = len(members), len(members[0])
    out = []
    for li in range(L):
        Ws = [m[li][0] for m in members]
        bs = [m[li][1] for m in members]
        if li == 0:
            W, b = np.concatenate(Ws, axis=0), np.concatenate(bs)
        elif li < L - 1:
            W, b = scipy.linalg.block_diag(*Ws), np.concatenate(bs)
        else:
            W, b = np.concatenate(Ws, axis=1) / K, np.mean(bs, axis=0)
        out.append((W.astype(np.float32), b.astype(np.float32)))
    return tuple(out)


def _train_member(X, Y, Xv, Yv, cfg: TrainConfig, seed: int, log):
    import torch

    torch.manual_seed(seed)
    layers, n_in = [], X.shape[1]
    for h in cfg.hidden:
        layers += [torch.nn.Linear(n_in, h), torch.nn.Tanh()]
        n_in = h
    layers.append(torch.nn.Linear(n_in, len(OUTPUTS)))
    net = torch.nn.Sequential(*layers)
    opt = (torch.optim.AdamW(net.parameters(), lr=cfg.lr, weight_decay=cfg.weight_decay) if cfg.weight_decay
           else torch.optim.Adam(net.parameters(), lr=cfg.lr))
    sched = torch.optim.lr_scheduler.ReduceLROnPlateau(opt, factor=0.5, patience=cfg.patience)
    gen = torch.Generator().manual_seed(seed)
    best, best_state, best_epoch, t0 = math.inf, None, -1, time.perf_counter()
    epoch = 0
    for epoch in range(cfg.epochs):
        net.train()
        perm = torch.randperm(X.shape[0], generator=gen)
        for s in range(0, X.shape[0], cfg.batch):
            b = perm[s:s + cfg.batch]
            opt.zero_grad()
            loss = torch.mean((net(X[b]) - Y[b]) ** 2)
            loss.backward()
            opt.step()
        net.eval()
        with torch.no_grad():
            vl = float(torch.mean((net(Xv) - Yv) ** 2))
        sched.step(vl)
        if vl < best:
            best, best_epoch = vl, epoch
            best_state = {k: v.detach().clone() for k, v in net.state_dict().items()}
        if log and epoch % 10 == 0:
            lr = opt.param_groups[0]["lr"]
            log(f"seed {seed} epoch {epoch}: val mse {vl:.3e} (best {best:.3e} at {best_epoch}), lr {lr:.1e}")
        if epoch - best_epoch > cfg.stop or time.perf_counter() - t0 > cfg.max_seconds:
            break
    net.load_state_dict(best_state)
    lin = [m for m in net if isinstance(m, torch.nn.Linear)]
    weights = tuple((m.weight.detach().numpy().astype(np.float32), m.bias.detach().numpy().astype(np.float32))
                    for m in lin)
    return weights, {"epochs": epoch + 1, "best_epoch": best_epoch, "val_mse": best,
                     "wall_s": time.perf_counter() - t0}


# ------------------------------------------------------------------------------------------------- scores


def r2(y: np.ndarray, p: np.ndarray) -> np.ndarray:
    """Coefficient of determination per column."""
    return 1.0 - ((y - p) ** 2).sum(0) / ((y - y.mean(0)) ** 2).sum(0)


@functools.lru_cache(maxsize=1)
def _model():
    from hawksim.insect.model import load_model

    return load_model()


def wing_geometry(kin: Kinematics, t: np.ndarray) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """(wing -> body rotations (n, 2, 3, 3), hinge positions relative to the body's centre of mass in body axes
    (n, 2, 3) [m], wing angular velocities relative to the body in body axes (n, 2, 3) [rad/s]) of the prescribed
    motion at times t (n,) [s], from the MuJoCo model's kinematics with the body at rest at the origin."""
    import mujoco

    from hawksim.insect.accessors import ModelIndex

    m = _model()
    d = mujoco.MjData(m)
    ix = ModelIndex.of(m)
    R, h, w = np.empty((len(t), 2, 3, 3)), np.empty((len(t), 2, 3)), np.empty((len(t), 2, 3))
    v6 = np.zeros(6)
    for i, ti in enumerate(t):
        wt = 2 * math.pi * kin.f * ti
        q, qd, _ = kin.eq1(math.cos(wt), math.sin(wt))
        d.qpos[:] = m.qpos0
        d.qpos[3:7] = (1.0, 0.0, 0.0, 0.0)
        d.qvel[:] = 0.0
        d.qpos[ix.wing_qpos] = q + q
        d.qvel[ix.wing_dof] = qd + qd
        mujoco.mj_kinematics(m, d)
        mujoco.mj_comPos(m, d)
        mujoco.mj_comVel(m, d)
        com = d.xipos[ix.body]
        for k, wid in enumerate(ix.wings):
            R[i, k] = d.xmat[wid].reshape(3, 3)
            h[i, k] = d.xpos[wid] - com
            mujoco.mj_objectVelocity(m, d, mujoco.mjtObj.mjOBJ_XBODY, wid, v6, 0)
            w[i, k] = v6[:3]
    return R, h, w


def flight_loads(fl: StoredFlight, y_left: np.ndarray, y_right: np.ndarray, geom) -> dict[str, np.ndarray]:
    """Per-row lift, drag, nose-up moment about the body's centre of mass [N, N, N m] and aerodynamic power [W] of
    wing loads (n, 6) in wing axes (left, right), along the recorded flight."""
    Rwb, hinge, w_rel = geom
    r = fl.rows
    Rb = r[:, [COLUMN_INDEX[f"R{i}{j}"] for i in range(3) for j in range(3)]].reshape(-1, 3, 3)
    F = np.stack([y_left[:, :3], y_right[:, :3]], axis=1)
    M = np.stack([y_left[:, 3:], y_right[:, 3:]], axis=1)
    Fb = np.einsum("nkij,nkj->nki", Rwb, F)
    Mb = np.einsum("nkij,nkj->nki", Rwb, M)
    F_tot = Fb.sum(1)
    M_com = (Mb + np.cross(hinge, Fb)).sum(1)
    F_world = np.einsum("nij,nj->ni", Rb, F_tot)
    head = Rb[:, :, 0].copy()
    head[:, 2] = 0.0
    head /= np.linalg.norm(head, axis=1, keepdims=True)
    return {"lift": F_world[:, 2], "drag": -(F_world * head).sum(1), "moment": -M_com[:, 1],
            "power_aero": -np.einsum("nki,nki->n", w_rel, Mb)}


def cycle_means(fl: StoredFlight, loads: dict[str, np.ndarray], power_aero_uvlm: np.ndarray,
                first: int = WARM_BEATS) -> np.ndarray:
    """(beats, 4) L+, D+, M+, P+ of every complete wingbeat from beat ``first`` (0-based; default past the
    warm-up); P+ from the recorded joint power with the UVLM's aerodynamic power replaced by
    ``loads['power_aero']``."""
    insect = default_insect()
    W, c, P0 = insect.weight, insect.cbar, insect.P0
    n = fl.rows.shape[0]
    p = fl.rows[:, COLUMN_INDEX["power_joint"]] - power_aero_uvlm + loads["power_aero"]
    out = []
    for k in range(first, n // UPDATES_PER_BEAT):
        s = slice(k * UPDATES_PER_BEAT, (k + 1) * UPDATES_PER_BEAT)
        out.append((loads["lift"][s].mean() / W, loads["drag"][s].mean() / W, loads["moment"][s].mean() / (W * c),
                    np.maximum(p[s], 0.0).mean() / P0))
    return np.array(out).reshape(-1, 4)


def flight_cycle_means(fl: StoredFlight, y_left: np.ndarray | None = None,
                       y_right: np.ndarray | None = None, first: int = WARM_BEATS) -> np.ndarray:
    """(beats, 4) L+, D+, M+, P+ of every complete wingbeat of a recorded flight from beat ``first`` (default past
    the warm-up; :func:`cycle_means`), from the flight's own UVLM wing loads or, where given, from other per-row
    wing loads y_left, y_right (n, 6) in wing axes (force [N], moment about the hinge [N m]; a network's
    predictions)."""
    r = fl.rows
    u_l = r[:, column_indices("FLx", "FLy", "FLz", "MLx", "MLy", "MLz")]
    u_r = r[:, column_indices("FRx", "FRy", "FRz", "MRx", "MRy", "MRz")]
    geom = wing_geometry(Kinematics.from_array(fl.kinematics), r[:, COLUMN_INDEX["t"]])
    yl = u_l if y_left is None else y_left
    yr = u_r if y_right is None else y_right
    return cycle_means(fl, flight_loads(fl, yl, yr, geom), r[:, COLUMN_INDEX["power_aero"]], first)


def replay(net: StepNetwork, fl: StoredFlight) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """The network's wing loads along a recorded flight (its inputs from the flight's rows, :func:`flight_inputs`,
    the flight launched from no wake at t = 0): (left (n, 6), right (n, 6) in their own wing axes, mask (n,) of the
    rows past the warm-up)."""
    x, keep = flight_inputs(fl, net.lags, net.age_beats)
    mirror = np.concatenate([MIRROR_F, MIRROR_M])
    return net.predict(x), net.predict(mirror_inputs(x)) * mirror, keep


def score(net: StepNetwork, flights: list[StoredFlight]) -> dict:
    """Held-out scores of ``net`` on ``flights`` (module docstring): per-step R^2 per output in wing axes (``r2``)
    and in body axes (``r2_body``: force and moment about the hinge turned to the body frame), over the rows past
    the warm-up of the left wings and of the right wings of lateral flights (mirrored onto the left); and the
    cycle-mean errors |network - UVLM| of L+, D+, M+, P+ over the complete held-out wingbeats."""
    mirror = np.concatenate([MIRROR_F, MIRROR_M])
    wing_u, wing_p, body_u, body_p, uvlm, pred = [], [], [], [], [], []
    for fl in flights:
        yl, yr, keep = replay(net, fl)
        r = fl.rows
        u_l = r[:, column_indices("FLx", "FLy", "FLz", "MLx", "MLy", "MLz")]
        u_r = r[:, column_indices("FRx", "FRy", "FRz", "MRx", "MRy", "MRz")]
        geom = wing_geometry(Kinematics.from_array(fl.kinematics), r[:, COLUMN_INDEX["t"]])
        Rwb = geom[0]
        sides = [(0, u_l, yl)] + ([] if fl.symmetric else [(1, u_r, yr)])
        for k, u, y in sides:
            m = 1.0 if k == 0 else mirror  # onto the left wing
            wing_u.append((u * m)[keep])
            wing_p.append((y * m)[keep])
            mb = 1.0 if k == 0 else np.concatenate([MIRROR_V, MIRROR_W])
            for dst, a in ((body_u, u), (body_p, y)):
                b = np.concatenate([np.einsum("nij,nj->ni", Rwb[:, k], a[:, :3]),
                                    np.einsum("nij,nj->ni", Rwb[:, k], a[:, 3:])], axis=1)
                dst.append((b * mb)[keep])
        pa = r[:, COLUMN_INDEX["power_aero"]]
        uvlm.append(cycle_means(fl, flight_loads(fl, u_l, u_r, geom), pa))
        pred.append(cycle_means(fl, flight_loads(fl, yl, yr, geom), pa))
    wing_u, wing_p = np.concatenate(wing_u), np.concatenate(wing_p)
    body_u, body_p = np.concatenate(body_u), np.concatenate(body_p)
    per_step = {k: float(v) for k, v in zip(OUTPUTS, r2(wing_u, wing_p))}
    per_body = {k: float(v) for k, v in zip(OUTPUTS, r2(body_u, body_p))}
    uvlm, pred = np.concatenate(uvlm), np.concatenate(pred)
    err = np.abs(pred - uvlm)
    names = ("L_plus", "D_plus", "M_plus", "P_plus")
    return {"n_rows": int(len(wing_u)), "n_flights": len(flights), "n_beats": int(len(uvlm)),
            "r2": per_step, "r2_min": float(min(per_step.values())), "r2_body": per_body,
            "r2_body_min": float(min(per_body.values())),
            "cycle_mean_abs_error": {k: float(v) for k, v in zip(names, err.mean(0))} if len(err) else {},
            "cycle_mean_max_error": {k: float(v) for k, v in zip(names, err.max(0))} if len(err) else {},
            "cycle_mean_p95_error": {k: float(v) for k, v in zip(names, np.percentile(err, 95, axis=0))}
            if len(err) else {},
            "cycle_mean_bias": {k: float(v) for k, v in zip(names, (pred - uvlm).mean(0))} if len(err) else {}}


def fit(path, cfg: TrainConfig, *, command: str = "", max_flights: int | None = None, log=None,
        flights: list[StoredFlight] | None = None, extra: tuple = ()) -> tuple[StepNetwork, dict]:
    """Train on the 'ok' flights of a data-set file (optionally those with idx < ``max_flights``; ``flights``: the
    flights already read from it) split by flight with ``cfg.seed``; returns the network (its ``meta``: provenance,
    split, held-out scores) and the scores (of the held-out flights of ``path``). ``extra``: more data-set files
    (other flight families, :data:`hawksim.surrogate.flights.FAMILIES`), each split by flight with the same seed on
    its own, so the split of ``path`` is the one it has alone; their train and validation flights join the
    training, their held-out flights are scored apart (``meta['extra']``)."""
    from hawksim.surrogate.flights import read_flights

    flights = read_flights(path) if flights is None else flights
    if max_flights is not None:
        flights = [f for f in flights if f.idx < max_flights]
    if len(flights) < 3:
        raise ValueError(f"{path}: {len(flights)} usable flights; need at least 3 (train, validation, test)")
    tr, va, te = split_flights(len(flights), cfg.seed)
    fl_tr, fl_va = [flights[i] for i in tr], [flights[i] for i in va]
    more = []
    for p in extra:
        fx = read_flights(p)
        if len(fx) < 3:
            raise ValueError(f"{p}: {len(fx)} usable flights; need at least 3 (train, validation, test)")
        a, b, c = split_flights(len(fx), cfg.seed)
        fl_tr += [fx[i] for i in a]
        fl_va += [fx[i] for i in b]
        more.append((p, fx, c))
    rows_tr, rows_va = rows_of(fl_tr, cfg.lags, cfg.age_beats), rows_of(fl_va, cfg.lags, cfg.age_beats)
    net, hist = train(rows_tr, rows_va, cfg, log=log)
    test = [flights[i] for i in te]
    sc = score(net, test)
    extra_meta = [{"data": str(p), "data_sha256": _flights_sha256(p), "n_flights": len(fx),
                   "test_flights": [int(fx[i].idx) for i in c], "test": score(net, [fx[i] for i in c])}
                  for p, fx, c in more]
    meta = {"command": command, "data": str(path), "data_sha256": _flights_sha256(path, max_flights),
            "max_flights": max_flights, "config": {
                "hidden": list(cfg.hidden), "lags": list(cfg.lags), "epochs": cfg.epochs, "batch": cfg.batch,
                "lr": cfg.lr, "seed": cfg.seed, **({"age_beats": cfg.age_beats} if cfg.age_beats else {})},
            "n_flights": len(flights), "n_train_rows": int(len(rows_tr.y)),
            "n_val_rows": int(len(rows_va.y)), "test_flights": [int(flights[i].idx) for i in te],
            "val_flights": [int(flights[i].idx) for i in va], "history": hist, "test": sc}
    if extra_meta:
        meta["extra"] = extra_meta
    return StepNetwork(net.weights, net.x_mean, net.x_std, net.y_mean, net.y_std, lags=net.lags, meta=meta,
                       age_beats=net.age_beats), sc


def _flights_sha256(path, max_flights: int | None = None) -> str:
    """SHA-256 of the flights' stored rows and specs (independent of the SQLite page layout); with ``max_flights``
    of the flights idx < max_flights only (a network trained on a prefix of a data set that grew since: the
    resumable generation appends flights, so the prefix's hash is the one the network recorded)."""
    import hashlib

    from hawksim.surrogate.dataset import open_dataset

    h = hashlib.sha256()
    conn = open_dataset(path)
    where = "" if max_flights is None else f" WHERE idx < {int(max_flights)}"
    try:
        for row in conn.execute(f"SELECT seed, idx, speed, status, data FROM flights{where} ORDER BY seed, idx"):
            h.update(repr(row[:4]).encode())
            h.update(row[4])
    finally:
        conn.close()
    return h.hexdigest()


__all__ = ["fit", "Rows", "TrainConfig", "rows_of", "split_flights", "train", "score", "input_names", "flight_inputs"]
