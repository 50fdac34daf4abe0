"""Convergence of the hawkmoth case, one discretisation at a time (issue 48, items 3-4).

At Table 3's kinematics and 0, 1, 2 m/s, the held-body UVLM run of `hawksim aero` (3 wingbeats, the last one
averaged) with, from the default resolution (6 x 12 rings per wing, 40 steps per beat, the whole wake kept):
the chordwise rings, the spanwise rings, the steps per beat and the wake kept (1 or 2 beats of rows) varied
separately; then all three refined together by factors of 2, (4, 8, 40) -> (8, 16, 80) -> (16, 32, 160), with a
Richardson limit from those three levels (observed order p = log2 of the ratio of successive differences;
p = 1 where the differences do not shrink monotonically, and that is said). Outputs: L+, D+, M+, P+ of the last
beat and the within-beat lift peak (max lift / W). Cached in --out (resumable).

    python scripts/studies/uvlm_resolution.py --out results/uvlm_resolution.json
    python scripts/studies/uvlm_resolution.py --out results/uvlm_resolution.json --summary --figures results
"""

from __future__ import annotations

import argparse
import json
import sys
import time
from pathlib import Path

import numpy as np

from hawksim.backends import make_backend
from hawksim.backends.held import held_flight
from hawksim.backends.resolution import DEFAULT, Resolution
from hawksim.insect.kinematics import table3_kinematics
from hawksim.insect.morphology import HAWKMOTH
from hawksim.jsonout import host_info

SPEEDS = (1.0, 2.0, 0.0)
OUTPUTS = ("L_plus", "D_plus", "M_plus", "P_plus", "lift_peak")
BASE = (DEFAULT.n_chord, DEFAULT.n_span, DEFAULT.steps_per_cycle, None)
AXES = {
    "n_chord": [(nc, BASE[1], BASE[2], None) for nc in (4, 8, 12)],
    "n_span": [(BASE[0], ns, BASE[2], None) for ns in (8, 16, 24)],
    "steps_per_cycle": [(BASE[0], BASE[1], spc, None) for spc in (80, 160)],
    "wake_beats": [(BASE[0], BASE[1], BASE[2], wb) for wb in (1, 2)],
}
TOGETHER = [(4, 8, 40, None), (8, 16, 80, None), (16, 32, 160, None)]


def key(speed, nc, ns, spc, wake_beats):
    return f"{speed:g}|{nc}|{ns}|{spc}|{wake_beats}"


def run_one(speed, nc, ns, spc, wake_beats):
    res = Resolution(n_chord=nc, n_span=ns, steps_per_cycle=spc, cycles=DEFAULT.cycles)
    rows = None if wake_beats is None else wake_beats * spc
    backend = make_backend("uvlm", resolution=res, max_wake_rows=rows)
    t0 = time.perf_counter()
    r = held_flight(table3_kinematics(speed), speed, backend, cycles=res.cycles, steps_per_cycle=spc)
    wall = time.perf_counter() - t0
    a = r.averages
    last = r.lift[-spc:]
    return {"L_plus": a.L_plus, "D_plus": a.D_plus, "M_plus": a.M_plus, "P_plus": a.P_plus,
            "lift_peak": float(last.max() / HAWKMOTH.weight), "wall_time_s": wall,
            "host": host_info()}


def richardson(f0, f1, f2):
    """(limit, order p, monotone) from three levels refined by 2."""
    d1, d2 = f1 - f0, f2 - f1
    monotone = d1 != 0 and d2 != 0 and np.sign(d1) == np.sign(d2) and abs(d2) < abs(d1)
    p = float(np.log2(d1 / d2)) if monotone else 1.0
    return f2 + d2 / (2.0**p - 1.0), p, bool(monotone)


def summarize(runs):
    out = {}
    for speed in SPEEDS:
        lv = [runs.get(key(speed, *t)) for t in TOGETHER]
        base = runs.get(key(speed, *BASE))
        if any(v is None for v in lv) or base is None:
            continue
        s = {}
        for o in OUTPUTS:
            lim, p, mono = richardson(*(v[o] for v in lv))
            s[o] = {"levels": [v[o] for v in lv], "limit": lim, "order": p, "monotone": mono,
                    "default": base[o], "default_error": base[o] - lim,
                    "default_relative_error": (base[o] - lim) / lim if abs(lim) > 1e-9 else None,
                    "axes": {ax: [[list(t), runs[key(speed, *t)][o]] for t in ts if key(speed, *t) in runs]
                             for ax, ts in AXES.items()}}
        s["wall_time_s"] = {"default": base["wall_time_s"], "levels": [v["wall_time_s"] for v in lv]}
        out[f"{speed:g}"] = s
    return out


def figure(runs: dict, out_dir: Path) -> None:
    """L+ and P+ against the refinement of each axis alone and of all together, one column per speed."""
    from hawksim import plotting
    with plotting.style():
        plt = plotting.pyplot()
        fig, axes = plt.subplots(2, len(SPEEDS), figsize=(plotting.WIDE, 5.2), squeeze=False)
        base_of = {"n_chord": 0, "n_span": 1, "steps_per_cycle": 2}
        for col, speed in enumerate(sorted(SPEEDS)):
            for row, o in enumerate(("L_plus", "P_plus")):
                ax = axes[row, col]
                for name, ts in list(AXES.items())[:3]:
                    i = base_of[name]
                    pts = sorted((t[i] / BASE[i], runs[key(speed, *t)][o]) for t in [BASE] + ts
                                 if key(speed, *t) in runs and "error" not in runs[key(speed, *t)])
                    ax.plot(*zip(*pts), "o-", ms=3, label=name.replace("_", " ") + " alone")
                pts = [(t[0] / BASE[0], runs[key(speed, *t)][o]) for t in TOGETHER if key(speed, *t) in runs]
                ax.plot(*zip(*pts), "ks-", ms=4, label="all together")
                ax.set(xscale="log", xlabel="refinement (x the default)", ylabel=o.replace("_plus", "+"),
                       title=f"V = {speed:g} m/s", xticks=[0.5, 1, 2, 4], xticklabels=["0.5", "1", "2", "4"])
                ax.minorticks_off()
                if row == 0 and col == 0:
                    ax.legend()
        plotting.save(fig, out_dir / "uvlm_resolution.png", title="The hawkmoth case against the resolution",
                      caption="Table 3's kinematics, held body, third beat; the default is 6 x 12 rings, 40 steps "
                              "per beat (refinement 1); together: 4 x 8 / 40, 8 x 16 / 80, 16 x 32 / 160.")


def main():
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--out", required=True)
    ap.add_argument("--summary", action="store_true")
    ap.add_argument("--figures", help="folder for the figure")
    a = ap.parse_args()
    path = Path(a.out)
    data = json.loads(path.read_text()) if path.exists() else {"runs": {}}
    data["command"] = "python " + " ".join(sys.argv)
    runs = data["runs"]
    todo = []
    for speed in SPEEDS:
        todo += [(speed, *BASE)] + [(speed, *t) for ts in AXES.values() for t in ts] + [(speed, *t) for t in TOGETHER]
    for item in todo:
        k = key(*item)
        if k in runs or a.summary:
            continue
        try:
            runs[k] = run_one(*item)
        except (FloatingPointError, ValueError) as e:  # a diverged wake or a step too coarse: said as such
            runs[k] = {"error": str(e)}
        print(f"{k}: {json.dumps(runs[k])}", file=sys.stderr, flush=True)
        tmp = path.with_suffix(".tmp")
        tmp.write_text(json.dumps(data, indent=1))
        tmp.replace(path)
    data["summary"] = summarize({k: v for k, v in runs.items() if "error" not in v})
    tmp = path.with_suffix(".tmp")
    tmp.write_text(json.dumps(data, indent=1))
    tmp.replace(path)
    if a.figures:
        figure(runs, Path(a.figures))
    print(json.dumps(data["summary"]))


if __name__ == "__main__":
    main()
