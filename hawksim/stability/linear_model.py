"""The linear model about an operating point: one frozen :class:`LinearModel` for every linearization hawksim makes
(python-control's state-space shape), whichever map it linearizes.

Maps (:data:`MAPS`):

- ``"beat"``: the controlled one-beat map x_{k+1} = A x_k + B0 u_{k-1} + B1 u_k (:mod:`hawksim.control.derivatives`;
  B0: the previous command, blended into the new one over the beat), dt = T;
- ``"half-stroke"``: the same sampled at phase 0 and 0.5 (:mod:`hawksim.control.halfstroke`), periodic with two
  phases: A, B0, B1 each a tuple of the phases' (n, n) / (n, m) matrices, dt = T / 2;
- ``"wings"``: the one-beat map in the per-wing channels (:mod:`hawksim.control.constrained`);
- ``"monodromy"``: the free body's one-beat map without inputs (:func:`hawksim.stability.floquet.monodromy`): its
  Floquet analysis is the eigen-analysis of A (:func:`hawksim.stability.floquet.floquet_analysis`);
- ``"history"``: the same on a history network's augmented state (body and its record of calls,
  :func:`hawksim.stability.history_floquet.history_monodromy`);
- ``"averaged"``: the paper's cycle-averaged model, CONTINUOUS time in t+ = t / T (dt None): A the block diagonal of
  A_long and A_lat (:func:`hawksim.stability.floquet.quasi_steady_system`).

States and inputs are NORMALIZED (velocities / U, rates x T, angles in rad, positions / (U T); f relative, angles in
rad): :attr:`LinearModel.scale` is SI per normalized unit of each state where the map has one.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from hawksim.trim.point import OperatingPoint

MAPS = ("beat", "half-stroke", "wings", "monodromy", "history", "averaged")
"""The maps a :class:`LinearModel` linearizes (module docstring)."""

LONG_STATES = ("u", "w", "q", "theta", "X")
LAT_STATES = ("v", "p", "r", "phi", "psi", "Y")
SYM_INPUT_NAMES = ("f", "phi0", "alpha0", "theta0")
ANTI_INPUT_NAMES = ("dphi_a", "dphi0", "dalpha0")
RECORD_LONG_NAMES, RECORD_LAT_NAMES = ("vx", "vz", "wy"), ("vy", "wx", "wz")
"""The longitudinal / lateral subsystems by name (the orders of :data:`hawksim.control.derivatives.LONG_X`,
``LAT_X``, :data:`hawksim.control.plant.SYM_INPUTS`, ``ANTI_INPUTS`` and a record's components
:data:`hawksim.stability.history_floquet.RECORD_LONG`, ``RECORD_LAT``)."""


def record_names(records: int) -> tuple[str, ...]:
    """Names of a history network's record values in an augmented state: ``rec{k}_{c}``, oldest record first, c in
    (vx, vy, vz, wx, wy, wz) (body axes: velocity relative to the air, angular velocity)."""
    return tuple(f"rec{k}_{c}" for k in range(records) for c in ("vx", "vy", "vz", "wx", "wy", "wz"))


@dataclass(frozen=True)
class LinearModel:
    """A linear model about the operating point ``point`` (module docstring), in normalized states and inputs
    (velocities / U, rates x T, angles in radians, positions / (U T); f relative).

    Attributes:
        point: the operating point (:class:`hawksim.trim.point.OperatingPoint`; :attr:`orbit` reads it too).
        map: which map (:data:`MAPS`).
        states, inputs: names of the state (n) and input (m) components (inputs empty without inputs).
        A: (n, n) discrete (per step) or continuous (``dt`` None); a periodic map's: a tuple of p, one per phase.
        B0: (n, m) the previous command's input matrix (the blend; None without inputs); periodic: a tuple.
        B1: (n, m) the new command's input matrix (None without inputs); periodic: a tuple.
        scale: (n,) SI per normalized unit of the states (None where not one map's).
        dt: the step [s] (T per beat, T / 2 per half-stroke); None: continuous time in t+ = t / T.
        delta: the central-difference step (normalized); 0 where not differenced.
        wall_time_s: the wall time of the linearization [s].
        coupling: the largest ``|entry|`` (per-beat and half-stroke maps) or Frobenius norm (monodromies) of the
            longitudinal-lateral cross blocks.
        clipped: differenced on the map saturated at Table 2 (:data:`hawksim.control.derivatives.
            SATURATED_DERIVATIVES`).
        records: a history network's records in the state (0: none); record_ref: the orbit's record (n, 6) SI at
            the linearization point (periodic: one per phase); record_scale: (6,) SI per normalized record unit.
        x_half, pos_half: the half-stroke map's phase-0.5 reference (body state (9,) SI, displacement (2,) [m]).
        launch: a monodromy with warm-up beats: d x(w) / d x0 of the launches (for each mode's reach).
        residual, record_mismatch: a history monodromy's (:class:`hawksim.stability.history_floquet.
            HistoryFloquet`).
        derivatives, nondimensional, scalars: the averaged model's derivatives and Eq. 8's scalars.
    """

    point: OperatingPoint
    map: str
    states: tuple[str, ...]
    inputs: tuple[str, ...]
    A: np.ndarray | tuple[np.ndarray, ...]
    B0: np.ndarray | tuple[np.ndarray, ...] | None = None
    B1: np.ndarray | tuple[np.ndarray, ...] | None = None
    scale: np.ndarray | None = None
    dt: float | None = None
    delta: float = 0.0
    wall_time_s: float = 0.0
    coupling: float = 0.0
    clipped: bool = False
    records: int = 0
    record_ref: np.ndarray | tuple | None = None
    record_scale: np.ndarray | None = None
    x_half: np.ndarray | None = None
    pos_half: np.ndarray | None = None
    launch: np.ndarray | None = None
    residual: float = float("nan")
    record_mismatch: float = float("nan")
    derivatives: dict | None = None
    nondimensional: dict | None = None
    scalars: dict | None = None

    def __post_init__(self):
        if self.map not in MAPS:
            raise ValueError(f"map must be one of {MAPS}, got {self.map!r}")

    @property
    def orbit(self) -> OperatingPoint:
        """The operating point (:attr:`point`; the name the per-map models used)."""
        return self.point

    @property
    def phases(self) -> int:
        """Samples per period of a periodic map (2 per half-stroke), 1 otherwise."""
        return len(self.A) if isinstance(self.A, tuple) else 1

    @property
    def continuous(self) -> bool:
        """Whether A is a continuous-time matrix (the averaged model)."""
        return self.dt is None

    @property
    def Bt(self) -> np.ndarray:
        """Sensitivity to a command held over the step and the one before (B0 + B1)."""
        return self.B0 + self.B1

    def index(self, names) -> list[int]:
        """Indices of the named states."""
        return [self.states.index(n) for n in names]

    def record_index(self, which: str) -> list[int]:
        """Indices of the records' longitudinal ('long': v_x, v_z, omega_y) or lateral ('lat') values in the state
        (record-major; empty without records)."""
        if not self.records:
            return []
        comps = RECORD_LONG_NAMES if which == "long" else RECORD_LAT_NAMES
        return self.index(f"rec{k}_{c}" for k in range(self.records) for c in comps)

    def block(self, which: str, phase: int | None = None) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
        """(A, B0, B1) of the 'long' (u, w, q, theta, X; f, phi0, alpha0, theta0) or 'lat' (v, p, r, phi, psi, Y;
        dphi_a, dphi0, dalpha0) subsystem of a controlled map, the records' values of that subsystem after the body
        states; ``phase``: a periodic map's phase (required there)."""
        xs_n, us_n = (LONG_STATES, SYM_INPUT_NAMES) if which == "long" else (LAT_STATES, ANTI_INPUT_NAMES)
        xs = self.index(xs_n) + self.record_index(which)
        us = [self.inputs.index(n) for n in us_n]
        A, B0, B1 = self.A, self.B0, self.B1
        if self.phases > 1 or phase is not None:
            if phase is None:
                raise ValueError(f"a periodic map ({self.phases} phases): give the phase")
            A, B0, B1 = A[phase], B0[phase], B1[phase]
        ix, iu = np.ix_(xs, xs), np.ix_(xs, us)
        return A[ix], B0[iu], B1[iu]

    @property
    def period_map(self) -> np.ndarray:
        """A over one period: A itself, or a periodic map's product of its phases (last phase on the left)."""
        if self.phases == 1:
            return self.A
        M = np.eye(self.A[0].shape[-1])
        for Aj in self.A:
            M = Aj @ M
        return M

    @property
    def monodromy(self) -> np.ndarray:
        """(8, 8) over (u, v, w, p, q, r, phi, theta): the one-beat Floquet monodromy block of a controlled map
        (body rows and columns)."""
        if self.map in ("monodromy", "history", "averaged"):
            raise ValueError(f"a {self.map} model: its A is the map itself "
                             "(see hawksim.stability.floquet.floquet_analysis)")
        return self.period_map[:8, :8]

    def eigenvalues(self) -> np.ndarray:
        """Eigenvalues of :attr:`period_map` (multipliers per period; continuous: exponents in t+), sorted by
        ``|value|`` (discrete) or real part (continuous) descending."""
        w = np.linalg.eigvals(self.period_map)
        key = -w.real if self.continuous else -np.abs(w)
        return w[np.argsort(key, kind="stable")]

    def to_json(self) -> dict:
        """The layout of the shipped control-model tables (per-beat and per-wing maps; the half-stroke maps'
        arrays per phase). A model on a history network's augmented state is made at start-up, not tabulated."""
        if self.map == "beat":
            if self.records:
                raise ValueError("a model on the augmented state is made at start-up, not tabulated (its body block "
                                 "is the record-held model, linearize(..., records=False))")
            return {"speed": self.point.speed, "aero": self.point.aero, "states": list(self.states),
                    "inputs": list(self.inputs), "A": self.A.tolist(), "B0": self.B0.tolist(),
                    "B1": self.B1.tolist(), "scale": self.scale.tolist(), "coupling": self.coupling,
                    "delta": self.delta, "clipped": self.clipped}
        if self.map == "half-stroke":
            return {"speed": self.point.speed, "aero": self.point.aero, "inputs": list(self.inputs),
                    "A": [a.tolist() for a in self.A], "B0": [b.tolist() for b in self.B0],
                    "B1": [b.tolist() for b in self.B1], "x_half": self.x_half.tolist(),
                    "pos_half": self.pos_half.tolist(), "scale": self.scale.tolist(), "coupling": self.coupling,
                    "delta": self.delta}
        if self.map == "wings":
            return {"speed": self.point.speed, "aero": self.point.aero, "states": list(self.states),
                    "inputs": list(self.inputs), "A": self.A.tolist(), "B0": self.B0.tolist(),
                    "B1": self.B1.tolist(), "delta": self.delta}
        return {"speed": self.point.speed, "aero": self.point.aero, "map": self.map, "states": list(self.states),
                "A": np.asarray(self.A).tolist(), "dt": self.dt, "delta": self.delta}

    @staticmethod
    def from_json(d: dict, point: OperatingPoint, *, map: str = "beat") -> LinearModel:
        """Inverse of :meth:`to_json` for a per-beat row of a shipped control-model table about ``point`` (the one it
        was made about; the caller checks which)."""
        if map != "beat":
            raise ValueError("from_json reads the per-beat rows of the shipped control-model tables")
        return LinearModel(point=point, map="beat", states=tuple(d["states"]), inputs=tuple(d["inputs"]),
                           A=np.asarray(d["A"], float), B0=np.asarray(d["B0"], float),
                           B1=np.asarray(d["B1"], float), scale=np.asarray(d["scale"], float),
                           dt=point.kinematics.period, coupling=float(d["coupling"]), delta=float(d["delta"]),
                           wall_time_s=float(d.get("wall_time_s", 0.0)), clipped=bool(d.get("clipped", False)))
