"""An insect's shipped tables and networks, keyed by insect, backend and model digest.

An insect folder's ``data/manifest.toml`` lists each shipped file: ``file`` (relative to ``data/``), ``kind`` (one of
:data:`KINDS`), ``aero`` (the backends it serves) and ``model_sha256``, the SHA-256 of the MJCF text the file was
computed on (:func:`mjcf_digest`). A table computed on another model is not this insect's: :func:`table_path`
refuses it (ValueError naming both digests) rather than let a flight start from another insect's orbit or gains.
The table files themselves are unchanged (their own records, e.g. the surrogate's ``network_sha256``, still apply).

Example manifest entry::

    [[file]]
    file = "orbit_table_uvlm.json"
    kind = "orbit"
    aero = ["uvlm"]
    model_sha256 = "9f0c..."
"""

from __future__ import annotations

import hashlib
from dataclasses import dataclass
from functools import lru_cache
from pathlib import Path

MANIFEST = "manifest.toml"
"""The manifest's file name in an insect folder's ``data/``."""

KINDS = ("trim", "orbit", "control_model", "network", "step_network", "forward_trim")
"""Kinds of shipped file: held-body trim table, free-body orbit table, one-beat control models, cycle-mean network
(per speed or speed-input), per-step network."""


@dataclass(frozen=True)
class ShippedFile:
    """One entry of a manifest: ``path`` (absolute), ``kind`` (:data:`KINDS`), ``aero`` (backend names it serves),
    ``model_sha256`` (digest of the MJCF it was computed on)."""

    path: Path
    kind: str
    aero: tuple[str, ...]
    model_sha256: str


def mjcf_digest(insect) -> str:
    """SHA-256 (hex) of the insect's MJCF text (:func:`hawksim.insect.model.insect_mjcf`): what its tables must
    record. For a shipped insect it is the digest of its committed MJCF file."""
    return _digest(insect.morphology, insect.name)


@lru_cache(maxsize=16)
def _digest(morphology, name: str) -> str:
    from hawksim.insect.model import mjcf

    return hashlib.sha256(mjcf(morphology, name).encode()).hexdigest()


def manifest(insect) -> tuple[ShippedFile, ...]:
    """The shipped files of an insect's folder (none for an insect without a folder or a manifest)."""
    if insect.folder is None:
        return ()
    return _read_manifest(Path(insect.folder) / "data")


@lru_cache(maxsize=8)
def _read_manifest(data: Path) -> tuple[ShippedFile, ...]:
    import tomllib

    path = data / MANIFEST
    if not path.is_file():
        return ()
    try:
        entries = tomllib.loads(path.read_text()).get("file", [])
    except tomllib.TOMLDecodeError as exc:
        raise ValueError(f"manifest {str(path)!r} is not valid TOML: {str(exc).splitlines()[0]}") from None
    out = []
    for i, e in enumerate(entries):
        where = f"manifest {str(path)!r}, file[{i}]"
        if not isinstance(e, dict) or set(e) != {"file", "kind", "aero", "model_sha256"}:
            raise ValueError(f"{where} must have exactly file, kind, aero, model_sha256")
        if e["kind"] not in KINDS:
            raise ValueError(f"{where}: kind must be one of {', '.join(KINDS)}, got {e['kind']!r}")
        aero = e["aero"]
        if not (isinstance(aero, list) and aero and all(isinstance(a, str) for a in aero)):
            raise ValueError(f"{where}: aero must be a list of backend names, got {aero!r}")
        out.append(ShippedFile(data / e["file"], e["kind"], tuple(aero), str(e["model_sha256"])))
    return tuple(out)


def restamp(insect, files) -> list[str]:
    """Set the ``model_sha256`` of ``files`` (names relative to the insect's ``data/``) in its manifest to the
    insect's MJCF digest (:func:`mjcf_digest`): what regenerating them on that MJCF makes them (`scripts/regenerate.py`
    calls it after each stage). The manifest's text is edited in place, its comments and order kept. ValueError for
    an insect without a folder or a name the manifest does not list. Returns the names whose digest changed."""
    import re

    if insect.folder is None:
        raise ValueError(f"insect {insect.name!r} has no folder, so no manifest to restamp")
    path = Path(insect.folder) / "data" / MANIFEST
    digest = mjcf_digest(insect)
    head, *blocks = path.read_text().split("[[file]]")
    names = {re.search(r'^file = "([^"]+)"', b, re.M).group(1): i for i, b in enumerate(blocks)}
    missing = sorted(set(files) - set(names))
    if missing:
        raise ValueError(f"files {missing} are not in the manifest {str(path)!r}")
    changed = []
    for name in files:
        i = names[name]
        new = re.sub(r'^model_sha256 = "[0-9a-f]*"', f'model_sha256 = "{digest}"', blocks[i], count=1, flags=re.M)
        if new != blocks[i]:
            blocks[i] = new
            changed.append(name)
    if changed:
        path.write_text("[[file]]".join([head, *blocks]))
        _read_manifest.cache_clear()
    return changed


def find_file(insect, kind: str, aero: str | None = None, name: str | None = None) -> ShippedFile | None:
    """The manifest entry of ``kind`` serving backend ``aero`` (and, if given, of file name ``name``, relative to
    ``data/``), None if the insect ships none."""
    if kind not in KINDS:
        raise ValueError(f"kind must be one of {', '.join(KINDS)}, got {kind!r}")
    for entry in manifest(insect):
        if entry.kind != kind or (aero is not None and aero not in entry.aero):
            continue
        if name is not None and entry.path != Path(insect.folder) / "data" / name:
            continue
        return entry
    return None


def table_status(insect, kind: str, aero: str | None = None, name: str | None = None) -> tuple[Path | None, str]:
    """(path, reason): the insect's shipped file of ``kind`` for ``aero`` (:func:`find_file`) if it holds for the
    insect's model, else None and the reason in one line."""
    entry = find_file(insect, kind, aero, name)
    what = f"{kind.replace('_', ' ')} {'file ' + repr(name) if name else 'table'}" + (f" for {aero}" if aero else "")
    if entry is None:
        return None, f"the insect {insect.name!r} ships no {what}"
    digest = mjcf_digest(insect)
    if entry.model_sha256 != digest:
        return None, (f"the insect {insect.name!r}'s shipped {what} ({entry.path.name}) was computed on the model "
                      f"{entry.model_sha256[:12]}, not on its MJCF {digest[:12]}: regenerate it "
                      "(hawksim reproduce) and its manifest entry")
    if not entry.path.is_file():
        return None, f"the insect {insect.name!r}'s shipped {what} is missing ({entry.path})"
    return entry.path, "ok"


def table_path(insect, kind: str, aero: str | None = None, name: str | None = None) -> Path | None:
    """The insect's shipped file of ``kind`` for backend ``aero`` (e.g. ``table_path(insect, "orbit", "uvlm")``),
    None if it ships none; ValueError (one line, naming both digests) if the file was computed on another model
    than the insect's MJCF, or is listed but missing."""
    path, reason = table_status(insect, kind, aero, name)
    if path is None and find_file(insect, kind, aero, name) is not None:
        raise ValueError(reason)
    return path


def network_path(insect, name: str) -> Path:
    """Path of the insect's shipped network ``name`` (relative to ``data/``, e.g. ``surrogates/uvlm_v1000.safetensors``)
    as its manifest lists it (a file the manifest does not list is looked for there all the same: a user's network
    beside the shipped ones); ValueError if the manifest lists it as computed on another model."""
    if insect.folder is None:
        raise ValueError(f"the insect {insect.name!r} has no folder, so no shipped networks")
    for kind in ("network", "step_network"):
        if find_file(insect, kind, name=name) is not None:
            return table_path(insect, kind, name=name)
    return Path(insect.folder) / "data" / name
