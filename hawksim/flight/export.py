"""A flight saved whole, readable without hawksim: one numpy ``.npz`` file (``hawksim fly --out FILE``).

The file holds plain arrays only (``np.load(path, allow_pickle=False)`` reads it; no hawksim import, no pickle):

- per-step arrays, one row per integration step (state at the step's start, loads held over the step), SI:
  the fields of :class:`hawksim.flight.result.FlightResult` under their own names (``t``, ``body_pos``, ``body_quat``,
  ``body_v``, ``body_omega``, ``wing_R``, ``wing_origin``, ``force``, ``moment``, ``wing_moment``, ``power_aero``,
  ``power_joint``) and two derived ones: ``attitude`` (n, 3) pitch, roll, yaw [rad] (:meth:`FlightResult.attitude`)
  and ``wing_angles`` (n, 2, 3) the sweep, elevation and rotation angles phi, theta, alpha [rad] of the left and
  right wing (paper Eq. 1's angles, read back from the wing frames);
- the per-beat table, one row per wingbeat, each column an array named ``beat_<key>`` (nested keys joined by ``_``:
  ``beat_commands_f_hz``); vectors become (beats, k) arrays;
- ``metadata``: a 0-d unicode array holding one JSON object: ``format`` (:data:`FORMAT`), ``hawksim_version``,
  ``command`` (the argument list), ``seed`` (None: a flight is deterministic), ``units`` (array name -> unit),
  ``descriptions`` (array name -> shape, frame and meaning), ``frames``, the run's ``summary`` (the compact JSON of
  ``hawksim fly --json``), and what :meth:`FlightResult.load` needs to rebuild the result exactly (``kinematics_si``,
  ``aero_every``, ``flight_wall_time_s``; under a controller ``speed_references_m_s`` and ``beat_log``, the
  loop's per-beat rows, :attr:`FlightResult.beat_log`). Read it with ``json.loads(str(z["metadata"]))``.

:func:`read_flight` reads a file back (arrays and metadata, the format checked); :meth:`FlightResult.save` and
:meth:`FlightResult.load` write and read a result through this module. The layout is documented for users in
docs/output.md.
"""

from __future__ import annotations

import datetime
import io
import json
import zipfile
from dataclasses import asdict
from pathlib import Path

import numpy as np

from hawksim.flight.result import FlightResult
from hawksim.frames import quat_to_matrix
from hawksim.insect.kinematics import R_BODY_STROKE

FORMAT = "hawksim-flight-npz/1"
"""The layout's name and version (a reader checks it; a change of layout changes the number)."""

STEP_ARRAYS = {
    "t": ("s", "(n,) time at the step's start"),
    "body_pos": ("m", "(n, 3) body centre of mass, world frame (z up)"),
    "body_quat": ("1", "(n, 4) body orientation, body -> world, (w, x, y, z)"),
    "body_v": ("m/s", "(n, 3) velocity of the body centre of mass, world frame"),
    "body_omega": ("rad/s", "(n, 3) body angular velocity, world frame"),
    "wing_R": ("1", "(n, 2, 3, 3) wing frames (left, right), wing -> world"),
    "wing_origin": ("m", "(n, 2, 3) wing hinge positions (left, right), world frame"),
    "force": ("N", "(n, 2, 3) aerodynamic force on each wing (left, right), world frame"),
    "moment": ("N m", "(n, 3) total aerodynamic moment about the body centre of mass, world frame"),
    "wing_moment": ("N m", "(n, 2, 3) aerodynamic moment of each wing (left, right) about the body centre of mass, "
                           "world frame (their sum is moment)"),
    "power_aero": ("W", "(n,) aerodynamic power of the wings"),
    "power_joint": ("W", "(n,) aerodynamic + inertial power of the wings relative to the body"),
    "attitude": ("rad", "(n, 3) body pitch (nose up), roll (right wing down), yaw, not wrapped"),
    "wing_angles": ("rad", "(n, 2, 3) sweep phi, elevation theta, rotation alpha of the left and right wing "
                           "(paper Eq. 1; alpha = 90 deg at stroke reversal)"),
}
"""Per-step arrays: name -> (unit, shape and meaning). n = steps flown."""

FRAMES = {
    "world": "MuJoCo's: z up, gravity -z; the flight heads +x",
    "body": "origin at the centre of mass, x toward the head, y left, z dorsal",
    "stroke plane": "fixed to the body at 120 deg from its axis (body angle chi = 60 deg - beta)",
}

BEAT_UNITS = {"beat": "1", "mean_vertical_speed": "m/s", "horizontal_speed": "m/s", "speed_command": "m/s",
              "speed_reference": "m/s", "speed_error": "m/s", "air_velocity": "m/s", "P_plus": "1", "saturated": "1",
              "state": "SI (u, v, w [m/s]; p, q, r [rad/s]; phi, theta, psi [rad])", "commands_f_hz": "Hz",
              "commands_half_stroke_f_hz": "Hz"}
"""Units of per-beat keys whose names carry no unit suffix."""

SUFFIX_UNITS = (("_deg_s", "deg/s"), ("_deg", "deg"), ("_hz", "Hz"), ("_m_s", "m/s"), ("_m", "m"), ("_s", "s"),
                ("_W", "W"), ("_N", "N"))


def _unit(key: str) -> str:
    if key in BEAT_UNITS:
        return BEAT_UNITS[key]
    for suffix, unit in SUFFIX_UNITS:
        if key.endswith(suffix):
            return unit
    return ""


def wing_angles(result: FlightResult) -> np.ndarray:
    """(n, 2, 3) phi, theta, alpha [rad] of the left and right wing from the wing frames and the body frame (the
    inverse of :func:`hawksim.insect.kinematics.wing_rotation_stroke`: left Rz(-phi) Rx(theta) Ry(-alpha), right
    Rz(phi) Rx(-theta) Ry(-alpha), in the stroke-plane frame)."""
    Rb = quat_to_matrix(result.body_quat)  # (n, 3, 3) body -> world
    M = np.einsum("ij,nkj,nwkl->nwil", R_BODY_STROKE.T, Rb, result.wing_R)  # wing -> stroke plane
    a = np.arctan2(-M[..., 0, 1], M[..., 1, 1])  # M = Rz(a) Rx(b) Ry(c)
    b = np.arcsin(np.clip(M[..., 2, 1], -1.0, 1.0))
    c = np.arctan2(-M[..., 2, 0], M[..., 2, 2])
    out = np.empty(M.shape[:2] + (3,))
    out[:, 0] = np.stack([-a[:, 0], b[:, 0], -c[:, 0]], axis=-1)
    out[:, 1] = np.stack([a[:, 1], -b[:, 1], -c[:, 1]], axis=-1)
    return out


def step_arrays(result: FlightResult) -> dict[str, np.ndarray]:
    """The per-step arrays of :data:`STEP_ARRAYS` (float64)."""
    out = {k: np.asarray(getattr(result, k), dtype=float) for k in STEP_ARRAYS
           if k not in ("attitude", "wing_angles") and getattr(result, k) is not None}
    out["attitude"] = result.attitude()
    out["wing_angles"] = wing_angles(result)
    return out


def _flatten(d: dict, prefix: str = "") -> dict:
    out = {}
    for k, v in d.items():
        if isinstance(v, dict):
            out.update(_flatten(v, f"{prefix}{k}_"))
        else:
            out[f"{prefix}{k}"] = v
    return out


def beat_arrays(beats: list[dict]) -> dict[str, np.ndarray]:
    """The per-beat table as columns ``beat_<key>`` (nested dicts flattened with ``_``; a key missing from some beats,
    or None, is NaN there; booleans stay booleans). Empty for no beats."""
    rows = [_flatten(b) for b in beats]
    keys = list(dict.fromkeys(k for r in rows for k in r))
    out = {}
    for k in keys:
        vals = [r.get(k) for r in rows]
        if all(isinstance(v, bool) for v in vals):
            out[f"beat_{k}"] = np.array(vals, dtype=bool)
            continue
        if any(isinstance(v, str) for v in vals):
            continue
        shape = next((np.shape(v) for v in vals if v is not None), ())
        out[f"beat_{k}"] = np.array([np.full(shape, np.nan) if v is None else np.asarray(v, dtype=float)
                                     for v in vals], dtype=float)
    return out


def _finite(obj):
    """``obj`` with every non-finite float replaced by None (strict JSON)."""
    if isinstance(obj, float):
        return obj if np.isfinite(obj) else None
    if isinstance(obj, dict):
        return {k: _finite(v) for k, v in obj.items()}
    if isinstance(obj, (list, tuple)):
        return [_finite(v) for v in obj]
    return obj


def flight_file_bytes(result: FlightResult, beats: list[dict], *, command: list[str] | None = None,
                      summary: dict | None = None, seed: int | None = None) -> bytes:
    """The ``.npz`` file's bytes (module docstring): ``result``'s per-step arrays, the per-beat table ``beats`` (one
    dict per wingbeat: scalars, lists, nested dicts; the CLI's merged table), and the metadata."""
    from hawksim import __version__

    arrays = step_arrays(result)
    table = beat_arrays(beats)
    units = {k: u for k, (u, _) in STEP_ARRAYS.items()}
    descriptions = {k: d for k, (_, d) in STEP_ARRAYS.items()}
    for k, v in table.items():
        units[k] = _unit(k[len("beat_"):])
        descriptions[k] = f"({len(beats)}{''.join(f', {s}' for s in v.shape[1:])}) per wingbeat"
    meta = {"format": FORMAT, "hawksim_version": __version__, "command": command, "seed": seed,
            "seed_note": "a flight has no random process: the same command gives the same numbers",
            "created_utc": datetime.datetime.now(datetime.timezone.utc).isoformat(timespec="seconds"),
            "aero": result.aero, "speed_target_m_s": result.speed_target, "cycles": result.cycles,
            "steps_per_cycle": result.steps_per_cycle, "steps": int(len(result.t)),
            "kinematics": result.kinematics.to_edge(),
            "kinematics_si": {k: float(v) for k, v in asdict(result.kinematics).items()},
            "kinematics_units": "f [Hz], the angles [deg] (the flight's start; a controlled flight's per-beat "
                                "commands are in the beat_commands_* columns)",
            "trim_source": result.trim_source, "aero_every": int(result.aero_every),
            "flight_wall_time_s": float(result.wall_time_s), "end_t_s": result.end_t,
            "end_pos_m": None if result.end_pos is None else [float(x) for x in result.end_pos],
            "speed_references_m_s": (None if result.speed_references is None
                                     else [float(v) for v in result.speed_references]),
            "beat_log": result.beat_log,
            **({"forward_speed_target_m_s": result.forward_speed_target} if result.forward_speed_target else {}),
            **({"reference_axis": result.reference_axis, "pitch_references_deg": [float(v) for v in
                                                                                 result.pitch_references]}
               if result.pitch_references is not None else {}),
            "insect": result.insect.to_dict(),
            "insect_units": "SI (kg, m); P0_W [W]; bounds_deg: f [Hz], the angles [deg] "
                            "(hawksim.insect.insect.Insect.to_dict)",
            "frames": FRAMES, "units": units, "descriptions": descriptions, "summary": summary}
    buf = io.BytesIO()
    np.savez(buf, metadata=np.array(json.dumps(_finite(meta), allow_nan=False)), **arrays, **table)
    return buf.getvalue()


def save_flight(path: str | Path, result: FlightResult, beats: list[dict], **kw) -> Path:
    """Write :func:`flight_file_bytes` to ``path`` all or nothing (:func:`hawksim.atomic.write_bytes`: OSError naming
    the path when it cannot be written, NotRegularFileError when it is a device or directory). Returns ``path``."""
    from hawksim.atomic import write_bytes

    return write_bytes(path, flight_file_bytes(result, beats, **kw), what="flight data")


def read_flight(path: str | Path) -> tuple[dict[str, np.ndarray], dict]:
    """The arrays (name -> array, ``metadata`` left out) and the metadata (a dict) of a file of this layout, read
    with ``np.load(path, allow_pickle=False)`` (nothing is unpickled). ValueError (one line, naming the path) for a
    file that is not one: not an ``.npz`` archive, no ``metadata``, or a ``format`` other than :data:`FORMAT`;
    OSError (FileNotFoundError, ...) when it cannot be read."""
    path = Path(path)
    what = f"{str(path)!r} is not a hawksim flight file ({FORMAT})"
    try:
        z = np.load(path, allow_pickle=False)
    except (ValueError, zipfile.BadZipFile, EOFError) as exc:  # a pickle, or bytes numpy cannot read
        raise ValueError(f"{what}: numpy cannot read it without unpickling ({type(exc).__name__})") from None
    if not isinstance(z, np.lib.npyio.NpzFile):
        raise ValueError(f"{what}: a single .npy array, not an .npz archive")
    with z:
        if "metadata" not in z.files:
            raise ValueError(f"{what}: no metadata array")
        try:
            meta = json.loads(str(z["metadata"]))
        except (ValueError, zipfile.BadZipFile) as exc:
            raise ValueError(f"{what}: its metadata is not JSON ({type(exc).__name__})") from None
        fmt = meta.get("format") if isinstance(meta, dict) else None
        if fmt != FORMAT:
            raise ValueError(f"{what}: its format is {fmt!r}")
        try:
            arrays = {k: z[k] for k in z.files if k != "metadata"}
        except (ValueError, zipfile.BadZipFile) as exc:  # an object array (pickled) or a damaged member
            raise ValueError(f"{what}: an array numpy cannot read without unpickling ({type(exc).__name__})") from None
    return arrays, meta
