"""Trims, the held-body operating points: the one :class:`OperatingPoint` type, the search and the shipped tables.

Modules:

- ``point``: :class:`OperatingPoint` (``Trim`` and ``Orbit`` are its names), one operating point: held body (a trim)
  or free body (a periodic orbit).
- ``search``: the paper's fitness (Eq. 3) and the GA + Nelder-Mead search on the cycle-mean surrogate.
- ``balance``: the trim balanced on the UVLM or the quasi-steady model (a least-squares solve from a guess).
- ``model_search``: the same search on a held-body model itself (quasi-steady), then balanced: forward flight.
- ``tables``: the shipped trim tables (hawksim/data) by speed and backend.
- ``registry``: the one registry of the shipped operating points, keyed by insect, backend, speed and MJCF.
"""

from hawksim.lazy import lazy_exports

__all__, __getattr__, __dir__ = lazy_exports(__name__, {
    ".point": ("OperatingPoint", "Trim", "BODIES"),
    ".search": ("fitness", "ga_nelder_mead", "trim_on_surrogate", "GAConfig", "GAResult"),
    ".balance": ("balance_on_uvlm",),
    ".model_search": ("trim_on_model",),
    ".tables": ("shipped_trim", "trim_kinematics"),
    ".registry": ("shipped_point", "shipped_table", "point_key"),
})
