"""Rotation matrices and quaternions (w, x, y, z: MuJoCo's order). Angles in radians.

Conventions: ``rot_*`` are active rotations; a matrix R maps frame coordinates to parent coordinates.
"""

from __future__ import annotations

import numpy as np
from numba import njit


def _stack(rows):
    return np.stack([np.stack(r, -1) for r in rows], -2)


def rot_x(a) -> np.ndarray:
    """Rotation matrices about x by angle(s) a [rad]: shape (*a.shape, 3, 3)."""
    a = np.asarray(a, dtype=float)
    c, s, o, z = np.cos(a), np.sin(a), np.ones_like(a), np.zeros_like(a)
    return _stack([(o, z, z), (z, c, -s), (z, s, c)])


def rot_y(a) -> np.ndarray:
    """Rotation matrices about y by angle(s) a [rad]: shape (*a.shape, 3, 3)."""
    a = np.asarray(a, dtype=float)
    c, s, o, z = np.cos(a), np.sin(a), np.ones_like(a), np.zeros_like(a)
    return _stack([(c, z, s), (z, o, z), (-s, z, c)])


def rot_z(a) -> np.ndarray:
    """Rotation matrices about z by angle(s) a [rad]: shape (*a.shape, 3, 3)."""
    a = np.asarray(a, dtype=float)
    c, s, o, z = np.cos(a), np.sin(a), np.ones_like(a), np.zeros_like(a)
    return _stack([(c, -s, z), (s, c, z), (z, z, o)])


def quat_to_matrix(q) -> np.ndarray:
    """Unit quaternions (..., 4) (w, x, y, z) -> rotation matrices (..., 3, 3)."""
    q = np.asarray(q, dtype=float)
    q = q / np.linalg.norm(q, axis=-1, keepdims=True)
    w, x, y, z = np.moveaxis(q, -1, 0)
    return _stack([
        (1 - 2 * (y * y + z * z), 2 * (x * y - w * z), 2 * (x * z + w * y)),
        (2 * (x * y + w * z), 1 - 2 * (x * x + z * z), 2 * (y * z - w * x)),
        (2 * (x * z - w * y), 2 * (y * z + w * x), 1 - 2 * (x * x + y * y)),
    ])


def quat_from_matrix(R) -> np.ndarray:
    """Rotation matrix (3, 3) -> unit quaternion (4,) (w, x, y, z) with w >= 0 (Shepperd's method)."""
    R = np.asarray(R, dtype=float)
    tr = np.trace(R)
    if tr > 0:
        s = 2 * np.sqrt(1 + tr)
        q = np.array([s / 4, (R[2, 1] - R[1, 2]) / s, (R[0, 2] - R[2, 0]) / s, (R[1, 0] - R[0, 1]) / s])
    else:
        i = int(np.argmax(np.diag(R)))
        j, k = (i + 1) % 3, (i + 2) % 3
        s = 2 * np.sqrt(1 + R[i, i] - R[j, j] - R[k, k])
        q = np.empty(4)
        q[0] = (R[k, j] - R[j, k]) / s
        q[1 + i] = s / 4
        q[1 + j] = (R[j, i] + R[i, j]) / s
        q[1 + k] = (R[k, i] + R[i, k]) / s
    q /= np.linalg.norm(q)
    return q if q[0] >= 0 else -q


def cross(a, b) -> np.ndarray:
    """Cross product over the last axis of (..., 3) arrays (cheaper than np.cross for small arrays). Two float64
    arrays of one shape (the flight loop's (2, 3) arms and forces, every step) take a compiled path with the same
    arithmetic."""
    a, b = np.asarray(a), np.asarray(b)
    if a.shape == b.shape and a.dtype == b.dtype == np.float64 and a.ndim and a.shape[-1] == 3:
        return _cross_rows(a.reshape(-1, 3), b.reshape(-1, 3)).reshape(a.shape)
    return np.stack([a[..., 1] * b[..., 2] - a[..., 2] * b[..., 1],
                     a[..., 2] * b[..., 0] - a[..., 0] * b[..., 2],
                     a[..., 0] * b[..., 1] - a[..., 1] * b[..., 0]], -1)


@njit(cache=True)
def _cross_rows(a, b):
    out = np.empty(a.shape)
    for i in range(a.shape[0]):
        out[i, 0] = a[i, 1] * b[i, 2] - a[i, 2] * b[i, 1]
        out[i, 1] = a[i, 2] * b[i, 0] - a[i, 0] * b[i, 2]
        out[i, 2] = a[i, 0] * b[i, 1] - a[i, 1] * b[i, 0]
    return out


def quat_from_matrices(R) -> np.ndarray:
    """(n, 3, 3) rotation matrices -> (n, 4) quaternions (w, x, y, z), w >= 0."""
    return np.array([quat_from_matrix(r) for r in np.asarray(R).reshape(-1, 3, 3)])


STABILITY_TO_WORLD = np.diag([1.0, -1.0, -1.0])
"""Stability axes (x forward horizontal, y right, z down; docs/conventions.md) -> world (z up, heading +x): a
rotation by 180 deg about x, so it maps vectors and pseudovectors alike (its own inverse)."""


def stability_position(pos_world: np.ndarray) -> np.ndarray:
    """(X forward, Y right) [m] of a world position (stability axes at heading 0)."""
    return (STABILITY_TO_WORLD @ np.asarray(pos_world, float))[:2]


def pitch_of(R) -> np.ndarray:
    """Pitch [rad] of body frames R (..., 3, 3) (body -> world): elevation of the body x axis above the horizontal,
    nose up positive, in [-pi/2, pi/2]."""
    R = np.asarray(R)
    return np.arcsin(np.clip(R[..., 2, 0], -1, 1))


def roll_of(R) -> np.ndarray:
    """Roll [rad] of body frames R (..., 3, 3), Z-Y-X Euler angles, right wing down positive (stability-axes sense:
    the body's left (+y) axis tilts up, a positive rotation about the heading +x)."""
    R = np.asarray(R)
    return np.arctan2(R[..., 2, 1], R[..., 2, 2])


def attitude_of(R) -> np.ndarray:
    """(pitch, roll, yaw) [rad] of body frames R (n, 3, 3) (body -> world, heading +x), pitch unwrapped along n.

    Pitch-first angles, R = Ry(-pitch) Rx(roll) Rz(-yaw): pitch nose up positive, roll right wing down positive,
    yaw nose right positive. Unlike Z-Y-X Euler angles (:func:`pitch_of`, :func:`roll_of`), a pitch-over stays a
    pitch past 90 deg instead of becoming a 180 deg roll; singular only with the wings' axis vertical (roll 90 deg),
    which an ascending hawkmoth never reaches. Returns shape (n, 3)."""
    R = np.asarray(R)
    pitch = np.unwrap(-np.arctan2(R[:, 0, 2], R[:, 2, 2]))
    roll = -np.arcsin(np.clip(R[:, 1, 2], -1.0, 1.0))
    yaw = np.unwrap(-np.arctan2(R[:, 1, 0], R[:, 1, 1]))
    return np.stack([pitch, roll, yaw], axis=1)
