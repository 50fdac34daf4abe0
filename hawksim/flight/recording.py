"""Rerun recording of a flight: `write_rrd` writes an offline ``.rrd`` file (open it with ``rerun FILE``; how to read
it: docs/recording.md).

Timelines: ``time`` (duration [s], the step start time ``FlightResult.t``) and ``step`` (sequence, the row
index). World frame: z up, SI (m, s, N) unless a series name says otherwise. Entity paths:

* ``world/moth`` - the body's centre-of-mass position per step (Transform3D, translation only [m]): the frame the
  3D view follows (its origin; :mod:`hawksim.flight.recording_layout`). Under it, with offsets from the centre of
  mass in world axes:
  ``world/moth/body`` - body attitude per step (Transform3D, quaternion xyzw, body -> world) with head, thorax and
  abdomen as Ellipsoids3D in the body frame (static), ``world/moth/body/labels`` their names (Points3D placed apart
  so that they do not overlap); ``world/moth/wings/{left,right}`` - wing pose per step (Transform3D, wing frame ->
  world axes, origin at the hinge) with ``.../outline`` (LineStrips3D) and, without UVLM panels, ``.../mesh``
  (translucent Mesh3D) in the wing frame (static); ``world/moth/forces/{left,right}`` - aerodynamic force of each
  wing (Arrows3D) from the wing's mid-span point on the feathering axis, scaled by ``FORCE_SCALE_M_PER_WEIGHT`` =
  2 cm per body weight W; ``world/moth/weight`` - the scale arrow: W itself, pointing down, ahead of the head.
* ``world/trajectory`` - body centre-of-mass path (LineStrips3D, static); ``world/ruler`` - a vertical scale
  beside the path, a tick per cm, labelled every 10 cm (static): the world-fixed references that slide past.
* ``world/legend`` - the 3D view's legend (TextDocument: colours, arrow scale).
* ``plots/...`` - Scalars per step (:data:`SERIES`: entity, series name with its unit, view):
  forces/{lift,drag} [N], forces_nd/{L_plus,D_plus} [-] (/W), moment/pitching [mN m], moment_nd/M_plus [-]
  (/(W cbar)), power/{aero,joint} [mW], velocity/{vx,vy,vz} [m/s] world, attitude/{pitch,roll,yaw} [deg]
  (:meth:`FlightResult.attitude`, the JSON's angles: pitch-first, unwrapped).
* ``world/uvlm/...`` - only when ``result.extras`` holds UVLM data (see `_log_extras`): ``panels/{left,right}``
  (Mesh3D coloured by the pressure jump), ``wake/{left,right}`` (LineStrips3D coloured by circulation), ``legend``
  (the colour scales: symmetric, ending at the 95th percentile of |value|, :func:`robust_limit`). World
  coordinates. They are logged at the steps the backend was called (every UVLM update when the flight kept extras
  every ``aero_every`` steps, as `hawksim fly --rrd` does); in between they hold, as the simulator holds the loads.
* With a :class:`hawksim.stability.prediction.Prediction` (a perturbed flight from a periodic orbit):
  ``world/ghost`` - the ghost body, pose per step (Transform3D) = the unperturbed flight's pose plus the Floquet
  prediction of the deviation, shifted by :data:`GHOST_OFFSET_M` so that it stands beside the nonlinear body;
  ``world/ghost/body`` (translucent Ellipsoids3D), ``world/ghost/wings/{left,right}`` (Transform3D relative to the
  ghost body, the prescribed wing motion) with ``.../mesh``; ``world/ghost_trajectory`` (static);
  ``world/ghost_legend`` (TextDocument); ``plots/beats/{u,w,q,theta,v,p,r,phi}/{nonlinear,floquet,averaged}`` -
  the per-beat state deviations at phase 0 (t = k T) in edge units (:data:`BEAT_STATES`).
* With a controlled flight's beats: ``plots/control/{commands,tracking}/KEY`` (:func:`control_views`), tracking
  errors in mm/s, deg, mm rounded to a stated resolution (:data:`CONTROL_TRACKING`).

A default blueprint is stored in the file (:func:`default_blueprint`): the 3D view following the moth, with its
legend, beside tabs of time-series views, one per group, each series named with its unit and a colour of its own
within its view.
"""

from __future__ import annotations

import os
import signal
import threading
from pathlib import Path

import numpy as np
import rerun as rr

from hawksim.atomic import ENVIRONMENT_ERRNOS, keep_mode, output_target, temporary_beside
from hawksim.flight.orbit import STATE_NAMES
from hawksim.flight.recording_layout import (  # noqa: F401  (re-exported: the recording's public names)
    BEAT_KINDS, BEAT_STATES, BODY_COLOR, CONTROL_TRACKING, EYE_POSITION_M, FORCE_SCALE_M_PER_WEIGHT, GHOST_COLOR,
    GHOST_OFFSET_M, MOTH, PALETTE, ROBUST_PERCENTILE, SERIES, SIDE_COLORS, TRAJECTORY_COLOR, VIEWS,
    WEIGHT_ARROW_ORIGIN_M, control_values, control_views, default_blueprint, diverging_colors, robust_limit,
    scene_legend, series_colors)
from hawksim.flight.result import FlightResult
from hawksim.frames import quat_from_matrices
from hawksim.insect.accessors import WING_SIDES as SIDES
from hawksim.insect.folder import default_insect
from hawksim.insect.morphology import Morphology

N_SPAN, N_CHORD = 21, 4
"""Wing mesh resolution: spanwise stations (cosine spaced, tips included) and chordwise divisions."""

LABEL_GAP_M = 0.006
"""Body-part labels stand this far [m] beyond the part (ahead of the head, behind the abdomen, above the thorax),
so that the three names never overlap."""


def _xyzw(q_wxyz: np.ndarray) -> np.ndarray:
    """MuJoCo (w, x, y, z) quaternions (..., 4) -> Rerun (x, y, z, w)."""
    return np.concatenate([q_wxyz[..., 1:], q_wxyz[..., :1]], axis=-1)


def wing_mesh(morph: Morphology | None = None, side: str = "left") -> tuple[np.ndarray, np.ndarray]:
    """Triangulated planform in the wing frame: vertices (N_SPAN (N_CHORD+1), 3) [m], triangles (m, 3).

    Stations r = R (1 - cos(pi k / (N_SPAN-1))) / 2, each from the leading to the trailing edge in N_CHORD
    equal steps; the right wing is the left one with y -> -y (winding reversed to keep normals along +z).
    ``morph``: the insect's (None: the default insect's).
    """
    morph = default_insect().morphology if morph is None else morph
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


def write_rrd(path, result: FlightResult, morph: Morphology | None = None, *, prediction=None, control=None,
              application_id: str = "hawksim") -> Path:
    """Write ``result`` as a Rerun recording (with its default blueprint) to ``path``; return the Path. ``morph``:
    the body and wings drawn (default the flight's own insect's, :attr:`FlightResult.insect`).

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
    morph = result.insect.morphology if morph is None else morph
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
            uvlm = any("panels" in e for _, e in _uvlm_extras(result))
            rec.send_blueprint(default_blueprint(uvlm=_uvlm_extras(result) != [], prediction=prediction is not None,
                                                 control=views), make_active=False, make_default=True)
            _log_flight(rec, result, morph, uvlm=uvlm)
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


def wing_outline(morph: Morphology | None = None, side: str = "left") -> np.ndarray:
    """Closed planform outline in the wing frame (2 N_SPAN + 1, 3) [m]: leading edge root to tip, trailing edge
    back to the root (the stations of :func:`wing_mesh`)."""
    verts, _ = wing_mesh(morph, side)
    grid = verts.reshape(N_SPAN, N_CHORD + 1, 3)
    return np.concatenate([grid[:, 0], grid[::-1, -1], grid[:1, 0]])


def body_labels(morph: Morphology | None = None) -> tuple[np.ndarray, list[str]]:
    """Label positions (3, 3) [m] in the body frame and the names: ahead of the head, above the thorax and behind
    the abdomen, :data:`LABEL_GAP_M` beyond each part's surface (``morph`` None: the default insect's)."""
    morph = default_insect().morphology if morph is None else morph
    c = morph.segment_centres()
    ax = {s.name: s.semi_axes for s in morph.segments}
    pos = [c["head"] + [ax["head"][0] + LABEL_GAP_M, 0, 0], c["thorax"] + [0, 0, ax["thorax"][2] + LABEL_GAP_M],
           c["abdomen"] - [ax["abdomen"][0] + LABEL_GAP_M, 0, 0]]
    return np.array(pos), ["head", "thorax", "abdomen"]


def _ruler(body_pos: np.ndarray, offset=(-0.06, 0.0)) -> rr.LineStrips3D:
    """A vertical scale [m] beside the path (``offset`` in world x, y from the start): a line over the climb with a
    4 mm tick every cm and a 1 cm tick, labelled with its height, every 10 cm."""
    x0, y0 = body_pos[0, 0] + offset[0], body_pos[0, 1] + offset[1]
    lo = np.floor(body_pos[:, 2].min() * 100) / 100 - 0.02
    hi = np.ceil(body_pos[:, 2].max() * 100) / 100 + 0.02
    strips, labels = [np.array([[x0, y0, lo], [x0, y0, hi]])], [""]
    for k in range(int(round(lo * 100)), int(round(hi * 100)) + 1):
        z, big = k / 100, k % 10 == 0
        strips.append(np.array([[x0, y0, z], [x0, y0 - (0.01 if big else 0.004), z]]))
        labels.append(f"z = {z:g} m" if big else "")
    return rr.LineStrips3D(strips, colors=[(110, 110, 110)], radii=rr.Radius.ui_points(1.0), labels=labels,
                           show_labels=True)


def _log_flight(rec: rr.RecordingStream, res: FlightResult, morph: Morphology, *, uvlm: bool = False) -> None:
    n = len(res.t)
    idx = [rr.TimeColumn("time", duration=np.asarray(res.t, dtype=float)),
           rr.TimeColumn("step", sequence=np.arange(n))]
    rec.log("world", rr.ViewCoordinates.RIGHT_HAND_Z_UP, static=True)
    rec.log("world/trajectory", rr.LineStrips3D([res.body_pos], colors=[TRAJECTORY_COLOR],
                                                radii=rr.Radius.ui_points(1.0)), static=True)
    rec.log("world/ruler", _ruler(res.body_pos), static=True)
    rec.log("world/legend", rr.TextDocument(scene_legend(morph.weight, uvlm)), static=True)

    # the followed frame (translation only) and the body's attitude in it
    pos = np.asarray(res.body_pos, dtype=float)
    rec.send_columns(MOTH, idx, rr.Transform3D.columns(translation=pos))
    rec.send_columns(f"{MOTH}/body", idx, rr.Transform3D.columns(quaternion=_xyzw(res.body_quat)))
    centres = morph.segment_centres()
    rec.log(f"{MOTH}/body", rr.Ellipsoids3D(
        centers=[centres[s.name] for s in morph.segments], half_sizes=[s.semi_axes for s in morph.segments],
        colors=[BODY_COLOR], fill_mode="solid"), static=True)
    where, names = body_labels(morph)
    rec.log(f"{MOTH}/body/labels", rr.Points3D(where, labels=names, radii=rr.Radius.ui_points(0.0),
                                                 colors=[(230, 230, 230)], show_labels=True), static=True)
    scale = FORCE_SCALE_M_PER_WEIGHT / morph.weight
    rec.log(f"{MOTH}/weight", rr.Arrows3D(origins=[WEIGHT_ARROW_ORIGIN_M], vectors=[[0, 0, -FORCE_SCALE_M_PER_WEIGHT]],
                                          colors=[(235, 235, 235)], radii=[1.5e-4],
                                          labels=[f"W = {1e3 * morph.weight:.1f} mN"], show_labels=True), static=True)

    # wings and force arrows, relative to the centre of mass
    for i, side in enumerate(SIDES):
        R = res.wing_R[:, i]
        rec.send_columns(f"{MOTH}/wings/{side}", idx, rr.Transform3D.columns(
            translation=res.wing_origin[:, i] - pos, quaternion=_xyzw(quat_from_matrices(R))))
        rec.log(f"{MOTH}/wings/{side}/outline", rr.LineStrips3D(
            [wing_outline(morph, side)], colors=[SIDE_COLORS[side]], radii=rr.Radius.ui_points(1.5)), static=True)
        if not uvlm:  # with UVLM panels, they fill the wing (two surfaces in one place would flicker)
            verts, tris = wing_mesh(morph, side)
            rec.log(f"{MOTH}/wings/{side}/mesh", rr.Mesh3D(
                vertex_positions=verts, triangle_indices=tris,
                vertex_normals=np.tile([0.0, 0.0, 1.0], (len(verts), 1)),
                albedo_factor=(*SIDE_COLORS[side], 110)), static=True)
        span = R[:, :, 1] * (0.5 * morph.R * (1.0 if side == "left" else -1.0))
        rec.log(f"{MOTH}/forces/{side}", rr.Arrows3D.from_fields(colors=[SIDE_COLORS[side]], radii=[2e-4]),
                static=True)
        rec.send_columns(f"{MOTH}/forces/{side}", idx, rr.Arrows3D.columns(
            vectors=res.force[:, i] * scale, origins=res.wing_origin[:, i] + span - pos))

    # time series
    W, cbar = morph.weight, morph.cbar
    lift, drag = res.lift_drag()
    M = res.pitching_moment()
    att = np.rad2deg(res.attitude())
    values = {
        "forces/lift": lift, "forces/drag": drag, "forces_nd/L_plus": lift / W, "forces_nd/D_plus": drag / W,
        "moment/pitching": 1e3 * M, "moment_nd/M_plus": M / (W * cbar),
        "power/aero": 1e3 * res.power_aero, "power/joint": 1e3 * res.power_joint,
        "velocity/vx": res.body_v[:, 0], "velocity/vy": res.body_v[:, 1], "velocity/vz": res.body_v[:, 2],
        "attitude/pitch": att[:, 0], "attitude/roll": att[:, 1], "attitude/yaw": att[:, 2],
    }
    colors = series_colors()
    for name, label, _ in SERIES:
        rec.log(f"plots/{name}", rr.SeriesLines(names=label, colors=[colors[name]]), static=True)
        rec.send_columns(f"plots/{name}", idx, rr.Scalars.columns(scalars=np.asarray(values[name], dtype=float)))


def _log_control(rec: rr.RecordingStream, res: FlightResult, beats: list[dict], views) -> None:
    """Each beat's tracking errors at its end (in the units of :data:`CONTROL_TRACKING`, rounded to its resolution);
    its commands there too, or, for a controller updated per half-stroke (``commands_half_stroke`` in the beats),
    the phase-0 commands at mid-beat and the phase-0.5 ones at its end."""
    n = res.steps_per_cycle
    T = n * (res.t[1] - res.t[0])
    k = np.arange(len(beats)) + 1
    idx = [rr.TimeColumn("time", duration=k * T), rr.TimeColumn("step", sequence=k * n)]
    half = "commands_half_stroke" in beats[0]
    if half:  # two updates per beat
        kk = np.ravel(np.column_stack([k - 0.5, k]))
        idx_c = [rr.TimeColumn("time", duration=kk * T), rr.TimeColumn("step", sequence=np.rint(kk * n).astype(int))]
    for path, key, kind, name in views:
        vals = control_values(beats, key, kind, half=half and kind == "commands")
        rec.log(path, rr.SeriesPoints(names=name, colors=[PALETTE[0]], markers=["circle"], marker_sizes=[3.0]),
                static=True)
        rec.send_columns(path, idx_c if kind == "commands" and half else idx, rr.Scalars.columns(scalars=vals))


def _panel_arrays(vertices: np.ndarray, pressure: np.ndarray, limit: float
                  ) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """A panel lattice (nc+1, ns+1, 3) as flat-coloured quads (4 own vertices per panel): vertex positions
    (4 nc ns, 3), vertex colours (4 nc ns, 4) and triangle indices (2 nc ns, 3)."""
    quads = np.stack([vertices[:-1, :-1], vertices[:-1, 1:], vertices[1:, 1:], vertices[1:, :-1]], 2)  # nc,ns,4,3
    base = 4 * np.arange(pressure.size)[:, None]
    tris = np.concatenate([base + [0, 1, 2], base + [0, 2, 3]]).astype(np.uint32)
    return quads.reshape(-1, 3), np.repeat(diverging_colors(pressure.reshape(-1), limit), 4, axis=0), tris


def _panel_mesh(vertices: np.ndarray, pressure: np.ndarray, limit: float) -> rr.Mesh3D:
    """Mesh3D of a panel lattice (nc+1, ns+1, 3), one flat-coloured quad (4 own vertices) per panel."""
    verts, colors, tris = _panel_arrays(vertices, pressure, limit)
    return rr.Mesh3D(vertex_positions=verts, triangle_indices=tris, vertex_colors=colors,
                     face_rendering="DoubleSided")


def _log_panels(rec: rr.RecordingStream, res: FlightResult, kept: list, limit: float) -> None:
    """The pressure-coloured panels of every kept step, one column per wing (one call, not one per step: the
    lattice's topology is the same at every step; a flight whose lattice changed is logged step by step)."""
    pan = [(i, np.asarray(e["panels"], dtype=float), np.asarray(e["pressure"], dtype=float))
           for i, e in kept if "panels" in e and "pressure" in e]
    if not pan:
        return
    steps = np.array([i for i, _, _ in pan])
    idx = [rr.TimeColumn("step", sequence=steps), rr.TimeColumn("time", duration=np.asarray(res.t, float)[steps])]
    for w, side in enumerate(SIDES):
        path = f"world/uvlm/panels/{side}"
        arrays = [_panel_arrays(P[w], p[w], limit) for _, P, p in pan]
        if any(a[2].shape != arrays[0][2].shape for a in arrays):
            for (i, P, p) in pan:
                rec.set_time("step", sequence=i)
                rec.set_time("time", duration=float(res.t[i]))
                rec.log(path, _panel_mesh(P[w], p[w], limit))
            rec.reset_time()
            continue
        rec.log(path, rr.Mesh3D.from_fields(triangle_indices=arrays[0][2], face_rendering="DoubleSided"),
                static=True)
        rec.send_columns(path, idx, rr.Mesh3D.columns(
            vertex_positions=np.concatenate([a[0] for a in arrays]),
            vertex_colors=np.concatenate([a[1] for a in arrays])).partition([len(a[0]) for a in arrays]))


WAKE_DIM, WAKE_BRIGHT = np.array([70, 95, 150], dtype=float), np.array([255, 255, 255], dtype=float)
"""Wake filament colours: weak dim blue-grey, strong white (brighter = stronger)."""

WAKE_MIN_FRACTION = 0.5
"""Wake filaments weaker than this fraction of the scale's end are not drawn (the lattice's interior lines, whose
neighbouring rings nearly cancel), so that the vortex structures stand out."""


def wake_filaments(vertices: np.ndarray, gamma: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """The wake lattice's edges as two-point segments (m, 2, 3) [m] with their net circulation |Gamma| (m,)
    [m^2/s]: an edge shared by two rings carries the difference of their circulations, an edge on the lattice's
    border (tip, root, oldest row) the circulation of its one ring. vertices (rows+1, ns+1, 3), gamma (rows, ns).
    The newest row's upstream edges (at the trailing edge, where the Kutta condition makes the net nearly zero)
    are left out."""
    rows, ns = gamma.shape
    g = np.zeros((rows + 2, ns + 2))
    g[1:-1, 1:-1] = gamma
    span = np.abs(g[2:, 1:-1] - g[1:-1, 1:-1])  # (rows, ns): edges at rows 1 .. rows, between rings r-1 and r
    stream = np.abs(g[1:-1, 1:] - g[1:-1, :-1])  # (rows, ns + 1): edges at columns 0 .. ns
    seg_span = np.stack([vertices[1:, :-1], vertices[1:, 1:]], 2).reshape(-1, 2, 3)
    seg_stream = np.stack([vertices[:-1, :], vertices[1:, :]], 2).reshape(-1, 2, 3)
    return np.concatenate([seg_span, seg_stream]), np.concatenate([span.ravel(), stream.ravel()])


def wake_strips(vertices: np.ndarray, gamma: np.ndarray, limit: float,
                filaments: tuple[np.ndarray, np.ndarray] | None = None) -> rr.LineStrips3D:
    """LineStrips3D of the wake's filaments (:func:`wake_filaments`, or ``filaments`` when already computed) at least
    :data:`WAKE_MIN_FRACTION` of ``limit`` [m^2/s], coloured from dim (weak) to white (``limit`` and above). One
    (m, 2, 3) array, which Rerun converts in one piece (a list of strips of different lengths is converted strip by
    strip, ~100 times slower)."""
    seg, strength = filaments if filaments is not None else wake_filaments(vertices, gamma)
    keep = strength >= WAKE_MIN_FRACTION * limit
    f = np.clip(strength[keep] / (limit if limit > 0 else 1.0), 0.0, 1.0)[:, None]
    colors = np.round(WAKE_DIM * (1 - f) + WAKE_BRIGHT * f).astype(np.uint8)
    return rr.LineStrips3D(seg[keep], colors=colors, radii=rr.Radius.ui_points(0.75))


WAKE_FRAMES_PER_BEAT = 20
"""The wake is drawn at most this many times per wingbeat (at the first kept step and then at kept steps at least
steps_per_cycle / 20 steps after the last one drawn); the panels at every kept step. The wake moves little within
a twentieth of a beat, and drawing it is most of a UVLM recording's cost (it grows by a row per update)."""


def wake_steps(steps: list[int], steps_per_cycle: int) -> set[int]:
    """The kept steps at which the wake is drawn (:data:`WAKE_FRAMES_PER_BEAT`)."""
    gap, out, last = max(1, steps_per_cycle // WAKE_FRAMES_PER_BEAT), set(), None
    for i in sorted(steps):
        if last is None or i - last >= gap:
            out.add(i)
            last = i
    return out


def _uvlm_extras(res: FlightResult) -> list:
    """The (step, dict) extras that hold UVLM panels or wake, within the flight's rows."""
    return [(int(i), e) for i, e in res.extras
            if isinstance(e, dict) and ("panels" in e or "wake" in e) and 0 <= int(i) < len(res.t)]


def uvlm_scales(kept: list, filaments: dict | None = None) -> dict[str, tuple[float, float]]:
    """Colour-scale ends of the kept UVLM extras (:func:`robust_limit`): {"pressure": (limit, largest) [Pa],
    "gamma": (limit, largest) [m^2/s]}. filaments: {(step, wing): :func:`wake_filaments`'s pair} where already
    computed (the wake's scale is then taken over those steps)."""
    if filaments is None:
        filaments = {(i, w): wake_filaments(np.asarray(v, dtype=float), np.asarray(g, dtype=float))
                     for i, e in kept for w, (v, g) in enumerate(e.get("wake", [])) if np.size(g)}
    return {"pressure": robust_limit([e["pressure"] for _, e in kept if "pressure" in e]),
            "gamma": robust_limit([strength for _, strength in filaments.values()])}


def _log_extras(rec: rr.RecordingStream, res: FlightResult) -> None:
    """UVLM extras (step, dict): ``panels`` (2, nc+1, ns+1, 3) world [m] with ``pressure`` (2, nc, ns) [Pa]
    (pressure jump across the wing: the panel's force per area along the wing frame's +z, which is the dorsal side
    on both wings, so positive pushes the wing toward its dorsal side), and ``wake``: per wing (vertices
    (rows+1, ns+1, 3) [m], ring circulations gamma (rows, ns) [m^2/s]). Pressure: a symmetric scale, blue
    (negative) - light grey - red (positive); wake: filaments (:func:`wake_strips`) by strength, dim to white.
    The wake is drawn at most :data:`WAKE_FRAMES_PER_BEAT` times a beat. Both scales end at the 95th percentile of
    |value| over the steps drawn (:func:`uvlm_scales`); they are written to ``world/uvlm/legend`` with the largest
    values."""
    kept = _uvlm_extras(res)
    if not kept:
        return
    drawn = wake_steps([i for i, _ in kept], res.steps_per_cycle)
    filaments = {(i, w): wake_filaments(np.asarray(v, dtype=float), np.asarray(g, dtype=float))
                 for i, e in kept if i in drawn for w, (v, g) in enumerate(e.get("wake", [])) if np.size(g)}
    sc = uvlm_scales(kept, filaments)
    (p_lim, p_max), (g_lim, g_max) = sc["pressure"], sc["gamma"]
    pct = f"{ROBUST_PERCENTILE:g}th percentile"
    rec.log("world/uvlm/legend", rr.TextDocument(
        f"Panels: pressure jump, force per area toward the wing's dorsal side: blue -{p_lim:.3g} Pa .. grey 0 .. "
        f"red +{p_lim:.3g} Pa (the {pct} of |value|; beyond it clipped; largest {p_max:.3g} Pa).\n"
        f"Wake: vortex filaments by strength |Gamma|, dim {WAKE_MIN_FRACTION * g_lim:.2g} .. white "
        f"{g_lim:.3g} m^2/s ({pct}; largest {g_max:.3g}); weaker ones not drawn."), static=True)
    _log_panels(rec, res, kept, p_lim)
    for i, e in kept:
        if i not in drawn:
            continue
        rec.set_time("step", sequence=i)
        rec.set_time("time", duration=float(res.t[i]))
        for w in range(len(e.get("wake", []))):
            if (i, w) in filaments:
                rec.log(f"world/uvlm/wake/{SIDES[w]}", wake_strips(None, None, g_lim, filaments[(i, w)]))
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
    rec.log("world/ghost_trajectory", rr.LineStrips3D([pos], colors=[(*GHOST_COLOR, 160)]), static=True)
    centres = morph.segment_centres()
    rec.log("world/ghost/body", rr.Ellipsoids3D(
        centers=[centres[s.name] for s in morph.segments], half_sizes=[s.semi_axes for s in morph.segments],
        colors=[(*GHOST_COLOR, 90)], fill_mode="solid"), static=True)
    Rb = ref.body_R[:n]
    for i, side in enumerate(SIDES):  # the prescribed wing motion relative to the body (the same in both flights)
        R_rel = np.einsum("nji,njk->nik", Rb, ref.wing_R[:n, i])
        o_rel = np.einsum("nji,nj->ni", Rb, ref.wing_origin[:n, i] - ref.body_pos[:n])
        rec.send_columns(f"world/ghost/wings/{side}", idx, rr.Transform3D.columns(
            translation=o_rel, quaternion=_xyzw(quat_from_matrices(R_rel))))
        verts, tris = wing_mesh(morph, side)
        rec.log(f"world/ghost/wings/{side}/mesh", rr.Mesh3D(
            vertex_positions=verts, triangle_indices=tris, vertex_normals=np.tile([0.0, 0.0, 1.0], (len(verts), 1)),
            albedo_factor=(*GHOST_COLOR, 90)), static=True)
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
        for kind, label, color in BEAT_KINDS:
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
