"""Periodicity and round-off sensitivity of the free wake at the trim, and what wake regularisations do to it.

For each ascent speed (the shipped trim kinematics, `hawksim.trim.tables`) and each wake variant, the held-body
UVLM runs ``--beats`` wingbeats at `hawksim aero`'s resolution (6 x 12 rings, 40 steps per beat) twice: as is,
and with the flapping frequency changed by a relative 1e-10 (round-off level). Reported per run: L+, D+, M+, P+
of every wingbeat; per (speed, variant): the mean and standard deviation of L+ over beats 2..N (the wake's
beat-to-beat scatter) and the largest |L+ - L+'| between the two realizations over beats 2-4 and 2..N (how far
round-off is amplified). A periodic, insensitive wake has both near zero.

Variants (`aero.uvlm.UVLMConfig` fields): Ramasamy & Leishman's rotor a' (the default before this study);
with it, larger initial wake cores (``wake_core_chords``, a Krasny-type blob regularisation) or a wake truncated
to 2 beats (``max_wake_rows``, as `hawksim fly` keeps 3); faster core growth (``a_prime`` 15, 50 and 150 times
the rotor value; 150 times, 1e-2, is the default since). Prints ONE JSON object.

    python scripts/studies/wake_sensitivity.py --out results/uvlm_wake_sensitivity.json
"""

import argparse
import json
import time

import numpy as np

from aero.uvlm import ROTOR_A_PRIME, UVLMConfig
from hawksim.backends.held import held_flight
from hawksim.backends.resolution import DEFAULT
from hawksim.backends.uvlm import RHO_AIR, UVLMBackend
from hawksim.insect.kinematics import ROUND_OFF_STEP, Kinematics, realization
from hawksim.jsonout import emit
from hawksim.trim.tables import trim_kinematics

VARIANTS = {
    "rotor_a_prime": {"a_prime": ROTOR_A_PRIME},
    "truncated_2_beats": {"max_wake_rows": 2 * DEFAULT.steps_per_cycle, "a_prime": ROTOR_A_PRIME},
    "wake_core_0.2c": {"wake_core_chords": 0.2, "a_prime": ROTOR_A_PRIME},
    "wake_core_0.5c": {"wake_core_chords": 0.5, "a_prime": ROTOR_A_PRIME},
    "a_prime_x15": {"a_prime": 1e-3},
    "a_prime_x50": {"a_prime": 3e-3},
    "a_prime_x150": {"a_prime": 1e-2},
}
"""Wake variants: Ramasamy-Leishman's rotor a' (the default before the study), the same truncated or with larger
initial cores, and faster core growth (1e-2 is now `UVLMConfig`'s default)."""


def per_beat(kin: Kinematics, speed: float, beats: int, config: UVLMConfig) -> np.ndarray:
    """(beats, 4): L+, D+, M+, P+ of every wingbeat."""
    backend = UVLMBackend(n_chord=DEFAULT.n_chord, n_span=DEFAULT.n_span, config=config)
    h = held_flight(kin, speed, backend, cycles=beats, average_cycles=1, steps_per_cycle=DEFAULT.steps_per_cycle)
    return np.array([(c.L_plus, c.D_plus, c.M_plus, c.P_plus) for c in h.per_cycle])


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("--speeds", type=float, nargs="+", default=[0.0, 0.5, 1.0, 2.0])
    ap.add_argument("--variants", nargs="+", default=list(VARIANTS), choices=list(VARIANTS))
    ap.add_argument("--beats", type=int, default=8)
    ap.add_argument("--merge", help="a JSON file written by this script: its rows are kept, these are added")
    ap.add_argument("--out")
    a = ap.parse_args()
    rows = []
    if a.merge:
        with open(a.merge) as f:
            old = json.load(f)
        if old["beats"] != a.beats:
            raise SystemExit(f"--merge {a.merge}: written with --beats {old['beats']}, not {a.beats}")
        rows = old["rows"]
    for v in a.speeds:
        kin = trim_kinematics(v)
        kin2 = realization(kin)
        for name in a.variants:
            cfg = UVLMConfig(rho=RHO_AIR, **VARIANTS[name])
            t0 = time.perf_counter()
            runs = []
            for k in (kin, kin2):
                try:
                    runs.append(per_beat(k, v, a.beats, cfg))
                except FloatingPointError as e:
                    runs.append(None)
                    print(f"V={v:g} {name}: {e}", flush=True)
            row = {"speed": v, "variant": name, "config": VARIANTS[name], "wall_time_s": time.perf_counter() - t0,
                   "per_beat": [r.tolist() if r is not None else None for r in runs]}
            if all(r is not None for r in runs):
                L = runs[0][1:, 0]
                dL = np.abs(runs[0][:, 0] - runs[1][:, 0])
                row.update({"L_plus_mean_beats_2_N": float(L.mean()), "L_plus_std_beats_2_N": float(L.std(ddof=1)),
                            "realization_dL_max_beats_2_4": float(dL[1:4].max()),
                            "realization_dL_max_beats_2_N": float(dL[1:].max())})
            rows.append(row)
            print(f"V={v:g} {name}: " + " ".join(f"{l:.3f}" for l in runs[0][:, 0]) if runs[0] is not None else "",
                  flush=True)
    emit({"resolution": DEFAULT.to_dict(), "beats": a.beats, "realization_step": ROUND_OFF_STEP, "rows": rows},
         a.out)


if __name__ == "__main__":
    main()
