"""The gain schedule over the ascent speed: periodic orbits, their linear models and LQR gains at grid speeds,
interpolated linearly in between; updated once per wingbeat or once per half-stroke (:data:`RATES`).

Quasi-steady: the orbits are solved (:func:`hawksim.flight.orbit.periodic_orbit`, ~1 s) and linearized
(:func:`hawksim.control.derivatives.linearize`, ~2 s; per half-stroke :func:`hawksim.control.halfstroke.
linearize_half_stroke`, ~3 s) at :data:`SCHEDULE_SPEEDS`, cached per process. UVLM (per beat only): the SHIPPED
orbits (insects/hawkmoth/data/orbit_table_uvlm.json, converged at :data:`UVLM_SCHEDULE_SPEEDS`) and their one-beat
control derivatives shipped in insects/hawkmoth/data/control_models_uvlm.json (``hawksim reproduce --only
control_uvlm``, :func:`control_model_table`; linearizing one speed takes minutes), so the schedule covers 0-2 m/s
(hawksim 0.2's: 1-2 m/s), and a speed outside the grid's range is refused (ValueError naming it). Per-step surrogate
(per beat only): the same from its shipped orbits (hawksim/insects/hawkmoth/data/orbit_table_surrogate.json, for the
shipped network only) at :func:`surrogate_schedule_speeds` (0, 0.5, 1, 1.5, 2 m/s) and
insects/hawkmoth/data/control_models_surrogate.json (``hawksim reproduce --only control_surrogate``; without it the
derivatives are recomputed, ~5 s per speed).

Forward flight (issue 51): a schedule over the forward speed U in level flight (``axis="forward"``), its orbits
solved at :data:`FORWARD_SCHEDULE_SPEEDS` (0-4 m/s, quasi-steady) from the shipped forward trims (U = 0: the hover
orbit of the forward table's hover trim, solved without the body's loads as vertical flight is), the body's own loads
on their flights and the hold point moving forward at the reference U
(:meth:`hawksim.control.controller.LQR.hold_velocity`).

Per beat the gains are :func:`hawksim.control.lqr.lqr_gain` of the one-beat map; per half-stroke
:func:`hawksim.control.lqr.periodic_lqr_gains` of the two half-stroke maps (a gain for phase 0 and one for
phase 0.5), with a sensing delay of d wingbeats counted as 2 d half-strokes and the commands weighted
:data:`HALF_STROKE_COMMAND_WEIGHT` times the per-beat design's.
"""

from __future__ import annotations

import contextlib
import json
from dataclasses import dataclass, replace

import numpy as np

from hawksim.backends.record import record_scale
from hawksim.backends.builtin import BUILTINS
from hawksim.backends.registry import descriptor
from hawksim.control.derivatives import XI_NAMES, BeatMapModel, linearize, xi_scale
from hawksim.control.halfstroke import HALVES, HalfStrokeModel, linearize_half_stroke
from hawksim.control.lqr import U_MAX, Gain, lqr_gain, periodic_lqr_gain
from hawksim.control.plant import INPUTS, SYM_INPUTS, command_of, wing_kinematics
from hawksim.flight.orbit import Orbit, periodic_orbit, shipped_orbit
from hawksim.trim.registry import point_key, shipped_table
from hawksim.insect.folder import default_insect
from hawksim.insect.insect import Insect
from hawksim.insect.kinematics import TABLE3_SPEEDS, Kinematics
from hawksim.stability.linear_model import LinearModel

SCHEDULE_SPEEDS = TABLE3_SPEEDS
"""Ascent speeds [m/s] of the quasi-steady gain schedule's orbits (0, 0.5, 1, 1.5, 2)."""

UVLM_SCHEDULE_SPEEDS = (0.0, 0.5, 1.0, 1.5, 2.0)
"""Speeds [m/s] of the UVLM schedule as shipped: the shipped UVLM orbits that converged (all five since hawksim
0.3.0, hover and 0.5 m/s with the prescribed far wake, docs/free_flight.md; hawksim 0.2's at 1-2 m/s only);
:func:`schedule_speeds` reads them from the table."""

SHIPPED_GRID = TABLE3_SPEEDS
"""Speeds [m/s] at which a schedule of shipped orbits looks for them (:func:`shipped_schedule_speeds`)."""

SURROGATE_GRID = SHIPPED_GRID


def shipped_schedule_speeds(aero: str) -> tuple[float, ...]:
    """Speeds [m/s] of :data:`SHIPPED_GRID` with a converged shipped orbit of ``aero`` that holds for the backend as
    built now (:func:`hawksim.flight.orbit.shipped_orbit`; the surrogate's: for the shipped network, else empty)."""
    out = []
    for v in SHIPPED_GRID:
        o = shipped_orbit(v, aero)
        if o is not None and o.converged:
            out.append(float(v))
    return tuple(out)


def surrogate_schedule_speeds() -> tuple[float, ...]:
    """:func:`shipped_schedule_speeds` of the per-step surrogate."""
    return shipped_schedule_speeds("surrogate")


def schedule_speeds(aero: str) -> tuple[float, ...]:
    """The grid speeds [m/s] of ``aero``'s gain schedule: for a backend whose schedule is its shipped orbits
    (descriptor ``shipped_orbits_only``: the UVLM, the surrogate) :func:`shipped_schedule_speeds`, else
    :data:`SCHEDULE_SPEEDS` (its orbits solved here)."""
    desc = descriptor(aero)
    desc.control.require("a gain schedule", aero)
    return shipped_schedule_speeds(aero) if desc.shipped_orbits_only else SCHEDULE_SPEEDS


RATES = ("beat", "half-stroke")
"""Control update rates: once per wingbeat (at phase 0) or once per half-stroke (phases 0 and 0.5)."""

def default_rate(aero: str) -> str:
    """The update rate `hawksim fly --control lqr` (and the backend table) use without --control-rate: the backend
    descriptor's ``default_control_rate`` (:mod:`hawksim.backends.builtin`: "half-stroke" for the per-step surrogate,
    "beat" otherwise). The per-step surrogate per half-stroke meets every target of issue 20 (the 0.5 m/s lateral gust
recovered 2-3 beats after it at 0-2 m/s, the one-beat delay from the full-size perturbed start at every speed), per
beat it does not (the gust departs at 0, 0.5, 1.5 and 2 m/s): scripts/studies/control_surrogate.py --rate
half-stroke, docs/control.md. The quasi-steady backend meets them at both rates and keeps per beat (the UVLM's
only rate, and the figures of docs/control.md)."""
    return descriptor(aero).default_control_rate


HALF_STROKE_COMMAND_WEIGHT = 2.0
"""The half-stroke LQR's command weight R relative to the per-beat Bryson weights (:data:`hawksim.control.lqr.
U_MAX` divided by sqrt of this). With equal weights the half-stroke LQR rejects small disturbances harder but, on
the 0 -> 1 m/s reference ramp (0.2 m/s per beat), drives theta0 to Table 2's -25 deg and phi0 alternately to
+-25 deg and departs; with 2 every command of the 0 -> 1 -> 2 m/s profile stays inside Table 2 and the gust and
perturbation peaks stay below the per-beat controller's (``scripts/studies/control_rate_study.py``,
docs/control.md "Per beat or per half-stroke")."""

AXES = ("vertical", "forward")
"""What a schedule's grid runs over: the vertical speed V (forward speed 0; the paper's ascent) or the forward speed U
(level flight, V = 0)."""

FORWARD_SCHEDULE_SPEEDS = (0.0, 0.5, 1.0, 1.5, 2.0, 2.5, 3.0, 3.5, 4.0)
"""Forward speeds [m/s] of the forward-flight schedule's orbits (level flight, quasi-steady): each solved from
:func:`hawksim.trim.tables.forward_trim_kinematics` (the shipped trims at whole m/s, interpolated in between; the
orbit solve balances them through f and phi0). Half-metre steps: with the orbits at whole m/s only, the references
interpolated between them (the minimum-power kinematics change by up to 46 deg in beta and 49 deg in alpha_a between
neighbours) were too far from any equilibrium and the hover-to-4 m/s profile departed near 1.7 m/s (measured,
docs/forward_flight.md)."""

FORWARD_PHI0_ROOM = float(U_MAX["phi0"])
"""[rad] The room a forward-flight schedule's orbit keeps between phi0 and its Table 2 bounds: Bryson's acceptable
phi0 command (:data:`hawksim.control.lqr.U_MAX`, 3 deg). Where the orbit solved through f and phi0 ends closer (the
minimum-power trims at 2-4 m/s sit on phi0 = -25 deg; the orbits at 1.5-2.5 m/s end at -23.5 to -25.8 deg), phi0 is
set that far inside the bound and the orbit solved through f and theta0 instead
(:func:`hawksim.flight.orbit.periodic_orbit`'s ``moment_parameter``; P+ rises by up to 6 %). Model choice, from a
measurement: with the orbits on or past the bound the LQR drove phi0 onto it from 1.5 m/s and the hover-to-4 m/s
profile departed near 2 m/s (docs/forward_flight.md)."""

FORWARD_X_MAX = 30.0
"""Bryson's acceptable forward-position deviation (normalized by U T, :data:`hawksim.control.lqr.X_MAX`) of a
forward-flight schedule's LQR: 100 times the hover's 0.3, so that the forward position is all but free and the
forward speed, not the place along the path, is what the LQR regulates (as the vertical speed, not the height, in
ascent). Model choice: with 0.3 the lag behind the moving hold point built up on the hover-to-4 m/s ramp (4 cm at
1.5 m/s) and its catch-up drove phi0 onto its bound (docs/forward_flight.md)."""

SCHEDULE_ORBIT_FLOOR = 1e-6
"""A forward-flight orbit whose Newton solve stalls above its backend's tolerance but at or below this normalized
residual is a schedule point all the same (model choice, from a measurement: the quasi-steady orbit at 4 m/s stalls at
1.85e-7 against the tolerance 1e-8, every backtracking halving failing, restarted from its own answer with the same
floor, results/forward_flight/orbits.json; the per-beat LQR about it holds 100 beats, results/forward_flight/
control.json). A residual above it is refused
(FloatingPointError)."""

# Which backends have half-stroke maps (a state settable, or a record kept, at phase 0.5) and why not: their
# descriptors' ``half_stroke``; their shipped one-beat control derivatives in ``hawksim/data`` (produced by
# ``hawksim reproduce --only control_uvlm`` / ``control_surrogate``, copied from ``results/control/``): their
# ``control_model_table``.


@dataclass(frozen=True)
class SchedulePoint:
    """Orbit, linear model(s) and gains at one speed of the schedule. ``long``/``lat``: the gains used at phase 0
    (per beat: the only ones); per half-stroke also ``half`` (the half-stroke maps) and ``long_half``/``lat_half``
    (the gains at phase 0.5); the multipliers of every gain are those of one wingbeat."""

    speed: float
    orbit: Orbit
    model: BeatMapModel
    long: Gain
    lat: Gain
    rate: str = "beat"
    half: HalfStrokeModel | None = None
    long_half: Gain | None = None
    lat_half: Gain | None = None
    forward_speed: float = 0.0
    """The orbit's forward speed U [m/s] (``speed`` is its vertical one)."""

    def at(self, axis: str) -> float:
        """The point's place [m/s] on a schedule's ``axis`` (:data:`AXES`): its forward speed or its vertical one."""
        return self.forward_speed if axis == "forward" else self.speed

    def gains(self, phase: int) -> tuple[Gain, Gain]:
        """(long, lat) at update ``phase`` (0; per half-stroke also 1 = phase 0.5)."""
        return (self.long, self.lat) if phase == 0 else (self.long_half, self.lat_half)

    def reference_record(self, phase: int) -> np.ndarray | None:
        """The orbit's record (n, 6) SI at update ``phase`` for a history network's design on the augmented state
        (its gains feed the record back), None otherwise."""
        if self.rate == "half-stroke":
            return self.half.record_ref[phase] if self.half is not None and self.half.records else None
        return self.model.record_ref if self.model.records else None

    def reference_state(self, phase: int) -> tuple[np.ndarray, np.ndarray]:
        """(body state (9,) SI, horizontal offset (2,) [m] from the hold point) of the orbit at ``phase``."""
        if phase == 0:
            return self.orbit.initial_state.as_array(), np.zeros(2)
        if self.forward_speed:  # the hold point has moved U T / 2 forward over the first half
            moved = 0.5 * self.forward_speed * self.orbit.kinematics.period
            return self.half.x_half, self.half.pos_half - np.array([moved, 0.0])
        return self.half.x_half, self.half.pos_half

    def to_json(self) -> dict:
        def mu(g):
            return [[float(z.real), float(z.imag)] for z in g.multipliers if abs(z) > 1e-12]

        out = {"speed": self.speed, **({"forward_speed": self.forward_speed} if self.forward_speed else {}),
               "aero": self.orbit.aero, "rate": self.rate, "orbit_f_hz": self.orbit.kinematics.f,
               "orbit_residual": self.orbit.residual,
               "open_loop_max_multiplier": float(max(
                   np.abs(self.long.open_loop).max(),
                   np.abs(self.lat.open_loop[np.abs(self.lat.open_loop - 1) > 1e-9]).max())),
               "closed_loop_spectral_radius_long": self.long.spectral_radius,
               "closed_loop_spectral_radius_lat": self.lat.spectral_radius,
               "closed_loop_multipliers_long": mu(self.long), "closed_loop_multipliers_lat": mu(self.lat),
               "K_long": self.long.K.tolist(), "K_lat": self.lat.K.tolist(),
               "inputs_long": [INPUTS[i] for i in self.long.inputs], "inputs_lat": [INPUTS[i] for i in self.lat.inputs]}
        if self.rate == "half-stroke":
            out["K_long_half"], out["K_lat_half"] = self.long_half.K.tolist(), self.lat_half.K.tolist()
        return out


def control_model_table(models: list[BeatMapModel], command: str) -> dict:
    """The layout of a shipped control-derivative table: one row per speed (:meth:`BeatMapModel.to_json` plus
    the orbit it linearizes, named by its f and residual), with the command that made it. The UVLM and the
    surrogate are deterministic (no random process), so there is no seed; a surrogate table records the SHA-256
    of the network (``network_sha256``)."""
    from hawksim import __version__

    extra = {}
    desc = descriptor(models[0].orbit.aero) if models else None
    if desc is not None and desc.tables_digest is not None:
        extra["network_sha256"] = desc.tables_digest()
    return {**extra, "source": "central differences of the controlled one-beat map about the shipped periodic orbits "
                      "(hawksim.control.derivatives.linearize)", "command": command, "seed": None,
            "seed_note": "deterministic: no random process", "hawksim_version": __version__,
            "aero": models[0].orbit.aero if models else None,
            "rows": [{**m.to_json(), "orbit_f_hz": m.orbit.kinematics.f, "orbit_residual": m.orbit.residual,
                      "wall_time_s": m.wall_time_s} for m in models]}


def shipped_control_model(speed: float, aero: str) -> BeatMapModel | None:
    """The shipped one-beat model of ``aero`` at exactly ``speed`` (its descriptor's ``control_model_table``, read once
    per process through the registry :func:`hawksim.flight.points.shipped_table`) about the shipped orbit there, None
    if absent (or if the orbit it was made about is not the shipped one, or the table does not hold for the backend
    as built now)."""
    desc = descriptor(aero)
    name = desc.control_model_table
    table = shipped_table(name) if name else None
    orbit = shipped_orbit(speed, aero)
    if table is None or orbit is None or not desc.tables_hold(table):
        return None
    for row in table["rows"]:
        if abs(row["speed"] - speed) < 1e-9 and row["orbit_f_hz"] == orbit.kinematics.f \
                and row["orbit_residual"] == orbit.residual:
            if tuple(row["states"]) != XI_NAMES or tuple(row["inputs"]) != INPUTS:
                raise ValueError("control model table: states or inputs differ from this version's")
            return LinearModel.from_json(row, orbit)
    return None


_POINTS: dict = {}
_HALF: dict = {}
"""The process's orbits and linear models, keyed by :func:`hawksim.flight.points.point_key` (insect digest, backend,
speed, MJCF digest; then what was made about the point), so that two insects or two MuJoCo models never share an
orbit or gains."""


def insect_key(insect: Insect | None) -> tuple:
    """The part of a cache key that names the insect: () for the default insect (the keys as they were), else its
    spec as sorted JSON (:meth:`Insect.to_dict`: morphology, P0 and bounds), which two insects share only if equal."""
    if insect is None or insect == default_insect():
        return ()
    return (json.dumps(insect.to_dict(), sort_keys=True),)


def _forward_orbit_and_model(speed: float, forward_speed: float, aero: str, model, log,
                             insect: Insect | None) -> tuple[Orbit, BeatMapModel]:
    """The orbit at (``forward_speed``, ``speed``) from the shipped forward trim there, and its one-beat model."""
    from hawksim.trim.tables import forward_trim_kinematics

    key = point_key(speed, aero, insect, model, "forward", float(forward_speed))
    if key not in _POINTS:
        if insect_key(insect) or descriptor(aero).shipped_orbits_only:
            raise ValueError(f"forward_speed {forward_speed:g} m/s: a forward-flight schedule flies the default "
                             f"hawkmoth's quasi-steady orbits (not {aero!r} or another insect; fly a given orbit with "
                             "Schedule.of_orbit)")
        kin = forward_trim_kinematics(forward_speed)
        orb = periodic_orbit(speed, aero, model=model, log=log, forward_speed=forward_speed, kinematics=kin)
        lo, hi = orbit_bounds(orb, "phi0")
        if not lo + FORWARD_PHI0_ROOM <= orb.kinematics.phi0 <= hi - FORWARD_PHI0_ROOM:  # keep room to command phi0
            kin = replace(kin, phi0=float(np.clip(orb.kinematics.phi0, lo + FORWARD_PHI0_ROOM, hi - FORWARD_PHI0_ROOM)))
            orb = periodic_orbit(speed, aero, model=model, log=log, forward_speed=forward_speed, kinematics=kin,
                                 moment_parameter="theta0")
        if not (orb.converged or orb.residual <= SCHEDULE_ORBIT_FLOOR):
            raise FloatingPointError(f"the periodic orbit at {forward_speed:g} m/s forward did not converge "
                                     f"({orb.residual:.1e})")
        _POINTS[key] = (orb, linearize(orb, model=model))
    return _POINTS[key]


def _orbit_and_model(speed: float, aero: str, model, log, insect: Insect | None = None,
                     forward_speed: float = 0.0, axis: str = "vertical") -> tuple[Orbit, BeatMapModel]:
    if forward_speed or axis == "forward":
        return _forward_orbit_and_model(speed, forward_speed, aero, model, log, insect)
    key = point_key(speed, aero, insect, model)
    desc = descriptor(aero)
    if key not in _POINTS:
        if insect_key(insect) and desc.shipped_orbits_only:
            raise ValueError(f"insect {insect.name!r}: the {aero} schedule flies shipped orbits, which are the default "
                             "hawkmoth's; control another insect with the quasi-steady backend")
        if desc.shipped_orbits_only:
            orb = shipped_orbit(speed, aero)
            if orb is None or not orb.converged:
                raise ValueError(f"no converged shipped {aero} orbit at {speed:g} m/s (the {aero} schedule covers "
                                 f"{', '.join(f'{v:g}' for v in schedule_speeds(aero)) or 'no speed'} m/s)")
            lin = shipped_control_model(speed, aero)
            if lin is None:
                if log is not None:
                    log(f"linearizing the {aero} orbit at {speed:g} m/s (no shipped control model; "
                        f"{desc.linearize_cost}) ...")
                lin = linearize(orb, model=model)
        else:
            orb = periodic_orbit(speed, aero, model=model, log=log, insect=insect)
            if not orb.converged:
                raise FloatingPointError(f"the periodic orbit at {speed:g} m/s did not converge ({orb.residual:.1e})")
            lin = linearize(orb, model=model)
        _POINTS[key] = (orb, lin)
    return _POINTS[key]


def schedule_point(speed: float, *, delay: int = 0, aero: str = "quasi-steady", model=None, log=None,
                   x_max=None, u_max=None, rate: str = "beat", command_weight: float | None = None,
                   insect: Insect | None = None, forward_speed: float = 0.0,
                   axis: str = "vertical") -> SchedulePoint:
    """Orbit, linearization and LQR gains at ``speed`` [m/s] for a sensing ``delay`` [wingbeats] and update
    ``rate`` (:data:`RATES`); orbits and linear models are cached per process and per insect. ``x_max``/``u_max``
    override Bryson's bounds (:mod:`hawksim.control.lqr`); ``command_weight`` multiplies R of the half-stroke design
    (default :data:`HALF_STROKE_COMMAND_WEIGHT`). ``insect``: the insect controlled (default
    :func:`hawksim.insect.folder.default_insect`): its own orbit (solved here: backends of shipped orbits only take
    the default insect, ValueError otherwise), linearized on its MJCF (``model`` must be its MJCF if given).
    ``forward_speed`` U [m/s] > 0 or ``axis="forward"``: the orbit at (U, ``speed``) from the shipped forward
    trims' kinematics at U (:func:`hawksim.trim.tables.forward_trim_kinematics`; the quasi-steady model and the
    default insect only; at U = 0 the forward table's hover trim)."""
    if rate not in RATES:
        raise ValueError(f"--control-rate {rate!r}: choose {', '.join(RATES)}")
    if rate == "half-stroke":
        descriptor(aero).half_stroke.require("rate='half-stroke'", aero)
    orb, lin = _orbit_and_model(speed, aero, model, log, insect, forward_speed, axis)
    fw = ("forward", float(forward_speed)) if forward_speed or axis == "forward" else ()
    if rate == "beat" and orb.record is not None:  # a history network: the per-beat design on the augmented state
        key = point_key(speed, aero, insect, model, "records")
        if key not in _POINTS:
            if log is not None:
                log(f"linearizing the {aero} orbit at {speed:g} m/s with its record of calls (seconds) ...")
            _POINTS[key] = linearize(orb, model=model, records=True)
        lin = _POINTS[key]
    sym = symmetric_inputs(orb) if descriptor(aero).drop_bound_channels else None
    if axis == "forward":
        x_max = {"X": FORWARD_X_MAX, **(x_max or {})}
    long, lat = lqr_gain(lin, "long", delay, x_max, u_max, inputs=sym), lqr_gain(lin, "lat", delay, x_max, u_max)
    if rate == "beat":
        return SchedulePoint(float(speed), orb, lin, long, lat, forward_speed=float(forward_speed))
    key = point_key(speed, aero, insect, model, "half-stroke", *fw)
    if key not in _HALF:
        _HALF[key] = linearize_half_stroke(orb, model=model)
    h = _HALF[key]
    d = HALVES * int(delay)
    cw = HALF_STROKE_COMMAND_WEIGHT if command_weight is None else float(command_weight)
    um = {k: v / np.sqrt(cw) for k, v in {**U_MAX, **(u_max or {})}.items()}
    gl = periodic_lqr_gain(h, "long", d, x_max, um, inputs=sym)  # theta0 out where it sits on its bound
    gt = periodic_lqr_gain(h, "lat", d, x_max, um)
    return SchedulePoint(float(speed), orb, lin, gl[0], gt[0], rate="half-stroke", half=h, long_half=gl[1],
                         lat_half=gt[1], forward_speed=float(forward_speed))


ONE_SIDED_DROPPED = tuple(d.name for d in BUILTINS if d.drop_bound_channels)
"""The built-in backends (any backend: its descriptor's ``drop_bound_channels``) whose LQR leaves out a symmetric
channel whose parameter sits on a Table 2 bound at the orbit (:func:`symmetric_inputs`): there the saturation passes
only commands of one sign, a kink no linear design sees. The surrogate's (and the UVLM's) orbits sit on theta0 = 25
deg, the upper bound: with theta0 in the design the surrogate's perturbed starts at 0 and 2 m/s departed (theta0
clipped in every beat), without it they hold (docs/control.md, "The per-step surrogate in the loop"). The
antisymmetric dphi_a at phi_a = 60 deg stays: one wing can always lower its amplitude
(:data:`hawksim.control.derivatives.SATURATED_DERIVATIVES`). The quasi-steady orbits have theta0 at 14-16 deg and
keep all four channels; the UVLM's shipped design is left as it was measured."""

BOUND_TOL = 1e-3
"""A parameter within this [rad; f: Hz] of a Table 2 bound counts as on it (the surrogate's orbits have theta0 at
24.997-25.000 deg)."""


def orbit_bounds(orbit: Orbit, name: str) -> tuple[float, float]:
    """(lower, upper) bound [rad; f: Hz] of the kinematic parameter ``name`` for the orbit's insect."""
    from hawksim.insect.kinematics import PARAM_NAMES

    lo, hi = orbit.insect.bounds_si()
    j = PARAM_NAMES.index(name)
    return float(lo[j]), float(hi[j])


def symmetric_inputs(orbit: Orbit) -> tuple[int, ...]:
    """The symmetric channels of :data:`hawksim.control.plant.SYM_INPUTS` whose parameter (f, phi0, alpha0, theta0)
    is not on a bound of the orbit's insect (:attr:`Orbit.insect`, Table 2 for the default) at ``orbit``
    (:data:`BOUND_TOL`)."""
    from hawksim.insect.kinematics import PARAM_NAMES

    lo, hi = orbit.insect.bounds_si()
    p = orbit.kinematics.as_array()
    keep = []
    for i in SYM_INPUTS:
        j = PARAM_NAMES.index(INPUTS[i])
        if min(p[j] - lo[j], hi[j] - p[j]) > BOUND_TOL:
            keep.append(i)
    return tuple(keep)


class Schedule:
    """Gain schedule over the ascent speed: :class:`SchedulePoint` at the grid speeds needed for [v_lo, v_hi]
    (``speeds``: default :func:`schedule_speeds` of ``aero``); a range outside the grid's is refused (ValueError).
    ``rate``: :data:`RATES`; ``delay`` [wingbeats]; ``insect`` (default
    :func:`hawksim.insect.folder.default_insect`, kept as :attr:`insect`); the rest as :func:`schedule_point`.
    ``axis="forward"``: the grid runs over the forward speed U in level flight instead (v_lo, v_hi and ``speeds`` are
    forward speeds; default grid :data:`FORWARD_SCHEDULE_SPEEDS`, quasi-steady, the default insect);
    :attr:`axis` says which, and every speed the schedule takes (:meth:`reference`, :meth:`command`) is on it."""

    def __init__(self, v_lo: float, v_hi: float, *, delay: int = 0, aero: str = "quasi-steady", model=None,
                 log=None, speeds=None, x_max=None, u_max=None, rate: str = "beat",
                 command_weight: float | None = None, insect: Insect | None = None, axis: str = "vertical"):
        if axis not in AXES:
            raise ValueError(f"axis {axis!r}: choose {', '.join(AXES)}")
        if speeds is None and axis == "forward":
            speeds = FORWARD_SCHEDULE_SPEEDS
        elif speeds is None:
            speeds = schedule_speeds(aero)
        if not len(speeds):
            raise ValueError(f"no {aero} control schedule: no shipped {aero} orbit for this network "
                             f"(`hawksim reproduce --only control_{aero}` after solving them)")
        sp = np.asarray(speeds, float)
        if v_lo < sp[0] - 1e-9 or v_hi > sp[-1] + 1e-9:
            raise ValueError(f"speeds {v_lo:g} to {v_hi:g} m/s are outside the {aero} control schedule's "
                             f"{sp[0]:g} to {sp[-1]:g} m/s")
        lo = sp[max(0, np.searchsorted(sp, v_lo, side="right") - 1)]
        hi = sp[min(len(sp) - 1, np.searchsorted(sp, v_hi, side="left"))]
        self.delay = int(delay)
        self.rate = rate
        self.axis = axis
        self.insect = default_insect() if insect is None else insect
        self.per_beat = HALVES if rate == "half-stroke" else 1
        fw = axis == "forward"
        self.points = [schedule_point(0.0 if fw else v, delay=delay, aero=aero, model=model, log=log, x_max=x_max,
                                      u_max=u_max, rate=rate, command_weight=command_weight, insect=insect,
                                      forward_speed=v if fw else 0.0, axis=axis)
                       for v in sp if lo - 1e-12 <= v <= hi + 1e-12]
        self.speeds = np.array([p.at(axis) for p in self.points])

    @classmethod
    def of_orbit(cls, orbit: Orbit, *, delay: int = 0, model=None, x_max=None, u_max=None) -> Schedule:
        """A one-point per-beat schedule about a given periodic orbit (a forward-flight one, issue 51: no grid of
        shipped or solved forward orbits exists): its linear model (:func:`hawksim.control.derivatives.linearize`,
        differenced here) and LQR gains as :func:`schedule_point` makes them; every speed reference is that orbit's.
        The orbit's insect must be the default one or the model its MJCF (``model``). The axis is "forward" for an
        orbit with a forward speed (the LQR's speed is then U), else "vertical"."""
        lin = linearize(orbit, model=model)
        sym = symmetric_inputs(orbit) if descriptor(orbit.aero).drop_bound_channels else None
        long, lat = lqr_gain(lin, "long", delay, x_max, u_max, inputs=sym), lqr_gain(lin, "lat", delay, x_max, u_max)
        self = cls.__new__(cls)
        self.delay, self.rate, self.insect, self.per_beat = int(delay), "beat", orbit.insect, 1
        self.axis = "forward" if orbit.forward_speed else "vertical"
        self.points = [SchedulePoint(float(orbit.speed), orbit, lin, long, lat,
                                     forward_speed=float(orbit.forward_speed))]
        self.speeds = np.array([self.points[0].at(self.axis)])
        return self

    def weights(self, v: float) -> list[tuple[float, SchedulePoint]]:
        """[(weight, point)] of the linear interpolation at v (clamped to the schedule's range)."""
        sp = self.speeds
        if len(sp) == 1 or v <= sp[0]:
            return [(1.0, self.points[0])]
        if v >= sp[-1]:
            return [(1.0, self.points[-1])]
        i = int(np.searchsorted(sp, v, side="right") - 1)
        a = (v - sp[i]) / (sp[i + 1] - sp[i])
        return [(w, p) for w, p in ((1 - a, self.points[i]), (a, self.points[i + 1])) if w > 0]

    def reference(self, v: float, phase: int = 0):
        """(kinematics (Kinematics), state (9,) at update ``phase``, chi_ref, mean pitch [rad]) interpolated at v."""
        ws = self.weights(v)
        p = sum(w * pt.orbit.kinematics.as_array() for w, pt in ws)
        x = sum(w * pt.reference_state(phase)[0] for w, pt in ws)
        chi = sum(w * pt.orbit.chi_ref for w, pt in ws)
        pitch = sum(w * pt.orbit.mean_pitch for w, pt in ws)
        return Kinematics.from_array(p), x, float(chi), float(pitch)

    @property
    def feeds_record(self) -> bool:
        """Whether the gains feed a history network's record back (:meth:`command` needs it)."""
        return any(g.record for pt in self.points for g in (pt.long, pt.lat))

    def reference_record(self, v: float, phase: int = 0) -> np.ndarray | None:
        """The orbits' record (n, 6) SI at update ``phase`` interpolated at v (None: no record feedback)."""
        ws = self.weights(v)
        recs = [(w, pt.reference_record(phase)) for w, pt in ws]
        return None if any(r is None for _, r in recs) else sum(w * r for w, r in recs)

    def wings(self, v: float, x_sensed: np.ndarray, pos_sensed: np.ndarray, past: list,
              phase: int = 0, record: np.ndarray | None = None) -> tuple[np.ndarray, np.ndarray]:
        """(left, right) parameter vectors (7,) SI, unsaturated, of :meth:`command` about the reference at v."""
        return wing_kinematics(self.reference(v, phase)[0],
                               self.command(v, x_sensed, pos_sensed, past, phase, record=record))

    def command(self, v: float, x_sensed: np.ndarray, pos_sensed: np.ndarray, past: list,
                phase: int = 0, record: np.ndarray | None = None) -> np.ndarray:
        """The command du (7,) (relative to the reference kinematics at v) at update ``phase`` from the body state
        (9,) and horizontal position (2,) [m] (from the hold point) sensed at the same phase (the delay is whole
        wingbeats), as deviations from the reference interpolated at v, and ``past``: the (left, right) parameter
        vectors actually flown in the last (d + 1) updates, oldest first (d: the delay in updates). ``record``
        (n, 6) SI: a history network's record of its calls sensed with the state, for gains that feed it back
        (:attr:`feeds_record`; its deviation from the orbits' record at this phase, normalized per orbit)."""
        kin, x_ref, _, _ = self.reference(v, phase)
        pos_ref = sum(w * pt.reference_state(phase)[1] for w, pt in self.weights(v))
        xi = np.concatenate([x_sensed - x_ref, pos_sensed - pos_ref])
        past_du = [command_of(kin, l, r) for l, r in past]
        du = np.zeros(len(INPUTS))
        rec_dev = None
        if self.feeds_record:
            if record is None:
                raise ValueError("these gains feed the history network's record back: pass the sensed record")
            rec_dev = record - self.reference_record(v, phase)
        for w, pt in self.weights(v):
            dxi = xi / xi_scale(pt.orbit.kinematics, pt.orbit.insect.morphology)
            for g in pt.gains(phase):
                parts = [dxi[list(g.states)]]
                if g.record:
                    parts.append((rec_dev / record_scale(pt.orbit.kinematics))[:, list(g.record)].ravel())
                z = np.concatenate(parts + [d[list(g.inputs)] for d in past_du])
                du[list(g.inputs)] += w * (-g.K @ z)
        return du


@contextlib.contextmanager
def operating_point_override(speed: float, aero: str, orbit: Orbit, model: BeatMapModel):
    """Within the block, the schedules at ``speed`` [m/s] with the backend ``aero`` design their per-beat gains on
    ``orbit`` and its linear model ``model`` (:func:`hawksim.control.derivatives.linearize`) instead of the shipped
    or solved ones (an experiment on other kinematics; the orbit's insect, the generated MJCF); the process's cache
    is put back after."""
    key = point_key(speed, aero, orbit.insect)
    saved = _POINTS.get(key)
    _POINTS[key] = (orbit, model)
    try:
        yield
    finally:
        if saved is None:
            _POINTS.pop(key, None)
        else:
            _POINTS[key] = saved
