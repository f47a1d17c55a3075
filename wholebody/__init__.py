"""Whole-body layers: `WholeBodyTargets` -> `JointCommand` (DESIGN.md, the loop), one module
each, registered in `wholebody.base.WHOLE_BODY_LAYERS`; `wholebody.ik` is the IK they share."""
