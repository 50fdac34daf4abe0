"""hawksim: an insect (the hawkmoth) in flapping flight, MuJoCo + extended UVLM.

The flat top level names the few things a script needs (each resolved on first use, so ``import hawksim`` stays
light); everything else lives in the subpackages, each with its own ``__all__``:

- :mod:`hawksim.insect`: the insect (morphology, P0, bounds; a folder of data, ``load_insect``), wing kinematics
  (Eq. 1), the MuJoCo model.
- :mod:`hawksim.backends`: the aerodynamic models behind one protocol.
- :mod:`hawksim.trim`: held-body trims (the paper's operating points) and the one :class:`OperatingPoint` type.
- :mod:`hawksim.flight`: free flight (the one flight loop :func:`fly`, open loop or under a :class:`Controller`),
  periodic orbits, recordings.
- :mod:`hawksim.stability`: averaged linear models and Floquet analysis.
- :mod:`hawksim.control`: LQR control on the one-beat map (the controllers :class:`hawksim.control.LQR`,
  :class:`hawksim.control.ConstrainedLQR`, :class:`hawksim.control.NoControl`), closed-loop flight.
- :mod:`hawksim.surrogate`: data sets and training of the neural surrogates.
- :mod:`hawksim.paper`: the paper's study reproduced.

The python-control shape: ``point = hawksim.find_operating_point(1.0, aero="quasi-steady")`` (a free-body periodic
orbit, or ``body="held"`` a trim) -> ``lin = hawksim.linearize(point, map="beat")`` (a :class:`LinearModel`) ->
:func:`hawksim.control.lqr.lqr_gain` ``(lin, "long")``.

Angles are radians and frequencies Hz in every Python call (the CLI and JSON take and print degrees).
"""

import aero  # noqa: F401  (first: applies the opt-in HAWKSIM_VECTOR_WIDTH before numba is imported)
from hawksim.lazy import lazy_exports

__version__ = "0.3.0"

__all__, __getattr__, __dir__ = lazy_exports(__name__, {
    "hawksim.insect.morphology": ("Morphology",),
    "hawksim.insect.insect": ("Insect",),
    "hawksim.insect.folder": ("load_insect", "default_insect"),
    "hawksim.insect.kinematics": ("Kinematics", "table3_kinematics"),
    "hawksim.insect.model": ("load_model",),
    "hawksim.backends": ("make_backend", "flight_backend"),
    "hawksim.trim.point": ("OperatingPoint", "Trim"),
    "hawksim.flight.points": ("find_operating_point",),
    "hawksim.stability.linear_model": ("LinearModel",),
    "hawksim.trim.tables": ("trim_kinematics",),
    "hawksim.flight.loop": ("fly", "Controller", "Gust"),
    "hawksim.flight.result": ("FlightResult",),
    "hawksim.flight.orbit": ("Orbit", "periodic_orbit", "shipped_orbit", "fly_orbit"),
    "hawksim.stability.floquet": ("Floquet", "monodromy"),
    "hawksim.control.linearization": ("linearize",),
    "hawksim.control.closed_loop": ("fly_closed_loop",),
})
