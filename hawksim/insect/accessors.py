"""Named accessors into the hawkmoth's MuJoCo model: the one place that looks ids and addresses up by name.

Names (:mod:`hawksim.insect.model`): the free body ``body``; the wing bodies ``wing_left``, ``wing_right``; the hinges
``{sweep,elevation,rotation}_{left,right}``. Wing-joint arrays are ordered left (sweep, elevation, rotation), then
right, the order of :meth:`hawksim.insect.kinematics.Kinematics.angles` tiled twice.
"""

from __future__ import annotations

from dataclasses import dataclass

import mujoco
import numpy as np

WING_SIDES = ("left", "right")
"""Wing order of every (2, ...) array in hawksim: index 0 is the left wing."""
JOINT_KINDS = ("sweep", "elevation", "rotation")
"""The three hinges of each wing, outermost first (Eq. 1's phi, theta, alpha)."""


def body_id(model: mujoco.MjModel, name: str) -> int:
    """Id of the body ``name`` (-1 if absent)."""
    return mujoco.mj_name2id(model, mujoco.mjtObj.mjOBJ_BODY, name)


def joint_id(model: mujoco.MjModel, kind: str, side: str) -> int:
    """Id of the wing hinge ``{kind}_{side}`` (-1 if absent)."""
    return mujoco.mj_name2id(model, mujoco.mjtObj.mjOBJ_JOINT, f"{kind}_{side}")


@dataclass(frozen=True)
class ModelIndex:
    """Ids and addresses hawksim drives: ``body`` (id of the free body), ``wings`` (2,) wing body ids,
    ``wing_qpos`` (6,) and ``wing_dof`` (6,) qpos / dof addresses of the wing hinges."""

    body: int
    wings: np.ndarray
    wing_qpos: np.ndarray
    wing_dof: np.ndarray

    @staticmethod
    def of(model: mujoco.MjModel) -> ModelIndex:
        jids = [joint_id(model, k, s) for s in WING_SIDES for k in JOINT_KINDS]
        return ModelIndex(body=body_id(model, "body"),
                          wings=np.array([body_id(model, f"wing_{s}") for s in WING_SIDES]),
                          wing_qpos=np.array([model.jnt_qposadr[j] for j in jids]),
                          wing_dof=np.array([model.jnt_dofadr[j] for j in jids]))
