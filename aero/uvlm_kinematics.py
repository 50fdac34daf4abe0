"""Simple prescribed flapping kinematics for tests and benchmarks (not the hawkmoth's; see hawksim).

Left wing hinged at ``hinge`` (world), stroke plane horizontal (world x-y), stroke angle about world +z
phi(t) = phi_a cos(2 pi f t), pitch about the wing's span axis beta(t) = -pi/2 + theta_a sin(2 pi f t), so the
leading edge leads on both half-strokes with geometric angle of attack pi/2 - theta_a at mid-stroke:
R = Rz(phi) Ry(beta). The right wing is the mirror image across the world x-z plane (y -> -y).
"""

from __future__ import annotations

import numpy as np

MIRROR = np.diag([1.0, -1.0, 1.0])
"""Reflection y -> -y (the world x-z plane)."""


def _rz(a):
    c, s = np.cos(a), np.sin(a)
    z, o = np.zeros_like(a), np.ones_like(a)
    return np.stack([np.stack([c, -s, z], -1), np.stack([s, c, z], -1), np.stack([z, z, o], -1)], -2)


def _ry(a):
    c, s = np.cos(a), np.sin(a)
    z, o = np.zeros_like(a), np.ones_like(a)
    return np.stack([np.stack([c, z, s], -1), np.stack([z, o, z], -1), np.stack([-s, z, c], -1)], -2)


def flapping_motion(times, freq=25.0, phi_a=np.radians(60.0), theta_a=np.radians(50.0), hinge=(0.0, 0.005, 0.0)):
    """Left-wing motion at times (nt,) [s]: R (nt, 3, 3), origin (nt, 3) [m], v_origin (nt, 3) [m/s],
    omega (nt, 3) [rad/s] (world); freq [Hz], amplitudes [rad]."""
    t = np.asarray(times, float)
    w = 2 * np.pi * freq
    phi, dphi = phi_a * np.cos(w * t), -phi_a * w * np.sin(w * t)
    beta, dbeta = -np.pi / 2 + theta_a * np.sin(w * t), theta_a * w * np.cos(w * t)
    rz = _rz(phi)
    R = rz @ _ry(beta)
    omega = dphi[:, None] * np.array([0.0, 0.0, 1.0]) + dbeta[:, None] * rz[:, :, 1]
    origin = np.broadcast_to(np.asarray(hinge, float), (t.size, 3)).copy()
    return R, origin, np.zeros((t.size, 3)), omega


def mirror_motion(R, origin, v_origin, omega):
    """The mirror-image (right-wing) motion across the world x-z plane, for meshes from
    :func:`aero.mesh.mirror_mesh`: R' = M R M, origin' = M origin, v' = M v, omega' = -M omega."""
    return MIRROR @ R @ MIRROR, origin @ MIRROR, v_origin @ MIRROR, -(omega @ MIRROR)


def two_wing_motion(times, **kw):
    """(R (nt, 2, 3, 3), origin, v_origin, omega (nt, 2, 3)) of the left wing and its mirror image."""
    left = flapping_motion(times, **kw)
    right = mirror_motion(*left)
    return tuple(np.stack([a, b], axis=1) for a, b in zip(left, right))
