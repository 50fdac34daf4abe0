"""The insect: its morphology, wing kinematics, MuJoCo model and the named indices into it.

Modules:

- ``morphology``: the morphology type and the hawkmoth's measured body and wings (Table 1 and the literature),
  with each number's source.
- ``insect``: :class:`Insect`, the insect a flight is of (morphology, reference power P0, kinematic bounds), its
  default :data:`DEFAULT_INSECT` (the hawkmoth) and :func:`read_insect` (a spec file).
- ``folder``: an insect is a folder of data (``hawksim/insects/<name>/``: spec, MJCF, README, tables):
  :func:`load_insect` (a shipped name, a folder or a spec file), :func:`default_insect` (docs/insects.md).
- ``tables``: an insect's shipped tables and networks keyed by kind, backend and model digest (:func:`table_path`).
- ``kinematics``: the wing kinematics of the paper's Eq. 1 (Tables 2-3), SI inside (radians, Hz).
- ``model``: the MJCF model generated from the morphology, and loading it into MuJoCo.
- ``accessors``: named body, joint and dof indices into the MuJoCo model.
- ``body_aero``: the body's own drag and lift (a slender-body crossflow model), counted in forward flight.
"""

from hawksim.lazy import lazy_exports

__all__, __getattr__, __dir__ = lazy_exports(__name__, {
    ".morphology": ("Morphology", "HAWKMOTH", "RHO_AIR", "P0_W", "MORPHOLOGIES"),
    ".insect": ("Insect", "DEFAULT_INSECT", "read_insect"),
    ".folder": ("load_insect", "default_insect", "shipped_insects", "SOURCE_CLASSES"),
    ".tables": ("table_path", "table_status", "network_path", "mjcf_digest", "ShippedFile"),
    ".kinematics": ("Kinematics", "table3_kinematics", "bounds_si", "reference_speed", "PARAM_NAMES",
                    "TABLE2_BOUNDS_DEG", "TABLE3_SPEEDS"),
    ".model": ("load_model", "mjcf", "write_model"),
    ".accessors": ("ModelIndex",),
    ".body_aero": ("BodyAero",),
})
