"""How well can any surrogate match `hawksim aero`? The reference labels' own beat-to-beat scatter (issue 22, item 3).

`hawksim aero` (and every held-out label of ``scripts/studies/surrogate_vs_reference.py``) averages ONE wingbeat,
the third of a run from rest at :data:`hawksim.backends.resolution.REFERENCE` (6 x 12 rings, 40 steps per beat).
Where the free wake is not periodic (hover: it stays under the wings, docs/uvlm.md) that average scatters from beat
to beat, and no function of the kinematics can follow the scatter. Here the same held-out kinematics (seed 22,
indices 0..n-1, drawn by :func:`hawksim.surrogate.dataset.sample_kinematics`) are run for ``--beats`` wingbeats
(6 by default) and scored four ways, per speed and output:

* ``uvlm_mean_vs_label``: the mean of beats 3..B (the UVLM's own best estimate of the periodic average) as a
  "predictor" of the beat-3 label: the score a perfect, noise-free surrogate would get against `hawksim aero`;
* ``uvlm_beat4_vs_label``: beat 4 against beat 3 (what `hawksim aero --cycles 4` against `--cycles 3` shows a user);
* per network (``shipped``, ``reference``): against the beat-3 label (the issue's measure, as in
  results/surrogate/reference_fidelity.json) and against the mean of beats 3..B.

Scored over the samples the held-out file calls 'ok' (``--labels``, as surrogate_vs_reference.py) whose B-beat run
did not diverge; beat 3 of each run is checked against the stored label (the runs are deterministic). Error scores
are surrogate_vs_reference.py's (mean, 95th percentile, max |error|, R^2). Prints ONE JSON object.

    NUMBA_NUM_THREADS=1 python -m scripts.studies.reference_label_noise --samples 100 --beats 6 \\
        --out results/surrogate/reference_label_noise.json
"""

from __future__ import annotations

import argparse
import shlex
import sys
from pathlib import Path

import numpy as np
from tqdm import tqdm

from hawksim.backends.held import beat_averages
from hawksim.backends.network import NETWORKS, SHIPPED_SPEEDS, default_for_speed
from hawksim.backends.resolution import REFERENCE
from hawksim.insect.kinematics import Kinematics
from hawksim.jsonout import emit, host_info

from scripts.studies.surrogate_vs_reference import error_scores, meets, read_labels

LABEL_BEAT = REFERENCE.cycles - 1
"""Row of beat_averages that is `hawksim aero`'s label (beat 3 of 3, zero-based 2)."""
MATCH_TOL = 1e-9
"""Beat 3 of a longer run against the stored label: the same deterministic computation (max |difference|)."""


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("--seed", type=int, default=22)
    ap.add_argument("--samples", type=int, default=100)
    ap.add_argument("--speeds", type=float, nargs="+", default=list(SHIPPED_SPEEDS))
    ap.add_argument("--beats", type=int, default=6, help="wingbeats per run (>= 4); the mean is over beats 3..B")
    ap.add_argument("--labels", default="data/uvlm_reference_heldout_s22.sqlite")
    ap.add_argument("--out")
    a = ap.parse_args()
    if a.beats < REFERENCE.cycles + 1:
        sys.exit(f"error: --beats must be >= {REFERENCE.cycles + 1}, got {a.beats}")
    if not Path(a.labels).exists():
        sys.exit(f"error: --labels {a.labels}: no such file (run scripts/studies/surrogate_vs_reference.py first)")
    began = host_info()
    per_speed = {}
    for v in a.speeds:
        lab = read_labels(a.labels, v, a.seed, a.samples)
        ok = np.flatnonzero(lab["status"] == "ok")
        beats, keep, worst_match = [], [], 0.0
        bar = tqdm(total=len(ok), desc=f"V={v:g} m/s, {a.beats} beats", file=sys.stderr, disable=None)
        for k in ok:
            kin = Kinematics.from_array(lab["x"][k])
            try:
                b = beat_averages(kin, v, REFERENCE, a.beats)
            except FloatingPointError:
                b = None
            if b is not None and np.all(np.isfinite(b)):
                worst_match = max(worst_match, float(np.max(np.abs(b[LABEL_BEAT] - lab["y"][k]))))
                beats.append(b)
                keep.append(k)
            bar.update(1)
        bar.close()
        if worst_match > MATCH_TOL:
            sys.exit(f"error: beat {LABEL_BEAT + 1} of a {a.beats}-beat run differs from the stored label by "
                     f"{worst_match:.3g} at V={v:g} (labels file from another version?)")
        B = np.asarray(beats)                      # (n, beats, 4)
        keep = np.asarray(keep, dtype=int)
        label, mean = B[:, LABEL_BEAT], B[:, LABEL_BEAT:].mean(axis=1)
        entry = {"n": int(len(keep)), "n_ok_in_file": int(len(ok)), "n_diverged_longer": int(len(ok) - len(keep)),
                 "beat3_matches_stored_label_to": worst_match,
                 "uvlm_mean_vs_label": error_scores(label, mean),
                 "uvlm_beat4_vs_label": error_scores(label, B[:, LABEL_BEAT + 1]),
                 "label_rms_about_mean": dict(zip(("L_plus", "D_plus", "M_plus", "P_plus"),
                                                  np.sqrt(np.mean((label - mean) ** 2, axis=0)).tolist())),
                 "label_std": dict(zip(("L_plus", "D_plus", "M_plus", "P_plus"), label.std(axis=0).tolist())),
                 "networks": {}}
        for fam in NETWORKS:
            try:
                net = default_for_speed(v, fam)
            except ValueError:
                continue
            p = net.predict(lab["x"][keep], v)
            vs_label, vs_mean = error_scores(label, p), error_scores(mean, p)
            entry["networks"][fam] = {"vs_label": vs_label, "meets_vs_label": meets(vs_label),
                                      "vs_mean": vs_mean, "meets_vs_mean": meets(vs_mean)}
        per_speed[f"{v:g}"] = entry
        nets = "  ".join(f"{f}: R2 L+ {e['vs_label']['L_plus']['r2']:.4f} -> {e['vs_mean']['L_plus']['r2']:.4f}, "
                         f"max {e['vs_label']['L_plus']['max_abs']:.3f} -> {e['vs_mean']['L_plus']['max_abs']:.3f}"
                         for f, e in entry["networks"].items())
        u = entry["uvlm_mean_vs_label"]["L_plus"]
        print(f"V={v:g} n {entry['n']}: UVLM mean vs label R2 L+ {u['r2']:.4f} max {u['max_abs']:.3f}; {nets}",
              file=sys.stderr)
    ended = host_info()
    command = shlex.join(["python", "-m", "scripts.studies.reference_label_noise", *sys.argv[1:]])
    emit({"command": command, "began": began["date"], "ended": ended["date"], "loadavg_before": began["loadavg"],
          "loadavg_after": ended["loadavg"], "seed": a.seed, "samples_per_speed": a.samples, "beats": a.beats,
          "mean_over_beats": [LABEL_BEAT + 1, a.beats], "resolution": REFERENCE.to_dict(), "labels": a.labels,
          "per_speed": per_speed}, a.out)


if __name__ == "__main__":
    main()
