"""An insect is a folder of data: its spec, its generated MJCF, its README and its shipped tables and networks.

A shipped insect lives in ``hawksim/insects/<name>/`` (inside the package, so it ships in the wheel; docs/insects.md):

* ``insect.toml`` (or ``insect.json``): the spec, read by :func:`load_insect`: the morphology (each number with its
  unit, source class and citation), the reference power P0, the kinematic bounds and the reference kinematics;
* ``<model>`` (the spec's ``model``, e.g. ``hawkmoth.xml``): the MJCF generated from the spec by
  ``python -m hawksim.insect.model`` (:mod:`hawksim.insect.model`);
* ``README.md``: provenance and units, in words;
* ``data/``: the shipped tables and networks, with ``data/manifest.toml`` keying each by kind, backend and model
  digest (:mod:`hawksim.insect.tables`).

The spec format (version 1; TOML because it is written and read by people, with comments, and Python 3.11 reads it
with the standard library's ``tomllib``; the same structure as JSON is accepted):

``format`` (1), ``name`` (an insect in a folder is named after the folder), ``species`` (text), ``model`` (the
MJCF's file name), ``base`` (optional: a shipped insect whose values the fields left out keep; without it every
morphology field must be given), ``[morphology]`` with ``name`` (the variant's label) and one table per
:class:`hawksim.insect.morphology.Morphology` field holding ``value``, ``unit``, ``source`` (one of
:data:`SOURCE_CLASSES`) and ``citation``; ``[P0]`` (``value`` [W], ``unit``, ``source``, ``citation``); ``[bounds]``
(``f``, ``beta``, ... as ``[lower, upper]`` in Hz and degrees, with ``unit``, ``source``, ``citation``);
``[reference_kinematics]`` (optional: ``speed`` [m/s] and each parameter, one
value per speed, Hz and degrees). A flat JSON spec (:meth:`hawksim.insect.insect.Insect.from_dict`: Morphology's
fields by name, ``P0_W``, ``bounds_deg``; the fields left out keep the default insect's) is read too.

Every error is a one-line ValueError naming the file and the field.
"""

from __future__ import annotations

import json
import math
from functools import lru_cache
from pathlib import Path
from types import MappingProxyType

from hawksim.insect.insect import Insect, _number
from hawksim.insect.kinematics import PARAM_NAMES

INSECTS_DIR = Path(__file__).resolve().parents[1] / "insects"
"""Where the shipped insects' folders live (``hawksim/insects``, package data)."""

DEFAULT_NAME = "hawkmoth"
"""The shipped insect every default argument means (:func:`default_insect`)."""

SPEC_FILES = ("insect.toml", "insect.json")
"""The spec's file name in an insect's folder, in the order looked for (then ``<folder name>.toml``/``.json``)."""

SOURCE_CLASSES = ("quoted", "measured", "derived", "model choice", "calibrated")
"""Source class of a number (../shared/sources/insect-morphology.md): quoted from a cited table, measured (read in the
measuring authors' data), derived (arithmetic on those), model choice (no source), calibrated (fitted to a result,
with the rule stated)."""

FORMAT = 1
"""The spec format version this module reads."""

_TOP = ("format", "name", "species", "model", "base", "morphology", "P0", "bounds", "reference_kinematics")
_ANNOTATION = ("unit", "source", "citation")
_STRUCTURED_ONLY = ("format", "species", "model", "base", "P0", "bounds", "reference_kinematics")


def shipped_insects() -> tuple[str, ...]:
    """Names of the shipped insects (the folders of :data:`INSECTS_DIR` holding a spec), sorted."""
    if not INSECTS_DIR.is_dir():
        return ()
    return tuple(sorted(p.name for p in INSECTS_DIR.iterdir() if p.is_dir() and spec_file(p) is not None))


def spec_file(folder: Path) -> Path | None:
    """The spec file of an insect folder (:data:`SPEC_FILES`, then ``<name>.toml``/``<name>.json``), None if none."""
    folder = Path(folder)
    for name in (*SPEC_FILES, f"{folder.name}.toml", f"{folder.name}.json"):
        if (folder / name).is_file():
            return folder / name
    return None


def load_insect(name_or_path: str | Path) -> Insect:
    """The insect named ``name_or_path``: a shipped insect's name (:func:`shipped_insects`, e.g. "hawkmoth"), an
    insect folder, or a spec file (``.toml`` or ``.json``). ValueError (one line, naming the file and the field) for
    an unknown name, a missing or unreadable file, a syntax error, or an unknown or invalid field."""
    text = str(name_or_path)
    if isinstance(name_or_path, str) and text in shipped_insects():
        return _load_folder(INSECTS_DIR / text)
    p = Path(name_or_path)
    if p.is_dir():
        if spec_file(p) is None:
            raise ValueError(f"insect folder {text!r} holds no spec ({' or '.join(SPEC_FILES)})")
        return _load_folder(p)
    if not p.exists() and isinstance(name_or_path, str) and not p.suffix and "/" not in text:
        raise ValueError(f"unknown insect {text!r}: neither a shipped insect ({', '.join(shipped_insects())}) "
                         "nor a spec file")
    return read_spec_file(p)


@lru_cache(maxsize=None)
def _load_folder(folder: Path) -> Insect:
    return read_spec_file(spec_file(folder), folder=folder.resolve())


@lru_cache(maxsize=1)
def default_insect() -> Insect:
    """The default insect, loaded once from its folder (:data:`DEFAULT_NAME`): every default argument that takes an
    insect is this one."""
    return _load_folder(INSECTS_DIR / DEFAULT_NAME)


def read_spec_file(path: Path, folder: Path | None = None) -> Insect:
    """The insect of a spec file (TOML by its ``.toml`` suffix, else JSON); ``folder``: the insect folder it is the
    spec of (its tables and MJCF). Without a name the insect is named after the file's stem."""
    p = Path(path)
    try:
        raw = p.read_bytes()
    except FileNotFoundError:
        raise ValueError(f"insect file {str(p)!r} does not exist") from None
    except OSError as exc:
        raise ValueError(f"insect file {str(p)!r} cannot be read: {exc.strerror or exc}") from None
    if p.suffix.lower() == ".toml":
        import tomllib

        try:
            spec = tomllib.loads(raw.decode())
        except (tomllib.TOMLDecodeError, UnicodeDecodeError) as exc:
            raise ValueError(f"insect file {str(p)!r} is not valid TOML: {str(exc).splitlines()[0]}") from None
    else:
        try:
            spec = json.loads(raw.decode())
        except UnicodeDecodeError as exc:
            raise ValueError(f"insect file {str(p)!r} cannot be read: {exc}") from None
        except json.JSONDecodeError as exc:
            raise ValueError(f"insect file {str(p)!r} is not valid JSON: {exc.msg} (line {exc.lineno})") from None
    try:
        return insect_from_spec(spec, default_name=folder.name if folder is not None else p.stem, folder=folder)
    except ValueError as exc:
        raise ValueError(f"insect file {str(p)!r}: {exc}") from None


def insect_from_spec(spec, default_name: str = "insect", folder: Path | None = None) -> Insect:
    """The insect of a parsed spec: the structured format (module docstring) when it has one of its own keys
    (``format``, ``base``, ``P0``, ``bounds``, ...) or a ``morphology`` table, else the flat one
    (:meth:`Insect.from_dict`). ValueError naming the field."""
    if not isinstance(spec, dict):
        raise ValueError(f"an insect spec must be an object of fields, got {type(spec).__name__}")
    if not (set(spec) & set(_STRUCTURED_ONLY)) and not isinstance(spec.get("morphology"), dict):
        flat = spec if "name" in spec else {**spec, "name": default_name}
        return Insect.from_dict(flat, base=default_insect())
    return _structured(spec, default_name, folder)


def _structured(spec: dict, default_name: str, folder: Path | None) -> Insect:
    import dataclasses

    from hawksim.insect.morphology import Morphology

    unknown = sorted(set(spec) - set(_TOP))
    if unknown:
        raise ValueError(f"unknown insect field {unknown[0]!r}; known: {', '.join(_TOP)}")
    if spec.get("format", FORMAT) != FORMAT:
        raise ValueError(f"insect field 'format' must be {FORMAT}, got {spec['format']!r}")
    for key in ("name", "species", "model", "base"):
        if key in spec and not (isinstance(spec[key], str) and spec[key]):
            raise ValueError(f"insect field {key!r} must be a non-empty string, got {spec[key]!r}")
    base = None
    if "base" in spec:
        if spec["base"] not in shipped_insects():
            raise ValueError(f"insect field 'base' must name a shipped insect ({', '.join(shipped_insects())}), "
                             f"got {spec['base']!r}")
        base = load_insect(spec["base"])
    morph = spec.get("morphology", {})
    if not isinstance(morph, dict):
        raise ValueError(f"insect field 'morphology' must be a table of fields, got {morph!r}")
    fields = [f.name for f in dataclasses.fields(Morphology)]
    flat: dict = {}
    sources: dict = {}
    for key, entry in morph.items():
        if key not in fields:
            raise ValueError(f"unknown insect field 'morphology.{key}'; known: {', '.join(fields)}")
        if key == "name":
            flat["name"] = entry
            continue
        flat[key], sources[f"morphology.{key}"] = _annotated(f"morphology.{key}", entry)
    missing = [k for k in fields if k not in flat and k != "name"]
    if base is None and missing:
        raise ValueError(f"insect field 'morphology.{missing[0]}' is missing (give every morphology field, or "
                         "'base' = a shipped insect whose values the ones left out keep)")
    if "name" not in flat:  # the variant's label: the base's where no morphology number changes, else the insect's
        flat["name"] = base.morphology.name if base is not None and not sources else spec.get("name", default_name)
    if "P0" in spec:
        p0, sources["P0"] = _annotated("P0", spec["P0"])
        flat["P0_W"] = _number("P0", p0, positive=True)
    elif base is None:
        raise ValueError("insect field 'P0' is missing (the reference power [W], the unit of P+)")
    if "bounds" in spec:
        b = spec["bounds"]
        if not isinstance(b, dict):
            raise ValueError(f"insect field 'bounds' must be a table {{parameter: [lower, upper]}}, got {b!r}")
        sources["bounds"] = _source("bounds", b)
        flat["bounds_deg"] = {k: v for k, v in b.items() if k not in _ANNOTATION}
        if base is None and set(PARAM_NAMES) - set(flat["bounds_deg"]):
            k = next(k for k in PARAM_NAMES if k not in flat["bounds_deg"])
            raise ValueError(f"insect field 'bounds.{k}' is missing")
    elif base is None:
        raise ValueError("insect field 'bounds' is missing (the kinematic bounds, Hz and degrees)")
    reference = _reference(spec["reference_kinematics"]) if "reference_kinematics" in spec else None
    if "reference_kinematics" in spec:
        sources["reference_kinematics"] = _source("reference_kinematics", spec["reference_kinematics"])
    insect = Insect.from_dict(flat, base=base if base is not None else default_insect_or_none())
    return dataclasses.replace(
        insect, label=default_name if folder is not None else spec.get("name", default_name), folder=folder,
        model_file=spec.get("model"),
        reference_deg=reference if reference is not None else (base.reference_deg if base else None),
        sources=MappingProxyType({k: v for k, v in {**(dict(base.sources) if base else {}), **sources}.items()
                                  if v is not None}))


def default_insect_or_none() -> Insect:
    """The base of a complete structured spec: any insect (every field is given); the class defaults, so that the
    default insect's own spec does not need itself to load."""
    return Insect()


def _source(key: str, entry: dict) -> tuple[str, str]:
    cls = entry.get("source")
    if cls not in SOURCE_CLASSES:
        raise ValueError(f"insect field '{key}.source' must be one of {', '.join(SOURCE_CLASSES)}, got {cls!r}")
    cit = entry.get("citation")
    if not (isinstance(cit, str) and cit):
        raise ValueError(f"insect field '{key}.citation' must be a non-empty string (the source, or the rule of a "
                         f"model choice), got {cit!r}")
    if "unit" in entry and not isinstance(entry["unit"], str):
        raise ValueError(f"insect field '{key}.unit' must be a string, got {entry['unit']!r}")
    return cls, cit


def _annotated(key: str, entry):
    """(value, (source class, citation)) of ``{value, unit, source, citation}``; a bare value has no source."""
    if not isinstance(entry, dict) or "value" not in entry:
        return entry, None
    extra = sorted(set(entry) - {"value", *_ANNOTATION})
    if extra:
        raise ValueError(f"unknown insect field '{key}.{extra[0]}'; known: value, {', '.join(_ANNOTATION)}")
    return entry["value"], _source(key, entry)


def _reference(entry) -> MappingProxyType:
    if not isinstance(entry, dict) or "speed" not in entry:
        raise ValueError("insect field 'reference_kinematics' must be a table of speed and the parameters")
    unknown = sorted(set(entry) - {"speed", *PARAM_NAMES, *_ANNOTATION})
    if unknown:
        raise ValueError(f"unknown insect field 'reference_kinematics.{unknown[0]}'")
    speeds = entry["speed"]
    if not (isinstance(speeds, list) and speeds and all(_finite(v) for v in speeds)
            and all(a < b for a, b in zip(speeds, speeds[1:]))):
        raise ValueError(f"insect field 'reference_kinematics.speed' must be increasing finite speeds [m/s], "
                         f"got {speeds!r}")
    out = {"speed": tuple(float(v) for v in speeds)}
    for k in PARAM_NAMES:
        v = entry.get(k)
        if not (isinstance(v, list) and len(v) == len(speeds) and all(_finite(x) for x in v)):
            raise ValueError(f"insect field 'reference_kinematics.{k}' must be {len(speeds)} finite numbers (one per "
                             f"speed), got {v!r}")
        out[k] = tuple(float(x) for x in v)
    return MappingProxyType(out)


def _finite(v) -> bool:
    return isinstance(v, (int, float)) and not isinstance(v, bool) and math.isfinite(v)
