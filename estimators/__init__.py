"""State estimators: `Sensors` -> `RobotState` (DESIGN.md, the loop), one module each,
registered in `estimators.base.ESTIMATORS`."""

DEFAULT_ESTIMATOR = "kinematic_inertial"
"""The estimator of every episode that names none: the sensors of Murooka et al.'s set-up
(`estimators.kinematic_inertial`), for every controller alike."""
