"""`five_mass_kalman`: Ficht & Behnke's state estimation (paper 003, Sec. 3.2, eqs. 6-7) from
the IMU and the joint encoders only, no force sensors.

- Base orientation and angular velocity: the IMU's (the paper: "an attitude estimator of
  choice"; our IMU reports its orientation).
- Support foot: the lower of the two soles (world z through the IMU's orientation and the
  encoders), switched only when the other sole is lower by more than `hysteresis` [m] (the
  paper's "semi double support" band; 5 mm at scale 1, scaled with the robot).
- Ground frame and odometry: the paper measures the state in a ground frame Sigma_G tied to
  the support foot ("laterally offset from the supporting foot by half of the step width from
  the last step taken") so that the measured and the control state are synchronised. Here the
  support sole is anchored on the plan's foothold for it while the plan has that foot as its
  support (`follow`), which expresses the measured CoM relative to the support foot in the
  frame of the reference; when the two disagree (around an exchange) the sole stays where
  the kinematics put it when it became the support (odometry over the exchange). The base is
  placed so that the support sole is at its anchor; the base velocity makes the support sole's
  velocity zero. (With a pure odometry world instead, each touchdown error becomes a CoM
  error that the controller chases: measured, the walk fell after 6.2 s in MuJoCo.)
- CoM: the five-mass CoM (`robots.five_mass`), which is the full robot's CoM.
- A Kalman filter per horizontal axis on [x, x', x''] with the "linear mass model" (constant
  acceleration, jerk as process noise; the paper does not enforce the LIPM in the filter),
  measuring the CoM position and the unrotated, gravity-free trunk acceleration
  G a_t = R_t a_imu - [0, 0, g] (eq. 6; the IMU's specific force rotated to the world).
  The filter is time-invariant, so its steady-state gain is computed once from the discrete
  Riccati equation (scipy; ours: the paper does not say whether its gain is the steady one).
  Its noises (`COM_POSITION_NOISE_M` ... `TILT_JERK_NOISE`) are ours, the paper gives none;
  the jerk noise is a density (per sqrt(Hz)) while the measurement noises are per sample, so
  at another period the filter trusts the accelerometer differently (its gain on the
  acceleration 0.72 at 500 Hz, 0.91 at 100 Hz, the paper's control rate).
- ZMP (eq. 7): p = x^ - z^ / g x^'', with z^ the CoM height above the support sole.
- `five_mass_kalman_com` (ours, not the paper's): the same filter measuring the IMU's
  acceleration transported to the CoM through the kinematics, G a_c = G a_t + d/dt (c' - t')
  (`transport_to_com`), for a robot whose IMU is not in its trunk: JVRC-1's is on its pelvis
  below the waist joints, where the touchdowns' impacts reach it (docs/ficht-behnke.md, "The
  five-mass filter on JVRC-1").
- A second filter of the same form on the flywheel angle, measuring the angles only, gives
  their rates and accelerations (ours, our reading: the paper filters "the angles of the
  inertia orientation" R_I; we filter what its eq. 13 controls, R_I's angles less the
  pendulum's): the projected tilt angles (`centroidal.tilt`) of the
  principal z axis of inertia less those of the line from the feet's midpoint to the CoM (the
  pendulum of eq. 5's neutral tilt: "the torque of a flywheel attached to a pendulum is zero
  [when] it does not rotate with respect to it").

The sensors' contact flags and wrenches are passed through to the state for the runner's
record (footsteps taken, measured wrenches); nothing here reads them.
"""

from __future__ import annotations

import numpy as np
import pinocchio as pin
from scipy.linalg import solve_discrete_are

from centroidal.gravity import GRAVITY
from centroidal.kernels import relative_configuration
from centroidal.tilt import flywheel_angles
from estimators.base import ComponentSpec, EstimatorBase, register
from robots.five_mass import FiveMassModel
from robots.model import RobotModel
from robots.types import CentroidalPlan, RobotState, Sensors

# Ours, all (the paper gives no values):
HYSTERESIS_M = 0.005  # [m] at scale 1
COM_POSITION_NOISE_M = 0.002  # [m] five-mass CoM against the true one (model, encoder errors)
TRUNK_ACCELERATION_NOISE = 1.0  # [m/s^2] the trunk's acceleration is the CoM's only roughly
COM_JERK_NOISE = 30.0  # [m/s^3 sqrt(s)], per sqrt(Hz): how fast the CoM acceleration may change
TILT_NOISE_RAD = 0.002  # [rad]
TILT_JERK_NOISE = 30.0  # [rad/s^3 sqrt(s)], per sqrt(Hz)


def constant_acceleration_model(dt: float, jerk: float) -> tuple[np.ndarray, np.ndarray]:
    """(F, Q) of [x, x', x''] over dt [s], the jerk held over each period (zero-order hold)
    as a white sequence of variance jerk^2 / dt, so Q = jerk^2 / dt g g^T with g = (dt^3 / 6,
    dt^2 / 2, dt): a rank-one approximation of a white jerk of spectral density jerk^2
    [(m/s^3)^2 / Hz], whose exact Q is jerk^2 [[dt^5/20, dt^4/8, dt^3/6], [dt^4/8, dt^3/3,
    dt^2/2], [dt^3/6, dt^2/2, dt]] (ours; the steady gain differs from the exact one's by
    about 7 % at 2 ms)."""
    f = np.array([[1.0, dt, dt * dt / 2], [0.0, 1.0, dt], [0.0, 0.0, 1.0]])
    g = np.array([[dt**3 / 6], [dt * dt / 2], [dt]])
    return f, jerk**2 / dt * (g @ g.T)


def steady_state_gain(f: np.ndarray, q: np.ndarray, h: np.ndarray, r: np.ndarray) -> np.ndarray:
    """The steady-state Kalman gain K (n, m) of x+ = F x + w, z = H x + v (scipy's DARE on the
    dual system gives the prior covariance P; K = P H^T (H P H^T + R)^-1)."""
    p = solve_discrete_are(f.T, h.T, q, r)
    return p @ h.T @ np.linalg.inv(h @ p @ h.T + r)


class AxisFilter:
    """Kalman filters on [x, x', x''] for several independent axes sharing one model:
    predict with F, correct with the steady-state gain."""

    def __init__(self, dt: float, jerk: float, h: np.ndarray, noise: np.ndarray, axes: int):
        self.f, q = constant_acceleration_model(dt, jerk)
        self.h = h
        self.gain = steady_state_gain(self.f, q, h, np.diag(np.square(noise)))
        self.state = np.zeros((3, axes))

    def reset(self, position: np.ndarray) -> None:
        self.state[:] = 0.0
        self.state[0] = position

    def update(self, measurement: np.ndarray) -> np.ndarray:
        """measurement (m, axes); returns the state (3, axes)."""
        prior = self.f @ self.state
        self.state = prior + self.gain @ (measurement - self.h @ prior)
        return self.state


def transport_to_com(
    acceleration_imu_world: np.ndarray,
    relative_velocity_world: np.ndarray,
    previous_relative_velocity_world: np.ndarray | None,
    dt: float,
) -> np.ndarray:
    """[m/s^2] the CoM's acceleration (world axes) from the IMU's: c'' = t'' + d/dt (c' - t'),
    with c' - t' [m/s] the CoM's velocity relative to the IMU's origin (world axes, from the
    encoders and the gyro, so independent of the base's linear velocity) this period and the
    last, differenced over dt [s] (one period's backward difference; None: the first period,
    the IMU's acceleration as it is). Ours: the paper measures the trunk's acceleration
    (eq. 6), which is the CoM's only as far as the trunk moves with the CoM."""
    if previous_relative_velocity_world is None:
        return acceleration_imu_world.copy()
    return (
        acceleration_imu_world + (relative_velocity_world - previous_relative_velocity_world) / dt
    )


class FiveMassKalmanEstimator(EstimatorBase):
    name = "five_mass_kalman"

    def __init__(self, model: RobotModel, dt: float = 0.002, at_com: bool = False) -> None:
        """at_com: measure the IMU's acceleration transported to the CoM (`transport_to_com`,
        ours) instead of the trunk's (eq. 6, the paper's)."""
        super().__init__(model)
        self.at_com = at_com
        self.imu_frame = model.frame_id[model.robot.imu_frame]
        self.five = FiveMassModel(model)
        self.dt = dt
        self.hysteresis = HYSTERESIS_M * model.robot.scale
        self.limb_names = list(model.robot.limb_names)
        self.foot_frames = [self.limb_frames[k] for k in self.foot_index]
        self.foot_names = frozenset(self.limb_names[k] for k in self.foot_index)
        self.com_filter = AxisFilter(
            dt,
            COM_JERK_NOISE,
            np.array([[1.0, 0.0, 0.0], [0.0, 0.0, 1.0]]),
            np.array([COM_POSITION_NOISE_M, TRUNK_ACCELERATION_NOISE]),
            axes=2,
        )
        self.tilt_filter = AxisFilter(
            dt, TILT_JERK_NOISE, np.array([[1.0, 0.0, 0.0]]), np.array([TILT_NOISE_RAD]), axes=2
        )
        self._q = np.zeros(self.model.nq)
        self._v = np.zeros(self.model.nv)
        self._rotation = np.eye(3)

    def reset(self, initial: RobotState, sensors: Sensors) -> None:
        q = self.robot_model.configuration(initial)
        pin.framesForwardKinematics(self.model, self.data, q)
        heights = [self.data.oMf[f].translation[2] for f in self.foot_frames]
        self.last_time = sensors.time
        self.planned_support: int | None = None
        self.planned_position = np.zeros((len(self.limb_frames), 3))
        self.support = int(np.argmin(heights))  # index into foot_frames
        self.anchor = self.data.oMf[self.foot_frames[self.support]].translation.copy()
        five = self.five.evaluate(q)
        self.com_filter.reset(five.com_world[:2])
        soles = [self.data.oMf[f].translation for f in self.foot_frames]
        pendulum = five.com_world - (soles[0] + soles[1]) / 2
        self.tilt_filter.reset(flywheel_angles(five.axes_world[:, 2], pendulum))
        self._relative_velocity: np.ndarray | None = None
        self._last: RobotState | None = None  # the estimate of the last sensor time

    def follow(self, plan: CentroidalPlan) -> None:
        """The plan's support foot and footholds: the ground frame in which the reference is
        expressed (see the module)."""
        planned_feet = [c for c in plan.contact_limbs if c in self.foot_names]  # no hands
        self.planned_support = None
        if len(planned_feet) == 1:
            self.planned_support = self.limb_names.index(planned_feet[0])
        elif len(planned_feet) == 2:  # double support: the foot found below is on its foothold
            self.planned_support = self.foot_index[self.support]
        self.planned_position = plan.limb_target_position_world

    def estimate(self, sensors: Sensors) -> RobotState:
        """One filter step per sensor time: a reading of the time already estimated (the
        runner reads the reset's twice, before its loop and in its first period) is no new
        measurement, and gets the last estimate (a second step would predict dt ahead)."""
        step = sensors.time - self.last_time
        if step <= 1e-9 and self._last is not None:
            return self._last
        if step > 1e-9 and abs(step - self.dt) > 1e-9:
            raise ValueError(f"five_mass_kalman is tuned for {self.dt} s periods, got {step} s")
        self.last_time = sensors.time
        orientation = sensors.imu_orientation_world
        q, v, rotation = self._q, self._v, self._rotation
        relative_configuration(
            orientation,
            sensors.imu_angular_velocity_imu,
            sensors.joint_position,
            sensors.joint_velocity,
            q,
            v,
            rotation,
        )
        model, data = self.model, self.data
        pin.forwardKinematics(model, data, q, v)
        pin.updateFramePlacements(model, data)
        soles = [data.oMf[f].translation for f in self.foot_frames]
        other = 1 - self.support
        if soles[other][2] < soles[self.support][2] - self.hysteresis:  # exchange: odometry
            base_now = self.anchor - soles[self.support]
            self.support = other
            self.anchor = base_now + soles[other]
        support_limb = self.foot_index[self.support]
        if self.planned_support is not None and self.planned_support == support_limb:
            moved = self.planned_position[support_limb] - self.anchor
            self.anchor = self.planned_position[support_limb]  # Sigma_G on the plan's foothold
            self.com_filter.state[0] += moved[:2]  # the frame moved, not the CoM
        base_position = self.anchor - soles[self.support]
        base_velocity = -pin.getFrameVelocity(
            model, data, self.foot_frames[self.support], pin.LOCAL_WORLD_ALIGNED
        ).linear
        # the five masses at the relative configuration, then shifted by the base position
        pin.centerOfMass(model, data, q, v, True)
        com_relative = np.array(data.com[0])
        com_velocity = np.array(data.vcom[0]) + base_velocity
        five = self.five.from_data(data)
        com = com_relative + base_position
        trunk_acceleration = rotation @ sensors.imu_linear_acceleration_imu
        trunk_acceleration[2] -= GRAVITY  # eq. 6
        if self.at_com:
            imu_velocity = pin.getFrameVelocity(
                model, data, self.imu_frame, pin.LOCAL_WORLD_ALIGNED
            )
            relative = data.vcom[0] - imu_velocity.linear
            trunk_acceleration = transport_to_com(
                trunk_acceleration, relative, self._relative_velocity, self.dt
            )
            self._relative_velocity = relative.copy()
        state = self.com_filter.update(np.array([com[:2], trunk_acceleration[:2]]))
        pendulum = com_relative - (soles[0] + soles[1]) / 2  # feet's midpoint to CoM
        flywheel = flywheel_angles(five.axes_world[:, 2], pendulum)
        tilt = self.tilt_filter.update(flywheel[None])
        height = com[2] - (soles[self.support][2] + base_position[2])
        zmp = np.array(
            [*(state[0] - height / GRAVITY * state[2]), soles[self.support][2] + base_position[2]]
        )  # eq. 7
        self._last = RobotState(
            base_position,
            orientation.copy(),
            base_velocity,
            rotation @ sensors.imu_angular_velocity_imu,
            sensors.joint_position,
            sensors.joint_velocity,
            time=sensors.time,
            com_position_world=np.array([state[0, 0], state[0, 1], com[2]]),
            com_velocity_world=np.array([state[1, 0], state[1, 1], com_velocity[2]]),
            contact_wrench_limb=sensors.contact_wrench_limb,
            contact_flag_limb=sensors.contact_flag_limb,
            zmp_world=zmp,
            # z: 0, not estimated (the filters are horizontal; eq. 7 needs none)
            com_acceleration_world=np.array([state[2, 0], state[2, 1], 0.0]),
            inertia_tilt=tilt[0].copy(),
            inertia_tilt_rate=tilt[1].copy(),
            inertia_tilt_acceleration=tilt[2].copy(),
        )
        return self._last


def _make(model: RobotModel, dt: float) -> FiveMassKalmanEstimator:
    return FiveMassKalmanEstimator(model, dt)


def _make_at_com(model: RobotModel, dt: float) -> FiveMassKalmanEstimator:
    return FiveMassKalmanEstimator(model, dt, at_com=True)


register(
    ComponentSpec(
        "five_mass_kalman",
        _make,
        "Ficht & Behnke: IMU and encoders only, lower-foot odometry, Kalman CoM and ZMP (eq. 6-7)",
        gives=frozenset({"inertia_tilt"}),
    )
)
register(
    ComponentSpec(
        "five_mass_kalman_com",
        _make_at_com,
        "ours: five_mass_kalman with the IMU's acceleration transported to the CoM through the "
        "kinematics (for an IMU outside the trunk)",
        gives=frozenset({"inertia_tilt"}),
    )
)
