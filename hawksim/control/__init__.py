"""Closed-loop flight: LQR control of the free body on its one-beat (or half-stroke) map. See docs/control.md.

Modules:

- ``plant``: the LQR's command channels and how they become each wing's kinematics.
- ``controller``: the controllers of the one flight loop (:class:`hawksim.flight.loop.Controller`): no control,
  the per-beat or per-half-stroke LQR, the constrained LQR.
- ``linearization``: :func:`linearize`, the one entry point from an operating point to its linear model.
- ``derivatives``: the one-beat map's linear model (A, B) about a periodic orbit.
- ``halfstroke``: the same per half-stroke.
- ``lqr``: discrete Riccati gains, delay augmentation.
- ``constrained``: LQR plans that stay within Table 2's kinematic bounds.
- ``schedule``: the gain schedule over the ascent speed (or the forward speed, ``axis="forward"``), and the shipped
  control models.
- ``closed_loop``: the scheduled controlled flight (``fly_closed_loop``, a wrapper of the one flight loop).
- ``surrogate``: the per-step surrogate backend that follows the controller's kinematics.
- ``command``: ``hawksim fly --control``'s option handling.
- ``cache``: the per-user cache of computed maps.
- ``figure``: the controlled flight's figure.
"""

from hawksim.lazy import lazy_exports

__all__, __getattr__, __dir__ = lazy_exports(__name__, {
    ".linearization": ("linearize",),
    ".derivatives": ("BeatMapModel",),
    ".halfstroke": ("HalfStrokeModel", "linearize_half_stroke"),
    ".lqr": ("Gain", "lqr_gain", "periodic_lqr_gains", "periodic_lqr_gain"),
    ".constrained": ("ConstrainedSchedule", "constrained_gain"),
    ".schedule": ("Schedule", "SchedulePoint", "schedule_point", "operating_point_override"),
    ".controller": ("NoControl", "LQR", "ConstrainedLQR"),
    ".closed_loop": ("fly_closed_loop", "ClosedLoop"),
    ".figure": ("controlled_flight_figure",),
})
