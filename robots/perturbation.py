"""What a robustness sweep changes in an episode (issue 21): the sensors, the loop's delays,
the simulated robot against the controller's model, its actuators and the ground.

A `Perturbation` is plain data with every field at a default that changes nothing (the
nominal episode). What it changes, and where:

- sensors (`sims.sensor_model`): Gaussian white noise on the joint encoders, the IMU and the
  force/torque sensors, per sensor group in multiples of a real sensor's data-sheet figures
  (`sims.sensor_model.DATASHEET`) or per channel as a standard deviation in SI units, and a
  constant bias per episode;
- delays (`sims.sensor_model`): the joint command applied `command_delay` control periods
  late; the estimator reads sensors `sensor_delay` periods old;
- model error (`simulated_robot` here): the simulated robot carries a payload on its torso,
  has its centre of mass moved forward, or has every link's mass off by up to a relative
  amount, while the controller keeps the nominal model;
- actuation: every joint's torque limit (`simulated_robot`) and the servo gains of every
  applied command (`sims.sensor_model.CommandDelay`) scaled;
- ground (`ground_boxes`): a seeded field of thin boxes of bounded height, or a ramp.
"""

from __future__ import annotations

from dataclasses import dataclass, fields, replace

import numpy as np

from robots.inertia import combined_inertial
from robots.scene import Box, Scene
from robots.spec import Inertial, RobotDescription

PAYLOAD_HALF_EXTENT_M = 0.05
"""The payload is a solid cube of this half extent [m] (a 10 cm block of the given mass)."""
PAYLOAD_OFFSET_FROM_TORSO_COM = (-0.10, 0.0, 0.10)
"""Where the payload's centre sits [m], from the torso link's centre of mass in the torso
frame: behind and above it, as a backpack (a payload at the torso's own centre of mass would
shift the robot's centre of mass only through the posture)."""
MASS_ERROR_STREAM = 7_001
"""The random stream of the link mass errors (`numpy.random.default_rng([seed, this])`)."""


NOISE_CHANNELS = (
    "encoder_position_rad",
    "encoder_velocity_rad_s",
    "imu_tilt_rad",
    "imu_heading_rad",
    "gyro_rad_s",
    "accelerometer_m_s2",
    "force_N",
    "moment_xy_Nm",
    "moment_z_Nm",
)
"""The sensor channels whose noise can be given in SI units (`Perturbation.noise_<channel>`),
the fields of `sims.sensor_model.NoiseFigures`, with the groups they belong to below."""
NOISE_GROUP_OF_CHANNEL = {
    "encoder_position_rad": "encoders",
    "encoder_velocity_rad_s": "encoders",
    "imu_tilt_rad": "imu",
    "imu_heading_rad": "imu",
    "gyro_rad_s": "imu",
    "accelerometer_m_s2": "imu",
    "force_N": "ft",
    "moment_xy_Nm": "ft",
    "moment_z_Nm": "ft",
}


@dataclass(frozen=True)
class Perturbation:
    """An episode's perturbations; every default leaves the episode nominal.

    noise_encoders, noise_imu, noise_ft: white-noise standard deviations in multiples of the
    data sheet's (`sims.sensor_model.DATASHEET`); noise_<channel> (`NOISE_CHANNELS`, one per
    field of `sims.sensor_model.NoiseFigures`, in the SI unit its name ends with): one
    channel's standard deviation, which when positive replaces its group's multiple of the
    data sheet; noise_bias: a constant bias per episode per channel, in multiples of the
    channel's figure (its SI value if given, else the data sheet's); command_delay,
    sensor_delay: control periods; payload_kg [kg] on the torso, unknown to the controller;
    com_offset_m [m]: the simulated robot's centre of mass moved forward (torso x) by this
    much; mass_error: every link's mass (and inertia) scaled by 1 + mass_error u, u uniform
    in [-1, 1] per link, seeded; torque_scale, gain_scale: factors on the torque limits and
    on the servo gains; ground_height_m [m]: the largest height of the uneven ground's boxes;
    slope_deg [deg]: the ground's inclination (rising along +x)."""

    noise_encoders: float = 0.0
    noise_imu: float = 0.0
    noise_ft: float = 0.0
    noise_encoder_position_rad: float = 0.0
    noise_encoder_velocity_rad_s: float = 0.0
    noise_imu_tilt_rad: float = 0.0
    noise_imu_heading_rad: float = 0.0
    noise_gyro_rad_s: float = 0.0
    noise_accelerometer_m_s2: float = 0.0
    noise_force_N: float = 0.0
    noise_moment_xy_Nm: float = 0.0
    noise_moment_z_Nm: float = 0.0
    noise_bias: float = 0.0
    command_delay: int = 0
    sensor_delay: int = 0
    payload_kg: float = 0.0
    com_offset_m: float = 0.0
    mass_error: float = 0.0
    torque_scale: float = 1.0
    gain_scale: float = 1.0
    ground_height_m: float = 0.0
    slope_deg: float = 0.0

    @property
    def changes_robot(self) -> bool:
        """Whether the simulated robot differs from the controller's model."""
        return (
            self.payload_kg != 0.0
            or self.com_offset_m != 0.0
            or self.mass_error != 0.0
            or self.torque_scale != 1.0
        )

    @property
    def changes_sensors(self) -> bool:
        return (
            self.noise_encoders != 0.0
            or self.noise_imu != 0.0
            or self.noise_ft != 0.0
            or any(getattr(self, f"noise_{channel}") != 0.0 for channel in NOISE_CHANNELS)
            or self.noise_bias != 0.0
            or self.sensor_delay != 0
        )

    def label(self) -> str:
        """ "nominal", or the changed fields as "name=value" joined by commas; every sensor's
        noise at one multiple is "noise=value", both delays at one value "delay=value"."""
        values = {
            f.name: getattr(self, f.name)
            for f in fields(self)
            if getattr(self, f.name) != getattr(NOMINAL, f.name)
        }
        for group, members in (
            ("noise", ("noise_encoders", "noise_imu", "noise_ft")),
            ("delay", ("command_delay", "sensor_delay")),
        ):
            if all(name in values for name in members) and len({values[n] for n in members}) == 1:
                value = values[members[0]]
                for name in members:
                    del values[name]
                values = {group: value, **values}
        return ",".join(f"{name}={value:g}" for name, value in values.items()) or "nominal"

    def columns(self) -> dict[str, float | int | str]:
        """The result row's columns: every field, and `perturbation` (`label`)."""
        return {
            "perturbation": self.label(),
            **{f.name: getattr(self, f.name) for f in fields(self)},
        }


NOMINAL = Perturbation()
PERTURBATION_FIELDS = tuple(f.name for f in fields(Perturbation))
LATER_PERTURBATION_FIELDS = tuple(f"noise_{channel}" for channel in NOISE_CHANNELS)
"""Fields added after perturbed episodes were first recorded: left out of an episode's id while
at their default (`bench.sweep_spec`), so that earlier result directories keep their ids."""


def simulated_robot(
    robot: RobotDescription, perturbation: Perturbation, seed: int
) -> RobotDescription:
    """The robot the simulator runs: `robot` with `perturbation`'s model errors and torque
    scale (the controller keeps `robot`). The same description when nothing changes."""
    if not perturbation.changes_robot:
        return robot
    links = list(robot.links)
    if perturbation.mass_error != 0.0:
        rng = np.random.default_rng([seed, MASS_ERROR_STREAM])
        factors = 1.0 + perturbation.mass_error * rng.uniform(-1.0, 1.0, len(links))
        if np.any(factors <= 0.0):
            raise ValueError(f"mass_error {perturbation.mass_error:g} makes a link massless")
        links = [
            replace(link, inertial=_scaled_inertial(link.inertial, float(f)))
            for link, f in zip(links, factors, strict=True)
        ]
    index = {link.name: k for k, link in enumerate(links)}
    torso = robot.torso_link
    k = index[torso]
    inertial = links[k].inertial
    if perturbation.com_offset_m != 0.0:
        # move the torso's centre of mass by d M / m_torso along the world's x in the standing
        # posture (JVRC-1's chest frame is pitched there): the whole robot's moves by d
        total = sum(link.inertial.mass for link in links)
        shift = perturbation.com_offset_m * total / inertial.mass
        forward_in_torso = _world_x_in_link(robot, torso)
        com = np.add(inertial.com_in_link, shift * forward_in_torso)
        inertial = replace(inertial, com_in_link=tuple(float(x) for x in com))
    if perturbation.payload_kg != 0.0:
        inertial = combined_inertial(
            [
                (inertial, (0.0, 0.0, 0.0)),
                payload_inertial(perturbation.payload_kg, inertial.com_in_link, robot.scale),
            ]
        )
    links[k] = replace(links[k], inertial=inertial)
    joints = robot.joints
    if perturbation.torque_scale != 1.0:
        joints = tuple(
            replace(j, torque_limit=j.torque_limit * perturbation.torque_scale) for j in joints
        )
    return replace(robot, links=tuple(links), joints=joints)


def _world_x_in_link(robot: RobotDescription, link: str) -> np.ndarray:
    """The world's x axis in `link`'s frame in the robot's standing state."""
    from robots.model import RobotModel

    model = RobotModel(robot)
    _, rotation = model.frame_pose(model.standing_state(), link)
    return np.asarray(rotation).T @ np.array([1.0, 0.0, 0.0])


def payload_inertial(
    mass: float, torso_com_in_link, scale: float = 1.0
) -> tuple[Inertial, tuple[float, float, float]]:
    """The payload (a solid cube, `PAYLOAD_HALF_EXTENT_M`) as (its inertial about its own
    centre, its centre in the torso frame: `PAYLOAD_OFFSET_FROM_TORSO_COM` from the torso's
    centre of mass); both lengths times the robot's `scale`."""
    if mass <= 0.0:
        raise ValueError(f"payload_kg must be positive, got {mass:g}")
    side = 2.0 * PAYLOAD_HALF_EXTENT_M * scale
    moment = mass * side**2 / 6.0  # a solid cube about its centre
    diagonal = ((moment, 0.0, 0.0), (0.0, moment, 0.0), (0.0, 0.0, moment))
    centre = tuple(
        float(c + scale * o)
        for c, o in zip(torso_com_in_link, PAYLOAD_OFFSET_FROM_TORSO_COM, strict=True)
    )
    return Inertial(mass, (0.0, 0.0, 0.0), diagonal), centre


def _scaled_inertial(inertial: Inertial, factor: float) -> Inertial:
    """The same body with mass and inertia times `factor` (a uniformly denser or lighter
    link: its centre of mass stays)."""
    inertia = tuple(tuple(factor * x for x in row) for row in inertial.inertia_at_com)
    return replace(inertial, mass=inertial.mass * factor, inertia_at_com=inertia)


def predicted_com_shift(
    robot: RobotDescription, com_world: np.ndarray, payload_world: np.ndarray, payload_kg: float
) -> np.ndarray:
    """Where a payload moves the centre of mass [m]: m_p (p - c) / (M + m_p), for the robot of
    mass M with its centre of mass at `com_world` and the payload's at `payload_world`."""
    total = robot.total_mass
    return payload_kg * (np.asarray(payload_world) - np.asarray(com_world)) / (total + payload_kg)


GROUND_START_M = 0.2
"""The uneven ground and the ramp begin this far [m, times the robot's scale] ahead of the
standing robot's sole centres (its soles end 0.1 m ahead): every episode starts on flat
ground, and a walk steps onto them with its first steps."""
TILE_SIZE_M = 0.15  # [m] side of an uneven-ground tile (times the scale)
TILE_FIELD_M = (3.0, 1.05)  # [m] length (from GROUND_START_M) and width of the tile field
GROUND_STREAM = 7_005
RAMP_HALF_EXTENTS_M = (2.0, 0.75, 0.05)  # [m] the ramp: 4 m long, 1.5 m wide, 0.1 m thick
PAD_LENGTH_M = 4.0  # [m] the flat pad before a falling ramp (behind the robot)


def simulated_scene(
    scene: Scene, perturbation: Perturbation, seed: int, scale: float = 1.0
) -> Scene:
    """The scene the simulator runs: `scene` with the ground of `perturbation`, the same in
    every simulator (the controller keeps `scene`: flat ground). The same scene when the
    ground is nominal.

    - ground_height_m > 0: a field of square tiles (side `TILE_SIZE_M`) from `GROUND_START_M`
      ahead of the robot over `TILE_FIELD_M`, each as high as a uniform draw in (0, h]
      (`default_rng([seed, GROUND_STREAM])`);
    - slope_deg > 0: a ramp rising along +x at that angle whose top face starts at ground level
      `GROUND_START_M` ahead (the flat ground stays behind it);
    - slope_deg < 0: the same ramp falling, after a flat pad (a box, top at z = 0, from 4 m
      behind to `GROUND_START_M` ahead) that replaces the ground plane (which would be above
      the ramp).
    Both at once are refused (one dimension at a time)."""
    height, slope = perturbation.ground_height_m, perturbation.slope_deg
    if height and slope:
        raise ValueError("uneven ground and a slope at once are not supported; give one")
    if height < 0:
        raise ValueError(f"ground_height_m must not be negative, got {height:g}")
    start = GROUND_START_M * scale
    if height:
        side = TILE_SIZE_M * scale
        nx = round(TILE_FIELD_M[0] * scale / side)
        ny = round(TILE_FIELD_M[1] * scale / side)
        rng = np.random.default_rng([seed, GROUND_STREAM])
        heights = height * (1.0 - rng.random((nx, ny)))  # (0, h]
        tiles = tuple(
            Box(
                name=f"ground_tile_{i}_{j}",
                center_world=(start + (i + 0.5) * side, (j + 0.5 - ny / 2) * side, h / 2),
                half_extents=(side / 2, side / 2, h / 2),
            )
            for i in range(nx)
            for j in range(ny)
            for h in [float(heights[i, j])]
        )
        return replace(scene, boxes=(*scene.boxes, *tiles))
    if not slope:
        return scene
    angle = np.radians(slope)
    length, width, thickness = (x * scale for x in RAMP_HALF_EXTENTS_M)
    top = np.array([start + length * np.cos(angle), 0.0, length * np.sin(angle)])
    normal = np.array([-np.sin(angle), 0.0, np.cos(angle)])
    centre = top - thickness * normal
    # a rotation by -angle about y takes x to (cos, 0, sin): the ramp rises along +x
    quaternion = (float(np.cos(-angle / 2)), 0.0, float(np.sin(-angle / 2)), 0.0)
    ramp = Box(
        name="ramp",
        center_world=tuple(float(x) for x in centre),
        half_extents=(length, width, thickness),
        orientation_world=quaternion,
    )
    if slope > 0:
        return replace(scene, boxes=(*scene.boxes, ramp))
    pad_length = PAD_LENGTH_M * scale
    pad = Box(
        name="start_pad",
        center_world=(start - pad_length / 2, 0.0, -thickness),
        half_extents=(pad_length / 2, width, thickness),
    )
    return replace(scene, ground=False, boxes=(*scene.boxes, pad, ramp))


__all__ = [
    "NOMINAL",
    "PERTURBATION_FIELDS",
    "Perturbation",
    "predicted_com_shift",
    "simulated_robot",
    "simulated_scene",
]
