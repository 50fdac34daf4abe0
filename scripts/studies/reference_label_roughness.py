"""Is `hawksim aero` a smooth function of the kinematics? The reference labels under small kinematic steps
(issue 22, item 3).

A label is `hawksim aero`'s output itself (:data:`hawksim.backends.resolution.REFERENCE`, the third wingbeat from
rest), a deterministic function y(x) of the kinematics x, so a surrogate is not bounded by the labels' beat-to-beat
scatter (``scripts/studies/reference_label_noise.py``) as such: it is bounded by how rough y(x) is at the scale of
the data set's sample spacing. This script measures that roughness directly. For each held-out kinematics x (seed
22, the periodic ones of ``--labels``, as reference_label_noise.py) and a random unit direction u (seeded by
``--seed-dir`` and the speed; u is scaled per parameter by Table 2's range,
:func:`hawksim.surrogate.dataset.bounds_si`), the label is evaluated at x - h u, x, x + h u for each relative step
h of ``--steps`` and scored by

* ``first``: |y(x + h u) - y(x)|, the change a step of h (a fraction of Table 2's ranges) makes;
* ``second``: |y(x + h u) - 2 y(x) + y(x - h u)|, the central second difference. For a smooth (twice
  differentiable) y it falls as h^2; a part of y that varies on scales below h (sensitive dependence of the free
  wake) leaves it at that part's amplitude, whatever h. A surrogate, a smooth function fitted to samples ~0.3 of
  the ranges apart in 8 dimensions, cannot follow such a part: its amplitude is the floor of the max-error target.

Every point is evaluated as a data-set sample is (:func:`hawksim.surrogate.dataset.evaluate_kinematics`) and
given the data set's status: 'diverged' (the UVLM blew up, or its peak force coefficient is above
:data:`hawksim.surrogate.dataset.PEAK_FORCE_CEILING`: a wake vortex crossing the lattice) or 'unsettled' (beat 3
differs from beat 2 by more than SETTLE_TOL) points are counted (``perturbed_status``) and the differences are
scored twice: over every point (``all``, `hawksim aero`'s outputs as a user gets them) and over the triples whose
three points are all 'ok' (``ok``, the population the held-out targets are scored on). Points that leave Table 2's
bounds are clipped to them (the direction is then shortened, the same for +h and -h). The stored label is checked
against a fresh run at x (deterministic: equal to 1e-9). Prints ONE JSON object.

    NUMBA_NUM_THREADS=1 python -m scripts.studies.reference_label_roughness --samples 20 \\
        --out results/surrogate/reference_label_roughness.json
"""

from __future__ import annotations

import argparse
import shlex
import sys
from pathlib import Path

import numpy as np
from tqdm import tqdm

from hawksim.backends.network import SHIPPED_SPEEDS
from hawksim.backends.resolution import REFERENCE
from hawksim.insect.kinematics import Kinematics
from hawksim.jsonout import emit, host_info
from hawksim.surrogate.dataset import OUTPUTS, bounds_si, evaluate_kinematics, speed_key

from scripts.studies.surrogate_vs_reference import read_labels

MATCH_TOL = 1e-9
"""A fresh run at x against the stored label: the same deterministic computation (max |difference|)."""
STEPS = (1e-7, 1e-4, 1e-2, 5e-2)
"""Default relative steps h (fractions of Table 2's ranges along a unit direction)."""


def label(x: np.ndarray, v: float) -> tuple[np.ndarray | None, str]:
    """`hawksim aero`'s L+, D+, M+, P+ at kinematics x (Kinematics.from_array order) and speed v (None where the
    UVLM blew up) and the data set's status of that evaluation."""
    s = evaluate_kinematics(Kinematics.from_array(x), v, REFERENCE)
    return (None if s.y is None else np.asarray(s.y)), s.status


def summary(values: np.ndarray) -> dict:
    """Median, 90th percentile and max per output of |values| (n, 4)."""
    a = np.abs(values)
    return {name: {"median": float(np.median(a[:, j])), "p90": float(np.percentile(a[:, j], 90)),
                   "max": float(a[:, j].max())} for j, name in enumerate(OUTPUTS)}


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("--seed", type=int, default=22, help="seed of the held-out kinematics")
    ap.add_argument("--seed-dir", type=int, default=0, help="seed of the step directions")
    ap.add_argument("--samples", type=int, default=20, help="held-out samples per speed (index order)")
    ap.add_argument("--speeds", type=float, nargs="+", default=list(SHIPPED_SPEEDS))
    ap.add_argument("--steps", type=float, nargs="+", default=list(STEPS))
    ap.add_argument("--labels", default="data/uvlm_reference_heldout_s22.sqlite")
    ap.add_argument("--out")
    a = ap.parse_args()
    if not Path(a.labels).exists():
        sys.exit(f"error: --labels {a.labels}: no such file (run scripts/studies/surrogate_vs_reference.py first)")
    if any(not (0.0 < h < 1.0) for h in a.steps):
        sys.exit(f"error: --steps must lie in (0, 1), got {a.steps}")
    lo, hi = bounds_si()
    began = host_info()
    per_speed = {}
    for v in a.speeds:
        lab = read_labels(a.labels, v, a.seed, a.samples)
        ok = np.flatnonzero(lab["status"] == "ok")
        rng = np.random.default_rng([a.seed_dir, speed_key(v)])  # the directions of one speed: any subset of speeds
        first = {h: {"all": [], "ok": []} for h in a.steps}
        second = {h: {"all": [], "ok": []} for h in a.steps}
        statuses = {h: {} for h in a.steps}
        worst_match, diverged = 0.0, 0
        bar = tqdm(total=len(ok) * (1 + 2 * len(a.steps)), desc=f"V={v:g} m/s", file=sys.stderr, disable=None)
        for k in ok:
            x = lab["x"][k]
            u = rng.normal(size=x.size)
            u /= np.linalg.norm(u)
            y0, st0 = label(x, v)
            bar.update(1)
            if y0 is None:
                diverged += 1
                bar.update(2 * len(a.steps))
                continue
            worst_match = max(worst_match, float(np.max(np.abs(y0 - lab["y"][k]))))
            for h in a.steps:
                d = h * u * (hi - lo)
                # shorten the step so that both x + d and x - d stay within the bounds
                room = np.min(np.where(d != 0, np.minimum((hi - x) / np.abs(d), (x - lo) / np.abs(d)), np.inf))
                d = d * min(1.0, room)
                (yp, sp), (ym, sm) = label(x + d, v), label(x - d, v)
                bar.update(2)
                for st in (sp, sm):
                    statuses[h][st] = statuses[h].get(st, 0) + 1
                if yp is None or ym is None:
                    diverged += 1
                    continue
                keep = ("all", "ok") if st0 == sp == sm == "ok" else ("all",)
                for key in keep:
                    first[h][key].append(yp - y0)
                    second[h][key].append(yp - 2.0 * y0 + ym)
        bar.close()
        if worst_match > MATCH_TOL:
            sys.exit(f"error: a fresh run differs from the stored label by {worst_match:.3g} at V={v:g} "
                     "(labels file from another version?)")
        per_speed[f"{v:g}"] = {
            "n": int(len(ok)), "diverged": diverged, "fresh_run_matches_stored_label_to": worst_match,
            "steps": {f"{h:g}": {"perturbed_status": statuses[h],
                                 **{key: {"first": summary(np.asarray(first[h][key])),
                                          "second": summary(np.asarray(second[h][key])), "n": len(first[h][key])}
                                    for key in ("all", "ok") if first[h][key]}} for h in a.steps}}
        row = "  ".join(f"h={h:g}: L+ d1 max all {np.abs(np.asarray(first[h]['all'])[:, 0]).max():.2g} "
                        f"ok {np.abs(np.asarray(first[h]['ok'])[:, 0]).max() if first[h]['ok'] else np.nan:.2g}"
                        for h in a.steps if first[h]["all"])
        print(f"V={v:g}: {row}", file=sys.stderr)
    ended = host_info()
    command = shlex.join(["python", "-m", "scripts.studies.reference_label_roughness", *sys.argv[1:]])
    emit({"command": command, "began": began["date"], "ended": ended["date"], "loadavg_before": began["loadavg"],
          "loadavg_after": ended["loadavg"], "seed": a.seed, "seed_dir": a.seed_dir, "samples_per_speed": a.samples,
          "resolution": REFERENCE.to_dict(), "labels": a.labels, "per_speed": per_speed}, a.out)


if __name__ == "__main__":
    main()
