"""What `hawksim reproduce` and `hawksim warmup` print without ``--json``: for each part reproduced, what it wrote and
where, with what did not converge or was skipped said plainly; for the warm-up, how many kernels were compiled, where
they are cached and what was run. docs/output.md shows both."""

from __future__ import annotations

from hawksim.cli.summary import line, num

WARMUP_STAGES = {"aero_uvlm_s": "a held-body UVLM run", "aero_quasi_steady_s": "a quasi-steady run",
                 "fly_quasi_steady_s": "a quasi-steady wingbeat", "fly_surrogate_s": "a surrogate wingbeat"}
"""The stages of `hawksim warmup` (its ``stages`` keys) in words."""


def render_warmup(out: dict) -> str:
    """`hawksim warmup`'s summary."""
    n = out["compiled"]
    what = (f"compiled {n} numba kernel{'s' if n != 1 else ''} for this CPU" if n
            else "nothing to compile: every kernel was already cached for this CPU")
    stages = ", ".join(f"{WARMUP_STAGES.get(k, k)} {num(v, 2)} s" for k, v in out["stages"].items())
    return "\n".join([f"hawksim warmup: {what}",
                      line("cache", out["cache_dir"] or "numba's default cache (NUMBA_CACHE_DIR unset)"),
                      line("ran", stages),
                      line("wall time", f"{out['wall_time_s']:.1f} s; `hawksim aero` and `hawksim fly` now start "
                                        "without compiling")])


def _failures(name: str, value) -> list[str]:
    """What a part of `hawksim reproduce` (its entry in the output) did not achieve, in words."""
    if isinstance(value, str):
        return [value] if value.startswith("skipped") else []
    bad = []
    if name == "orbits":
        for aero, t in value.items():
            speeds = [v for v, ok in t["converged"].items() if not ok]
            if speeds:
                bad.append(f"{aero} orbit NOT converged at {', '.join(speeds)} m/s")
    if name == "forward_flight":
        if not value["trims_agree"]:
            bad.append("a shipped forward trim does NOT re-fly to its table's averages within its tolerance")
        if value["orbits_agree"] is False:
            bad.append("a forward orbit or its Floquet multipliers do NOT agree with the study's (orbits.json)")
    if name == "trim":
        conv = value.get("balanced_converged") or []
        if not all(conv):
            bad.append(f"UVLM balance NOT converged at {conv.count(False)} of {len(conv)} speeds")
    return bad


def _produced(name: str, value) -> str:
    """Where a part of `hawksim reproduce` wrote, and the count of what it wrote."""
    if isinstance(value, str):
        return value
    if name == "orbits":
        return "; ".join(f"{t['path']} ({len(t['converged'])} speeds)" for t in value.values())
    if name in ("stability", "stability_table3"):
        unstable = sorted({m["speed"] for m in value["modes"] for s in ("longitudinal", "lateral")
                           for _, stable in m[s] if not stable})
        return (f"{len(value['speeds'])} speeds" + (f"; unstable modes at {', '.join(f'{v:g}' for v in unstable)} m/s"
                                                   if unstable else "; every mode stable"))
    if name.startswith("validation"):
        return f"{value['json']} and {len(value['figures'])} figures"
    if name.startswith("control"):
        return f"{value['path']} ({len(value['speeds'])} speeds)"
    if name == "backends":
        return f"{value['path']}, {value['table']}"
    if name == "trim":
        return f"{value['dir']} ({len(value['figures'])} figures)"
    if name == "forward_flight":
        return (f"{value['path']} (trims re-flown; orbits " + ("not compared: no results/forward_flight/orbits.json"
                                                                if value["orbits_agree"] is None else "compared") + ")")
    return ", ".join(str(v) for v in value.values())


def render_reproduce(out: dict, out_dir: str = "results", wall_time_s: float | None = None) -> str:
    """`hawksim reproduce`'s summary: one line per part (where it wrote, what did not converge), then the failures
    together, and the wall time. ``out_dir`` is --out (the stability parts write under it: DIR/stability/)."""
    width = max([len(k) for k in out] + [9])
    lines = [f"hawksim reproduce: {len(out)} part{'s' if len(out) != 1 else ''} into {out_dir}/"]
    failed = []
    for name, value in out.items():
        text = _produced(name, value)
        if name in ("stability", "stability_table3"):
            text = f"{out_dir}/{name}/: {text}"
        lines.append(f"  {name:<{width}} {text}")
        failed += [f"{name}: {f}" for f in _failures(name, value)]
    lines.append(f"  {'failed':<{width}} " + ("; ".join(failed) if failed else "nothing"))
    if wall_time_s is not None:
        took = f"{wall_time_s:.0f} s" if wall_time_s < 120 else f"{wall_time_s / 60:.1f} min"
        lines.append(f"  {'wall time':<{width}} {took}")
    return "\n".join(lines)
