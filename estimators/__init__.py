"""State estimators: `Sensors` -> `RobotState` (DESIGN.md, the loop), one module each,
registered in `estimators.base.ESTIMATORS`."""
