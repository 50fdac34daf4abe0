"""Study: the UVLM's opt-in mixed-precision wake convection (``UVLMConfig.wake_precision="mixed"``) against float64.

Prints ONE JSON object. Cases (issue 23, item 2): the reference case of scripts/benchmarks/bench_uvlm.py (two
flapping wings as mirror images, 8 x 16 rings, 3 beats, 220 steps, free wake; cycle averages of the last beat:
lift F_z, drag F_x, pitching moment M_y about the hinge and power), and hawksim's held-body evaluation at the
default resolution with Table 3's kinematics at hover and 2 m/s (L+, D+, M+, P+ of the last beat). For each:
both precisions' values, the relative difference |mixed - float64| / |float64| per output (and relative to the
largest output, for outputs near zero), whether all are within ``BOUND``, and the wall times side by side
(``--repeats`` alternations, the machine's load average at each).

    python -m scripts.studies.mixed_precision [--repeats 2] [--out FILE]
"""

from __future__ import annotations

import argparse
import sys
import time

import numpy as np

from scripts.benchmarks.bench_uvlm import reference_wing  # noqa: I001  (imports aero first)

from aero.uvlm import UVLMConfig, run_prescribed  # noqa: E402
from aero.uvlm_kinematics import two_wing_motion  # noqa: E402
from hawksim.backends.held import held_flight  # noqa: E402
from hawksim.backends.resolution import DEFAULT  # noqa: E402
from hawksim.backends.uvlm import UVLMBackend  # noqa: E402
from hawksim.insect.kinematics import table3_kinematics  # noqa: E402
from hawksim.insect.morphology import RHO_AIR  # noqa: E402
from hawksim.jsonout import emit  # noqa: E402

BOUND = 1e-4
"""Issue 23's error bound on the cycle averages (relative to the float64 values)."""

PRECISIONS = ("float64", "mixed")


def _load():
    try:
        return float(open("/proc/loadavg").read().split()[0])
    except OSError:
        return None


def reference(precision: str, steps: int = 220) -> dict:
    t = np.linspace(0.0, 3 / 25.0 * steps / 220, steps)  # 220 steps per 3 beats, as bench_uvlm.py
    R, o, v, w = two_wing_motion(t, freq=25.0)
    plane = (np.zeros(3), np.array([0.0, 1.0, 0.0]))
    res = run_prescribed([reference_wing()], UVLMConfig(wake_precision=precision), t, R[:, :1], o[:, :1],
                         v[:, :1], w[:, :1], mirror_plane=plane)
    last = slice(steps - steps // 3, steps)
    f, m = 2 * res.force[last, 0], res.moment[last, 0]
    return {"F_z_N": float(f[:, 2].mean()), "F_x_N": float(f[:, 0].mean()), "M_y_N_m": float(2 * m[:, 1].mean()),
            "P_W": float(2 * res.power[last].mean())}


def held(precision: str, speed: float) -> dict:
    backend = UVLMBackend(n_chord=DEFAULT.n_chord, n_span=DEFAULT.n_span,
                          config=UVLMConfig(rho=RHO_AIR, wake_precision=precision))
    a = held_flight(table3_kinematics(speed), speed, backend, cycles=DEFAULT.cycles,
                    average_cycles=DEFAULT.average_cycles, steps_per_cycle=DEFAULT.steps_per_cycle).averages
    return {"L_plus": a.L_plus, "D_plus": a.D_plus, "M_plus": a.M_plus, "P_plus": a.P_plus}


CASES = {"reference": reference, "hover": lambda p: held(p, 0.0), "2 m/s": lambda p: held(p, 2.0)}


def main() -> None:
    ap = argparse.ArgumentParser()
    ap.add_argument("--repeats", type=int, default=2)
    ap.add_argument("--out")
    args = ap.parse_args()
    reference("float64", steps=4)
    reference("mixed", steps=4)
    out = {"command": " ".join(["python", *sys.argv]), "bound": BOUND, "cases": {}}
    for name, case in CASES.items():
        values, walls, loads = {}, {p: [] for p in PRECISIONS}, {p: [] for p in PRECISIONS}
        for _ in range(args.repeats):
            for p in PRECISIONS:
                loads[p].append(_load())
                t0 = time.perf_counter()
                values[p] = case(p)
                walls[p].append(round(time.perf_counter() - t0, 2))
        ref, mix = values["float64"], values["mixed"]
        scale = max(abs(x) for x in ref.values())
        rel = {k: abs(mix[k] - ref[k]) / abs(ref[k]) if ref[k] else float("inf") for k in ref}
        rel_scale = {k: abs(mix[k] - ref[k]) / scale for k in ref}
        out["cases"][name] = {"float64": ref, "mixed": mix, "relative": rel, "relative_to_largest": rel_scale,
                              "within_bound": all(r <= BOUND for r in rel.values()),
                              "wall_s": walls, "loadavg_1min": loads,
                              "speed_ratio_median": round(float(np.median(walls["float64"])
                                                                / np.median(walls["mixed"])), 3)}
    emit(out, args.out, host=True)


if __name__ == "__main__":
    main()
