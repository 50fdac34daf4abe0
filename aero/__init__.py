"""Generic flapping-wing aerodynamics: extended UVLM and quasi-steady blade elements.

Imports neither mujoco nor hawksim, and does no file I/O of its own. Importing it applies, before numba is
imported, the opt-in vector width of :mod:`aero.vector_width` (``HAWKSIM_VECTOR_WIDTH=512``) and the per-user
numba cache folder of :mod:`aero.numba_cache` (numba's compiled kernels never land inside the installed package).
"""

from aero.numba_cache import apply_cache_dir
from aero.vector_width import apply_vector_width

apply_cache_dir()
apply_vector_width()
