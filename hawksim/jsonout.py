"""Edge helper for scripts: print one JSON object on stdout and optionally write it to a file."""

from __future__ import annotations

import json


def emit(obj: dict, out: str | None = None) -> None:
    """Write ``obj`` to ``out`` (indented) if given, and print it as one line on stdout."""
    if out:
        with open(out, "w") as f:
            json.dump(obj, f, indent=1)
    print(json.dumps(obj))
