"""Generic flapping-wing aerodynamics: extended UVLM and quasi-steady blade elements.

Imports neither mujoco nor hawksim, and does no file I/O of its own. Importing it applies, before numba is
imported, the opt-in vector width of :mod:`aero.vector_width` (``HAWKSIM_VECTOR_WIDTH=512``) and the per-user
numba cache folder of :mod:`aero.numba_cache` (numba's compiled kernels never land inside the installed package).
The public names below are imported on first use.

Modules:

- ``uvlm``: the unsteady vortex-lattice method (free wake, vortex-core growth, leading-edge suction, loads).
- ``uvlm_config``: the UVLM's constants and switches (:class:`UVLMConfig`).
- ``wake``: the shed wake's rows of vortex rings.
- ``mesh``: wing meshes of a planform.
- ``lattice``, ``lattice_lanes``, ``biot_savart``: induced velocities of vortex lattices (the kernels).
- ``treecode``: a far-field approximation of the wake's induced velocities (opt-in).
- ``scheduling``: the kernels' thread pool.
- ``quasi_steady``: blade-element quasi-steady wing loads.
- ``uvlm_kinematics``: prescribed flapping motions for runs without a body.
- ``plate``, ``unsteady_theory``: classical unsteady cases (Wagner, Theodorsen, Garrick) for validation.
- ``vector_width``, ``numba_cache``: the compiled kernels' vector width and cache folder.
"""

import importlib as _importlib

from aero.numba_cache import apply_cache_dir
from aero.vector_width import apply_vector_width

apply_cache_dir()
apply_vector_width()

_EXPORTS = {
    "aero.uvlm": ("UVLM", "UVLMConfig", "FreeStream", "StepResult", "RunResult", "run_prescribed"),
    "aero.wake": ("Wake",),
    "aero.mesh": ("WingMesh", "wing_mesh", "mirror_mesh", "planform_area"),
    "aero.lattice": ("Lattice", "ring_lattice", "lattice_velocity"),
    "aero.treecode": ("TreeParams",),
    "aero.quasi_steady": ("QuasiSteadyConfig", "BladeElements", "WingResultant", "wing_loads"),
    "aero.uvlm_kinematics": ("flapping_motion", "mirror_motion", "two_wing_motion"),
    "aero.unsteady_theory": ("theodorsen", "wagner", "heave_lift", "pitch_lift", "garrick_thrust"),
    "aero.vector_width": ("vector_bits",),
}
_WHERE = {name: module for module, names in _EXPORTS.items() for name in names}
__all__ = list(_WHERE)


def __getattr__(name: str):
    module = _WHERE.get(name)
    if module is None:
        raise AttributeError(f"module 'aero' has no attribute {name!r}")
    value = getattr(_importlib.import_module(module), name)
    globals()[name] = value
    return value


def __dir__() -> list[str]:
    return sorted(set(globals()) | set(_WHERE))
