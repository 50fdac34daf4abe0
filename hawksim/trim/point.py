"""The operating point: one frozen :class:`OperatingPoint` that flows through the API (python-control's
find_operating_point -> linearize -> controller shape). A point balances the insect at an ascent speed on an
aerodynamic model, with the body HELD on its trim path (``body="held"``: the trim searches and balances of
:mod:`hawksim.trim`, the shipped trim tables) or FREE on its periodic orbit (``body="free"``: the Newton shooting
solve :func:`hawksim.flight.orbit.periodic_orbit`, the shipped orbit tables). `hawksim.flight.fly` flies from it,
:func:`hawksim.control.linearization.linearize` linearises about it; :func:`hawksim.flight.points.find_operating_point`
finds either.

``Trim`` and ``Orbit`` (:mod:`hawksim.flight.orbit`) are names of this one type, kept for the call sites that
still use them.
"""

from __future__ import annotations

import functools
from dataclasses import dataclass, field
from typing import Any

import numpy as np

from hawksim.backends.averages import OUTPUTS, CycleAverages
from hawksim.backends.far_wake import FarWake
from hawksim.insect.folder import default_insect
from hawksim.insect.insect import Insect
from hawksim.insect.kinematics import PARAM_NAMES, Kinematics
from hawksim.state import BodyState

BODIES = ("free", "held")
"""How the body is held at an operating point: free (a periodic orbit of the free body) or held (a trim on the
held body's path)."""


@dataclass(frozen=True)
class OperatingPoint:
    """Kinematics that balance the insect at ascent speed ``speed`` [m/s] on the aerodynamic model ``aero``, the body
    held (a trim) or free (a periodic orbit). SI throughout (angles in radians, f in Hz).

    Common to both: ``speed``: ascent speed V [m/s] (``forward_speed``: forward speed U [m/s], default 0, the last
    field: :mod:`hawksim.condition`); ``kinematics``: the seven parameters of Eq. 1 (a free-body
    orbit's: f and phi0 solved, the rest the trim's); ``aero``: the aerodynamic model it balances on ("uvlm",
    "quasi-steady", "surrogate"; "paper" for Table 3; ``model=`` is accepted for it in the constructor and
    :attr:`model` reads it, the names of ``Trim``); ``source``: where it comes from, in words (a search, a balance, a
    shipped table and its command); ``body``: "held" or "free" (:data:`BODIES`; default "free" when
    ``initial_state`` is given, else "held"); ``insect``: the insect balanced (its wings, MJCF and P0; default
    :func:`hawksim.insect.folder.default_insect`), which the flights from a free-body point fly; ``converged``:
    whether the search, balance or Newton solve met its tolerance; ``wall_time_s``: its wall time [s].

    Held body (a trim): ``averages``: the model's cycle averages there (Eq. 2), None where not recorded (an
    interpolated table row); ``tolerance``: the balance's tolerance; ``fitness``: Eq. 3's F at the point (surrogate
    searches); ``evaluations``: model evaluations spent; ``search_seed``: seed of a random search; ``start``: the trim
    a balance started from; ``search``: the genetic algorithm's result (:class:`hawksim.trim.search.GAResult`).

    Free body (a periodic orbit, :mod:`hawksim.flight.orbit`): ``initial_state``: the state at the start of the
    periodic beat (:class:`hawksim.state.BodyState`); ``launch_state``: the state at t = 0 (equal to initial_state
    except for the UVLM, where ``warm_beats`` beats from an empty wake precede the periodic beat); ``residual``: max
    abs normalized residual (periodicity of (u, w, q, theta) by U, 1/T, rad; mean velocity by U); ``residuals``
    (6,): the vector; ``mean_velocity`` (3,): mean velocity of the body centre of mass over the periodic beat, world
    frame (z up) [m/s]; ``mean_pitch`` [rad]: cycle-mean body pitch; ``P_plus``: cycle mean of max(0, joint power) /
    P0 over the periodic beat (:func:`hawksim.flight.power.P_plus`); ``iterations``: Newton iterations; ``floor``:
    for the UVLM, the max abs normalized periodicity residual of the NEXT beat (the wake's beat-to-beat variation),
    0 otherwise; ``history``: max abs residual after each iteration; ``chi_ref``: the reference body angle [rad] of
    the state's chart (the held-body trim's chi); ``record``, ``record_dt``, ``record_change``: a history network's
    record (below).
    """

    speed: float
    kinematics: Kinematics
    aero: str | None = None
    source: str = ""
    body: str | None = None
    insect: Insect = field(default_factory=default_insect, repr=False)
    converged: bool = True
    wall_time_s: float = 0.0
    # held body (a trim)
    averages: CycleAverages | None = None
    tolerance: float | None = None
    fitness: float | None = None
    evaluations: int = 0
    search_seed: int | None = None
    start: OperatingPoint | None = None
    search: Any = None
    # free body (a periodic orbit)
    initial_state: BodyState | None = None
    launch_state: BodyState | None = None
    warm_beats: int = 0
    residual: float = 0.0
    residuals: np.ndarray | None = None
    mean_velocity: np.ndarray | None = None
    mean_pitch: float = 0.0
    P_plus: float | None = None
    iterations: int = 0
    floor: float = 0.0
    history: tuple[float, ...] = field(default=(), repr=False)
    chi_ref: float = 0.0
    far_wake: FarWake | None = None
    """The UVLM's prescribed far wake its flights fly (:mod:`hawksim.backends.far_wake`; the hover and 0.5 m/s
    orbits'), None: the whole wake free (and every other backend). Written to JSON only when set."""
    record: np.ndarray | None = field(default=None, repr=False, compare=False)
    """The orbit of a per-step surrogate with history inputs (a delay system): its record (n, 6) of the n calls
    before the periodic beat (body-axes velocity relative to the air [m/s] and angular velocity [rad/s], oldest
    first), which is the periodic beat's own calls: the augmented state (body state and record) repeats. Every
    flight from the orbit starts with it (:meth:`seed`); warm_beats is then 0. None for a memoryless backend."""
    record_dt: float = 0.0
    """The interval [s] between the record's calls (T / calls per beat)."""
    record_change: float = 0.0
    """max ``|record after the periodic beat - record before|`` (normalized: velocities / U, rates x T) at the solution
    (the fixed point of the record, :data:`hawksim.flight.orbit.RECORD_TOL`); 0 without a record."""
    forward_speed: float = 0.0
    """Forward speed U [m/s] of the flight condition (:mod:`hawksim.condition`; ``speed`` is the vertical one); 0
    for vertical ascent. Written to JSON only where nonzero (older files read as U = 0)."""

    def __post_init__(self):
        body = self.body if self.body is not None else ("free" if self.initial_state is not None else "held")
        if body not in BODIES:
            raise ValueError(f"body must be one of {BODIES}, got {body!r}")
        if body == "free" and (self.initial_state is None or self.launch_state is None):
            raise ValueError("a free-body operating point (a periodic orbit) needs initial_state and launch_state")
        object.__setattr__(self, "body", body)
        from hawksim.condition import check_forward_speed

        object.__setattr__(self, "forward_speed", check_forward_speed(self.forward_speed))

    def __hash__(self) -> int:
        """Over the fields that name the point (equal points hash equal; the insect's spec and the arrays are left
        out: they are not hashable)."""
        return hash((self.speed, self.forward_speed, self.kinematics, self.aero, self.body, self.source))

    @property
    def model(self) -> str | None:
        """The aerodynamic model's name (:attr:`aero`; the name ``Trim`` gave it)."""
        return self.aero

    @property
    def free(self) -> bool:
        """Whether this is a periodic orbit of the free body (else a held-body trim)."""
        return self.body == "free"

    @property
    def outputs(self) -> dict[str, float]:
        """{L_plus, D_plus, M_plus, P_plus} of :attr:`averages` (empty if not recorded)."""
        return {} if self.averages is None else {k: float(getattr(self.averages, k)) for k in OUTPUTS}

    @property
    def has_memory(self) -> bool:
        """Whether the orbit's flights carry backend memory that its body state does not set (warm-up beats or a
        record): its derivatives branch from a flight of it (:class:`hawksim.control.derivatives.Snapshot`)."""
        return bool(self.warm_beats) or self.record is not None

    def seed(self, backend) -> None:
        """Make ``backend`` fly this point's flights as the orbit was solved: start them with its record (a history
        network's orbit) and with its prescribed far wake (:attr:`far_wake`: the UVLM's orbits at hover and 0.5 m/s);
        nothing for a point with neither."""
        if self.record is not None:
            backend.seed(np.asarray(self.record, float), float(self.record_dt))
        if self.far_wake is not None:
            self.far_wake.apply(backend, self.kinematics)

    def to_json(self) -> dict:
        """SI, JSON-ready (kinematics in SI under ``kinematics_si``, edge units under ``kinematics``). A free-body
        point writes the layout of the shipped orbit tables (no ``body`` key: the tables read unchanged); a held one
        adds ``"body": "held"`` and its search's scalars (not the GA's history nor the start)."""
        kin = {"kinematics": self.kinematics.to_edge(),
               "kinematics_si": dict(zip(PARAM_NAMES, map(float, self.kinematics.as_array())))}
        ins = {} if self.insect == default_insect() else {"insect": self.insect.to_dict()}
        if self.forward_speed:
            ins = {"forward_speed": self.forward_speed} | ins
        if not self.free:
            return {"body": "held", "speed": self.speed, "aero": self.aero, **kin, "source": self.source,
                    "converged": bool(self.converged), "tolerance": self.tolerance, "fitness": self.fitness,
                    "evaluations": int(self.evaluations), "wall_time_s": self.wall_time_s,
                    "search_seed": self.search_seed,
                    "averages": None if self.averages is None else self.averages.to_dict()} | ins
        return {"speed": self.speed, "aero": self.aero, **kin,
                "initial_state": self.initial_state.to_dict(), "launch_state": self.launch_state.to_dict(),
                "warm_beats": self.warm_beats, "residual": self.residual, "residuals": list(map(float, self.residuals)),
                "mean_velocity": list(map(float, self.mean_velocity)), "mean_pitch": self.mean_pitch,
                "P_plus": self.P_plus, "iterations": self.iterations, "converged": bool(self.converged),
                "floor": self.floor, "history": list(self.history), "wall_time_s": self.wall_time_s,
                "chi_ref": self.chi_ref} | ({} if self.far_wake is None else {
                    "far_wake": self.far_wake.to_json()}) | ({} if self.record is None else {
                    "record": np.asarray(self.record).tolist(), "record_dt": self.record_dt,
                    "record_change": self.record_change}) | ins

    @staticmethod
    def from_json(d: dict) -> OperatingPoint:
        """Inverse of :meth:`to_json`; reads the rows of the shipped orbit tables as they are (free body)."""
        kin = Kinematics.from_array(np.array([d["kinematics_si"][k] for k in PARAM_NAMES]))
        insect = Insect.from_dict(d["insect"]) if d.get("insect") is not None else default_insect()
        u = float(d.get("forward_speed", 0.0))
        if d.get("body", "free") == "held":
            av = d.get("averages")
            return OperatingPoint(float(d["speed"]), kin, aero=d.get("aero"), source=d.get("source", ""),
                                  body="held", insect=insect, converged=bool(d.get("converged", True)),
                                  wall_time_s=float(d.get("wall_time_s", 0.0)), tolerance=d.get("tolerance"),
                                  fitness=d.get("fitness"), evaluations=int(d.get("evaluations", 0)),
                                  search_seed=d.get("search_seed"), forward_speed=u,
                                  averages=None if av is None else CycleAverages(**av))
        return OperatingPoint(speed=float(d["speed"]), aero=d["aero"], kinematics=kin, body="free",
                              initial_state=BodyState(**d["initial_state"]),
                              launch_state=BodyState(**d["launch_state"]),
                              warm_beats=int(d["warm_beats"]), residual=float(d["residual"]),
                              residuals=np.asarray(d["residuals"], dtype=float),
                              mean_velocity=np.asarray(d["mean_velocity"]),
                              mean_pitch=float(d["mean_pitch"]), P_plus=float(d["P_plus"]),
                              iterations=int(d["iterations"]), converged=bool(d["converged"]),
                              floor=float(d["floor"]), history=tuple(d["history"]),
                              wall_time_s=float(d["wall_time_s"]), chi_ref=float(d["chi_ref"]),
                              record=np.asarray(d["record"], float) if d.get("record") is not None else None,
                              record_dt=float(d.get("record_dt", 0.0)),
                              record_change=float(d.get("record_change", 0.0)), insect=insect,
                              far_wake=FarWake.from_json(d.get("far_wake")), forward_speed=u)


_dataclass_init = OperatingPoint.__init__


@functools.wraps(_dataclass_init)
def _init(self, *args, model: str | None = None, **kw):
    """The dataclass's constructor, also taking ``model=`` for :attr:`aero` (the keyword of ``Trim``)."""
    if model is not None:
        if kw.get("aero") is not None:
            raise ValueError("give the aerodynamic model once: aero or model (its old name), not both")
        kw["aero"] = model
    _dataclass_init(self, *args, **kw)


OperatingPoint.__init__ = _init

Trim = OperatingPoint
"""The held-body name of :class:`OperatingPoint` (the same type; ``Trim(speed, kinematics, model=..., source=...)``
makes a held-body point)."""
