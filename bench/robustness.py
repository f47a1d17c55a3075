"""Robustness dimensions of a sweep (issue 21): the `[robustness]` table of a sweep spec and
the `--noise`, `--delay`, ... flags of `centrobench sweep`, expanded to one `Perturbation`
per (dimension, magnitude), each changing one dimension from the nominal episode (so that a
degradation curve varies one thing at a time)::

    [robustness]
    nominal = true            # also the unperturbed episodes (default)
    noise = [0.5, 1, 2]       # every sensor's white noise, multiples of the data sheet's
    noise_encoders = [1]      # ... or one group: encoders, imu, ft
    noise_gyro_rad_s = [0.01] # ... or one channel's standard deviation in SI units [rad/s]
    noise_bias = [1]          # a constant bias per episode, multiples of the same figures
    delay = [1, 2]            # control periods: the command late and the readings old
    command_delay = [1]       # ... or one of them
    sensor_delay = [1]
    payload_kg = [5, 10]      # on the torso, unknown to the controller
    com_offset_m = [0.02]     # the simulated robot's centre of mass moved forward [m]
    mass_error = [0.1]        # every link's mass off by up to this fraction (seeded)
    torque_scale = [0.5]      # the torque limits scaled
    gain_scale = [0.5]        # the servo gains scaled
    ground_height_m = [0.02]  # uneven ground ahead: tiles up to this high [m]
    slope_deg = [5]           # a ramp ahead rising at this angle [deg]

What each changes and where: `robots.perturbation`, `sims.sensor_model`.
"""

from __future__ import annotations

from collections.abc import Mapping
from dataclasses import replace
from typing import Any

from robots.perturbation import NOISE_CHANNELS, NOMINAL, Perturbation
from sims.sensor_model import DATASHEET

MAX_NOISE_MULTIPLE = 1_000.0
MAX_DELAY_PERIODS = 100
MAX_PAYLOAD_KG = 1_000.0
MAX_COM_OFFSET_M = 1.0
MAX_MASS_ERROR = 0.9  # a link can lose 90 % of its mass at most (never none)
MAX_ACTUATION_SCALE = 10.0
MAX_GROUND_HEIGHT_M = 0.2
MAX_SLOPE_DEG = 30.0

_UNITS = {channel: channel.rsplit("_", 1)[1] for channel in NOISE_CHANNELS}
_UNITS.update(
    encoder_velocity_rad_s="rad/s",
    gyro_rad_s="rad/s",
    accelerometer_m_s2="m/s^2",
    moment_xy_Nm="N m",
    moment_z_Nm="N m",
)
_WHAT = {
    "encoder_position_rad": "joint positions",
    "encoder_velocity_rad_s": "joint velocities",
    "imu_tilt_rad": "IMU's roll and pitch",
    "imu_heading_rad": "IMU's heading",
    "gyro_rad_s": "gyro",
    "accelerometer_m_s2": "accelerometer",
    "force_N": "F/T forces",
    "moment_xy_Nm": "F/T moments about x and y",
    "moment_z_Nm": "F/T moments about z",
}

# dimension -> (the Perturbation fields it sets, integer values, minimum, maximum, strict
# minimum, what it accepts)
DIMENSIONS: dict[str, tuple[tuple[str, ...], bool, float, float, bool, str]] = {
    "noise": (
        ("noise_encoders", "noise_imu", "noise_ft"),
        False,
        0.0,
        MAX_NOISE_MULTIPLE,
        False,
        "multiples of the data sheet's noise (every sensor)",
    ),
    "noise_encoders": (
        ("noise_encoders",),
        False,
        0.0,
        MAX_NOISE_MULTIPLE,
        False,
        "multiples of the data sheet's encoder noise",
    ),
    "noise_imu": (
        ("noise_imu",),
        False,
        0.0,
        MAX_NOISE_MULTIPLE,
        False,
        "multiples of the data sheet's IMU noise",
    ),
    "noise_ft": (
        ("noise_ft",),
        False,
        0.0,
        MAX_NOISE_MULTIPLE,
        False,
        "multiples of the data sheet's force/torque noise",
    ),
    **{
        f"noise_{channel}": (
            (f"noise_{channel}",),
            False,
            0.0,
            MAX_NOISE_MULTIPLE * getattr(DATASHEET, channel),
            False,
            f"{_UNITS[channel]}, one standard deviation of white noise on the {_WHAT[channel]} "
            f"only (data sheet: {getattr(DATASHEET, channel):.3g} at 2 ms)",
        )
        for channel in NOISE_CHANNELS
    },
    "noise_bias": (
        ("noise_bias",),
        False,
        0.0,
        MAX_NOISE_MULTIPLE,
        False,
        "a constant bias per episode, multiples of the data sheet's noise",
    ),
    "delay": (
        ("command_delay", "sensor_delay"),
        True,
        0,
        MAX_DELAY_PERIODS,
        False,
        "control periods (command and readings)",
    ),
    "command_delay": (("command_delay",), True, 0, MAX_DELAY_PERIODS, False, "control periods"),
    "sensor_delay": (("sensor_delay",), True, 0, MAX_DELAY_PERIODS, False, "control periods"),
    "payload_kg": (
        ("payload_kg",),
        False,
        0.0,
        MAX_PAYLOAD_KG,
        False,
        "kg on the torso, unknown to the controller",
    ),
    "com_offset_m": (
        ("com_offset_m",),
        False,
        -MAX_COM_OFFSET_M,
        MAX_COM_OFFSET_M,
        False,
        "m, the simulated centre of mass moved forward",
    ),
    "mass_error": (
        ("mass_error",),
        False,
        0.0,
        MAX_MASS_ERROR,
        False,
        "relative link mass errors (each link off by up to this fraction, seeded)",
    ),
    "torque_scale": (
        ("torque_scale",),
        False,
        0.0,
        MAX_ACTUATION_SCALE,
        True,
        "factors on every joint's torque limit",
    ),
    "ground_height_m": (
        ("ground_height_m",),
        False,
        0.0,
        MAX_GROUND_HEIGHT_M,
        False,
        "m, the highest tile of an uneven ground ahead of the robot",
    ),
    "slope_deg": (
        ("slope_deg",),
        False,
        -MAX_SLOPE_DEG,
        MAX_SLOPE_DEG,
        False,
        "deg, a ramp ahead of the robot rising along its walk (negative: falling)",
    ),
    "gain_scale": (
        ("gain_scale",),
        False,
        0.0,
        MAX_ACTUATION_SCALE,
        True,
        "factors on the servo gains",
    ),
}


EXAMPLES = {
    "noise": "0.5,1,2",
    "noise_encoders": "1,4",
    "noise_imu": "1,4",
    "noise_ft": "1,4",
    **{
        f"noise_{channel}": ",".join(f"{m * getattr(DATASHEET, channel):.2g}" for m in (1, 4))
        for channel in NOISE_CHANNELS
    },
    "noise_bias": "1,10",
    "delay": "1,2",
    "command_delay": "1,2",
    "sensor_delay": "1,2",
    "payload_kg": "5,10",
    "com_offset_m": "0.01,0.02",
    "mass_error": "0.05,0.1",
    "torque_scale": "0.5,0.75",
    "gain_scale": "0.5,2",
    "ground_height_m": "0.01,0.02",
    "slope_deg": "2,5",
}
"""A magnitude list per dimension, for the command line's help."""


def perturbation_for(dimension: str, value: float) -> Perturbation:
    """The perturbation that sets `dimension` (a `DIMENSIONS` name) to `value`."""
    names, integer, *_ = DIMENSIONS[dimension]
    value = int(value) if integer else float(value)
    return replace(NOMINAL, **dict.fromkeys(names, value))


def dimension_of(perturbation: Perturbation) -> tuple[str, float] | None:
    """(dimension, magnitude) of a perturbation that changes one dimension (`DIMENSIONS`,
    the grouped ones first: noise, delay); None for the nominal one or one that changes
    several."""
    if perturbation == NOMINAL:
        return None
    for dimension, (names, *_rest) in DIMENSIONS.items():
        value = getattr(perturbation, names[0])
        if perturbation_for(dimension, value) == perturbation:
            return dimension, float(value)
    return None


def parse_robustness(data: Any) -> tuple[Perturbation | None, ...]:
    """The perturbations of a `[robustness]` table (None stands for the nominal episode), in
    the table's order; ValueError naming the field (the caller prefixes "robustness.")."""
    if not isinstance(data, Mapping):
        raise TypeError("the robustness field must be a table of dimensions")
    valid = ["nominal", *DIMENSIONS]
    unknown = sorted(set(data) - set(valid))
    if unknown:
        raise ValueError(f"{unknown[0]}' is unknown; valid fields: {', '.join(valid)}")
    nominal = data.get("nominal", True)
    if not isinstance(nominal, bool):
        raise ValueError(f"nominal' must be true or false, got {nominal!r}")
    result: list[Perturbation | None] = [None] if nominal else []
    for dimension, values in data.items():
        if dimension == "nominal":
            continue
        _names, integer, low, high, strict, accepts = DIMENSIONS[dimension]
        kind = "integers" if integer else "numbers"
        rule = f"a list of {kind} in {'(' if strict else '['}{low:g}, {high:g}] ({accepts})"
        if not isinstance(values, list) or not values:
            raise ValueError(f"{dimension}' must be {rule}, got {values!r}")
        for value in values:
            number = isinstance(value, int | float) and not isinstance(value, bool)
            if integer:
                number = number and isinstance(value, int)
            if not (number and (value > low if strict else value >= low) and value <= high):
                raise ValueError(f"{dimension}' must be {rule}, got {value!r}")
            perturbation = perturbation_for(dimension, value)
            key = None if perturbation == NOMINAL else perturbation
            if key in result:
                continue  # the nominal value of a dimension, or a value given twice
            result.append(key)
    if not result:
        raise ValueError("nominal' is false and no dimension is given: no episodes")
    return tuple(result)


def robustness_to_dict(perturbations: tuple[Perturbation | None, ...]) -> dict[str, Any]:
    """The `[robustness]` table that `parse_robustness` reads back to `perturbations`."""
    table: dict[str, Any] = {"nominal": None in perturbations}
    for perturbation in perturbations:
        if perturbation is None:
            continue
        found = dimension_of(perturbation)
        if found is None:
            raise ValueError(f"perturbation {perturbation.label()} changes several dimensions")
        dimension, value = found
        integer = DIMENSIONS[dimension][1]
        table.setdefault(dimension, []).append(int(value) if integer else value)
    return table
