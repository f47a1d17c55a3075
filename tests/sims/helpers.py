"""Helpers shared by the simulator tests (not fixtures)."""

from robots.types import JointCommand


def knees_bent(robot, hold: JointCommand, knee: float = 0.033) -> JointCommand:
    """`hold` (a posture-holding command) with both knees bent `knee` [rad] more and the hips
    and ankles half as much the other way: the body sinks a little, level, onto whatever is
    under a hand."""
    position = hold.position.copy()
    for side in ("left", "right"):
        position[robot.joint_names.index(f"{side}_knee")] += knee
        position[robot.joint_names.index(f"{side}_hip_pitch")] -= knee / 2
        position[robot.joint_names.index(f"{side}_ankle_pitch")] -= knee / 2
    return JointCommand(position, hold.velocity, hold.torque_feedforward, hold.kp, hold.kd)
