"""The insect a flight is of: its morphology, its reference power P0 and its kinematic bounds, as one value.

:class:`Insect` is what travels with a flight (the backends' geometry, the MuJoCo model generated from it, and the
scales of the nondimensional outputs: L+ = L/W and D+ = D/W with W = m g, M+ = M/(W cbar), P+ = P/P0). It is a type
apart from :class:`hawksim.insect.morphology.Morphology` because P0 and the bounds are not mass properties or
geometry: P0 is a measured flight power (the hawkmoth's hover, Nguyen et al. 2020 Sec. 3.1) and the bounds are the
kinematic envelope of the searches (Table 2); the MJCF and the aerodynamic models depend on the morphology alone.

:data:`DEFAULT_INSECT` (:func:`hawksim.insect.folder.default_insect`) is the default insect, loaded from its folder
(``hawksim/insects/hawkmoth``: ``Morphology()``, P0 = 84.2 mW, Table 2's bounds; equal to ``Insect()``): every default
argument that takes an insect is this one, so the hawkmoth's numbers are unchanged where none is given.

:meth:`Insect.from_dict` reads a spec (the JSON of ``--insect FILE``, or the ``insect`` entry of a saved flight):
Morphology's fields by name (any left out keep the default hawkmoth's), ``P0_W`` and ``bounds_deg``; an unknown or
invalid field is a ValueError naming it.
"""

from __future__ import annotations

import dataclasses
import math
from dataclasses import dataclass, field
from pathlib import Path
from types import MappingProxyType

import numpy as np

from hawksim.insect.kinematics import PARAM_NAMES, TABLE2_BOUNDS_DEG, _to_si
from hawksim.insect.morphology import HAWKMOTH, P0_W, Ellipsoid, Morphology, WingMassModel


def _table2() -> MappingProxyType:
    return MappingProxyType({k: tuple(map(float, v)) for k, v in TABLE2_BOUNDS_DEG.items()})


@dataclass(frozen=True)
class Insect:
    """An insect as hawksim flies it.

    Attributes:
        morphology: mass properties and geometry (:class:`hawksim.insect.morphology.Morphology`, SI).
        P0: reference power [W], the unit of P+ (default :data:`hawksim.insect.morphology.P0_W`, the hawkmoth's).
        bounds_deg: kinematic bounds {parameter: (lower, upper)}, f in Hz and angles in degrees, in
            :data:`hawksim.insect.kinematics.PARAM_NAMES` (default Table 2 of Nguyen et al. 2020).
        label: the insect's name (its folder's, :func:`hawksim.insect.folder.load_insect`); None: the morphology's.
        folder: the insect's folder (its MJCF, tables and networks: :mod:`hawksim.insect.tables`); None for an
            insect made in Python or read from a lone spec file.
        model_file: file name of its generated MJCF in ``folder``.
        reference_deg: its reference kinematics {"speed": speeds [m/s], parameter: values (Hz, deg)}, or None.
        sources: {spec field: (source class, citation)} of the numbers its spec annotated.

    Two insects are equal when their morphology, P0 and bounds are (the other attributes say where it came from).
    """

    morphology: Morphology = HAWKMOTH
    P0: float = P0_W
    bounds_deg: MappingProxyType = field(default_factory=_table2)
    label: str | None = field(default=None, compare=False)
    folder: Path | None = field(default=None, compare=False)
    model_file: str | None = field(default=None, compare=False)
    reference_deg: MappingProxyType | None = field(default=None, compare=False, repr=False)
    sources: MappingProxyType = field(default_factory=lambda: MappingProxyType({}), compare=False, repr=False)

    def __post_init__(self):
        if not isinstance(self.morphology, Morphology):
            raise ValueError(f"morphology must be a Morphology, got {type(self.morphology).__name__}")
        if not (isinstance(self.P0, (int, float)) and math.isfinite(self.P0) and self.P0 > 0):
            raise ValueError(f"P0 must be a positive reference power [W], got {self.P0!r}")
        b = dict(self.bounds_deg)
        if set(b) != set(PARAM_NAMES):
            extra = sorted(set(b) - set(PARAM_NAMES)) or sorted(set(PARAM_NAMES) - set(b))
            raise ValueError(f"bounds_deg must name each of {', '.join(PARAM_NAMES)}; {extra[0]!r} is "
                             f"{'unknown' if extra[0] in b else 'missing'}")
        for k in PARAM_NAMES:
            lo, hi = b[k]
            if not (math.isfinite(lo) and math.isfinite(hi) and lo < hi):
                raise ValueError(f"bounds_deg[{k!r}] must be finite with lower < upper, got {b[k]!r}")
        object.__setattr__(self, "bounds_deg", MappingProxyType({k: (float(b[k][0]), float(b[k][1]))
                                                                 for k in PARAM_NAMES}))

    @property
    def name(self) -> str:
        """Its label, else the morphology's."""
        return self.label or self.morphology.name

    @property
    def weight(self) -> float:
        """W = m g [N], the force unit of L+ and D+."""
        return self.morphology.weight

    @property
    def cbar(self) -> float:
        """Mean chord [m]; W cbar is the moment unit of M+."""
        return self.morphology.cbar

    def bounds_si(self) -> tuple[np.ndarray, np.ndarray]:
        """The bounds as two (7,) SI arrays (lower, upper) in PARAM_NAMES order (Hz, rad)."""
        lo = np.array([_to_si(k, self.bounds_deg[k][0]) for k in PARAM_NAMES])
        hi = np.array([_to_si(k, self.bounds_deg[k][1]) for k in PARAM_NAMES])
        return lo, hi

    def reference_kinematics(self, speed: float):
        """Its reference kinematics (:attr:`reference_deg`) at ascent ``speed`` [m/s], interpolated linearly in the
        speed (held at the end values outside them): a :class:`hawksim.insect.kinematics.Kinematics` (SI); None if
        the insect has none."""
        from hawksim.insect.kinematics import Kinematics

        if self.reference_deg is None:
            return None
        v = self.reference_deg["speed"]
        return Kinematics.from_edge({k: float(np.interp(speed, v, self.reference_deg[k])) for k in PARAM_NAMES},
                                    check_bounds=False)

    def with_morphology(self, morph: Morphology) -> Insect:
        """This insect with another morphology (same P0 and bounds; no folder: its tables and MJCF are another
        morphology's)."""
        return dataclasses.replace(self, morphology=morph, label=None, folder=None, model_file=None)

    def to_dict(self) -> dict:
        """JSON-ready: Morphology's fields by name (segments as lists of {name, mass, centre, semi_axes}, the wing
        mass model as {name, span_decay, chord_decay}), ``P0_W`` and ``bounds_deg``; :meth:`from_dict` reads it
        back to an equal insect."""
        m = self.morphology
        out: dict = {}
        for f in dataclasses.fields(Morphology):
            v = getattr(m, f.name)
            if f.name == "segments":
                v = [{"name": s.name, "mass": s.mass, "centre": list(s.centre), "semi_axes": list(s.semi_axes)}
                     for s in v]
            elif f.name == "wing_mass_model":
                v = dataclasses.asdict(v)
            elif isinstance(v, tuple):
                v = list(v)
            out[f.name] = v
        return out | {"P0_W": self.P0, "bounds_deg": {k: list(v) for k, v in self.bounds_deg.items()}}

    @staticmethod
    def from_dict(spec: dict, base: Insect | None = None) -> Insect:
        """The insect of a spec (:meth:`to_dict`'s keys; any left out keep ``base``'s, default
        :func:`hawksim.insect.folder.default_insect`). ValueError naming the field for an unknown field or an invalid
        value."""
        if base is None:
            from hawksim.insect.folder import default_insect

            base = default_insect()
        if not isinstance(spec, dict):
            raise ValueError(f"an insect spec must be an object of fields, got {type(spec).__name__}")
        names = {f.name for f in dataclasses.fields(Morphology)}
        morph_kw, P0, bounds = {}, base.P0, dict(base.bounds_deg)
        for key, value in spec.items():
            if key == "P0_W":
                P0 = _number(key, value, positive=True)
            elif key == "bounds_deg":
                bounds = _bounds(value, base.bounds_deg)
            elif key not in names:
                known = ", ".join(sorted([*names, "P0_W", "bounds_deg"]))
                raise ValueError(f"unknown insect field {key!r}; known: {known}")
            else:
                morph_kw[key] = _morph_value(key, value)
        try:
            morph = dataclasses.replace(base.morphology, **morph_kw)
        except ValueError as exc:  # Morphology's own checks name their field first
            raise ValueError(f"invalid insect field: {exc}") from None
        try:
            morph.planform  # noqa: B018 (checks r2_hat, R, cbar together)
        except ValueError as exc:
            raise ValueError(f"invalid insect field 'r2_hat': {exc}") from None
        try:
            return Insect(morph, P0, bounds)
        except ValueError as exc:
            raise ValueError(f"invalid insect field: {exc}") from None


def _number(key: str, value, *, positive: bool = False, allow_zero: bool = False) -> float:
    if isinstance(value, bool) or not isinstance(value, (int, float)) or not math.isfinite(value):
        raise ValueError(f"insect field {key!r} must be a finite number, got {value!r}")
    if positive and not (value > 0 or (allow_zero and value == 0)):
        raise ValueError(f"insect field {key!r} must be {'>= 0' if allow_zero else 'positive'}, got {value!r}")
    return float(value)


_POSITIVE = ("total_mass", "wing_mass", "R", "cbar", "r2_hat", "wing_thickness")


def _morph_value(key: str, value):
    if key == "name":
        if not isinstance(value, str) or not value:
            raise ValueError(f"insect field 'name' must be a non-empty string, got {value!r}")
        return value
    if key in _POSITIVE or key == "axis_fraction":
        v = _number(key, value, positive=key in _POSITIVE)
        if key == "r2_hat" and not v < 1:
            raise ValueError(f"insect field 'r2_hat' must lie in (0, 1), got {value!r}")
        return v
    if key == "hinge_from_thorax":
        return _vector(key, value)
    if key == "wing_mass_model":
        if not isinstance(value, dict) or set(value) - {"name", "span_decay", "chord_decay"}:
            raise ValueError(f"insect field 'wing_mass_model' must be an object of name, span_decay, chord_decay, "
                             f"got {value!r}")
        try:
            return WingMassModel(**value)
        except (TypeError, ValueError) as exc:
            raise ValueError(f"insect field 'wing_mass_model': {exc}") from None
    if key == "segments":
        if not isinstance(value, list) or not value:
            raise ValueError(f"insect field 'segments' must be a non-empty list, got {value!r}")
        out = []
        for i, s in enumerate(value):
            if not isinstance(s, dict) or set(s) != {"name", "mass", "centre", "semi_axes"}:
                raise ValueError(f"insect field 'segments[{i}]' must be an object of name, mass, centre, semi_axes")
            out.append(Ellipsoid(str(s["name"]), _number(f"segments[{i}].mass", s["mass"], positive=True),
                                 _vector(f"segments[{i}].centre", s["centre"]),
                                 _vector(f"segments[{i}].semi_axes", s["semi_axes"])))
        if not any(s.name == "thorax" for s in out):
            raise ValueError("insect field 'segments' must include one named 'thorax' (the wing hinges' reference)")
        return tuple(out)
    raise ValueError(f"unknown insect field {key!r}")  # pragma: no cover (every Morphology field is handled above)


def _vector(key: str, value) -> tuple[float, float, float]:
    if not isinstance(value, (list, tuple)) or len(value) != 3:
        raise ValueError(f"insect field {key!r} must be a list of 3 numbers [m], got {value!r}")
    return tuple(_number(key, v) for v in value)


def _bounds(value, base_bounds) -> dict:
    if not isinstance(value, dict):
        raise ValueError(f"insect field 'bounds_deg' must be an object {{parameter: [lower, upper]}}, got {value!r}")
    out = dict(base_bounds)
    for k, v in value.items():
        if k not in PARAM_NAMES:
            raise ValueError(f"insect field 'bounds_deg' has an unknown parameter {k!r}; "
                             f"known: {', '.join(PARAM_NAMES)}")
        if not isinstance(v, (list, tuple)) or len(v) != 2:
            raise ValueError(f"insect field 'bounds_deg.{k}' must be [lower, upper], got {v!r}")
        lo, hi = (_number(f"bounds_deg.{k}", x) for x in v)
        if not lo < hi:
            raise ValueError(f"insect field 'bounds_deg.{k}' must have lower < upper, got {v!r}")
        out[k] = (lo, hi)
    return out


def read_insect(path) -> Insect:
    """The insect of a spec file (TOML or JSON: :func:`hawksim.insect.folder.read_spec_file`). ValueError (one line,
    naming the file or the field) for a missing or unreadable file, a syntax error, or an unknown or invalid field.
    Without a ``name`` the insect is named after the file's stem."""
    from hawksim.insect.folder import read_spec_file

    return read_spec_file(Path(path))


def __getattr__(name: str):
    if name == "DEFAULT_INSECT":  # the default insect, loaded from its folder on first use
        from hawksim.insect.folder import default_insect

        return default_insect()
    raise AttributeError(f"module {__name__!r} has no attribute {name!r}")
