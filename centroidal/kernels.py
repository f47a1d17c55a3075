"""Compiled kernels of the control stages (numba, cached on disk in `__pycache__`).

They live in one file on purpose: numba's disk cache checks only the file a kernel is defined
in, so a cached kernel that called a kernel of another file would keep the old code of that
file after it changed (and then fail or compute the old thing: seen as "NRT_adapt_ndarray_to_
python: descr is NULL"). `tests/centroidal/test_kernels.py` checks that no cached kernel calls
one of another file. The modules that own the methods call these kernels from Python:
`centroidal.rotations` (the rotation helpers), `robots.model` (the estimator's kinematics
input), `wholebody.ik` (the pose errors), `stabilizers.centroidal_feedback` (Murooka's eqs.
15-16), `centroidal.mpc_formulations` (the linear MPC's face rows).
"""

from __future__ import annotations

import numpy as np
from numba import njit

_EPS = float(np.finfo(float).eps)


@njit(cache=True)
def matrix_of_quaternion(q: np.ndarray) -> np.ndarray:
    """`to_matrix` for compiled callers (a float64 array (4,))."""
    norm = np.sqrt(q[0] * q[0] + q[1] * q[1] + q[2] * q[2] + q[3] * q[3])
    w, x, y, z = q[0] / norm, q[1] / norm, q[2] / norm, q[3] / norm
    r = np.empty((3, 3))
    r[0, 0], r[0, 1], r[0, 2] = 1 - 2 * (y * y + z * z), 2 * (x * y - w * z), 2 * (x * z + w * y)
    r[1, 0], r[1, 1], r[1, 2] = 2 * (x * y + w * z), 1 - 2 * (x * x + z * z), 2 * (y * z - w * x)
    r[2, 0], r[2, 1], r[2, 2] = 2 * (x * z - w * y), 2 * (y * z + w * x), 1 - 2 * (x * x + y * y)
    return r


@njit(cache=True)
def quaternion_of_matrix(m: np.ndarray) -> np.ndarray:
    m00, m01, m02 = m[0, 0], m[0, 1], m[0, 2]
    m10, m11, m12 = m[1, 0], m[1, 1], m[1, 2]
    m20, m21, m22 = m[2, 0], m[2, 1], m[2, 2]
    trace = m00 + m11 + m22
    q = np.empty(4)
    if trace > 0:
        s = 2.0 * np.sqrt(trace + 1.0)
        q[0], q[1], q[2], q[3] = 0.25 * s, (m21 - m12) / s, (m02 - m20) / s, (m10 - m01) / s
    elif m00 > m11 and m00 > m22:
        s = 2.0 * np.sqrt(1.0 + m00 - m11 - m22)
        q[0], q[1], q[2], q[3] = (m21 - m12) / s, 0.25 * s, (m01 + m10) / s, (m02 + m20) / s
    elif m11 > m22:
        s = 2.0 * np.sqrt(1.0 + m11 - m00 - m22)
        q[0], q[1], q[2], q[3] = (m02 - m20) / s, (m01 + m10) / s, 0.25 * s, (m12 + m21) / s
    else:
        s = 2.0 * np.sqrt(1.0 + m22 - m00 - m11)
        q[0], q[1], q[2], q[3] = (m10 - m01) / s, (m02 + m20) / s, (m12 + m21) / s, 0.25 * s
    q /= np.sqrt(q[0] * q[0] + q[1] * q[1] + q[2] * q[2] + q[3] * q[3])
    if q[0] < 0:
        q = -q
    return q


@njit(cache=True)
def log_of_matrix(r: np.ndarray) -> np.ndarray:
    """`log` for compiled callers (a float64 array (3, 3))."""
    cos_angle = min(max((r[0, 0] + r[1, 1] + r[2, 2] - 1.0) / 2.0, -1.0), 1.0)
    angle = np.arccos(cos_angle)
    axis_times_sin = 0.5 * np.array([r[2, 1] - r[1, 2], r[0, 2] - r[2, 0], r[1, 0] - r[0, 1]])
    if angle < 1e-6:
        return axis_times_sin  # sin(angle) ~ angle
    if np.pi - angle < 1e-6:  # near pi: axis from the symmetric part
        symmetric = (r + np.eye(3)) / 2.0
        diagonal = np.sqrt(np.maximum(np.diag(symmetric).copy(), 0.0))
        k = int(np.argmax(diagonal))
        axis = symmetric[k] / diagonal[k]
        return angle * axis / np.sqrt(axis @ axis)
    return angle / np.sin(angle) * axis_times_sin


@njit(cache=True)
def exp_of_vector(v: np.ndarray) -> np.ndarray:
    angle = np.sqrt(v[0] * v[0] + v[1] * v[1] + v[2] * v[2])
    k = np.array([[0.0, -v[2], v[1]], [v[2], 0.0, -v[0]], [-v[1], v[0], 0.0]])
    if angle < 1e-9:
        return np.eye(3) + k
    return np.eye(3) + np.sin(angle) / angle * k + (1 - np.cos(angle)) / angle**2 * (k @ k)


@njit(cache=True)
def multiply_quaternion_rows(a: np.ndarray, b: np.ndarray) -> np.ndarray:
    out = np.empty((a.shape[0], 4))
    for i in range(a.shape[0]):
        aw, ax, ay, az = a[i, 0], a[i, 1], a[i, 2], a[i, 3]
        bw, bx, by, bz = b[i, 0], b[i, 1], b[i, 2], b[i, 3]
        out[i, 0] = aw * bw - ax * bx - ay * by - az * bz
        out[i, 1] = aw * bx + ax * bw + ay * bz - az * by
        out[i, 2] = aw * by - ax * bz + ay * bw + az * bx
        out[i, 3] = aw * bz + ax * by - ay * bx + az * bw
    return out


@njit(cache=True)
def quaternion_rows_of_vectors(vectors: np.ndarray) -> np.ndarray:
    out = np.empty((vectors.shape[0], 4))
    for i in range(vectors.shape[0]):
        x, y, z = vectors[i, 0], vectors[i, 1], vectors[i, 2]
        angle = np.sqrt(x * x + y * y + z * z)
        # sin(angle / 2) / angle, exact at zero (as numpy's sinc(angle / 2pi) / 2)
        half = np.pi * (angle / (2.0 * np.pi))
        if half == 0.0:
            half = _EPS
        scale = 0.5 * (np.sin(half) / half)
        out[i, 0] = np.cos(0.5 * angle)
        out[i, 1], out[i, 2], out[i, 3] = scale * x, scale * y, scale * z
    return out


@njit(cache=True)
def vector_rows_of_quaternions(quaternions: np.ndarray) -> np.ndarray:
    out = np.empty((quaternions.shape[0], 3))
    for i in range(quaternions.shape[0]):
        w, x, y, z = quaternions[i, 0], quaternions[i, 1], quaternions[i, 2], quaternions[i, 3]
        if w < 0:
            w, x, y, z = -w, -x, -y, -z
        sin_half = np.sqrt(x * x + y * y + z * z)
        angle = 2.0 * np.arctan2(sin_half, w)
        # angle / sin(angle / 2), with its limit 2 / w for a vanishing vector part
        scale = angle / sin_half if sin_half > 1e-9 else 2.0 / max(w, 1e-300)
        out[i, 0], out[i, 1], out[i, 2] = scale * x, scale * y, scale * z
    return out


@njit(cache=True)
def matrix_rows_of_quaternions(quaternions: np.ndarray) -> np.ndarray:
    out = np.empty((quaternions.shape[0], 3, 3))
    for i in range(quaternions.shape[0]):
        w, x, y, z = quaternions[i, 0], quaternions[i, 1], quaternions[i, 2], quaternions[i, 3]
        norm = np.sqrt(w * w + x * x + y * y + z * z)
        w, x, y, z = w / norm, x / norm, y / norm, z / norm
        out[i, 0, 0] = w * w + x * x - y * y - z * z
        out[i, 0, 1] = 2 * (x * y - w * z)
        out[i, 0, 2] = 2 * (x * z + w * y)
        out[i, 1, 0] = 2 * (x * y + w * z)
        out[i, 1, 1] = w * w - x * x + y * y - z * z
        out[i, 1, 2] = 2 * (y * z - w * x)
        out[i, 2, 0] = 2 * (x * z - w * y)
        out[i, 2, 1] = 2 * (y * z + w * x)
        out[i, 2, 2] = w * w - x * x - y * y + z * z
    return out


@njit(cache=True)
def relative_configuration(
    quaternion_wxyz: np.ndarray,
    angular_velocity_base: np.ndarray,
    joint_position: np.ndarray,
    joint_velocity: np.ndarray,
    q: np.ndarray,
    v: np.ndarray,
    rotation: np.ndarray,
) -> None:
    """Write into q, v (pinocchio's conventions, see `RobotModel.configuration`) the state with
    the base at the origin, orientation `quaternion_wxyz` (normalised), no base linear
    velocity, base angular velocity [rad/s] in the base's own axes (a gyro's), and the joints';
    and into `rotation` (3, 3) the base rotation (`centroidal.rotations.to_matrix`)."""
    rotation[:] = matrix_of_quaternion(quaternion_wxyz)
    norm = np.sqrt(quaternion_wxyz @ quaternion_wxyz)
    q[0] = q[1] = q[2] = 0.0
    q[3] = quaternion_wxyz[1] / norm
    q[4] = quaternion_wxyz[2] / norm
    q[5] = quaternion_wxyz[3] / norm
    q[6] = quaternion_wxyz[0] / norm
    q[7:] = joint_position
    v[0] = v[1] = v[2] = 0.0
    v[3:6] = angular_velocity_base
    v[6:] = joint_velocity


@njit(cache=True)
def pose_errors(
    target_positions: np.ndarray,
    target_orientations: np.ndarray,
    positions: np.ndarray,
    rotations: np.ndarray,
) -> np.ndarray:
    """Pose errors (k, 6): target position - position [m] for the first len(positions) poses
    (zero for the others), and log(R_target R^T) [rad] in world axes for every pose, with
    R_target of the (normalised) target quaternions (k, 4) (w, x, y, z)."""
    errors = np.zeros((len(rotations), 6))
    for i in range(len(positions)):
        for j in range(3):
            errors[i, j] = target_positions[i, j] - positions[i, j]
    difference = np.empty((3, 3))
    for i in range(len(rotations)):
        target, actual = matrix_of_quaternion(target_orientations[i]), rotations[i]
        for r in range(3):  # R_target R^T
            for c in range(3):
                difference[r, c] = (
                    target[r, 0] * actual[c, 0]
                    + target[r, 1] * actual[c, 1]
                    + target[r, 2] * actual[c, 2]
                )
        errors[i, 3:] = log_of_matrix(difference)
    return errors


@njit(cache=True)
def damping_control(
    target_position_world: np.ndarray,
    target_orientation_world: np.ndarray,
    wrench_measured_limb: np.ndarray,
    wrench_desired_limb: np.ndarray,
    kd: np.ndarray,
    ks: np.ndarray,
    kf: np.ndarray,
    dt: float,
    compliance_linear: np.ndarray,
    compliance_angular: np.ndarray,
) -> tuple[np.ndarray, np.ndarray]:
    """Eqs. 15-16 for every limb at once (compiled), per axis of each limb's contact frame (the
    frame of its target orientation, (k, 4)): the wrench error e = measured - desired (limb
    frames, (k, 6)) drives Kd dp/dt = Kf e - Ks p with the damping, stiffness and force gains
    (k, 6), so that Table II's entries for the contact normal and its tangents act along the
    contact's own normal and tangents (a hand on a wall, a foot on a rung). Ours: the paper's
    eq. 15 names no frame; Table II's separate normal and tangential gains (its sixth K_s
    entry about the normal) suggest the contact's. The compliances are contact-frame vectors,
    updated in place over `dt` [s]: the linear one (k, 3) [m] by Euler, the angular one
    (k, 3) [rad] on SO(3) (exp(dt rate) exp(p)). Returns the compliant limb positions
    target + R p (k, 3) [m] and orientations R exp(p) (k, 4). For a contact frame that differs
    from the world's by a yaw only, with Table II's equal x and y gains, this is the
    world-axes form R e that it replaced (issue 19; `tests/centroidal/test_kernel_equivalence`)."""
    targets = np.empty_like(target_orientation_world)
    for k in range(len(targets)):
        q = target_orientation_world[k]
        targets[k] = q / np.sqrt(q[0] * q[0] + q[1] * q[1] + q[2] * q[2] + q[3] * q[3])
    rotations = matrix_rows_of_quaternions(targets)
    angular_rate = np.empty_like(compliance_angular)
    compliant_position = np.empty_like(target_position_world)
    for k in range(len(targets)):
        difference = wrench_measured_limb[k] - wrench_desired_limb[k]
        for i in range(3):  # contact-frame errors
            compliance_linear[k, i] += dt * (
                (kf[k, i] * difference[i] - ks[k, i] * compliance_linear[k, i]) / kd[k, i]
            )
            angular_rate[k, i] = (
                kf[k, 3 + i] * difference[3 + i] - ks[k, 3 + i] * compliance_angular[k, i]
            ) / kd[k, 3 + i]
        r, p = rotations[k], compliance_linear[k]
        for i in range(3):
            compliant_position[k, i] = target_position_world[k, i] + (
                r[i, 0] * p[0] + r[i, 1] * p[1] + r[i, 2] * p[2]
            )
    turned = multiply_quaternion_rows(
        quaternion_rows_of_vectors(dt * angular_rate),
        quaternion_rows_of_vectors(compliance_angular),
    )
    compliance_angular[:] = vector_rows_of_quaternions(turned)  # eq. 16 on SO(3)
    compliant_orientation = multiply_quaternion_rows(
        targets, quaternion_rows_of_vectors(compliance_angular)
    )
    return compliant_position, compliant_orientation


@njit(cache=True)
def unit_face_rows(faces: np.ndarray, sample: np.ndarray, points: np.ndarray) -> np.ndarray:
    """The face form's constraint rows F_k T_k^-1 scaled to unit norm (`centroidal.
    mpc_formulations.FaceForm`): row i of `faces` (m, 6), a face [a_f, a_n] of its sample's
    cone with moments about the origin, becomes [a_f + a_n x c-hat_k, a_n] / norm for the
    moment about c-hat_k = points[sample[i]] (points (N, 3) [m]): a . (c x f) = f . (a x c).
    The same arithmetic, in the same order, as the numpy expressions it replaced (the rows
    are equal to the bit: `tests/centroidal/test_kernel_equivalence.py`; that order is the
    pinned numpy's on x86-64, where its einsum sums without fused multiply-adds)."""
    m = faces.shape[0]
    rows = np.empty((m, 6))
    for i in range(m):
        c = points[sample[i]]
        a0, a1, a2 = faces[i, 3], faces[i, 4], faces[i, 5]
        rows[i, 0] = faces[i, 0] + (a1 * c[2] - a2 * c[1])
        rows[i, 1] = faces[i, 1] + (a2 * c[0] - a0 * c[2])
        rows[i, 2] = faces[i, 2] + (a0 * c[1] - a1 * c[0])
        rows[i, 3], rows[i, 4], rows[i, 5] = a0, a1, a2
        # even and odd terms summed apart, then added: numpy's einsum("ij,ij->i") order,
        # so that the rows are the same to the bit as the expression this replaced
        even = rows[i, 0] * rows[i, 0] + rows[i, 2] * rows[i, 2] + rows[i, 4] * rows[i, 4]
        odd = rows[i, 1] * rows[i, 1] + rows[i, 3] * rows[i, 3] + rows[i, 5] * rows[i, 5]
        norm = np.sqrt(even + odd)
        for j in range(6):
            rows[i, j] /= norm
    return rows


@njit(cache=True)
def face_rows_hold(
    rows: np.ndarray, sample: np.ndarray, inputs: np.ndarray, slack: np.ndarray
) -> np.ndarray:
    """Whether each unit face row holds at the inputs U (N, 6): rows[i] . U[sample[i]] <=
    slack[i] (the face form's F T^-1 U <= 0, with quadprog's anti-cycling slack, from each
    row's 6 nonzeros)."""
    m = rows.shape[0]
    holds = np.empty(m, dtype=np.bool_)
    for i in range(m):
        u = inputs[sample[i]]
        even = rows[i, 0] * u[0] + rows[i, 2] * u[2] + rows[i, 4] * u[4]
        odd = rows[i, 1] * u[1] + rows[i, 3] * u[3] + rows[i, 5] * u[5]
        holds[i] = even + odd <= slack[i]  # einsum's order, as for the norms
    return holds
