"""What a flight's Rerun recording shows and how it is laid out: the series (entity, name with unit, colour), the
views that hold them, the default blueprint, the colour scales and the legend texts.

:mod:`hawksim.flight.recording` logs the data; this module decides where it goes and what it looks like, so that
the layout can be checked without writing a recording (``tests/hawksim/test_recording.py`` reads it back).

The 3D view's origin is ``world/moth``, an entity whose transform is the body's centre-of-mass position only
(no rotation): the view follows the moth, with its axes parallel to the world's (z up), and its eye
(:data:`EYE_POSITION_M`) is fixed in that frame, so the whole insect stays in frame while it climbs, wings flapping.
"""

from __future__ import annotations

import numpy as np
import rerun.blueprint as rrb

FORCE_SCALE_M_PER_WEIGHT = 0.02
"""Force arrows: an arrow of length 2 cm is a force equal to the body weight W = m g (a scale arrow of that length
hangs below the centre of mass, labelled)."""

MOTH = "world/moth"
"""Entity whose transform is the body's centre-of-mass position (translation only): the 3D view's origin."""

EYE_POSITION_M = (0.07, -0.11, 0.045)
"""Eye of the 3D view [m] in the ``world/moth`` frame (axes parallel to the world's, origin at the centre of mass):
in front of the moth's right side and a little above, 14 cm away, looking at the centre of mass. The span tip to tip
is about 10 cm, so the flapping wings fill most of the view's height."""

WEIGHT_ARROW_ORIGIN_M = (0.045, 0.0, 0.03)
"""Where the scale arrow (the body weight W, pointing down) starts [m] in the ``world/moth`` frame: ahead of and
above the centre of mass, clear of the body, of its labels and of the path below it."""

GHOST_OFFSET_M = (0.0, 0.15, 0.0)
"""World offset [m] of the ghost body (the linear prediction) from the nonlinear one: 15 cm to the left (+y;
the wingspan is ~10 cm), fixed, so that both are visible side by side. With a ghost, the 3D view looks at the point
midway between them from twice as far."""

PALETTE = ((77, 163, 255), (255, 140, 40), (90, 205, 100), (240, 85, 85), (190, 130, 255), (235, 205, 60))
"""Series colours (RGB) on the viewer's dark background, assigned in this order within each view: blue, orange,
green, red, purple, yellow."""

SIDE_COLORS = {"left": (240, 185, 40), "right": (60, 200, 150)}
"""Left wing and its force arrow gold, right wing and its arrow teal: outside the blue-white-red pressure scale."""

BODY_COLOR = (150, 115, 85)
GHOST_COLOR = (120, 200, 255)
TRAJECTORY_COLOR = (170, 170, 170)

DIVERGING = np.array([[59, 76, 192], [221, 221, 221], [180, 4, 38]], dtype=float)
"""Pressure and circulation scale: blue (-limit) - light grey (0) - red (+limit)."""

ROBUST_PERCENTILE = 95.0
"""UVLM colour scales end at this percentile of |value| over the recording (larger values are clipped to the end
colours): the pressure jump peaks on the leading-edge panels (the largest several times the 95th percentile),
which would otherwise set the scale and leave every other panel pale. The legend states the limit and the largest
value."""

SERIES = (
    ("forces/lift", "lift [N]", "plots/forces"), ("forces/drag", "drag [N]", "plots/forces"),
    ("forces_nd/L_plus", "L+ = L/W [-]", "plots/forces_nd"), ("forces_nd/D_plus", "D+ = D/W [-]", "plots/forces_nd"),
    ("moment/pitching", "pitching moment [mN m]", "plots/moment"),
    ("moment_nd/M_plus", "M+ = M/(W cbar) [-]", "plots/moment_nd"),
    ("power/aero", "aerodynamic power [mW]", "plots/power"), ("power/joint", "joint power [mW]", "plots/power"),
    ("velocity/vx", "vx [m/s]", "plots/velocity"), ("velocity/vy", "vy [m/s]", "plots/velocity"),
    ("velocity/vz", "vz [m/s]", "plots/velocity"),
    ("attitude/pitch", "pitch [deg]", "plots/attitude"), ("attitude/roll", "roll [deg]", "plots/attitude"),
    ("attitude/yaw", "yaw [deg]", "plots/attitude"),
)
"""Per-step series under ``plots/``: (entity, series name with its unit, view origin). Moments in mN m and powers in
mW (the values are ~1e-3 N m and ~0.1 W)."""

VIEWS = (
    ("plots/forces", "Lift (world z), drag [N]"), ("plots/forces_nd", "L+, D+ (/ weight) [-]"),
    ("plots/moment", "Pitching moment, nose up [mN m]"), ("plots/moment_nd", "M+ [-]"),
    ("plots/power", "Power [mW]"), ("plots/velocity", "Velocity, world (z up) [m/s]"),
    ("plots/attitude", "Pitch, roll, yaw (as the JSON) [deg]"),
)
"""Time-series views of the per-step series: (origin, name with the unit)."""

BEAT_STATES = (
    ("u", "m/s", 1.0), ("w", "m/s", 1.0), ("q", "deg/s", 180 / np.pi), ("theta", "deg", 180 / np.pi),
    ("v", "m/s", 1.0), ("p", "deg/s", 180 / np.pi), ("r", "deg/s", 180 / np.pi), ("phi", "deg", 180 / np.pi),
)
"""Per-beat deviation plots: (state, edge unit, factor from SI). States of the orbit's chart
(:mod:`hawksim.flight.orbit`): u, v, w in the level heading axes (forward, right, down), p, q, r the body rates in
them, theta the pitch (nose up), phi the bank (right wing down)."""

BEAT_KINDS = (("nonlinear", "nonlinear flight", (235, 235, 235)), ("floquet", "Floquet M^k x0", PALETTE[0]),
              ("averaged", "averaged expm(A k) x0", PALETTE[3]))
"""Per-beat series: (kind, series name, colour): the nonlinear flight white points, the two predictions lines."""

CONTROL_TRACKING = {"speed_error": ("mm/s", 1e3, 1e-3), "pitch_error_deg": ("deg", 1.0, 1e-4),
                    "roll_deg": ("deg", 1.0, 1e-4), "yaw_deg": ("deg", 1.0, 1e-4),
                    "horizontal_drift_m": ("mm", 1e3, 1e-3)}
"""Tracking errors of a controlled flight's beats that the recording plots: key -> (plotted unit, factor from the
beat's value, resolution in the plotted unit). Values are rounded to the resolution (1 um/s, 1e-4 deg, 1 um), so
that a flight that holds exactly plots 0 rather than round-off (tick labels like 0.000 000 000 000 3)."""

COMMAND_RESOLUTION = 1e-6
"""Commands of a controlled flight are rounded to this many of their unit (Hz, deg) before plotting."""

_SUFFIX_UNITS = (("_hz", "Hz"), ("_deg", "deg"), ("_m", "m"))


def series_colors(series=SERIES) -> dict[str, tuple[int, int, int]]:
    """Entity (under ``plots/``) -> colour: :data:`PALETTE` in order within each view, so distinct within a view."""
    count: dict[str, int] = {}
    out = {}
    for name, _, view in series:
        k = count.get(view, 0)
        out[name] = PALETTE[k % len(PALETTE)]
        count[view] = k + 1
    return out


def diverging_colors(value: np.ndarray, limit: float) -> np.ndarray:
    """RGB uint8 (..., 3) of ``value`` on a blue (-limit) - light grey (0) - red (+limit) scale, clipped."""
    s = np.clip(np.asarray(value, dtype=float) / (limit if limit > 0 else 1.0), -1.0, 1.0) + 1.0  # in [0, 2]
    i = np.minimum(s.astype(int), 1)
    f = (s - i)[..., None]
    return np.round(DIVERGING[i] * (1 - f) + DIVERGING[i + 1] * f).astype(np.uint8)


def robust_limit(values, percentile: float = ROBUST_PERCENTILE) -> tuple[float, float]:
    """(limit, largest) of |values| (any shapes, iterable of arrays): the ``percentile`` of |value| (the colour
    scale's end) and the largest |value|; (0, 0) for no values."""
    a = np.concatenate([np.abs(np.asarray(v, dtype=float)).ravel() for v in values] or [np.zeros(0)])
    if a.size == 0:
        return 0.0, 0.0
    return float(np.percentile(a, percentile)), float(a.max())


def control_views(beats: list[dict]) -> list[tuple[str, str, str, str]]:
    """(entity path, key, kind, view name with unit) of every command and tracking error in ``beats``; a command's
    unit comes from its key's suffix (``f_hz``, ``phi0_deg``), a tracking error's from :data:`CONTROL_TRACKING`."""
    out = []
    for key in beats[0].get("commands", {}):
        unit = next((u for s, u in _SUFFIX_UNITS if key.endswith(s)), "-")
        out.append((f"plots/control/commands/{key}", key, "commands", f"command {key} [{unit}]"))
    for key, (unit, _, _) in CONTROL_TRACKING.items():
        if key in beats[0]:
            label = key.removesuffix("_deg").removesuffix("_m").replace("_", " ")
            out.append((f"plots/control/tracking/{key}", key, "tracking", f"{label} [{unit}]"))
    return out


def control_values(beats: list[dict], key: str, kind: str, half: bool = False) -> np.ndarray:
    """The plotted values of a control series (:func:`control_views`): tracking errors in their plotted unit rounded
    to its resolution (:data:`CONTROL_TRACKING`), commands rounded to :data:`COMMAND_RESOLUTION`; with ``half``
    (a controller updated per half-stroke) each beat's two commands in turn."""
    if kind == "commands":
        vals = (np.ravel([[b["commands"][key], b["commands_half_stroke"][key]] for b in beats]) if half
                else np.array([b["commands"][key] for b in beats], dtype=float))
        return np.round(np.asarray(vals, dtype=float) / COMMAND_RESOLUTION) * COMMAND_RESOLUTION
    _, factor, res = CONTROL_TRACKING[key]
    vals = np.array([b[key] for b in beats], dtype=float) * factor
    return np.round(vals / res) * res + 0.0  # + 0.0: no -0


def scene_legend(morph_weight: float, uvlm: bool) -> str:
    """The 3D view's legend (``world/legend``): what each thing is, its colour, the force scale."""
    mn = 1e3 * morph_weight
    return (
        "View follows the moth (centre of mass at its origin, world axes, z up). Grey: centre-of-mass path and a "
        "height ruler (1 cm ticks), fixed in the world.\n"
        f"Wings and force arrows: left gold, right teal. Arrow scale: {100 * FORCE_SCALE_M_PER_WEIGHT:g} cm = "
        f"body weight W = {mn:.1f} mN (white arrow)."
        + ("\nWing panels: pressure; wake: vortex filaments (see UVLM colour scales)." if uvlm else ""))


def default_blueprint(*, uvlm: bool = False, prediction: bool = False, control=()) -> rrb.Blueprint:
    """The 3D view (origin ``world/moth``, eye :data:`EYE_POSITION_M`) with its legend, beside tabs: the per-step
    time series (:data:`VIEWS`, colours :func:`series_colors`), with ``control`` the controlled flight's commands and
    tracking errors, with ``prediction`` the per-beat state deviations (one view per :data:`BEAT_STATES` entry) and
    the ghost's legend, with ``uvlm`` the colour scales of the panels and wake."""
    legend = rrb.PlotLegend(corner=rrb.components.Corner2D.LeftTop)
    tabs = [rrb.Grid(*[rrb.TimeSeriesView(origin=o, name=n, plot_legend=legend) for o, n in VIEWS],
                     name="Per step")]
    if control:
        tabs.append(rrb.Grid(*[rrb.TimeSeriesView(origin=path, name=name, plot_legend=legend)
                               for path, _, _, name in control],
                             name="Control: commands (per update) and tracking (per beat)"))
    if prediction:
        tabs.append(rrb.Grid(*[rrb.TimeSeriesView(origin=f"plots/beats/{k}", name=f"Δ{k} per beat [{u}]",
                                                  plot_legend=legend)
                               for k, u, _ in BEAT_STATES], name="Per beat: nonlinear vs linear"))
    texts = [rrb.TextDocumentView(origin="world/legend", name="Legend: 3D view")]
    texts += [rrb.TextDocumentView(origin="world/ghost_legend", name="Ghost")] if prediction else []
    texts += [rrb.TextDocumentView(origin="world/uvlm/legend", name="UVLM colour scales")] if uvlm else []
    side = rrb.Tabs(*tabs) if len(tabs) > 1 else tabs[0]
    look = 0.5 * np.asarray(GHOST_OFFSET_M) if prediction else np.zeros(3)
    eye = look + (2.0 if prediction else 1.0) * np.asarray(EYE_POSITION_M)
    view3d = rrb.Spatial3DView(
        origin=MOTH, name="Hawkmoth (view follows the body)",
        contents=["+ /world/**", "- /world/legend", "- /world/uvlm/legend", "- /world/ghost_legend"],
        eye_controls=rrb.EyeControls3D(kind=rrb.components.Eye3DKind.Orbital, position=eye,
                                       look_target=look, eye_up=(0.0, 0.0, 1.0)),
        line_grid=rrb.LineGrid3D(visible=False))
    left = rrb.Vertical(view3d, rrb.Horizontal(*texts), row_shares=[3, 1])
    return rrb.Blueprint(rrb.Horizontal(left, side, column_shares=[3, 2]), collapse_panels=True)
