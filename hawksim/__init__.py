"""hawksim: a hawkmoth in vertically ascending flight (MuJoCo + extended UVLM)."""

import aero  # noqa: F401  (first: applies the opt-in HAWKSIM_VECTOR_WIDTH before numba is imported)

__version__ = "0.3.0.dev0"
