"""Figs. 15-19 against the paper's statements (Sec. 3.3): the cycle-averaged eigenvalues and derivatives of a
`hawksim reproduce` stability stage, each qualitative statement of the paper checked with its numbers, beside a
previous run of the same stage.

The paper gives its eigenvalue plots (Figs. 15, 17-19) and derivative plots (Fig. 16) without tables; what its text
states about them is checked here, one statement a row (the paper's words quoted in ``STATEMENTS``).

    python -m scripts.studies.stability_vs_paper --studies results/stability_table3/stability_studies.json \
        --previous-ref 1ae352a --out results/stability_table3/paper_comparison.json

``--previous-ref`` reads the same file at a git revision (hawksim 0.2's results live on main before the merge).
Prints a markdown table of the eigenvalues per speed and the statements with their measured numbers.
"""

from __future__ import annotations

import argparse
import json
import subprocess
from pathlib import Path

import numpy as np

STATEMENTS = {
    "long_unstable": "the longitudinal dynamic system is unstable for all speeds ranging from 0 to 2.0 m/s",
    "long_structure": "below 1.5 m/s two stable subsidence modes and an unstable oscillatory mode; from 1.5 m/s "
                      "two separate unstable nonoscillatory modes",
    "long_fast_left": "the eigenvalue of the fast subsidence mode moves leftward when the model ascends faster",
    "long_slow_fixed": "the slow subsidence mode appears to be independent of the ascending speed",
    "long_imag_falls": "the imaginary parts decrease (the oscillation is weakened)",
    "lat_structure": "lateral: an unstable oscillatory mode, a slow and a fast subsidence mode (Figs. 15b, 18, 19)",
    "lat_fast_left": "the fast subsidence mode moves leftward as the ascending speed increases (Fig. 15b)",
    "nr_grows": "N_r+ is profoundly affected by the ascending speed: larger (damping) at a faster ascent (Fig. 16b)",
    "long_derivs_flat": "the ascending speed has very little influence on the longitudinal derivatives (Fig. 16a)",
}
"""The paper's statements on Figs. 15-19 (Nguyen et al. 2020, Sec. 3.3; quoted or closely paraphrased)."""


def _eig(lst) -> np.ndarray:
    return np.array([complex(re, im) for re, im in lst])


def _modes(eigs: np.ndarray) -> dict:
    """Sort one speed's four eigenvalues into the paper's mode names (real ones by real part)."""
    real = np.sort(eigs[np.abs(eigs.imag) < 1e-12].real)
    osc = eigs[eigs.imag > 1e-12]
    return {"real": real.tolist(), "oscillatory": [[z.real, z.imag] for z in osc]}


def compare(studies: dict) -> dict:
    """Each statement of :data:`STATEMENTS`: (holds, the numbers that decide it) for one stability_studies.json."""
    speeds = studies["speeds"]
    lon = [_eig(e) for e in studies["fig15"]["longitudinal"]]
    lat = [_eig(e) for e in studies["fig15"]["lateral"]]
    lon_m, lat_m = [_modes(e) for e in lon], [_modes(e) for e in lat]
    out = {}
    max_re = [float(e.real.max()) for e in lon]
    out["long_unstable"] = (all(r > 0 for r in max_re), {"max_real": max_re})
    shape = [(sum(r < 0 for r in m["real"]), len(m["oscillatory"]), sum(r > 0 for r in m["real"])) for m in lon_m]
    want = [(2, 1, 0) if v < 1.5 else (2, 0, 2) for v in speeds]
    out["long_structure"] = (shape == want, {"stable_real, oscillatory_pairs, unstable_real": shape})
    fast = [m["real"][0] for m in lon_m]
    out["long_fast_left"] = (all(np.diff(fast) < 0), {"fast_subsidence": fast})
    slow = [m["real"][1] for m in lon_m]
    # "appears independent" on the paper's plot, whose scale the fast mode's travel sets: the slow mode's range
    # under a quarter of the fast mode's (a reading of the figure, stated)
    out["long_slow_fixed"] = (float(np.ptp(slow)) < 0.25 * float(np.ptp(fast)),
                              {"slow_subsidence": slow, "slow_range_over_fast_range":
                               float(np.ptp(slow) / np.ptp(fast))})
    imag = [m["oscillatory"][0][1] if m["oscillatory"] else 0.0 for m in lon_m]
    out["long_imag_falls"] = (all(np.diff(imag) <= 0), {"long_oscillatory_imag": imag})
    lat_shape = [(len(m["oscillatory"]), sum(r < 0 for r in m["real"]),
                  bool(m["oscillatory"]) and m["oscillatory"][0][0] > 0) for m in lat_m]
    out["lat_structure"] = (all(s == (1, 2, True) for s in lat_shape),
                            {"oscillatory_pairs, stable_real, oscillatory_unstable": lat_shape})
    lat_fast = [m["real"][0] if m["real"] else None for m in lat_m]
    out["lat_fast_left"] = (lat_fast[-1] is not None and lat_fast[0] is not None and lat_fast[-1] < lat_fast[0],
                            {"fast_subsidence": lat_fast})
    nr = studies["fig16"]["lateral"]["Nr"]
    out["nr_grows"] = (abs(nr[-1]) > 1.5 * abs(nr[0]), {"Nr_plus": nr})
    d = studies["fig16"]["longitudinal"]
    spread = {k: float(np.ptp(v) / max(np.max(np.abs(v)), 1e-12)) for k, v in d.items()}
    out["long_derivs_flat"] = (float(np.median(list(spread.values()))) < 0.3,
                               {"range_over_max_by_derivative": spread,
                                "median": float(np.median(list(spread.values())))})
    return {"speeds": speeds, "longitudinal": lon_m, "lateral": lat_m,
            "statements": {k: {"paper": STATEMENTS[k], "holds": bool(h), "measured": m}
                           for k, (h, m) in out.items()}}


def _fmt(m: dict) -> str:
    parts = [f"{r:+.3f}" for r in m["real"]] + [f"{re:+.3f}±{im:.3f}i" for re, im in m["oscillatory"]]
    return ", ".join(parts)


def markdown(now: dict, prev: dict | None) -> str:
    rows = ["| V (m/s) | longitudinal (this run) | lateral (this run) | longitudinal (previous) | lateral (previous) |",
            "|---|---|---|---|---|"]
    for i, v in enumerate(now["speeds"]):
        p = ("", "") if prev is None else (_fmt(prev["longitudinal"][i]), _fmt(prev["lateral"][i]))
        rows.append(f"| {v:g} | {_fmt(now['longitudinal'][i])} | {_fmt(now['lateral'][i])} | {p[0]} | {p[1]} |")
    rows += ["", "| paper's statement | this run | previous |", "|---|---|---|"]
    for k, s in now["statements"].items():
        before = "" if prev is None else ("holds" if prev["statements"][k]["holds"] else "departs")
        rows.append(f"| {s['paper']} | {'holds' if s['holds'] else 'departs'} | {before} |")
    return "\n".join(rows)


def main(argv=None) -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--studies", type=Path, default=Path("results/stability_table3/stability_studies.json"))
    ap.add_argument("--previous-ref", help="git revision whose copy of --studies is the previous run")
    ap.add_argument("--out", type=Path)
    a = ap.parse_args(argv)
    now = compare(json.loads(a.studies.read_text()))
    prev = None
    if a.previous_ref:
        text = subprocess.run(["git", "show", f"{a.previous_ref}:{a.studies.as_posix()}"], check=True,
                              capture_output=True, text=True).stdout
        prev = compare(json.loads(text))
    print(markdown(now, prev))
    if a.out:
        a.out.write_text(json.dumps({"command": "python -m scripts.studies.stability_vs_paper", "studies":
                                     str(a.studies), "previous_ref": a.previous_ref, "now": now, "previous": prev},
                                    indent=1, default=lambda o: o.item()) + "\n")


if __name__ == "__main__":
    main()
