"""Issue 23's speed targets measured in one sitting: every benchmark one after the other, then ONE JSON summary.

Stages (each a subprocess of the benchmark named, its JSON kept as ``OUT/<stage>.raw.json`` and, with the
stage's command, times and load average, as ``OUT/<stage>.json``; a stage whose file is
already there is not run again, so an interrupted sitting resumes, and ``--force`` reruns them all):

* ``ptera``: scripts/benchmarks/bench_pterasoftware.py (PteraSoftware 5.1.0 on the reference case);
* ``uvlm``: scripts/benchmarks/bench_uvlm.py --ptera-json OUT/ptera.json (the reference case, the ratio to
  PteraSoftware, `hawksim aero` warm and as a command);
* ``fly``: scripts/benchmarks/bench_treecode.py --sections crossover fly roofline (a 20-wingbeat
  `hawksim fly --aero uvlm` with a 10-wingbeat wake, direct, tree and auto; the wake sizes of a held-body flight
  after 1-10 beats; the FMA roofline of this CPU and the lattice kernel's fraction of it);
* ``uvlm<W>``, ``fly<W>``: the ``uvlm`` stage and the ``fly`` stage's flights (``--sections fly``) again at the
  other vector width W (``HAWKSIM_VECTOR_WIDTH=W``, aero.vector_width): 512 where the host's default is 256 (Intel
  Xeons), 256 where it is 512 (AMD Zen 5), reported beside the default's (``other_vector_width``); every stage says
  the width it ran (``vector_bits``, read off the compiled code); on a host without AVX-512F both widths run the
  256-bit code and the summary says so (``available``); the default stages run with HAWKSIM_VECTOR_WIDTH and
  NUMBA_CPU_FEATURES removed from their environment;
* ``cold``: scripts/benchmarks/bench_cold_start.py --variant new=HEAD (the first `hawksim aero` after an install,
  with the README's `hawksim warmup` step, and without it);
* ``contention``: scripts/benchmarks/bench_contention.py (1 and 2 threads, idle and with one core busy);
* ``datasets`` (unless ``--skip-datasets``): scripts/benchmarks/time_datasets.sh OUT/datasets (the 5 x 3000
  training-lattice set and the 5 x 1000 reference-lattice correction set, ~75 min on the 2 cores).

The summary (``OUT/summary.json`` and stdout) has, per target, the measured value, the target, whether it is met,
and the stage's load average before and after; the host and the sitting's first and last time. For the 10-beat
wake it also gives the pair rate the target needs, from the measured wake sizes, against the most this CPU's FMA
pipes can deliver at the lattice kernel's lane-operations per pair (the roofline section): where the first
exceeds the second the direct sum cannot meet the target on this machine at any efficiency. For the reference
case likewise (``reference_case_floor``): its counted pair evaluations at the lattice kernel's measured rate and
at the FMA ceiling, the speed-ups over PteraSoftware they allow, and the pair rate 50x needs.

    python -m scripts.benchmarks.bench_targets --out-dir results/targets_2026-12-02 [--skip-datasets] [--force]
"""
from __future__ import annotations

import argparse
import json
import os
import subprocess
import sys
import time

from hawksim.jsonout import emit, host_info
from scripts.benchmarks.roofline import lane_peak, pair_ceiling, roofline_fractions

HERE = os.path.dirname(os.path.abspath(__file__))
REPO = os.path.dirname(os.path.dirname(HERE))

FLY_STEPS_PER_BEAT = 40
"""UVLM steps per wingbeat of the fly backend (hawksim.backends: the fly lattice), as in bench_treecode's wakes."""
FLY_CYCLES = 20
FLY_WAKE_CYCLES = 10

TARGETS = {
    "speedup_vs_ptera": (50.0, ">="),
    "aero_warm_s": (0.5, "<="),
    "fly_10_beat_wake_wingbeats_per_s": (1.0, ">="),
    "datasets_elapsed_min": (120.0, "<="),
    "cold_first_aero_command_s": (3.0, "<="),
    "busy_core_2t_over_1t": (1.0, "<="),
}
"""Issue 23's targets (item 5; item 4's 3 s cold start; item 3: two threads never slower than one with a core busy)."""


def _load():
    return host_info()["loadavg"]


def _now():
    return host_info()["date"]


WIDTH_VARS = ("HAWKSIM_VECTOR_WIDTH", "NUMBA_CPU_FEATURES")
"""Environment variables that set the kernels' vector width (aero.vector_width): removed for the default stages."""


def default_vector_bits(py: str) -> int:
    """The vector width [bits] numba compiles for on this host by default (aero.vector_bits in a fresh process
    without :data:`WIDTH_VARS`)."""
    env = {k: v for k, v in os.environ.items() if k not in WIDTH_VARS}
    code = "import aero; from aero.vector_width import vector_bits; print(vector_bits())"
    proc = subprocess.run([py, "-c", code], cwd=REPO, env=env, capture_output=True, text=True, check=True)
    return int(proc.stdout.split()[-1])


def other_width(default_bits: int) -> int:
    """The vector width measured beside the default's: 256 where the default is 512, else 512."""
    return 256 if default_bits == 512 else 512


def _stages(out: str, py: str, other: int = 512) -> dict:
    b, m = os.path.join(HERE, ""), "scripts.benchmarks."  # the stages run in REPO: -m imports its scripts package
    return {
        "ptera": [py, "-m", m + "bench_pterasoftware"],
        "uvlm": [py, "-m", m + "bench_uvlm", "--ptera-json", os.path.join(out, "ptera.raw.json")],
        "fly": [py, "-m", m + "bench_treecode", "--sections", "crossover", "fly", "roofline", "--cycles",
                str(FLY_CYCLES)],
        f"uvlm{other}": [py, "-m", m + "bench_uvlm", "--ptera-json", os.path.join(out, "ptera.raw.json")],
        f"fly{other}": [py, "-m", m + "bench_treecode", "--sections", "fly", "--cycles", str(FLY_CYCLES)],
        "cold": [py, "-m", m + "bench_cold_start", "--variant", "new=HEAD", "--variant",
                 "new_nowarmup=HEAD:nowarmup"],
        "contention": [py, "-m", m + "bench_contention", "--repeats", "2"],
        "datasets": ["bash", b + "time_datasets.sh", os.path.join(out, "datasets")],
    }


OTHER_WIDTH_STAGES = ("uvlm256", "fly256", "uvlm512", "fly512")
"""Stage names of the other vector width (:func:`_stages`); their width is the name's."""


def stage_env(name: str) -> dict:
    """A stage's environment: the default stages without :data:`WIDTH_VARS`, the other-width stages with
    HAWKSIM_VECTOR_WIDTH from their name, the kernels' stages on 2 threads unless NUMBA_NUM_THREADS says."""
    env = {k: v for k, v in os.environ.items() if k not in WIDTH_VARS}
    if name in OTHER_WIDTH_STAGES:
        env["HAWKSIM_VECTOR_WIDTH"] = name[-3:]
    if name in ("fly", "uvlm", "ptera", *OTHER_WIDTH_STAGES):
        env.setdefault("NUMBA_NUM_THREADS", "2")
    return env


def run_stage(name: str, cmd: list[str], out: str, force: bool) -> dict:
    path = os.path.join(out, f"{name}.json")
    if os.path.exists(path) and not force:
        return json.load(open(path))
    env = stage_env(name)
    began, load0, t0 = _now(), _load(), time.perf_counter()
    print(f"{began} {name}: {' '.join(cmd)}", file=sys.stderr, flush=True)
    proc = subprocess.run(cmd, cwd=REPO, env=env, capture_output=True, text=True)
    if proc.returncode != 0:
        sys.stderr.write(proc.stderr[-4000:])
        raise SystemExit(f"bench_targets: stage {name} failed (exit {proc.returncode})")
    result = {"stage": {"command": " ".join(cmd), "began": began, "ended": _now(), "load_before": load0,
                        "load_after": _load(), "wall_s": round(time.perf_counter() - t0, 1)},
              "result": last_json(proc.stdout)}
    return _keep(name, result, out)


def last_json(stdout: str) -> dict:
    """The last JSON object a benchmark printed: one line, or indented over several (its first line '{')."""
    lines = stdout.splitlines()
    for i in range(len(lines) - 1, -1, -1):
        if lines[i].startswith("{"):
            try:
                return json.loads("\n".join(lines[i:]))
            except json.JSONDecodeError:
                continue
    raise SystemExit("bench_targets: the benchmark printed no JSON object")


def datasets_from_log(cmd: list[str], out: str) -> dict | None:
    """The datasets stage recorded from a finished OUT/datasets/run.log (the stage ran, its record did not get
    written), so that 77 minutes are not rerun: times and load averages from the log's first and last lines."""
    log = os.path.join(out, "datasets", "run.log")
    lines = open(log).read().splitlines() if os.path.exists(log) else []
    if not any(" done " in ln for ln in lines):
        return None
    first, last = lines[0].split(), next(ln for ln in reversed(lines) if " done " in ln).split()
    proc = subprocess.run([sys.executable, os.path.join(HERE, "time_datasets_summary.py"), log], cwd=REPO,
                          capture_output=True, text=True, check=True)
    summary = last_json(proc.stdout)
    stage = {"command": " ".join(cmd), "began": first[0], "ended": last[0],
             "load_before": [float(x) for x in first[first.index("load") + 1:first.index("load") + 4]],
             "load_after": [float(x) for x in last[last.index("load") + 1:last.index("load") + 4]],
             "wall_s": round(summary["elapsed_min"] * 60, 1), "recorded_from_log": True}
    return _keep("datasets", {"stage": stage, "result": summary}, out)


def _keep(name: str, result: dict, out: str) -> dict:
    path = os.path.join(out, f"{name}.json")
    with open(path, "w") as f:
        json.dump(result, f, indent=1)
    with open(os.path.join(out, f"{name}.raw.json"), "w") as f:  # the benchmark's own JSON, as it printed it
        json.dump(result["result"], f, indent=1)
    return result


def _met(name: str, value) -> bool | None:
    if value is None:
        return None
    target, sense = TARGETS[name]
    return bool(value >= target) if sense == ">=" else bool(value <= target)


def fly_floor(fly: dict) -> dict:
    """The pair rate a 20-beat flight with a 10-beat wake needs at 1 wingbeat/s, against the FMA ceiling.

    Pairs per convection call after b beats: wake segments x targets (with mirror images), measured by the
    crossover section at b = 10 and scaled as b^2 below it (wake sizes grow linearly in b; the measured b = 1-7
    figures follow this to a few per cent). Over the flight, beat k has a wake of min(k, 10) beats, each beat
    FLY_STEPS_PER_BEAT convection calls. This counts the wake-on-wake sum alone (the solve and the wings' share
    come on top), so the rate is a lower bound. Ceiling: all threads' FP lane-operations/s (:func:`lane_peak`, the
    wider of the 256- and 512-bit peaks) / the kernel's lane-operations per pair, i.e. the kernel at 100 % of the
    roofline. ``port_ceiling_g_pairs_s``: the tighter port model of roofline.pair_ceiling (the multiplies and FMAs
    per pair on the FMA pipes alone), the wider width's."""
    wakes = {w["beats"]: w for w in fly["crossover"]["uvlm_wakes_1ms"]}
    w10 = wakes[FLY_WAKE_CYCLES]
    pairs10 = w10["wake_segments"] * w10["targets"]
    units = sum(min(k, FLY_WAKE_CYCLES) ** 2 for k in range(1, FLY_CYCLES + 1)) / FLY_WAKE_CYCLES ** 2
    total_pairs = units * pairs10 * FLY_STEPS_PER_BEAT
    need = total_pairs / FLY_CYCLES  # pairs per second of wall time at 1 wingbeat/s
    roof = fly["roofline"]
    out = {"pairs_per_call_10_beat_wake": pairs10, "direct_call_s_10_beat_wake": w10["direct_s"],
           "wake_on_wake_pairs_per_flight": total_pairs, "needed_g_pairs_s_at_1_beat_per_s": round(need / 1e9, 2)}
    if roof.get("peak"):
        ceiling = max(lane_peak(roof, b) for b in ("256", "512")) / roof["lane_ops_per_pair"]
        achieved = max(v["all"] for v in roof["lattice_kernel_g_pairs_s"].values())
        ports = max(pair_ceiling(roof, b) for b in ("256", "512"))
        out.update({"fp_ceiling_g_pairs_s": round(ceiling, 2), "kernel_g_pairs_s": achieved,
                    "needed_over_ceiling": round(need / 1e9 / ceiling, 2),
                    "needed_over_kernel": round(need / 1e9 / achieved, 2),
                    "port_ceiling_g_pairs_s": round(ports, 2),
                    "needed_over_port_ceiling": round(need / 1e9 / ports, 2)})
    return out


FLOAT64_FLIGHTS = ("wake_10_direct", "wake_10_tree", "wake_10_auto")
"""bench_treecode's float64 flights with the 10-beat wake: the target's value is the fastest of them."""


def reference_floor(uvlm: dict, fly: dict | None, ptera_s: float | None) -> dict | None:
    """The reference case's kernel work against what 50x PteraSoftware needs: its counted edge-target pairs
    (bench_uvlm.reference_pairs), the time they take at the lattice kernel's measured rate (the uvlm stage's
    benchmark case, all threads) and at the FP ceiling (all threads' FP lane-operations/s at the stage's vector
    width, :func:`lane_peak`, / the kernel's lane-operations per pair), the speed-ups over PteraSoftware those
    times allow (the case's other work, 12-19 % of it on 2026-12-04, not counted: upper bounds), and the pair rate
    a 50x run would need for the pairs alone; likewise at roofline.pair_ceiling's port model
    (``port_ceiling_g_pairs_s``, ``speedup_bound_at_port_ceiling``)."""
    pairs = uvlm.get("reference_case_pairs")
    if not pairs or not ptera_s:
        return None
    rate = uvlm["lattice_kernel_geval_s"]
    target = TARGETS["speedup_vs_ptera"][0]
    out = {"vector_bits": uvlm.get("vector_bits"), "pairs": pairs, "kernel_g_pairs_s": rate,
           "kernel_only_s": round(pairs / rate / 1e9, 2),
           "speedup_bound_at_kernel_rate": round(ptera_s / (pairs / rate / 1e9), 1),
           "needed_g_pairs_s_for_target": round(pairs / (ptera_s / target) / 1e9, 2)}
    roof = (fly or {}).get("roofline") or {}
    if roof.get("peak"):
        ceiling = lane_peak(roof, str(uvlm.get("vector_bits", 256))) / roof["lane_ops_per_pair"]
        ports = pair_ceiling(roof, str(uvlm.get("vector_bits", 256)))
        out.update({"fp_ceiling_g_pairs_s": round(ceiling, 2),
                    "speedup_bound_at_fp_ceiling": round(ptera_s / (pairs / ceiling / 1e9), 1),
                    "port_ceiling_g_pairs_s": round(ports, 2),
                    "speedup_bound_at_port_ceiling": round(ptera_s / (pairs / ports / 1e9), 1)})
    return out


def summarise(res: dict) -> dict:
    vals, loads = {}, {}
    if "uvlm" in res:
        u = res["uvlm"]["result"]
        ptera = res.get("ptera", {}).get("result", {}).get("ptera_wall_s")
        vals["speedup_vs_ptera"] = round(ptera / u["reference_case_s"], 1) if ptera else None
        vals["reference_case_s"], vals["ptera_wall_s"] = u["reference_case_s"], ptera
        vals["aero_warm_s"] = u.get("aero_warm_s")
        loads["speedup_vs_ptera"] = loads["aero_warm_s"] = [res["uvlm"]["stage"]["load_before"],
                                                            res["uvlm"]["stage"]["load_after"]]
    if "fly" in res:
        f = res["fly"]["result"]
        vals["fly_10_beat_wake_wingbeats_per_s"] = max(f["fly"]["runs"][k]["wingbeats_per_s"]
                                                       for k in FLOAT64_FLIGHTS)
        loads["fly_10_beat_wake_wingbeats_per_s"] = [res["fly"]["stage"]["load_before"],
                                                     res["fly"]["stage"]["load_after"]]
    if "cold" in res:
        c = res["cold"]["result"]["results"]
        vals["cold_first_aero_command_s"] = c["new"]["aero"][0]["command_s"]
        vals["cold_first_aero_command_s_without_warmup"] = c["new_nowarmup"]["aero"][0]["command_s"]
        loads["cold_first_aero_command_s"] = [res["cold"]["stage"]["load_before"], res["cold"]["stage"]["load_after"]]
    if "contention" in res:
        r = res["contention"]["result"]["results"]
        busy = r.get("busy", {})
        one, two = busy.get("1 thread", {}).get("median_s"), busy.get("2 threads", {}).get("median_s")
        vals["busy_core_2t_over_1t"] = round(two / one, 3) if one and two else None
        loads["busy_core_2t_over_1t"] = [res["contention"]["stage"]["load_before"],
                                         res["contention"]["stage"]["load_after"]]
    if "datasets" in res:
        d = res["datasets"]["result"]
        vals["datasets_elapsed_min"] = d["elapsed_min"]
        loads["datasets_elapsed_min"] = [res["datasets"]["stage"]["load_before"],
                                         res["datasets"]["stage"]["load_after"]]
    targets = {k: {"value": vals.get(k), "target": f"{TARGETS[k][1]} {TARGETS[k][0]}", "met": _met(k, vals.get(k)),
                   "load_before_after": loads.get(k)} for k in TARGETS}
    out = {"targets": targets, "reference_case_s": vals.get("reference_case_s"),
           "ptera_wall_s": vals.get("ptera_wall_s")}
    if "cold_first_aero_command_s_without_warmup" in vals:
        out["cold_first_aero_command_s_without_warmup"] = vals["cold_first_aero_command_s_without_warmup"]
    if "fly" in res:
        mixed = res["fly"]["result"]["fly"]["runs"].get("wake_10_mixed")
        if mixed is not None:  # the opt-in --wake-precision mixed (the target's value is float64's)
            out["fly_10_beat_wake_wingbeats_per_s_mixed"] = mixed["wingbeats_per_s"]
        out["fly_10_beat_wake_floor"] = fly_floor(res["fly"]["result"])
        roof = res["fly"]["result"]["roofline"]
        out["fraction_of_fma_roofline"] = roof.get("fraction_of_fma_roofline")
        out["fraction_of_fp_roofline"] = roofline_fractions(roof)
    ptera = out["ptera_wall_s"]
    fly = res.get("fly", {}).get("result")
    if "uvlm" in res:
        out["reference_case_floor"] = reference_floor(res["uvlm"]["result"], fly, ptera)
    other = next((n[-3:] for n in OTHER_WIDTH_STAGES if n in res), None)
    if other is not None:
        wide = {"vector_bits_asked": int(other)}
        if f"uvlm{other}" in res:
            st, u = res[f"uvlm{other}"]["stage"], res[f"uvlm{other}"]["result"]
            wide.update({"vector_bits": u.get("vector_bits"), "reference_case_s": u["reference_case_s"],
                         "speedup_vs_ptera": round(ptera / u["reference_case_s"], 1) if ptera else None,
                         "aero_warm_s": u.get("aero_warm_s"), "lattice_kernel_g_pairs_s": u["lattice_kernel_geval_s"],
                         "reference_case_floor": reference_floor(u, fly, ptera),
                         "load_before_after": [st["load_before"], st["load_after"]]})
        if f"fly{other}" in res:
            st, f = res[f"fly{other}"]["stage"], res[f"fly{other}"]["result"]
            runs = f["fly"]["runs"]
            wide.update({"fly_vector_bits": f["fly"].get("vector_bits"),
                         "fly_10_beat_wake_wingbeats_per_s": max(runs[k]["wingbeats_per_s"] for k in FLOAT64_FLIGHTS),
                         "fly_10_beat_wake_wingbeats_per_s_mixed": runs["wake_10_mixed"]["wingbeats_per_s"],
                         "fly_load_before_after": [st["load_before"], st["load_after"]]})
        wide["met"] = {k: _met(k, wide.get(k)) for k in ("speedup_vs_ptera", "aero_warm_s",
                                                          "fly_10_beat_wake_wingbeats_per_s")}
        default_bits = res.get("uvlm", {}).get("result", {}).get("vector_bits")
        if default_bits is not None and default_bits in (wide.get("vector_bits"), wide.get("fly_vector_bits")):
            wide = {"available": False, "note": "no AVX-512F: both widths ran the default's code",
                    "vector_bits": wide.get("vector_bits"), "fly_vector_bits": wide.get("fly_vector_bits")}
        out["other_vector_width"] = wide
    if "uvlm" in res:
        out["default_vector_bits"] = res["uvlm"]["result"].get("vector_bits")
    stages = [r["stage"] for r in res.values()]
    out["sitting"] = {"first": min(s["began"] for s in stages), "last": max(s["ended"] for s in stages),
                      "stages": {k: r["stage"] for k, r in res.items()}}
    return out


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("--out-dir", required=True)
    ap.add_argument("--skip-datasets", action="store_true")
    ap.add_argument("--only", nargs="+", help="run only these stages (the summary reads any others already there)")
    ap.add_argument("--force", action="store_true", help="rerun stages whose JSON is already there")
    a = ap.parse_args()
    os.makedirs(a.out_dir, exist_ok=True)
    stages = _stages(a.out_dir, sys.executable, other_width(default_vector_bits(sys.executable)))
    if a.skip_datasets:
        stages.pop("datasets")
    res = {}
    for name, cmd in stages.items():
        path = os.path.join(a.out_dir, f"{name}.json")
        if a.only and name not in a.only:
            if os.path.exists(path):
                res[name] = json.load(open(path))
            continue
        if name == "datasets":
            dpath = os.path.join(a.out_dir, "datasets")
            if os.path.exists(os.path.join(dpath, "run.log")) and not os.path.exists(path) and not a.force:
                adopted = datasets_from_log(cmd, a.out_dir)
                if adopted is not None:
                    res[name] = adopted
                    continue
                raise SystemExit(f"bench_targets: {dpath} holds a partial run; remove it to time the data sets afresh")
        res[name] = run_stage(name, cmd, a.out_dir, a.force)
    summary = {"command": " ".join(["python", *sys.argv]), **summarise(res)}
    emit(summary, os.path.join(a.out_dir, "summary.json"), host=True)


if __name__ == "__main__":
    main()
