"""The FP roofline's bookkeeping, shared by bench_treecode.py (which measures the peaks) and bench_targets.py
(which summarises a sitting): pure functions of bench_treecode's ``roofline`` section, no numba."""

from __future__ import annotations


def lane_peak(roof: dict, bits: str, threads: str = "all") -> float | None:
    """FP lane-operations/s at a vector width on all threads (``threads="all"``) or one (``"one"``): the largest of
    the FMA-only peak and the peak of FMAs and additions interleaved (bench_treecode's ``peak`` and ``fp_peak``;
    the second is higher where additions have pipes of their own, as on AMD Zen 5), and for all threads also the
    one-thread peaks times the thread count (the cores are independent; on this shared host another process can
    take a core during the all-threads run: 13.4 against 23.0 G instructions/s for fp_peak at 256 bits minutes
    apart on 2026-12-04). None without the roofline's peaks."""
    if not roof.get("peak"):
        return None
    peaks = [roof["peak"]] + ([roof["fp_peak"]] if roof.get("fp_peak") else [])
    values = [p[bits][threads]["lane_ops_g_s"] for p in peaks]
    if threads == "all":
        values += [p[bits]["one"]["lane_ops_g_s"] * roof["threads"] for p in peaks]
    return max(values)


def roofline_fractions(roof: dict) -> dict | None:
    """The lattice kernel's fraction of the FP roofline per vector width and thread count: its rate x lane-operations
    per pair / :func:`lane_peak`."""
    if not roof.get("peak"):
        return None
    rates = roof["lattice_kernel_g_pairs_s"]
    return {b: {k: round(rates[b][k] * roof["lane_ops_per_pair"] / lane_peak(roof, b, k), 3) for k in ("one", "all")}
            for b in rates}
