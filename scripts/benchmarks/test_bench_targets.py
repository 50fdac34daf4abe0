"""scripts/benchmarks/bench_targets.py's bookkeeping: the FP ceilings it divides by, the environment of each
stage's vector width, and the summary of the other width's stages (synthetic stage records, no benchmark runs).

Beside the script it checks, not in tests/: no test imports a script (tests/test_layers.py); pytest collects it
from scripts/ (``testpaths`` in pyproject.toml)."""

from __future__ import annotations

import pytest

from scripts.benchmarks import bench_targets as bt

ROOF = {
    "threads": 2,
    "lane_ops_per_pair": 36.0,
    # FMA-only and FMA + addition peaks [G lane-ops/s]; "all" of fp_peak disturbed (below 2 x "one")
    "peak": {"256": {"one": {"lane_ops_g_s": 30.0}, "all": {"lane_ops_g_s": 59.0}},
             "512": {"one": {"lane_ops_g_s": 60.0}, "all": {"lane_ops_g_s": 110.0}}},
    "fp_peak": {"256": {"one": {"lane_ops_g_s": 46.0}, "all": {"lane_ops_g_s": 53.0}},
                "512": {"one": {"lane_ops_g_s": 90.0}, "all": {"lane_ops_g_s": 172.0}}},
    "lattice_kernel_g_pairs_s": {"256": {"one": 0.9, "all": 1.8}, "512": {"one": 1.25, "all": 2.1}},
}


def test_the_ceiling_is_the_widest_peak_and_no_less_than_the_cores_apart():
    assert bt.lane_peak(ROOF, "256", "one") == 46.0  # the adders' own pipes count
    assert bt.lane_peak(ROOF, "256", "all") == 92.0  # 2 x 46: the disturbed all-threads 53 does not lower it
    assert bt.lane_peak(ROOF, "512", "all") == 180.0
    assert bt.lane_peak({"peak": None}, "256") is None
    fma_only = {k: v for k, v in ROOF.items() if k != "fp_peak"}
    assert bt.lane_peak(fma_only, "256", "all") == 60.0


def test_fractions_divide_the_kernel_lane_ops_by_the_ceiling():
    f = bt.roofline_fractions(ROOF)
    assert f["256"]["one"] == pytest.approx(0.9 * 36 / 46, abs=1e-3)
    assert f["512"]["all"] == pytest.approx(2.1 * 36 / 180, abs=1e-3)


def test_the_pair_ceiling_is_the_tighter_of_all_fp_ops_and_the_fma_pipes_alone():
    # without a multiply/FMA count (sittings before 2026-12-06): the FP ceiling alone
    assert bt.pair_ceiling(ROOF, "256", "one") == pytest.approx(46.0 / 36.0)
    ports = {**ROOF, "fma_port_ops_per_pair": 24.0}
    # 256 bits, one thread: all ops 46 / 36 = 1.28 against the FMA pipes 30 / 24 = 1.25
    assert bt.pair_ceiling(ports, "256", "one") == pytest.approx(30.0 / 24.0)
    # all threads: FMA-only 2 x 30 = 60 (no less than the cores apart) / 24 = 2.5 against 92 / 36 = 2.56
    assert bt.pair_ceiling(ports, "256", "all") == pytest.approx(60.0 / 24.0)
    # where additions share the FMA pipes (fp_peak = FMA peak) the all-ops bound binds
    intel = {**ports, "fp_peak": None}
    assert bt.pair_ceiling(intel, "512", "all") == pytest.approx(120.0 / 36.0)
    assert bt.pair_ceiling({"peak": None}, "256") is None


def test_stage_environments(monkeypatch):
    monkeypatch.setenv("HAWKSIM_VECTOR_WIDTH", "512")
    monkeypatch.setenv("NUMBA_CPU_FEATURES", "+avx2")
    monkeypatch.delenv("NUMBA_NUM_THREADS", raising=False)
    default = bt.stage_env("uvlm")
    assert "HAWKSIM_VECTOR_WIDTH" not in default and "NUMBA_CPU_FEATURES" not in default
    assert default["NUMBA_NUM_THREADS"] == "2"
    assert bt.stage_env("fly256")["HAWKSIM_VECTOR_WIDTH"] == "256"
    assert bt.stage_env("uvlm512")["HAWKSIM_VECTOR_WIDTH"] == "512"
    assert "NUMBA_NUM_THREADS" not in bt.stage_env("datasets")
    assert (bt.other_width(512), bt.other_width(256)) == (256, 512)
    assert set(bt._stages("OUT", "py", 256)) >= {"uvlm256", "fly256"}


def _stage(**result):
    st = {"command": "x", "began": "2026-12-04T00:00:00+00:00", "ended": "2026-12-04T00:01:00+00:00",
          "load_before": [0.0, 0.0, 0.0], "load_after": [0.0, 0.0, 0.0], "wall_s": 60.0}
    return {"stage": st, "result": result}


def _uvlm(bits, seconds):
    return _stage(vector_bits=bits, reference_case_s=seconds, aero_warm_s=0.4, lattice_kernel_geval_s=2.0)


def test_the_other_width_is_reported_beside_the_default():
    res = {"ptera": _stage(ptera_wall_s=150.0), "uvlm": _uvlm(512, 2.5), "uvlm256": _uvlm(256, 3.75)}
    out = bt.summarise(res)
    assert out["default_vector_bits"] == 512 and out["targets"]["speedup_vs_ptera"]["value"] == 60.0
    other = out["other_vector_width"]
    assert other["vector_bits_asked"] == 256 and other["vector_bits"] == 256 and other["speedup_vs_ptera"] == 40.0
    assert other["met"]["speedup_vs_ptera"] is False


def test_a_host_without_avx512_says_the_other_width_is_not_available():
    res = {"ptera": _stage(ptera_wall_s=150.0), "uvlm": _uvlm(256, 3.0), "uvlm512": _uvlm(256, 3.0)}
    other = bt.summarise(res)["other_vector_width"]
    assert other["available"] is False and "vector_bits_asked" not in other
