"""Closed-loop flight (issue 20): a wingbeat-to-wingbeat LQR controller on the free body's one-beat map.

Layers inside: :mod:`plant` (a Simulator with per-wing kinematics changed at phase 0 and a uniform wind),
:mod:`derivatives` (the one-beat map's A and B matrices about a periodic orbit), :mod:`lqr` (discrete Riccati
gains, delay augmentation, gain schedule over the ascent speed), :mod:`closed_loop` (the controlled flight).
See docs/control.md.
"""
