"""Rerun recording of a flight: `write_rrd` writes an offline ``.rrd`` file (open it with ``rerun FILE``).

Timelines: ``time`` (duration [s], the step start time ``FlightResult.t``) and ``step`` (sequence, the row
index). World frame: z up, SI (m, s, N, W). Entity paths:

* ``world/moth`` - body pose per step (Transform3D: translation [m], quaternion xyzw, body -> world);
  ``world/moth/body`` - head, thorax, abdomen as Ellipsoids3D in the body frame (static).
* ``world/wings/{left,right}`` - wing pose per step (Transform3D, wing frame -> world, origin at the hinge);
  ``world/wings/{left,right}/mesh`` - triangulated planform in the wing frame (Mesh3D, static).
* ``world/forces/{left,right}`` - aerodynamic force of each wing (Arrows3D) drawn from the wing's mid-span
  point on the feathering axis, scaled by ``FORCE_SCALE_M_PER_WEIGHT`` = 2 cm per body weight W.
* ``world/trajectory`` - body centre-of-mass path (LineStrips3D, static).
* ``plots/...`` - Scalars per step (:data:`SERIES`: entity, series name with its unit, view): forces/{lift,drag}
  [N], forces_nd/{L_plus,D_plus} [-] (/W), moment/pitching [N m], moment_nd/M_plus [-] (/(W cbar)),
  power/{aero,joint} [W], velocity/{vx,vy,vz} [m/s] world, attitude/{pitch,roll} [deg].
* ``world/uvlm/...`` - only when ``result.extras`` holds UVLM data (see `_log_extras`): ``panels`` (pressure-
  coloured Mesh3D), ``wake/{left,right}`` (LineStrips3D coloured by circulation), ``legend`` (colour scales).
  They are logged at the steps the backend was called (every UVLM update when the flight kept extras every
  ``aero_every`` steps, as `hawksim fly --rrd` does); in between they hold, as the simulator holds the loads.
* With a :class:`hawksim.stability.prediction.Prediction` (a perturbed flight from a periodic orbit):
  ``world/ghost`` - the ghost body, pose per step (Transform3D) = the unperturbed flight's pose plus the Floquet
  prediction of the deviation, shifted by :data:`GHOST_OFFSET_M` so that it stands beside the nonlinear body;
  ``world/ghost/body`` (translucent Ellipsoids3D), ``world/ghost/wings/{left,right}`` (Transform3D relative to the
  ghost body, the prescribed wing motion) with ``.../mesh``; ``world/ghost_trajectory`` (static);
  ``world/ghost_legend`` (TextDocument); ``plots/beats/{u,w,q,theta,v,p,r,phi}/{nonlinear,floquet,averaged}`` -
  the per-beat state deviations at phase 0 (t = k T) in edge units (:data:`BEAT_STATES`).

A default blueprint is stored in the file: the 3D view beside tabs of time-series views, each series named with
its unit, one view per group (:func:`default_blueprint`), plus a text view of each legend present.
"""

from __future__ import annotations

import os
import signal
import threading
from pathlib import Path

import numpy as np
import rerun as rr
import rerun.blueprint as rrb

from hawksim.atomic import ENVIRONMENT_ERRNOS, keep_mode, output_target, temporary_beside
from hawksim.flight.orbit import STATE_NAMES
from hawksim.flight.result import FlightResult
from hawksim.frames import quat_from_matrices
from hawksim.insect.accessors import WING_SIDES as SIDES
from hawksim.insect.morphology import HAWKMOTH, Morphology

FORCE_SCALE_M_PER_WEIGHT = 0.02
"""Force arrows: an arrow of length 2 cm is a force equal to the body weight W = m g."""

N_SPAN, N_CHORD = 21, 4
"""Wing mesh resolution: spanwise stations (cosine spaced, tips included) and chordwise divisions."""

GHOST_OFFSET_M = (0.0, 0.15, 0.0)
"""World offset [m] of the ghost body (the linear prediction) from the nonlinear one: 15 cm to the left (+y;
the wingspan is ~10 cm), fixed, so that both are visible side by side."""

SERIES = (
    ("forces/lift", "lift [N]"), ("forces/drag", "drag [N]"),
    ("forces_nd/L_plus", "L+ = L/W [-]"), ("forces_nd/D_plus", "D+ = D/W [-]"),
    ("moment/pitching", "pitching moment [N m]"), ("moment_nd/M_plus", "M+ = M/(W cbar) [-]"),
    ("power/aero", "aerodynamic power [W]"), ("power/joint", "joint power [W]"),
    ("velocity/vx", "vx [m/s]"), ("velocity/vy", "vy [m/s]"), ("velocity/vz", "vz [m/s]"),
    ("attitude/pitch", "pitch [deg]"), ("attitude/roll", "roll [deg]"),
)
"""Per-step series under ``plots/``: (entity, series name with its unit)."""

VIEWS = (
    ("plots/forces", "Lift, drag [N]"), ("plots/forces_nd", "L+, D+ [-]"),
    ("plots/moment", "Pitching moment [N m]"), ("plots/moment_nd", "M+ [-]"), ("plots/power", "Power [W]"),
    ("plots/velocity", "Velocity, world [m/s]"), ("plots/attitude", "Pitch, roll [deg]"),
)
"""Time-series views of the per-step series: (origin, name with the unit)."""

BEAT_STATES = (
    ("u", "m/s", 1.0), ("w", "m/s", 1.0), ("q", "deg/s", 180 / np.pi), ("theta", "deg", 180 / np.pi),
    ("v", "m/s", 1.0), ("p", "deg/s", 180 / np.pi), ("r", "deg/s", 180 / np.pi), ("phi", "deg", 180 / np.pi),
)
"""Per-beat deviation plots: (state, edge unit, factor from SI). States of the orbit's chart
(:mod:`hawksim.flight.orbit`): u, v, w in the level heading axes (forward, right, down), p, q, r the body rates in
them, theta the pitch (nose up), phi the bank (right wing down)."""

_BEAT_KINDS = (("nonlinear", "nonlinear flight", (20, 20, 20)), ("floquet", "Floquet M^k x0", (31, 119, 180)),
               ("averaged", "averaged expm(A k) x0", (214, 39, 40)))
_GHOST_COLOR = (120, 200, 255)
_SIDE_COLORS = {"left": (230, 120, 40), "right": (40, 140, 230)}
_DIVERGING = np.array([[59, 76, 192], [221, 221, 221], [180, 4, 38]], dtype=float)  # blue-white-red


def _xyzw(q_wxyz: np.ndarray) -> np.ndarray:
    """MuJoCo (w, x, y, z) quaternions (..., 4) -> Rerun (x, y, z, w)."""
    return np.concatenate([q_wxyz[..., 1:], q_wxyz[..., :1]], axis=-1)


def diverging_colors(value: np.ndarray, limit: float) -> np.ndarray:
    """RGB uint8 (..., 3) of ``value`` on a blue (-limit) - white (0) - red (+limit) scale, clipped."""
    s = np.clip(np.asarray(value, dtype=float) / (limit if limit > 0 else 1.0), -1.0, 1.0) + 1.0  # in [0, 2]
    i = np.minimum(s.astype(int), 1)
    f = (s - i)[..., None]
    return np.round(_DIVERGING[i] * (1 - f) + _DIVERGING[i + 1] * f).astype(np.uint8)


def wing_mesh(morph: Morphology = HAWKMOTH, side: str = "left") -> tuple[np.ndarray, np.ndarray]:
    """Triangulated planform in the wing frame: vertices (N_SPAN (N_CHORD+1), 3) [m], triangles (m, 3).

    Stations r = R (1 - cos(pi k / (N_SPAN-1))) / 2, each from the leading to the trailing edge in N_CHORD
    equal steps; the right wing is the left one with y -> -y (winding reversed to keep normals along +z).
    """
    pl = morph.planform
    r = morph.R * 0.5 * (1 - np.cos(np.pi * np.arange(N_SPAN) / (N_SPAN - 1)))
    s = np.linspace(0.0, 1.0, N_CHORD + 1)
    x = pl.leading_edge(r)[:, None] + s[None, :] * (pl.trailing_edge(r) - pl.leading_edge(r))[:, None]
    y = np.broadcast_to(r[:, None], x.shape) * (1.0 if side == "left" else -1.0)
    verts = np.stack([x, y, np.zeros_like(x)], -1).reshape(-1, 3)
    k, j = np.meshgrid(np.arange(N_SPAN - 1), np.arange(N_CHORD), indexing="ij")
    a = (k * (N_CHORD + 1) + j).ravel()
    b, c, d = a + 1, a + N_CHORD + 1, a + N_CHORD + 2
    tris = np.concatenate([np.stack([a, c, b], 1), np.stack([b, c, d], 1)])
    if side == "right":
        tris = tris[:, ::-1]
    return verts, tris.astype(np.uint32)


def _check_target(path: Path) -> None:
    if path.is_dir():
        raise ValueError(f"cannot write recording {path}: it is a directory")
    if not path.parent.is_dir():
        raise ValueError(f"cannot write recording {path}: directory {path.parent} does not exist")


def _write_error(path: Path, exc: OSError) -> Exception:
    """The one-line error naming ``path`` (not the temporary file): OSError for an environment failure (disk full),
    ValueError (a bad path: exit status 2) otherwise."""
    text = f"cannot write recording {path}: {exc.strerror or exc}"
    return OSError(exc.errno, text) if exc.errno in ENVIRONMENT_ERRNOS else ValueError(text)


def write_rrd(path, result: FlightResult, morph: Morphology = HAWKMOTH, *, prediction=None, control=None,
              application_id: str = "hawksim") -> Path:
    """Write ``result`` as a Rerun recording (with its default blueprint) to ``path``; return the Path.

    ``prediction``: a :class:`hawksim.stability.prediction.Prediction` of the flight (ghost body and per-beat
    plots), or None. ``control``: the per-beat objects of a controlled flight (`hawksim fly --control lqr` JSON's
    ``control.beats``: ``commands`` and tracking errors), logged at the end of each beat under ``plots/control``
    with a view each (:func:`control_views`).

    The recording is encoded in memory (Rerun's binary stream: about 130 kB per quasi-steady wingbeat, 1.3 MB per
    UVLM wingbeat with its panels and wake) and written by this process to a temporary file in the same directory,
    fsync'ed and renamed at the end, so a failure (a full disk, an interrupt) leaves nothing half-written and is
    reported with its cause: OSError naming ``path`` when the environment fails
    (:data:`hawksim.atomic.ENVIRONMENT_ERRNOS`: disk full, file too large, quota, I/O error, read-only file system),
    ValueError (one line, naming the path) when the path cannot be written. (Rerun's own file sink writes from a
    thread of its own, and a full disk there surfaced as "File-writer thread shut down prematurely" with log lines
    on stderr and no errno.)
    """
    path = Path(path)
    target = output_target(path, "recording")  # a link's target; a device, FIFO or directory: ValueError
    _check_target(target)
    tmp = temporary_beside(target)
    try:
        fh = open(tmp, "xb")  # probes writability; created with the usual umask permissions
    except OSError as exc:
        raise _write_error(path, exc) from None
    rec = rr.RecordingStream(application_id)
    try:
        with fh:
            stream = rec.binary_stream()
            views = control_views(control) if control else []
            rec.send_blueprint(default_blueprint(uvlm=_uvlm_extras(result) != [], prediction=prediction is not None,
                                                 control=views), make_active=False, make_default=True)
            _log_flight(rec, result, morph)
            _log_extras(rec, result)
            if prediction is not None:
                _log_prediction(rec, result, prediction, morph)
            if control:
                _log_control(rec, result, control, views)
            data = stream.read(flush=True)  # one complete .rrd stream (a second read would start another)
            rec.disconnect()
            fh.write(data or b"")
            fh.flush()
            os.fsync(fh.fileno())
        keep_mode(tmp, target)
        os.replace(tmp, target)
    except OSError as exc:
        raise _write_error(path, exc) from None
    finally:
        rec.disconnect()
        tmp.unlink(missing_ok=True)
    return path


CONTROL_TRACKING = {"speed_error": "m/s", "pitch_error_deg": "deg", "roll_deg": "deg", "yaw_deg": "deg",
                    "horizontal_drift_m": "m"}
"""Tracking errors of a controlled flight's beats that the recording plots, with their units."""

_SUFFIX_UNITS = (("_hz", "Hz"), ("_deg", "deg"), ("_m", "m"))


def control_views(beats: list[dict]) -> list[tuple[str, str, str, str]]:
    """(entity path, key, kind, view name with unit) of every command and tracking error in ``beats``; a command's
    unit comes from its key's suffix (``f_hz``, ``phi0_deg``)."""
    out = []
    for key in beats[0].get("commands", {}):
        unit = next((u for s, u in _SUFFIX_UNITS if key.endswith(s)), "-")
        out.append((f"plots/control/commands/{key}", key, "commands", f"command {key} [{unit}]"))
    for key, unit in CONTROL_TRACKING.items():
        if key in beats[0]:
            out.append((f"plots/control/tracking/{key}", key, "tracking", f"{key} [{unit}]"))
    return out


def _log_control(rec: rr.RecordingStream, res: FlightResult, beats: list[dict], views) -> None:
    """Each beat's tracking errors at its end; its commands there too, or, for a controller updated per half-stroke
    (``commands_half_stroke`` in the beats), the phase-0 commands at mid-beat and the phase-0.5 ones at its end."""
    n = res.steps_per_cycle
    T = n * (res.t[1] - res.t[0])
    k = np.arange(len(beats)) + 1
    idx = [rr.TimeColumn("time", duration=k * T), rr.TimeColumn("step", sequence=k * n)]
    half = "commands_half_stroke" in beats[0]
    if half:  # two updates per beat
        kk = np.ravel(np.column_stack([k - 0.5, k]))
        idx_c = [rr.TimeColumn("time", duration=kk * T), rr.TimeColumn("step", sequence=np.rint(kk * n).astype(int))]
    for path, key, kind, name in views:
        if kind == "commands" and half:
            vals = np.ravel([[b["commands"][key], b["commands_half_stroke"][key]] for b in beats])
        else:
            vals = [b["commands"][key] if kind == "commands" else b[key] for b in beats]
        rec.log(path, rr.SeriesPoints(names=name, markers=["circle"], marker_sizes=[3.0]), static=True)
        rec.send_columns(path, idx_c if kind == "commands" and half else idx,
                         rr.Scalars.columns(scalars=np.asarray(vals, dtype=float)))


def default_blueprint(*, uvlm: bool = False, prediction: bool = False, control=()) -> rrb.Blueprint:
    """The 3D view beside tabs: the per-step time series (:data:`VIEWS`), with ``prediction`` the per-beat state
    deviations (one view per :data:`BEAT_STATES` entry, named with its unit) and the ghost's legend, with ``uvlm``
    the colour legend of the panels and wake."""
    tabs = [rrb.Grid(*[rrb.TimeSeriesView(origin=o, name=n) for o, n in VIEWS], name="Per step")]
    if control:
        tabs.append(rrb.Grid(*[rrb.TimeSeriesView(origin=path, name=name) for path, _, _, name in control],
                             name="Control: commands (per update) and tracking (per beat)"))
    if prediction:
        tabs.append(rrb.Grid(*[rrb.TimeSeriesView(origin=f"plots/beats/{k}", name=f"Δ{k} per beat [{u}]")
                               for k, u, _ in BEAT_STATES], name="Per beat: nonlinear vs linear"))
    texts = ([rrb.TextDocumentView(origin="world/ghost_legend", name="Ghost")] if prediction else []) + (
        [rrb.TextDocumentView(origin="world/uvlm/legend", name="UVLM colour scales")] if uvlm else [])
    side = rrb.Tabs(*tabs) if len(tabs) > 1 else tabs[0]
    right = rrb.Vertical(side, *texts, row_shares=[6] + [1] * len(texts)) if texts else side
    return rrb.Blueprint(
        rrb.Horizontal(
            rrb.Spatial3DView(origin="world", name="Hawkmoth", contents=["+ /world/**", "- /world/uvlm/legend",
                                                                         "- /world/ghost_legend"]),
            right,
            column_shares=[3, 2],
        ),
        collapse_panels=True,
    )


def _log_flight(rec: rr.RecordingStream, res: FlightResult, morph: Morphology) -> None:
    n = len(res.t)
    idx = [rr.TimeColumn("time", duration=np.asarray(res.t, dtype=float)),
           rr.TimeColumn("step", sequence=np.arange(n))]
    rec.log("world", rr.ViewCoordinates.RIGHT_HAND_Z_UP, static=True)
    rec.log("world/trajectory", rr.LineStrips3D([res.body_pos], colors=[(120, 120, 120)]), static=True)

    # body
    rec.send_columns("world/moth", idx, rr.Transform3D.columns(
        translation=res.body_pos, quaternion=_xyzw(res.body_quat)))
    centres = morph.segment_centres()
    rec.log("world/moth/body", rr.Ellipsoids3D(
        centers=[centres[s.name] for s in morph.segments], half_sizes=[s.semi_axes for s in morph.segments],
        colors=[(110, 90, 70)], fill_mode="solid", labels=[s.name for s in morph.segments]), static=True)

    # wings and force arrows
    scale = FORCE_SCALE_M_PER_WEIGHT / morph.weight
    for i, side in enumerate(SIDES):
        R = res.wing_R[:, i]
        rec.send_columns(f"world/wings/{side}", idx, rr.Transform3D.columns(
            translation=res.wing_origin[:, i], quaternion=_xyzw(quat_from_matrices(R))))
        verts, tris = wing_mesh(morph, side)
        rec.log(f"world/wings/{side}/mesh", rr.Mesh3D(
            vertex_positions=verts, triangle_indices=tris, vertex_normals=np.tile([0.0, 0.0, 1.0], (len(verts), 1)),
            albedo_factor=(*_SIDE_COLORS[side], 180)), static=True)
        span = R[:, :, 1] * (0.5 * morph.R * (1.0 if side == "left" else -1.0))
        rec.log(f"world/forces/{side}", rr.Arrows3D.from_fields(
            colors=[_SIDE_COLORS[side]], radii=[2e-4]), static=True)
        rec.send_columns(f"world/forces/{side}", idx, rr.Arrows3D.columns(
            vectors=res.force[:, i] * scale, origins=res.wing_origin[:, i] + span))

    # time series
    W, cbar = morph.weight, morph.cbar
    lift, drag = res.lift_drag()
    M = res.pitching_moment()
    values = {
        "forces/lift": lift, "forces/drag": drag, "forces_nd/L_plus": lift / W, "forces_nd/D_plus": drag / W,
        "moment/pitching": M, "moment_nd/M_plus": M / (W * cbar),
        "power/aero": res.power_aero, "power/joint": res.power_joint,
        "velocity/vx": res.body_v[:, 0], "velocity/vy": res.body_v[:, 1], "velocity/vz": res.body_v[:, 2],
        "attitude/pitch": np.rad2deg(res.pitch()), "attitude/roll": np.rad2deg(res.roll()),
    }
    for name, label in SERIES:
        rec.log(f"plots/{name}", rr.SeriesLines(names=label), static=True)
        rec.send_columns(f"plots/{name}", idx, rr.Scalars.columns(scalars=np.asarray(values[name], dtype=float)))


def _panel_mesh(vertices: np.ndarray, pressure: np.ndarray, limit: float) -> rr.Mesh3D:
    """Mesh3D of a panel lattice (nc+1, ns+1, 3), one flat-coloured quad (4 own vertices) per panel."""
    quads = np.stack([vertices[:-1, :-1], vertices[:-1, 1:], vertices[1:, 1:], vertices[1:, :-1]], 2)  # nc,ns,4,3
    verts = quads.reshape(-1, 3)
    base = 4 * np.arange(pressure.size)[:, None]
    tris = np.concatenate([base + [0, 1, 2], base + [0, 2, 3]])
    colors = np.repeat(diverging_colors(pressure.reshape(-1), limit), 4, axis=0)
    return rr.Mesh3D(vertex_positions=verts, triangle_indices=tris.astype(np.uint32), vertex_colors=colors,
                     face_rendering="DoubleSided")


def _wake_strips(vertices: np.ndarray, gamma: np.ndarray, limit: float) -> rr.LineStrips3D:
    """The wake lattice (rows+1, ns+1, 3) as LineStrips3D: each ring's upstream spanwise segment coloured by
    its circulation gamma (rows, ns); the streamwise lines (ns+1 strips) in grey."""
    seg = np.stack([vertices[:-1, :-1], vertices[:-1, 1:]], 2).reshape(-1, 2, 3)
    strips = list(seg) + list(np.swapaxes(vertices, 0, 1))
    colors = np.concatenate([diverging_colors(gamma.reshape(-1), limit),
                             np.full((vertices.shape[1], 3), 150, dtype=np.uint8)])
    return rr.LineStrips3D(strips, colors=colors, radii=5e-5)


def _uvlm_extras(res: FlightResult) -> list:
    """The (step, dict) extras that hold UVLM panels or wake, within the flight's rows."""
    return [(int(i), e) for i, e in res.extras
            if isinstance(e, dict) and ("panels" in e or "wake" in e) and 0 <= int(i) < len(res.t)]


def _log_extras(rec: rr.RecordingStream, res: FlightResult) -> None:
    """UVLM extras (step, dict): ``panels`` (2, nc+1, ns+1, 3) world [m] with ``pressure`` (2, nc, ns) [Pa]
    (pressure jump across the wing), and ``wake``: per wing (vertices (rows+1, ns+1, 3) [m], gamma (rows, ns)
    [m^2/s]). Colour scales are symmetric, blue (negative) - white - red (positive), with limits the largest
    |pressure| and |gamma| over all kept steps; they are written to ``world/uvlm/legend``."""
    kept = _uvlm_extras(res)
    if not kept:
        return
    p_lim = max([float(np.abs(e["pressure"]).max()) for _, e in kept if "pressure" in e] + [0.0])
    g_lim = max([float(np.abs(g).max()) for _, e in kept for _, g in e.get("wake", []) if np.size(g)] + [0.0])
    rec.log("world/uvlm/legend", rr.TextDocument(
        f"Panel colour: pressure jump, blue -{p_lim:.4g} Pa .. white 0 .. red +{p_lim:.4g} Pa.\n"
        f"Wake colour: ring circulation, blue -{g_lim:.4g} m^2/s .. white 0 .. red +{g_lim:.4g} m^2/s."),
        static=True)
    for i, e in kept:
        rec.set_time("step", sequence=i)
        rec.set_time("time", duration=float(res.t[i]))
        if "panels" in e and "pressure" in e:
            P, p = np.asarray(e["panels"], dtype=float), np.asarray(e["pressure"], dtype=float)
            for w, side in enumerate(SIDES):
                rec.log(f"world/uvlm/panels/{side}", _panel_mesh(P[w], p[w], p_lim))
        for w, (V, g) in enumerate(e.get("wake", [])):
            V, g = np.asarray(V, dtype=float), np.asarray(g, dtype=float)
            if g.size:
                rec.log(f"world/uvlm/wake/{SIDES[w]}", _wake_strips(V, g, g_lim))
    rec.reset_time()


def _log_prediction(rec: rr.RecordingStream, res: FlightResult, pred, morph: Morphology) -> None:
    """The ghost body (pose per step, wings relative to it), its trajectory and legend, and the per-beat series."""
    ref = pred.reference
    n = min(len(res.t), len(ref.t), len(pred.ghost_pos))
    idx = [rr.TimeColumn("time", duration=np.asarray(ref.t[:n], dtype=float)),
           rr.TimeColumn("step", sequence=np.arange(n))]
    off = np.asarray(GHOST_OFFSET_M, dtype=float)
    pos = pred.ghost_pos[:n] + off
    rec.send_columns("world/ghost", idx, rr.Transform3D.columns(translation=pos,
                                                                 quaternion=_xyzw(pred.ghost_quat[:n])))
    rec.log("world/ghost_trajectory", rr.LineStrips3D([pos], colors=[(*_GHOST_COLOR, 160)]), static=True)
    centres = morph.segment_centres()
    rec.log("world/ghost/body", rr.Ellipsoids3D(
        centers=[centres[s.name] for s in morph.segments], half_sizes=[s.semi_axes for s in morph.segments],
        colors=[(*_GHOST_COLOR, 90)], fill_mode="solid"), static=True)
    Rb = ref.body_R[:n]
    for i, side in enumerate(SIDES):  # the prescribed wing motion relative to the body (the same in both flights)
        R_rel = np.einsum("nji,njk->nik", Rb, ref.wing_R[:n, i])
        o_rel = np.einsum("nji,nj->ni", Rb, ref.wing_origin[:n, i] - ref.body_pos[:n])
        rec.send_columns(f"world/ghost/wings/{side}", idx, rr.Transform3D.columns(
            translation=o_rel, quaternion=_xyzw(quat_from_matrices(R_rel))))
        verts, tris = wing_mesh(morph, side)
        rec.log(f"world/ghost/wings/{side}/mesh", rr.Mesh3D(
            vertex_positions=verts, triangle_indices=tris, vertex_normals=np.tile([0.0, 0.0, 1.0], (len(verts), 1)),
            albedo_factor=(*_GHOST_COLOR, 90)), static=True)
    rec.log("world/ghost_legend", rr.TextDocument(
        "Ghost (pale blue, translucent): the LINEAR prediction of this perturbed flight - the unperturbed orbit "
        "flight's pose plus the Floquet prediction of the deviation (M^k x0 at phase 0 of each beat, linearly "
        "interpolated; heading and position from the one-beat map's neutral rows), drawn "
        f"{off[1] * 100:g} cm to the left (+y world) of the nonlinear body.\n"
        "Per-beat plots: deviation from the unperturbed flight at phase 0 (t = k T): nonlinear flight (points), "
        "Floquet M^k x0 and cycle-averaged T^-1 expm(A k) T x0 (lines).\n" + (pred.notes or "")), static=True)

    spc = res.steps_per_cycle
    series = {"nonlinear": pred.nonlinear, "floquet": pred.floquet, "averaged": pred.averaged}
    for name, unit, factor in BEAT_STATES:
        j = STATE_NAMES.index(name)  # the first 8 are the prediction's states (hawksim.stability.prediction)
        for kind, label, color in _BEAT_KINDS:
            d = np.asarray(series[kind], dtype=float)
            k = np.arange(len(d))
            ent = f"plots/beats/{name}/{kind}"
            style = (rr.SeriesPoints(names=f"{label} [{unit}]", colors=[color], markers=["circle"], marker_sizes=[3.0])
                     if kind == "nonlinear" else rr.SeriesLines(names=f"{label} [{unit}]", colors=[color]))
            rec.log(ent, style, static=True)
            rec.send_columns(ent, [rr.TimeColumn("time", duration=np.asarray(pred.beat_t[: len(d)], dtype=float)),
                                   rr.TimeColumn("step", sequence=k * spc)],
                             rr.Scalars.columns(scalars=d[:, j] * factor))


class InterruptGuard:
    """Ctrl-C (SIGINT) and SIGTERM around a flight whose recording is asked for (`hawksim fly --rrd`).

    Before the flight's first step a signal raises KeyboardInterrupt at once (nothing to save). During the flight
    (from the first call of the wrapped progress hook, :meth:`progress`) it is only noted; the hook raises
    KeyboardInterrupt after the step in progress, so :func:`hawksim.flight.fly.fly` (``partial_on_interrupt``)
    returns the steps flown. :meth:`deferred` notes signals while the recording is written (so that the write
    completes; write_rrd's temporary file is removed on any exception anyway); :attr:`signum` tells whether one
    came. Handlers are installed only in the main thread and restored on exit.
    """

    SIGNALS = (signal.SIGINT, signal.SIGTERM)

    def __init__(self):
        self.signum: int | None = None
        self._defer = False
        self._old: dict = {}

    def __enter__(self) -> InterruptGuard:
        if threading.current_thread() is threading.main_thread():
            for s in self.SIGNALS:
                self._old[s] = signal.signal(s, self._handler)
        return self

    def __exit__(self, *exc) -> None:
        for s, h in self._old.items():
            signal.signal(s, h)
        self._old = {}

    def _handler(self, signum, frame) -> None:
        self.signum = signum
        if not self._defer:
            raise KeyboardInterrupt

    def progress(self, inner=None):
        """A progress hook (step, n) that defers signals from the first step on and raises KeyboardInterrupt
        after the step in which one came; then calls ``inner``. The deferral ends when the flight's last step
        is done."""
        def hook(i, n):
            self._defer = i < n
            if self.signum is not None:
                self._defer = False
                raise KeyboardInterrupt
            if inner is not None:
                inner(i, n)
        return hook

    def deferred(self):
        """Context: signals are noted, not raised (restores the previous mode on exit)."""
        import contextlib

        @contextlib.contextmanager
        def cm():
            old, self._defer = self._defer, True
            try:
                yield
            finally:
                self._defer = old
        return cm()
