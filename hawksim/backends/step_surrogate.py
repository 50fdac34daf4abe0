"""`hawksim fly --aero surrogate`: the per-step neural surrogate of the UVLM as a flight backend.

Every call evaluates the left-wing network of :mod:`hawksim.backends.step_network` (shipped:
``insects/hawkmoth/data/surrogates/uvlm_step.safetensors``) for both wings in one (2, n_in) float32 batch, the
right wing at the mirrored inputs, in numpy with the normalisation folded into the weights. Inputs: the flight's
kinematics, the phase 2 pi f t, the body's velocity relative to the air and its angular velocity in body axes (and, for
a network with history lags, the same at t - lag T from this backend's own record of past calls, linearly interpolated;
before the flight's start the first call's state; and, for a network with the wake-age input, the wingbeats since the
flight's launch, see below). Outputs: each wing's force and moment about its hinge in its wing
axes, turned to the world frame with the flight state's wing attitude. Power: P = -sum_wings (omega_wing - omega_body) .
M_hinge [W], the UVLM's definition for a rigid wing hinged on the body (:mod:`hawksim.backends.base`).

The wake's age (a network with ``age_beats`` > 0, :func:`hawksim.backends.step_network.wake_age`). The UVLM starts
every flight from no wake and its loads differ over the first beats (the wake's start-up); a network with this input
learned them. How the loop knows the wake's age: a flight is a launch from no wake at its reset (t = 0, as the UVLM's
is) unless the backend was seeded with a record (:meth:`StepSurrogateBackend.seed`: the flight continues a periodic
orbit, whose wake is developed) or told so (:meth:`StepSurrogateBackend.set_developed_wake`, for a flight started
from a state saved mid-flight); then the input is saturated from the first call. The launch time lives in a
one-element array that the native callback reads by address, as it does the record.

Where it holds: the states of the training flights (:mod:`hawksim.surrogate.flights`: the shipped UVLM orbits at
0-2 m/s, kinematics within +-2.5 % of Table 2's ranges about them, perturbations up to ~1 m/s and 45 deg); outside
it extrapolates without warning, like any regression.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from hawksim.backends.base import FlightState, WingLoads
from hawksim.backends.record import (HISTORY_ROW, HISTORY_ROWS_PER_BEAT, MAX_NATIVE_LAGS,  # noqa: F401 (re-exported)
                                     history_rows, lagged_states, new_history, record_scale, record_size,
                                     set_history_rows, set_history_values)
from hawksim.backends.step_network import (MIRROR_F, MIRROR_M, MIRROR_V, MIRROR_W, StepNetwork, load, shipped_path,
                                           wake_age)
from hawksim.insect.kinematics import Kinematics


class StepSurrogateBackend:
    """Per-step surrogate loads for kinematics ``kin`` (network: default the shipped one)."""

    name = "surrogate"

    def __init__(self, kin: Kinematics, network: StepNetwork | None = None):
        self.net = network if network is not None else _shipped()
        self.layers = self.net.folded()
        self.blocks = ensemble_blocks(self.layers)
        self.kin = kin
        self.lags = tuple(self.net.lags)
        self._x = np.zeros((2, self.net.n_in), dtype=np.float32)
        self._x[:, :7] = kin.as_array()
        self._omega_f = 2.0 * math.pi * kin.f
        self._lag_beats = np.asarray(self.lags, dtype=np.float64)
        self.history = new_history(self.lags)
        """The record of this backend's calls that its history inputs read (:func:`lagged_states`); the flight
        loop's native callback reads and writes the same array, so the two paths share one record."""
        self._lagged_out = np.zeros((len(self.lags), 6))
        self._seed: tuple[np.ndarray, float] | None = None
        self.age_beats = float(self.net.age_beats)
        self.launch = np.zeros(1)
        """The launch time [s] the wake-age input counts from (-inf: a developed wake); set at :meth:`reset`,
        read by the native callback at its address."""
        self._developed: bool | None = None

    def set_developed_wake(self, developed: bool | None = True) -> None:
        """Whether the flights' wake is developed from their start (the wake-age input saturated): True for a flight
        started from a state saved mid-flight, False for a launch from no wake, None (default) developed exactly when
        the backend is seeded with a record (module docstring). Takes effect at the next :meth:`reset`."""
        self._developed = developed

    # the record memory protocol (:class:`hawksim.backends.memory.RecordMemory`)
    def seed(self, record: np.ndarray, dt: float) -> None:
        """Start every flight (:meth:`reset`) with ``record`` (n, 6), written as calls at t - n dt ... t - dt
        before the start t [s]: a periodic orbit's own record (:attr:`hawksim.flight.orbit.Orbit.record`), so that
        a flight launched on the orbit continues it. Without a seed a flight starts with no record."""
        self._seed = (np.asarray(record, float), float(dt))

    def snapshot(self, calls_per_beat: int) -> np.ndarray | None:
        """The newest records (n, 6) that a beat's history inputs read (n = :func:`record_size` of the lags at
        ``calls_per_beat`` calls per wingbeat), oldest first; None for a network without lags."""
        n = record_size(self.lags, calls_per_beat)
        return history_rows(self.history, n) if n else None

    def restore(self, record: np.ndarray) -> None:
        """Overwrite the values of the newest len(record) records with ``record`` (n, 6), their times kept."""
        set_history_values(self.history, np.asarray(record, float))

    def memory_beats(self) -> int:
        """Whole wingbeats of history the network's inputs reach back (:func:`memory_beats`)."""
        return memory_beats(self.net)

    def native(self, every: int):
        """This network for the flight loop's native callback (:class:`NativeNetwork`), updated every ``every``
        steps; a network with history lags reads and writes this backend's :attr:`history`."""
        blocks = self.blocks if self.blocks is not None else tuple(
            (W[None], b.reshape(1, 1, -1)) for W, b in self.layers[:-1]) + (
            (self.layers[-1][0][None], np.zeros((1, 1, 6), np.float32)),)
        K, h = blocks[0][0].shape[0], blocks[0][0].shape[2]
        parts = []
        for k, (W, b) in enumerate(blocks):
            parts.append(np.ascontiguousarray(W.transpose(0, 2, 1)).ravel())  # (K, out, in): the layout of mlp
            parts.append(np.broadcast_to(b.reshape(-1, b.shape[-1]), (K, b.shape[-1])).ravel() if k < len(blocks) - 1
                         else np.zeros(K * 6, np.float32))
        parts.append(self.layers[-1][1])
        return NativeNetwork(buffer=NativeNetwork.pack(np.concatenate(parts)), members=K, n_in=self.net.n_in,
                             hidden=h, layers=len(blocks), every=every, omega_f=self._omega_f,
                             kinematics=self._x[0, :7].astype(np.float64),
                             mirrors=np.concatenate([MIRROR_V, MIRROR_W, MIRROR_F, MIRROR_M]).astype(float),
                             lags=self.lags, history=self.history, period=1.0 / self.kin.f,
                             age_beats=self.age_beats, launch=self.launch, age_frequency=float(self.kin.f))

    def _phase(self, state: FlightState) -> float:
        """The phase input [rad] at this call: 2 pi f t of this backend's kinematics."""
        return self._omega_f * state.t

    def reset(self, state: FlightState) -> None:
        if self._seed is None:
            self.history[1] = 0.0  # no records
        else:
            set_history_rows(self.history, self._seed[0], state.t, self._seed[1])
        developed = self._seed is not None if self._developed is None else self._developed
        self.launch[0] = -math.inf if developed else state.t

    def _lagged(self, t: float, s: np.ndarray) -> np.ndarray:
        """States (n_lags, 6) at t - lag T for each lag, after recording s (6,) at t (:func:`lagged_states`)."""
        lagged_states(self.history, t, s, self._lag_beats, 1.0 / self.kin.f, self._lagged_out)
        return self._lagged_out

    def evaluate(self, x: np.ndarray) -> np.ndarray:
        """The folded network at SI inputs x (n, n_in) float32 -> (n, 6). An ensemble folded into one network
        (block-diagonal hidden layers) is evaluated block by block, one stacked matmul per layer: K small products
        instead of one K^2 times larger, which OpenBLAS would also spread over threads (measured 4.4 ms a call
        on the loaded 2-core host against 0.28 ms on one thread)."""
        last = len(self.layers) - 1
        if self.blocks is not None:
            h = x[None]
            for k, (WT, b) in enumerate(self.blocks):
                h = np.matmul(h, WT)
                h += b
                if k < last:
                    np.tanh(h, out=h)
            return h.sum(0) + self.layers[-1][1]
        h = x
        for k, (WT, b) in enumerate(self.layers):
            h = h @ WT
            h += b
            if k < last:
                np.tanh(h, out=h)
        return h

    def loads(self, state: FlightState) -> WingLoads:
        R = state.body_R
        v = R.T @ (state.body_v - state.air_v)
        w = R.T @ state.body_omega
        x = self._x
        ph = self._phase(state)
        x[:, 7] = math.sin(ph)
        x[:, 8] = math.cos(ph)
        x[0, 9:12], x[0, 12:15] = v, w
        x[1, 9:12], x[1, 12:15] = v * MIRROR_V, w * MIRROR_W
        if self.lags:
            for k, s in enumerate(self._lagged(state.t, np.concatenate([v, w]))):
                j = 15 + 6 * k
                x[0, j:j + 3], x[0, j + 3:j + 6] = s[:3], s[3:]
                x[1, j:j + 3], x[1, j + 3:j + 6] = s[:3] * MIRROR_V, s[3:] * MIRROR_W
        if self.age_beats > 0:
            x[:, -1] = wake_age(state.t, self.kin.f, self.age_beats, self.launch[0])
        y = self.evaluate(x).astype(np.float64)
        F_w = np.stack([y[0, :3], y[1, :3] * MIRROR_F])
        M_w = np.stack([y[0, 3:], y[1, 3:] * MIRROR_M])
        WR = state.wing_R
        force = np.einsum("kij,kj->ki", WR, F_w)
        moment = np.einsum("kij,kj->ki", WR, M_w)
        power = -float(np.sum((state.wing_omega - state.body_omega) * moment))
        return WingLoads(force=force, moment=moment, power=power)


@dataclass(frozen=True)
class NativeNetwork:
    """A per-step surrogate for the flight loop's native callback (:meth:`StepSurrogateBackend.native`;
    :func:`hawksim.flight.network_kernel.mlp` evaluates it):
    ``buffer`` float64-aligned bytes: its first float64 the number of float32 values that follow (the layout of
    :func:`hawksim.flight.network_kernel.mlp`); members, n_in, hidden, layers; ``every`` steps per update; omega_f =
    2 pi f [rad/s] of its phase input; kinematics (7,) its kinematic inputs (SI); mirrors (12,) MIRROR_V,
    MIRROR_W, MIRROR_F, MIRROR_M; plant_kinematics below."""

    buffer: np.ndarray
    members: int
    n_in: int
    hidden: int
    layers: int
    every: int
    omega_f: float
    kinematics: np.ndarray
    mirrors: np.ndarray
    plant_kinematics: bool = False
    """True: the kinematic inputs and the phase are the controlled plant's blend (mode 1) instead of ``kinematics``
    and omega_f t (:class:`hawksim.backends.controlled_step_surrogate.ControlledStepSurrogate`)."""
    lags: tuple[float, ...] = ()
    """History lags [wingbeats] (at most :data:`MAX_NATIVE_LAGS`); their inputs follow the first 15."""
    history: np.ndarray | None = None
    """The backend's record of calls (:func:`new_history`), read and written by the callback (None: no lags)."""
    period: float = 0.0
    """The wingbeat period T [s] the lags are counted in."""
    age_beats: float = 0.0
    """Saturation of the wake-age input, the last input [wingbeats] (0: the network has none)."""
    launch: np.ndarray | None = None
    """The backend's launch time (1,) [s] (:attr:`StepSurrogateBackend.launch`) the age input counts from."""
    age_frequency: float = 0.0
    """The frequency [Hz] the age input counts wingbeats in (the backend's kinematics')."""

    @staticmethod
    def pack(values: np.ndarray) -> np.ndarray:
        """The buffer for float32 ``values``: a float64 count, then the values."""
        values = np.ascontiguousarray(values, np.float32)
        out = np.zeros(1 + (len(values) + 1) // 2, np.float64)
        out[0] = len(values)
        out[1:].view(np.float32)[:len(values)] = values
        return out


def ensemble_blocks(layers) -> tuple[tuple[np.ndarray, np.ndarray], ...] | None:
    """The folded layers ((W^T (in, out), b), ...) split into K > 1 independent members when every hidden-to-hidden
    weight matrix is block-diagonal with K equal blocks (an ensemble folded by
    :func:`hawksim.surrogate.step_train.fold_ensemble`): ((W0 (K, n_in, h), b0 (K, 1, h)), (W (K, h, h), b (K, 1, h)),
    ..., (W_L (K, h, 6), 0)); the output bias is added once after the sum over members. None if not an ensemble."""
    if len(layers) < 3:
        return None
    width = layers[0][0].shape[1]
    for K in range(8, 1, -1):
        if width % K:
            continue
        hb = width // K
        mask = np.kron(np.eye(K, dtype=bool), np.ones((hb, hb), dtype=bool))
        if all(W.shape == (width, width) and not np.any(W[~mask]) for W, _ in layers[1:-1]):
            out = [(np.ascontiguousarray(layers[0][0].reshape(-1, K, hb).transpose(1, 0, 2)),
                    layers[0][1].reshape(K, 1, hb).copy())]
            for W, b in layers[1:-1]:
                out.append((np.ascontiguousarray(np.stack([W[i * hb:(i + 1) * hb, i * hb:(i + 1) * hb]
                                                           for i in range(K)])), b.reshape(K, 1, hb).copy()))
            WL = layers[-1][0]
            out.append((np.ascontiguousarray(WL.reshape(K, hb, -1)), np.zeros((1, 1, WL.shape[1]), np.float32)))
            return tuple(out)
    return None


def memory_beats(network: StepNetwork | None = None) -> int:
    """Whole wingbeats of history the network's inputs reach back (0 without lags): a flight must run that long
    before its loads are those of a continued flight (the orbit's warm-up beats, :mod:`hawksim.flight.orbit`)."""
    net = network if network is not None else _shipped()
    return int(math.ceil(max(net.lags, default=0.0) - 1e-9))


_CACHE: dict[str, StepNetwork] = {}


def _shipped() -> StepNetwork:
    p = str(shipped_path())
    if p not in _CACHE:
        _CACHE[p] = load(p)
    return _CACHE[p]
