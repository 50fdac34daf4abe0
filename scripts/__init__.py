"""Reproduction scripts, benchmarks and studies of hawksim: a package, run from the repository root as
``python -m scripts.<group>.<name>`` (docs/layout.md)."""
