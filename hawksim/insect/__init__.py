"""The insect: its morphology, wing kinematics, MuJoCo model and the named indices into it.

Modules:

- ``morphology``: the hawkmoth's measured body and wings (Table 1 and the literature), with each number's source.
- ``insect``: :class:`Insect`, the insect a flight is of (morphology, reference power P0, kinematic bounds), its
  default :data:`DEFAULT_INSECT` (the hawkmoth) and :func:`read_insect` (a JSON spec file).
- ``kinematics``: the wing kinematics of the paper's Eq. 1 (Tables 2-3), SI inside (radians, Hz).
- ``model``: the MJCF model generated from the morphology, and loading it into MuJoCo.
- ``accessors``: named body, joint and dof indices into the MuJoCo model.
"""

from hawksim.lazy import lazy_exports

__all__, __getattr__, __dir__ = lazy_exports(__name__, {
    ".morphology": ("Morphology", "HAWKMOTH", "RHO_AIR", "P0_W", "MORPHOLOGIES"),
    ".insect": ("Insect", "DEFAULT_INSECT", "read_insect"),
    ".kinematics": ("Kinematics", "table3_kinematics", "bounds_si", "reference_speed", "PARAM_NAMES",
                    "TABLE2_BOUNDS_DEG", "TABLE3_SPEEDS"),
    ".model": ("load_model", "mjcf", "write_model"),
    ".accessors": ("ModelIndex",),
})
