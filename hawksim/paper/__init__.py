"""The paper's study reproduced (Nguyen et al. 2020; docs/results.md).

Modules:

- ``reference``: the paper's published numbers.
- ``trims``: the trims, Tables 3-4 and Figs. 9, 11, 13, 14.
- ``studies``: the stability studies of Figs. 15-19.
- ``backends``: every backend side by side (trims, Floquet, open- and closed-loop flights).
- ``reproduce``: ``hawksim reproduce``.
"""

from hawksim.lazy import lazy_exports

__all__, __getattr__, __dir__ = lazy_exports(__name__, {
    ".reference": ("PAPER_TABLE4", "PAPER_POWER_FIT_W"),
    ".trims": ("trim_table", "write_trim_results", "table4_markdown"),
    ".studies": ("w_e_sweep", "nr_sweep"),
    ".backends": ("write_backends",),
    ".reproduce": ("run_all",),
})
