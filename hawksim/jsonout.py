"""Edge helpers for scripts: print one JSON object on stdout (optionally also to a file), and the host facts
every benchmark records beside its figures (speed on a shared machine is a ratio of the same sitting, never an
absolute: compare runs only with their date and load average)."""

from __future__ import annotations

import datetime
import json
import os
import platform


def host_info() -> dict:
    """Date (UTC, ISO 8601), load average (/proc/loadavg: 1, 5, 15 min; None where absent), CPU count, machine,
    processor, Python version."""
    try:
        load = [float(v) for v in open("/proc/loadavg").read().split()[:3]]
    except OSError:
        load = None
    return {"date": datetime.datetime.now(datetime.timezone.utc).isoformat(timespec="seconds"), "loadavg": load,
            "cpus": os.cpu_count(), "machine": platform.machine(), "processor": platform.processor(),
            "python": platform.python_version()}


def emit(obj: dict, out: str | None = None, *, host: bool = False) -> None:
    """Write ``obj`` to ``out`` (indented) if given, and print it as one line on stdout; ``host`` adds
    ``"host": host_info()`` (benchmarks)."""
    if host:
        obj = {**obj, "host": host_info()}
    if out:
        with open(out, "w") as f:
            json.dump(obj, f, indent=1)
    print(json.dumps(obj))
