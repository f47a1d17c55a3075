"""Per-period whole-body terms for an inverse-dynamics formulation (Sherikov et al. 2014,
Sec. II and IV), from pinocchio in one pass: the generalized inertia matrix H and the bias h
(eq. 1), and for named frames and the CoM their Jacobians and drift accelerations J' q', so
that a task acceleration is J q'' + J' q' (eqs. 8, 15-18).

Conventions: q, v, q'' in pinocchio's (base twist in the base frame); frame Jacobians in
LOCAL_WORLD_ALIGNED (linear rows: the frame origin's velocity in world axes; angular rows:
the angular velocity in world axes); drifts are the classical accelerations (the frame
origin's second derivative, not the spatial one) at q'' = 0, in the same axes.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np
import pinocchio as pin


@dataclass(frozen=True)
class WholeBodyTerms:
    """One state's terms. mass_matrix (nv, nv) H [kg, kg m, kg m^2]; bias (nv,) h (Coriolis,
    centrifugal and gravity) [N, N m]; jacobian / drift per frame id: (6, nv) and (6,)
    [m/s^2, rad/s^2] (linear then angular); com_position (3,) [m], com_velocity (3,) [m/s],
    com_jacobian (3, nv), com_drift (3,) [m/s^2]; placement per frame id: (position (3,),
    rotation (3, 3)) in the world."""

    mass_matrix: np.ndarray
    bias: np.ndarray
    jacobian: dict[int, np.ndarray]
    drift: dict[int, np.ndarray]
    placement: dict[int, tuple[np.ndarray, np.ndarray]]
    com_position: np.ndarray
    com_velocity: np.ndarray
    com_jacobian: np.ndarray
    com_drift: np.ndarray


def whole_body_terms(
    model: pin.Model, data: pin.Data, q: np.ndarray, v: np.ndarray, frames: list[int]
) -> WholeBodyTerms:
    """H, h, the frames' and the CoM's Jacobians and drifts at (q, v) (see the module)."""
    pin.computeAllTerms(model, data, q, v)  # H (upper triangle), h, Jacobians, CoM, J_com
    mass_matrix = np.triu(data.M) + np.triu(data.M, 1).T
    bias = data.nle.copy()
    com_jacobian = data.Jcom.copy()
    pin.updateFramePlacements(model, data)
    jacobian = {f: pin.getFrameJacobian(model, data, f, pin.LOCAL_WORLD_ALIGNED) for f in frames}
    placement = {f: (data.oMf[f].translation.copy(), data.oMf[f].rotation.copy()) for f in frames}
    # drifts: kinematics with q'' = 0
    zero = np.zeros(model.nv)
    pin.forwardKinematics(model, data, q, v, zero)
    drift = {
        f: pin.getFrameClassicalAcceleration(model, data, f, pin.LOCAL_WORLD_ALIGNED).vector.copy()
        for f in frames
    }
    pin.centerOfMass(model, data, q, v, zero)
    return WholeBodyTerms(
        mass_matrix,
        bias,
        jacobian,
        drift,
        placement,
        data.com[0].copy(),
        data.vcom[0].copy(),
        com_jacobian,
        data.acom[0].copy(),
    )
