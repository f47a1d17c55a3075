"""The humanoid description, its generated URDF/MJCF, and (later) its pinocchio model."""
