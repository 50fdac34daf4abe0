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


def fma_lane_peak(roof: dict, bits: str, threads: str = "all") -> float | None:
    """The FMA-only peak [G lane-operations/s] at a vector width (bench_treecode's ``peak``), for all threads no
    less than the one-thread peak times the thread count (as :func:`lane_peak`). None without it."""
    if not roof.get("peak"):
        return None
    p = roof["peak"][bits]
    if threads == "one":
        return p["one"]["lane_ops_g_s"]
    return max(p["all"]["lane_ops_g_s"], p["one"]["lane_ops_g_s"] * roof["threads"])


def pair_ceiling(roof: dict, bits: str, threads: str = "all") -> float | None:
    """The most edge-target pairs/s [G] the lattice kernel's arithmetic allows at a vector width: the smaller of
    (a) the FP peak :func:`lane_peak` / all its FP lane-operations per pair (``lane_ops_per_pair``: every FP
    operation on the same pipes, as on Intel's Xeons, whose additions use the FMA ports) and (b) the FMA-only peak
    :func:`fma_lane_peak` / its multiplies and FMAs per pair (``fma_port_ops_per_pair``: on AMD Zen 4 and 5 the
    additions have pipes of their own, but a multiply or FMA needs an FMA pipe on every x86 core). An upper bound
    (a port model: no latency, no loads); (a) alone where the record has no ``fma_port_ops_per_pair`` (sittings
    before 2026-12-06). None without the peaks."""
    fp = lane_peak(roof, bits, threads)
    if fp is None:
        return None
    bound = fp / roof["lane_ops_per_pair"]
    if roof.get("fma_port_ops_per_pair"):
        bound = min(bound, fma_lane_peak(roof, bits, threads) / roof["fma_port_ops_per_pair"])
    return bound


def roofline_fractions(roof: dict) -> dict | None:
    """The lattice kernel's fraction of the FP roofline per vector width and thread count: its rate x lane-operations
    per pair / :func:`lane_peak`."""
    if not roof.get("peak"):
        return None
    rates = roof["lattice_kernel_g_pairs_s"]
    return {b: {k: round(rates[b][k] * roof["lane_ops_per_pair"] / lane_peak(roof, b, k), 3) for k in ("one", "all")}
            for b in rates}
