"""The backend registry: one descriptor per aerodynamic backend, registered once, looked up by name.

A :class:`BackendDescriptor` says everything the rest of hawksim needs to know about a backend besides its loads
(:class:`hawksim.backends.base.AeroBackend`): how to build it (``factory``), how often the flight loop calls it, the
finite-difference steps and orbit tolerances its maps need, its memory (:mod:`hawksim.backends.memory`), what it
supports (:class:`Support`: yes or no, and why not in one line), and where its shipped tables are. Flight, control,
stability, trim and the CLI look these up (:func:`descriptor`, :func:`descriptor_of`) instead of comparing names.

The built-in backends ("quasi-steady", "uvlm", "surrogate", "surrogate-mean", and "none", the vacuum of the tests)
are registered by :mod:`hawksim.backends.builtin` on the first lookup. A new backend is a module with its
:class:`hawksim.backends.base.AeroBackend` class and one :func:`register` call; its name is then accepted wherever
an ``aero`` name is (the CLI's ``--aero`` choices are :func:`names`).
"""

from __future__ import annotations

from collections.abc import Callable
from dataclasses import dataclass, field

from hawksim.backends.memory import MEMORY_KINDS, MEMORYLESS


@dataclass(frozen=True)
class Support:
    """Whether a backend supports a feature, and if not, why (one line, used in error messages)."""

    ok: bool = True
    why_not: str = ""

    def __bool__(self) -> bool:
        return self.ok

    def require(self, what: str, name: str) -> None:
        """ValueError "``what`` is not available for aero=``name``: ``why_not``" unless supported."""
        if not self.ok:
            raise ValueError(f"{what} is not available for aero={name!r}: {self.why_not}")


def no(why: str) -> Support:
    """An unsupported feature and the reason."""
    return Support(False, why)


YES = Support()


@dataclass(frozen=True)
class FiniteDifferenceSteps:
    """Finite-difference steps of the one-beat map in its normalized variables (velocities / U, rates x T, angles
    [rad], kinematic parameters in :func:`hawksim.control.derivatives.xi_scale`'s units).

    Attributes:
        orbit: forward-difference step of the orbit's Newton-shooting Jacobian (:func:`hawksim.flight.orbit.
            periodic_orbit`).
        monodromy: central-difference step of the monodromy matrix (:func:`hawksim.stability.floquet.monodromy`).
        control: central-difference step of the control derivatives, per beat and per half-stroke
            (:mod:`hawksim.control.derivatives`, :mod:`hawksim.control.halfstroke`, :mod:`hawksim.control.
            constrained`).
    """

    orbit: float = 1e-6
    monodromy: float = 1e-5
    control: float = 1e-5


@dataclass(frozen=True)
class OrbitTolerance:
    """When a periodic orbit's Newton solve counts as converged: the max abs normalized residual (periodicity of
    u, w, q, theta by U, 1/T, rad; mean velocity by U) within ``residual``, or, where ``velocity`` is given, the
    residuals in SI: velocities within ``velocity`` [m/s], the pitch rate within ``rate`` [rad/s] and the pitch
    within ``rate`` x T [rad] (a model whose beat-to-beat floor is physical, the UVLM's wake)."""

    residual: float = 1e-8
    velocity: float | None = None
    rate: float | None = None

    def met(self, r, U: float, T: float) -> bool:
        """Whether the normalized 6-residual r (u, w, q, theta periodicity; mean horizontal and vertical velocity)
        meets this tolerance at reference speed U [m/s] and period T [s]."""
        import numpy as np

        r = np.abs(np.asarray(r))
        if self.velocity is None:
            return float(r.max()) <= self.residual
        return bool(max(r[0], r[1], r[4], r[5]) * U <= self.velocity and r[2] / T <= self.rate
                    and r[3] <= self.rate * T)


@dataclass(frozen=True)
class BackendDescriptor:
    """One aerodynamic backend, as the rest of hawksim sees it.

    Attributes:
        name: the registry key (`hawksim ... --aero NAME`; ``aero`` parameters of the library).
        summary: one line: what the model is.
        factory: ``factory(**options) -> AeroBackend``: a new backend. The options the flight code passes
            (each factory takes what it needs and ignores the rest): ``kinematics`` (the flight's
            :class:`hawksim.insect.kinematics.Kinematics`), ``morphology`` (the insect's
            :class:`hawksim.insect.morphology.Morphology`, None: the default hawkmoth's; a backend that cannot
            model another refuses it with a ValueError naming ``morphology``), ``symmetric`` (the motion stays
            left/right symmetric), ``resolution`` (:class:`hawksim.backends.resolution.Resolution`), ``freestream``,
            ``keep_panels``, ``max_wake_rows``, ``wake_summation``, ``wake_precision``
            (:func:`hawksim.backends.make_backend`).
        calls_per_beat: None: the flight loop calls the backend at every integrator step; n: at most n times per
            wingbeat, holding the loads in between (:meth:`update_interval`).
        fd: its finite-difference steps (:class:`FiniteDifferenceSteps`).
        orbit_tolerance: when its periodic orbits count as converged (:class:`OrbitTolerance`).
        memory: its memory kind (:data:`hawksim.backends.memory.MEMORY_KINDS`); the backend implements that
            kind's protocol.
        warm_beats: wingbeats a flight from an orbit develops the backend's memory before the orbit's periodic
            beat (a :data:`~hawksim.backends.memory.WAKE` memory, which cannot be set).
        hover: flies at zero ascent speed.
        orbits: has periodic orbits of the free body (its loads vary within the beat).
        orbits_on_demand: its orbits are solved in seconds where none is shipped (otherwise only the shipped
            ones are flown from).
        half_stroke: a controller updated per half-stroke (its state settable, or its record kept, at phase 0.5).
        history: a record of past calls carried as part of the orbit's state (:data:`~hawksim.backends.memory.
            RECORD`).
        control: the wingbeat-to-wingbeat LQR (a gain schedule over its orbits).
        constrained_control: the constrained LQR (per-wing derivatives from a settable state or a record).
        averaged_system: cycle-averaged A matrices of the same model (beside the Floquet multipliers).
        linear_prediction: the linear prediction of a perturbed flight (monodromy and averaged A).
        held_body: held-body cycle averages (`hawksim aero`, data sets; :class:`hawksim.backends.resolution.
            Resolution`).
        default_control: `hawksim fly`'s control from the orbit without --control ("lqr" or "none").
        default_control_rate: its LQR's update rate without --control-rate ("beat" or "half-stroke").
        speed_rate: the largest change of the speed reference per wingbeat [m/s] under control (None: the
            controller's default, :data:`hawksim.control.closed_loop.SPEED_RATE`).
        shipped_orbits_only: its gain schedule and comparisons use its shipped orbits and control models only
            (solving or linearizing them takes minutes, or the shipped orbits define where the model holds);
            otherwise they are solved in this process.
        linearize_cost: "seconds" or "minutes": what linearizing one orbit costs (for progress messages).
        saturated_plant: its control derivatives are taken with each wing saturated at Table 2
            (:data:`hawksim.control.derivatives.SATURATED_DERIVATIVES`).
        drop_bound_channels: its LQR leaves out a symmetric channel whose parameter sits on a Table 2 bound
            (:func:`hawksim.control.schedule.symmetric_inputs`).
        controlled_factory: ``(kinematics) -> backend`` of the controlled plant, bound to it with
            ``backend.bind(plant)`` (None: the flight backend, both wings solved).
        orbit_guess: the backend whose shipped orbit starts this one's Newton solve (None: the held-body trim).
        trim_table, orbit_table, control_model_table: file names of its shipped tables in ``hawksim/data``
            (None: none shipped; trim: the UVLM's).
        tables_digest: ``() -> str``: the digest its shipped orbit and control tables must carry (the network's
            SHA-256) to hold; None: they hold for any.
        flight_options: the options of :func:`hawksim.backends.flight_backend` beyond ``kinematics`` and
            ``symmetric`` that its factory uses ("wake_cycles", "wake_precision", "keep_panels": the UVLM's wake
            and its panels in recordings); the CLI refuses them for the others.
        listed: offered as an ``--aero`` choice (False: the vacuum of the tests).
    """

    name: str
    summary: str
    factory: Callable[..., object]
    calls_per_beat: int | None = None
    fd: FiniteDifferenceSteps = field(default_factory=FiniteDifferenceSteps)
    orbit_tolerance: OrbitTolerance = field(default_factory=OrbitTolerance)
    memory: str = MEMORYLESS
    warm_beats: int = 0
    hover: Support = YES
    orbits: Support = YES
    orbits_on_demand: bool = True
    half_stroke: Support = YES
    history: Support = no("its loads read no record of past calls")
    control: Support = YES
    constrained_control: Support = YES
    averaged_system: Support = YES
    linear_prediction: Support = no("the linear prediction (monodromy, averaged A) is computed for the quasi-steady "
                                    "backend only")
    held_body: Support = no("held-body averages are computed with the UVLM or the quasi-steady model")
    default_control: str = "none"
    default_control_rate: str = "beat"
    speed_rate: float | None = None
    shipped_orbits_only: bool = False
    linearize_cost: str = "seconds"
    saturated_plant: bool = False
    drop_bound_channels: bool = False
    controlled_factory: Callable[..., object] | None = None
    orbit_guess: str | None = None
    trim_table: str | None = None
    orbit_table: str | None = None
    control_model_table: str | None = None
    tables_digest: Callable[[], str] | None = None
    flight_options: tuple[str, ...] = ()
    listed: bool = True

    def __post_init__(self):
        if self.memory not in MEMORY_KINDS:
            raise ValueError(f"memory must be one of {', '.join(MEMORY_KINDS)}, got {self.memory!r}")
        if self.calls_per_beat is not None and self.calls_per_beat < 1:
            raise ValueError(f"calls_per_beat must be None or >= 1, got {self.calls_per_beat!r}")

    def make(self, **options):
        """A new backend (``factory(**options)``)."""
        return self.factory(**options)

    def update_interval(self, steps_per_cycle: int) -> int:
        """Integrator steps per backend call at ``steps_per_cycle`` steps per wingbeat: 1 without
        ``calls_per_beat``, else the largest divisor of ``steps_per_cycle`` not above steps_per_cycle //
        calls_per_beat (at least 1)."""
        if self.calls_per_beat is None:
            return 1
        every = max(1, steps_per_cycle // self.calls_per_beat)
        while steps_per_cycle % every:
            every -= 1
        return every

    def tables_hold(self, table: dict) -> bool:
        """Whether a shipped orbit or control table (its JSON object) holds for this backend as built now (its
        ``network_sha256`` is :attr:`tables_digest`'s, where there is one)."""
        return self.tables_digest is None or table.get("network_sha256") == self.tables_digest()


_REGISTRY: dict[str, BackendDescriptor] = {}
_BUILTINS_LOADED = False


def register(desc: BackendDescriptor, *, replace: bool = False) -> BackendDescriptor:
    """Add ``desc`` under ``desc.name`` (ValueError if that name is taken, unless ``replace``); returns it."""
    _builtins()
    if desc.name in _REGISTRY and not replace:
        raise ValueError(f"a backend named {desc.name!r} is already registered")
    _REGISTRY[desc.name] = desc
    return desc


def unregister(name: str) -> None:
    """Remove the backend called ``name`` (nothing if absent)."""
    _REGISTRY.pop(name, None)


def _builtins() -> None:
    global _BUILTINS_LOADED
    if not _BUILTINS_LOADED:
        _BUILTINS_LOADED = True
        from hawksim.backends import builtin

        for d in builtin.BUILTINS:
            _REGISTRY.setdefault(d.name, d)


def names(*, listed: bool = True, having: str | None = None) -> tuple[str, ...]:
    """Registered names in registration order (``listed``: only those offered as ``--aero`` choices; ``having``:
    only those whose :class:`Support` field of that name is supported)."""
    _builtins()
    out = [d for d in _REGISTRY.values() if d.listed or not listed]
    if having is not None:
        out = [d for d in out if getattr(d, having)]
    return tuple(d.name for d in out)


def descriptor(name: str) -> BackendDescriptor:
    """The descriptor of the backend called ``name``; ValueError naming ``aero`` and the choices if unknown."""
    _builtins()
    try:
        return _REGISTRY[name]
    except (KeyError, TypeError):
        raise ValueError(f"unknown aero {name!r}; choose {', '.join(names())}") from None


def find(name: str) -> BackendDescriptor | None:
    """The descriptor of the backend called ``name``, None if none is registered under it."""
    _builtins()
    return _REGISTRY.get(name)


UNREGISTERED = BackendDescriptor(name="unregistered", summary="a backend object that no descriptor describes",
                                 factory=lambda **_: None, orbits_on_demand=False, listed=False)
"""What the flight loop assumes of a backend object whose ``name`` is not registered (a test double): called at
every step, no memory."""


def descriptor_of(backend) -> BackendDescriptor:
    """The descriptor of a backend object, by its ``name`` (:data:`UNREGISTERED` for an unregistered one)."""
    _builtins()
    return _REGISTRY.get(getattr(backend, "name", None), UNREGISTERED)
