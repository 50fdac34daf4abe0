"""Free flight of the insect in MuJoCo, the free body's periodic orbits, and recordings.

The one flight loop is :func:`hawksim.flight.loop.fly` (also ``hawksim.fly``; the module :mod:`hawksim.flight.fly`,
its open-loop wrapper of the older signature, keeps the name out of this package's namespace): open loop or under a
:class:`Controller`, every backend, one :class:`FlightResult`.

Modules:

- ``simulator``: the flight loop (RK4 + computed torque on the wing joints, the backend's loads each update).
- ``steps``: what the flight loop's steps produce (:class:`StepBatch`, one step's ``StepRecord``).
- ``native``, ``network_kernel``, ``mujoco_abi``: the compiled control callback and the per-step network in it.
- ``body_state``: the body's 9-state chart (velocities, rates, attitude) and reading/writing it in MuJoCo.
- ``start``: the start on the trim's periodic path and named perturbations.
- ``loop``: the one flight loop and the :class:`Controller` protocol; ``plant``: the controlled plant (per-wing
  kinematics blended at phase 0, a uniform wind); ``fly``: the open-loop wrapper (progress in steps); ``result``:
  the :class:`FlightResult` of every flight.
- ``orbit``: the free body's periodic orbit (Newton shooting on the one-beat map) and the shipped orbit tables.
- ``points``: find an operating point (free-body orbit or held-body trim).
- ``power``: the required power P+ of a flight.
- ``lift_coefficient``: the mean lift coefficient and mid-downstroke incidence as Willmott & Ellington (1997)
  compute them (forward flight).
- ``export``: a flight's per-step and per-beat arrays saved to a self-describing file.
- ``recording``, ``recording_layout``: Rerun recordings and their views.
"""

from hawksim.lazy import lazy_exports

__all__, __getattr__, __dir__ = lazy_exports(__name__, {
    ".simulator": ("Simulator", "StepBatch", "aero_every_for"),
    ".body_state": ("BodyState", "STATE_NAMES", "read_body_state", "set_body_state"),
    ".start": ("start_on_orbit", "PERTURBATIONS"),
    ".result": ("FlightResult",),
    ".loop": ("Controller", "Observation", "Gust"),
    ".plant": ("ControlledSimulator", "controlled_plant"),
    ".orbit": ("Orbit", "Beats", "OrbitFlight", "periodic_orbit", "shipped_orbit", "fly_orbit", "beat_map"),
    ".points": ("find_operating_point",),
    ".power": ("P_plus", "required_power"),
    ".lift_coefficient": ("mean_lift_coefficient", "mid_downstroke_incidence"),
    ".export": ("save_flight", "read_flight"),
    ".recording": ("write_rrd",),
})
