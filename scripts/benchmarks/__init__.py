"""Benchmarks (each prints JSON; docs/performance.md). Run as ``python -m scripts.benchmarks.<name>``."""
