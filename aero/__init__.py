"""Generic flapping-wing aerodynamics: extended UVLM and quasi-steady blade elements.

Imports neither mujoco nor hawksim, and does no file I/O. Importing it applies the opt-in vector width of
:mod:`aero.vector_width` (``HAWKSIM_VECTOR_WIDTH=512``) before numba is imported.
"""

from aero.vector_width import apply_vector_width

apply_vector_width()
