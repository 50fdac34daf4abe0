"""A per-user disk cache of the linear maps a controller is designed on, for maps that take seconds to difference.

A history network's half-stroke maps are on the augmented state (body and the record of 40 calls: 251 states,
1052 branched half-beats, 3-4 s per orbit on the 2-core machine; :mod:`hawksim.control.halfstroke`), which
`hawksim fly --aero surrogate` would otherwise redo at every start. They are a deterministic function of the
orbit, the network, the MuJoCo model and the code, so they are kept in ``$XDG_CACHE_HOME/hawksim/control/<sources
digest>/`` (default ``~/.cache/hawksim/control/...``; the digest of :func:`aero.numba_cache.sources_digest`, so any
change to a source file starts a new folder, as for the compiled kernels), one ``.npz`` file per map, named by the
SHA-256 of everything the map depends on (:func:`map_key`). Files are written all or nothing
(:mod:`hawksim.atomic`) and read with ``allow_pickle=False``; one that cannot be read is recomputed.
``HAWKSIM_NO_CACHE=1`` turns the cache off.
"""

from __future__ import annotations

import hashlib
import io
import json
import os
from pathlib import Path

import numpy as np

from hawksim.trim.registry import model_digest  # noqa: F401 (its home: hawksim.trim.registry)

ENV_OFF = "HAWKSIM_NO_CACHE"


def cache_dir() -> Path:
    """The folder of this version of the sources."""
    from aero.numba_cache import sources_digest

    base = os.environ.get("XDG_CACHE_HOME") or str(Path.home() / ".cache")
    return Path(base) / "hawksim" / "control" / sources_digest()


def map_key(kind: str, orbit, model, **settings) -> str:
    """The name of a map: SHA-256 of its kind, the orbit (its JSON), the shipped network's SHA-256 for the
    surrogate, the model's mechanics and the differencing settings."""
    from hawksim.backends.registry import descriptor

    parts = {"kind": kind, "orbit": orbit.to_json(), "model": model_digest(model), "settings": settings}
    digest = descriptor(orbit.aero).tables_digest
    if digest is not None:
        parts["network"] = digest()
    return hashlib.sha256(json.dumps(parts, sort_keys=True, default=float).encode()).hexdigest()


def load(key: str) -> dict[str, np.ndarray] | None:
    """The arrays stored under ``key``, or None (absent, unreadable, or the cache off)."""
    if os.environ.get(ENV_OFF):
        return None
    path = cache_dir() / f"{key}.npz"
    try:
        with np.load(path, allow_pickle=False) as z:
            return {k: z[k] for k in z.files}
    except (OSError, ValueError, KeyError):
        return None


def store(key: str, arrays: dict[str, np.ndarray]) -> None:
    """Keep ``arrays`` under ``key`` (all or nothing; a cache that cannot be written is skipped silently: it only
    saves time)."""
    if os.environ.get(ENV_OFF):
        return
    from hawksim.atomic import write_bytes

    buf = io.BytesIO()
    np.savez(buf, **{k: np.asarray(v) for k, v in arrays.items()})
    try:
        d = cache_dir()
        d.mkdir(parents=True, exist_ok=True)
        write_bytes(d / f"{key}.npz", buf.getvalue(), what="control-map cache")
    except OSError:
        pass
