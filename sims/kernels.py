"""Compiled kernels of the simulators' per-period sensor path (numba, cached on disk in
`__pycache__`: the first process compiles them, later ones load them in milliseconds).

Each kernel does in one call what would otherwise be a dozen numpy calls on arrays of 2-20
entries, where numpy's per-call dispatch (about 1 us, 2-3 us once the control stages have
evicted it from the caches) costs more than the arithmetic. Numba without `fastmath` neither
reorders nor fuses operations: elementwise formulas (the servo law) are bit-identical to their
numpy versions; sums and 3x3 products may round differently from numpy's (BLAS) order, to
1e-12 (tests/sims/test_sensor_path.py).
"""

from __future__ import annotations

import numpy as np
from numba import njit


@njit(cache=True)
def servo_torque_kernel(
    position: np.ndarray,
    velocity: np.ndarray,
    torque_feedforward: np.ndarray,
    kp: np.ndarray,
    kd: np.ndarray,
    q: np.ndarray,
    dq: np.ndarray,
    torque_limit: np.ndarray,
) -> np.ndarray:
    """`sims.servo.servo_torque` (tau = Kp (q_d - q) + Kd (dq_d - dq) + tau_ff clipped to
    +-limit [N m]) in one call."""
    n = len(q)
    tau = np.empty(n)
    for i in range(n):
        t = kp[i] * (position[i] - q[i]) + kd[i] * (velocity[i] - dq[i]) + torque_feedforward[i]
        limit = torque_limit[i]
        tau[i] = min(max(t, -limit), limit)
    return tau


@njit(cache=True)
def limb_contacts_from_spatial(
    spatial_body: np.ndarray,
    reference_point_world: np.ndarray,
    frame_origin_world: np.ndarray,
    frame_rotation_world: np.ndarray,
    limb_body: np.ndarray,
    limb_reference: np.ndarray,
    limb_frame: np.ndarray,
    contact_geoms: np.ndarray,
    scene_geom: np.ndarray,
    geom_body: np.ndarray,
    wrench: np.ndarray,
) -> tuple[np.ndarray, np.ndarray]:
    """The sensor contract's contact wrenches and flags from a physics engine's per-body
    external spatial forces.

    spatial_body (n_bodies, 6): moment [N m] about the body's reference point, then force [N],
    world axes (MuJoCo's `cfrc_ext`); reference_point_world (n_points, 3) [m] (MuJoCo's
    `subtree_com`); frame origins (n_frames, 3) [m] and row-major rotations (n_frames, 9)
    (`site_xpos`, `site_xmat`); per limb: its body, reference point and frame indices;
    contact_geoms (n_contacts, 2) the geoms of each active contact, scene_geom (n_geoms,) bool,
    geom_body (n_geoms,) the body of each geom.

    Writes the wrench on each limb into `wrench` (k, 6) (force, then moment about its frame's
    origin, in its frame's axes); returns whether each limb touches the scene (k,) and the robot
    bodies of the robot-scene contacts (n,)."""
    n_limbs = len(limb_body)
    for k in range(n_limbs):
        s = spatial_body[limb_body[k]]
        c = reference_point_world[limb_reference[k]]
        o = frame_origin_world[limb_frame[k]]
        r = frame_rotation_world[limb_frame[k]]
        rx, ry, rz = c[0] - o[0], c[1] - o[1], c[2] - o[2]
        fx, fy, fz = s[3], s[4], s[5]
        mx = s[0] + (ry * fz - rz * fy)
        my = s[1] + (rz * fx - rx * fz)
        mz = s[2] + (rx * fy - ry * fx)
        for j in range(3):  # R^T: column j of the row-major rotation
            wrench[k, j] = r[j] * fx + r[3 + j] * fy + r[6 + j] * fz
            wrench[k, 3 + j] = r[j] * mx + r[3 + j] * my + r[6 + j] * mz
    n = len(contact_geoms)
    bodies = np.empty(n, dtype=np.int64)
    count = 0
    for i in range(n):
        g1, g2 = contact_geoms[i, 0], contact_geoms[i, 1]
        if scene_geom[g1] != scene_geom[g2]:
            bodies[count] = geom_body[g2] if scene_geom[g1] else geom_body[g1]
            count += 1
    flags = np.zeros(n_limbs, dtype=np.bool_)
    for k in range(n_limbs):
        for i in range(count):
            if bodies[i] == limb_body[k]:
                flags[k] = True
                break
    return flags, bodies[:count]


@njit(cache=True)
def rotate_by_quaternion(quaternion_wxyz: np.ndarray, vector: np.ndarray, out: np.ndarray) -> None:
    """out = R(q) v, with R(q) the rotation matrix of `sims.base.quaternion_to_matrix` (the
    same entries, multiplied row by row)."""
    w, x, y, z = quaternion_wxyz[0], quaternion_wxyz[1], quaternion_wxyz[2], quaternion_wxyz[3]
    v0, v1, v2 = vector[0], vector[1], vector[2]
    out[0] = (1 - 2 * (y * y + z * z)) * v0 + 2 * (x * y - w * z) * v1 + 2 * (x * z + w * y) * v2
    out[1] = 2 * (x * y + w * z) * v0 + (1 - 2 * (x * x + z * z)) * v1 + 2 * (y * z - w * x) * v2
    out[2] = 2 * (x * z - w * y) * v0 + 2 * (y * z + w * x) * v1 + (1 - 2 * (x * x + y * y)) * v2


@njit(cache=True)
def mujoco_sensors(
    qpos: np.ndarray,
    qvel: np.ndarray,
    sensordata: np.ndarray,
    joint_torque: np.ndarray,
    joint_qpos: np.ndarray,
    joint_dof: np.ndarray,
    root_and_imu: np.ndarray,
    spatial_body: np.ndarray,
    reference_point_world: np.ndarray,
    frame_origin_world: np.ndarray,
    frame_rotation_world: np.ndarray,
    limb_body: np.ndarray,
    limb_reference: np.ndarray,
    limb_frame: np.ndarray,
    contact_geoms: np.ndarray,
    scene_geom: np.ndarray,
    geom_body: np.ndarray,
    limb_body_mask: np.ndarray,
    warnings: np.ndarray,
    unstable_warnings: np.ndarray,
    out: np.ndarray,
    checks: np.ndarray,
) -> tuple[np.ndarray, np.ndarray]:
    """Fill a `sims.sensor_buffer` buffer from MuJoCo's qpos, qvel and sensordata: joints at
    `joint_qpos` / `joint_dof`; root_and_imu = (root qpos address, root dof address, IMU
    quaternion, gyro and accelerometer addresses in sensordata); the free joint's angular
    velocity is in the base frame: rotated into the world. The limb wrenches and the returned
    contact flags and touching bodies: `limb_contacts_from_spatial` with the other arguments.

    `checks` (4,) receives: the base's `tilt_angle` [rad]; the number of robot-scene contacts on
    bodies that are not limbs (`limb_body_mask` (n_bodies,) bool); 1.0 if the joint and base
    positions are finite, else 0.0; the number of MuJoCo warnings (`warnings`, MjData's
    per-warning counts) among `unstable_warnings`."""
    n = len(joint_qpos)
    for i in range(n):
        out[i] = qpos[joint_qpos[i]]
        out[n + i] = qvel[joint_dof[i]]
        out[2 * n + i] = joint_torque[i]
    o = 3 * n
    r, v = root_and_imu[0], root_and_imu[1]
    for i in range(7):
        out[o + i] = qpos[r + i]
    for i in range(3):
        out[o + 7 + i] = qvel[v + i]
    rotate_by_quaternion(out[o + 3 : o + 7], qvel[v + 3 : v + 6], out[o + 10 : o + 13])
    quat, gyro, accel = root_and_imu[2], root_and_imu[3], root_and_imu[4]
    for i in range(4):
        out[o + 13 + i] = sensordata[quat + i]
    for i in range(3):
        out[o + 17 + i] = sensordata[gyro + i]
        out[o + 20 + i] = sensordata[accel + i]
    x, y = out[o + 4], out[o + 5]
    checks[0] = np.arccos(min(max(1.0 - 2.0 * (x * x + y * y), -1.0), 1.0))
    total = 0.0
    for i in range(n):
        total += out[i]
    for i in range(3):
        total += out[o + i]
    checks[2] = 1.0 if np.isfinite(total) else 0.0
    count = 0
    for i in unstable_warnings:
        count += warnings[i]
    checks[3] = count
    flags, bodies = limb_contacts_from_spatial(
        spatial_body,
        reference_point_world,
        frame_origin_world,
        frame_rotation_world,
        limb_body,
        limb_reference,
        limb_frame,
        contact_geoms,
        scene_geom,
        geom_body,
        out[o + 23 :].reshape(len(limb_body), 6),
    )
    others = 0
    for b in bodies:
        if not limb_body_mask[b]:
            others += 1
    checks[1] = others
    return flags, bodies


@njit(cache=True)
def quaternion_matrix(w: float, x: float, y: float, z: float) -> np.ndarray:
    """`sims.base.quaternion_to_matrix` of (w, x, y, z) (unnormalised; it repeats
    `centroidal.kernels.matrix_of_quaternion` because a cached kernel may call only kernels
    of its own file, see `centroidal.kernels`)."""
    r = np.empty((3, 3))
    r[0, 0], r[0, 1], r[0, 2] = 1 - 2 * (y * y + z * z), 2 * (x * y - w * z), 2 * (x * z + w * y)
    r[1, 0], r[1, 1], r[1, 2] = 2 * (x * y + w * z), 1 - 2 * (x * x + z * z), 2 * (y * z - w * x)
    r[2, 0], r[2, 1], r[2, 2] = 2 * (x * z - w * y), 2 * (y * z + w * x), 1 - 2 * (x * x + y * y)
    return r


@njit(cache=True)
def pybullet_sensors(
    values: np.ndarray,
    joint_position: np.ndarray,
    joint_velocity: np.ndarray,
    joint_torque: np.ndarray,
    contacts: np.ndarray,
    limb_link: np.ndarray,
    base_com_in_link: np.ndarray,
    base_inertial_rotation: np.ndarray,
    base_inertial_conjugate: np.ndarray,
    gravity: float,
    physics_dt: float,
    out: np.ndarray,
    checks: np.ndarray,
) -> np.ndarray:
    """Fill a `sims.sensor_buffer` buffer from PyBullet's reads of one period.

    values: the base's CoM [m], inertial-frame quaternion (x, y, z, w), CoM velocity [m/s] and
    angular velocity [rad/s] (world); then per limb its contact frame's origin [m] and
    quaternion (x, y, z, w); then the IMU frame's quaternion (x, y, z, w), linear [m/s] and
    angular velocity [rad/s] (world), and its linear velocity before the last physics step.
    contacts (n, 17): per contact point, the robot link, the point on the robot [m], the
    distance [m], the normal force [N] and the normal (on the robot), the two friction forces
    [N] and their directions. PyBullet places the base at its inertial frame: the base link's
    pose and origin velocity follow from `base_com_in_link`, `base_inertial_rotation` and the
    conjugate of its quaternion (w, x, y, z). The accelerometer is the finite difference of the
    IMU frame's velocity over the last physics step, minus gravity [m/s^2], in the IMU frame.

    Returns whether each limb touches the scene (k,); `checks` (4,) receives the base's
    `tilt_angle` [rad], the number of contacts on links that are not limbs, 1.0 if the state is
    finite (else 0.0), and 0."""
    n = len(joint_position)
    for i in range(n):
        out[i] = joint_position[i]
        out[n + i] = joint_velocity[i]
        out[2 * n + i] = joint_torque[i]
    o = 3 * n
    # the base link's pose from the inertial frame's
    cx, cy, cz = values[0], values[1], values[2]
    iw, ix, iy, iz = values[6], values[3], values[4], values[5]
    rotation = quaternion_matrix(iw, ix, iy, iz) @ base_inertial_rotation.T
    origin = np.empty(3)
    for i in range(3):
        origin[i] = values[i] - (
            rotation[i, 0] * base_com_in_link[0]
            + rotation[i, 1] * base_com_in_link[1]
            + rotation[i, 2] * base_com_in_link[2]
        )
        out[o + i] = origin[i]
    bw, bx, by, bz = (
        base_inertial_conjugate[0],
        base_inertial_conjugate[1],
        base_inertial_conjugate[2],
        base_inertial_conjugate[3],
    )
    qw = iw * bw - ix * bx - iy * by - iz * bz
    qx = iw * bx + ix * bw + iy * bz - iz * by
    qy = iw * by - ix * bz + iy * bw + iz * bx
    qz = iw * bz + ix * by - iy * bx + iz * bw
    norm = np.sqrt(qw * qw + qx * qx + qy * qy + qz * qz)
    sign = -1.0 if qw < 0 else 1.0
    out[o + 3] = sign * qw / norm
    out[o + 4] = sign * qx / norm
    out[o + 5] = sign * qy / norm
    out[o + 6] = sign * qz / norm
    wx, wy, wz = values[10], values[11], values[12]
    rx, ry, rz = origin[0] - cx, origin[1] - cy, origin[2] - cz
    out[o + 7] = values[7] + (wy * rz - wz * ry)
    out[o + 8] = values[8] + (wz * rx - wx * rz)
    out[o + 9] = values[9] + (wx * ry - wy * rx)
    out[o + 10], out[o + 11], out[o + 12] = wx, wy, wz
    # the IMU
    k_limbs = len(limb_link)
    m = 13 + 7 * k_limbs
    uw, ux, uy, uz = values[m + 3], values[m], values[m + 1], values[m + 2]
    imu = quaternion_matrix(uw, ux, uy, uz)
    out[o + 13], out[o + 14], out[o + 15], out[o + 16] = uw, ux, uy, uz
    for j in range(3):
        out[o + 17 + j] = (
            imu[0, j] * values[m + 7] + imu[1, j] * values[m + 8] + imu[2, j] * (values[m + 9])
        )
    specific = np.empty(3)
    for i in range(3):
        specific[i] = (values[m + 4 + i] - values[m + 10 + i]) / physics_dt
    specific[2] += gravity
    for j in range(3):
        out[o + 20 + j] = (
            imu[0, j] * specific[0] + imu[1, j] * specific[1] + imu[2, j] * specific[2]
        )
    # the limbs' contact wrenches: contacts summed per limb about its frame's origin
    flags = np.zeros(k_limbs, dtype=np.bool_)
    others = 0
    for k in range(k_limbs):
        for j in range(6):
            out[o + 23 + 6 * k + j] = 0.0
    force = np.zeros((k_limbs, 3))
    moment = np.zeros((k_limbs, 3))
    for c in range(len(contacts)):
        p = contacts[c]
        if p[4] > 0.0 and p[5] <= 0.0:  # separated and carrying no force
            continue
        limb = -1
        for k in range(k_limbs):
            if limb_link[k] == p[0]:
                limb = k
        if limb < 0:
            others += 1
            continue
        flags[limb] = True
        f = np.empty(3)
        for i in range(3):
            f[i] = p[5] * p[6 + i] + p[9] * p[10 + i] + p[13] * p[14 + i]
        force[limb, 0] += f[0]
        force[limb, 1] += f[1]
        force[limb, 2] += f[2]
        moment[limb, 0] += p[2] * f[2] - p[3] * f[1]
        moment[limb, 1] += p[3] * f[0] - p[1] * f[2]
        moment[limb, 2] += p[1] * f[1] - p[2] * f[0]
    for k in range(k_limbs):
        b = 13 + 7 * k
        ox, oy, oz = values[b], values[b + 1], values[b + 2]
        r = quaternion_matrix(values[b + 6], values[b + 3], values[b + 4], values[b + 5])
        fx, fy, fz = force[k, 0], force[k, 1], force[k, 2]
        mx = moment[k, 0] - (oy * fz - oz * fy)
        my = moment[k, 1] - (oz * fx - ox * fz)
        mz = moment[k, 2] - (ox * fy - oy * fx)
        for j in range(3):
            out[o + 23 + 6 * k + j] = r[0, j] * fx + r[1, j] * fy + r[2, j] * fz
            out[o + 26 + 6 * k + j] = r[0, j] * mx + r[1, j] * my + r[2, j] * mz
    x, y = out[o + 4], out[o + 5]
    checks[0] = np.arccos(min(max(1.0 - 2.0 * (x * x + y * y), -1.0), 1.0))
    checks[1] = others
    total = 0.0
    for i in range(n):
        total += out[i]
    for i in range(3):
        total += out[o + i]
    checks[2] = 1.0 if np.isfinite(total) else 0.0
    checks[3] = 0.0
    return flags
