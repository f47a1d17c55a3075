"""The scenario library: named experiments built as data (`robots.scene.Scenario`).

- `stand`: double support on flat ground, 10 s.
- `stand_push`: `stand` with one push to the torso at t = 2 s lasting 0.1 s; impulse [N s]
  (default 20) and horizontal direction [deg] (0 = +x, forward; 90 = +y, left; default 0).
- `walk`: 10 straight steps on flat ground, right foot first. Stride 0.25 m (each swing foot
  moves 0.25 m, footprints 0.125 m apart; the first and last steps are half, so the feet start
  and end side by side); step period 0.9 s with 15 % double support (0.135 s); swing clearance
  0.05 m; 1.0 s of double support before the first step and 1.5 s after the last. Sized for the
  0.22 m feet and 0.36 m leg segments of the centrobench humanoid at scale 1 (scaled with it).
- `walk_push`: `walk` with a lateral push to the torso in the middle of the 5th step's single
  support; impulse [N s] (default 10: the paper's pairs walk through it in both simulators,
  15 falls) and direction [deg] (default 90: to the left).
- `walk_side`: 10 steps to the left, 0.05 m each, left foot first (`WALK_SIDE_GAIT`).
- `walk_turn`: 10 steps turning left by 10 deg each (90 deg in all) while advancing 0.05 m per
  step, left foot first (`WALK_TURN_GAIT`).
- `reach`: Sherikov, Dimitrov & Wieber 2014, Sec. VII-B, Test 1 (reaching an object): standing
  start, 12 s, the right palm's target out of reach at first and moved twice (`REACH_TARGETS`);
  the robot must walk to it. Judged by the hand error (`bench.runner`, `hand_error_m`).
- `reach_push`: the same, Sec. VII-C, Test 2: plus two 15 N s pushes to the torso, from the
  right at 2.5 s and from the front at 7 s (`REACH_PUSHES`).
- Murooka et al. 2022's multi-contact motions (Fig. 4), `bench.motions`: `moving_contacts`
  (E).

Walks are built from a `GaitCommand` (forward and lateral step length or speed, turn per step
or yaw rate, step width, step period, double-support ratio, swing height, steps, standing time
before and after); `walk` and
`walk_push` take a forward `speed` [m/s].
"""

from __future__ import annotations

from collections.abc import Callable
from dataclasses import dataclass, replace
from functools import partial

import numpy as np

from bench.limits import MAX_WALK_STEPS
from bench.motions import (
    hand_supports_motion,
    hand_wall_motion,
    handrail_stairs_motion,
    ladder_motion,
    moving_contacts_motion,
)
from centroidal.rotations import heading_quaternion, yaw_of
from robots.gait import GAIT_STEPS, GaitCommand
from robots.model import RobotModel
from robots.registry import FLAT_GROUND, MULTI_CONTACT, WALKING
from robots.scene import Contact, ContactPhase, HandTarget, PushEvent, Scenario, Scene
from robots.similarity import froude_time_scale

WALK_STEPS = GAIT_STEPS  # steps of `walk` (and so the single-support phases `walk_push` pushes)


@dataclass(frozen=True)
class ScenarioSpec:
    name: str
    build: Callable[..., Scenario]
    description: str
    takes_push: bool = False
    requires: frozenset[str] = FLAT_GROUND  # what a controller must be able to do


def _standing_contacts(model: RobotModel) -> tuple[Contact, ...]:
    state = model.standing_state()
    contacts = []
    for limb in model.robot.limbs:
        if limb.name.endswith("foot"):
            position, _ = model.frame_pose(state, limb.contact_frame)
            contacts.append(Contact(limb.name, tuple(float(x) for x in position)))
    return tuple(contacts)


def stand(model: RobotModel, duration: float = 10.0, **_: object) -> Scenario:
    return Scenario(
        name="stand",
        duration=duration,
        scene=Scene(),
        phases=(ContactPhase(0.0, duration, _standing_contacts(model)),),
        initial_posture=model.robot.nominal_posture,
    )


def _horizontal_impulse(impulse: float, direction_deg: float) -> tuple[float, float, float]:
    """[N s] of magnitude `impulse`, horizontal, towards `direction_deg` [deg] (0 = +x,
    forward; 90 = +y, left), as every push of the scenarios is given."""
    angle = np.deg2rad(direction_deg)
    return (float(impulse * np.cos(angle)), float(impulse * np.sin(angle)), 0.0)


def stand_push(
    model: RobotModel,
    duration: float = 10.0,
    push_impulse: float = 20.0,
    push_direction_deg: float = 0.0,
    push_time: float = 2.0,
    push_duration: float = 0.1,
) -> Scenario:
    impulse = _horizontal_impulse(push_impulse, push_direction_deg)
    base = stand(model, duration)
    push = PushEvent(push_time, model.robot.torso_link, impulse, push_duration)
    return Scenario("stand_push", duration, base.scene, base.phases, base.initial_posture, (push,))


DEFAULT_GAIT = GaitCommand()
WALK_SIDE_GAIT = GaitCommand(step_length=0.0, lateral_step=0.05)
WALK_TURN_GAIT = GaitCommand(step_length=0.05, turn=float(np.deg2rad(10.0)))
"""`walk_turn`: 10 steps turning left by 10 deg each while advancing 0.05 m (90 deg in all)."""


REACH_DURATION = 12.0  # [s]
REACH_LIMB = "right_hand"
REACH_TARGETS: tuple[tuple[float, tuple[float, float, float]], ...] = (
    (0.0, (0.5, -0.1, 0.05)),
    (4.0, (0.8, -0.1, 0.05)),
    (8.0, (0.8, -0.4, 0.05)),
)
"""`reach`'s right-hand targets: (from time [s], offset [m] at scale 1 from the right palm's
position in the standing posture, world axes). Sherikov et al. 2014, Sec. VII-B prints no
positions (only their Fig. 4 plots them), so these are ours, after its text: the target is
"initially unreachable" (0.5 m ahead: 0.70 m from the shoulder, the arm reaching 0.48 m), the
robot walks "until the target is reached, around 4 (s). However, due to a change in the x
position of the target, the walk is resumed" (0.3 m further forward at 4 s), and "the
lateral motion of the target also influences the walk" (0.3 m further right at 8 s, when the
text's second footstep modification happens: "around 4 (s) and 8 (s)")."""
REACH_PUSHES: tuple[tuple[float, float, float], ...] = ((2.5, 15.0, 90.0), (7.0, 15.0, 180.0))
"""`reach_push`'s pushes to the torso: (time [s], impulse [N s], direction [deg], 0 = +x and
90 = +y), Sherikov et al. 2014, Sec. VII-C: "Disturbances of 15 Ns are applied to the robot
at 2.5 (s) from the right, forcing the robot to make a step to the left, and at 7 (s) from the
front, forcing the robot to make a step backward". The paper's disturbances are instantaneous
impacts (a velocity jump, eq. 23); here, as every push of the bench, the impulse is spread
over `REACH_PUSH_DURATION`. As printed (the paper's HRP-2 weighs 58 kg, as our humanoid at
scale 1): not scaled with the robot, like `stand_push`'s and `walk_push`'s impulses."""
REACH_PUSH_DURATION = 0.1  # [s]
REACH_PASS_HAND_ERROR_M = 0.02
"""`reach` and `reach_push` are passed with a final hand error (`hand_error_final_m`) under
this [m] and no fall."""


def reach(model: RobotModel, duration: float = REACH_DURATION, **_: object) -> Scenario:
    """Sherikov et al. 2014, Test 1: standing in double support on flat ground (as `stand`),
    with the right palm's targets `REACH_TARGETS`, offsets scaled with the robot, from the
    palm's position in `model.standing_state()` (forward kinematics). No contact sequence
    beyond standing: a controller must choose its own steps to get there (a fixed-schedule
    one stands, and its hand error says how far it stays). Passed (by a controller of the
    paper's kind): final hand error under `REACH_PASS_HAND_ERROR_M` (2 cm), and no fall."""
    palm = model.robot.limb(REACH_LIMB).contact_frame
    standing = model.frame_positions_world(model.standing_state(), [palm])[0]
    scale = model.robot.scale
    targets = tuple(
        HandTarget(
            REACH_LIMB,
            time,
            tuple(float(v) for v in standing + scale * np.array(offset)),
        )
        for time, offset in REACH_TARGETS
    )
    return replace(stand(model, duration), name="reach", hand_targets=targets)


def reach_push(model: RobotModel, duration: float = REACH_DURATION, **_: object) -> Scenario:
    """Sherikov et al. 2014, Test 2: `reach` with the pushes `REACH_PUSHES` to the torso (the
    base link), each over `REACH_PUSH_DURATION` [s]."""
    pushes = tuple(
        PushEvent(
            time,
            model.robot.torso_link,
            _horizontal_impulse(impulse, direction),
            REACH_PUSH_DURATION,
        )
        for time, impulse, direction in REACH_PUSHES
    )
    return replace(reach(model, duration), name="reach_push", pushes=pushes)


def walk(
    model: RobotModel,
    duration: float | None = None,
    gait: GaitCommand = DEFAULT_GAIT,
    name: str = "walk",
) -> Scenario:
    """The contact sequence of `gait` (flat ground, straight: the path keeps its heading)."""
    scale = model.robot.scale
    forward, lateral = gait.step_length_for(scale)
    swing_height = gait.swing_height * scale
    step_period = gait.step_period * froude_time_scale(scale)
    steps = gait.steps
    start = {c.limb: c for c in _standing_contacts(model)}
    feet = {name: np.array(contact.position_world) for name, contact in start.items()}
    orientation = {name: contact.orientation_world for name, contact in start.items()}
    double = gait.double_support_ratio * step_period
    single = step_period - double
    turn = gait.turn_per_step(scale)
    leftward = lateral > 0 or (lateral == 0 and turn > 0)
    first, second = ("left_foot", "right_foot") if leftward else ("right_foot", "left_foot")
    footholds = None if gait.straight else _footholds(gait, scale, start)
    phases = []
    t = gait.start_double_support
    phases.append(ContactPhase(0.0, t, tuple(start.values())))
    for k in range(1, steps + 1):
        swing = first if k % 2 else second
        support = second if swing == first else first
        phases.append(
            ContactPhase(
                t, t + single, (Contact(support, tuple(feet[support]), orientation[support]),)
            )
        )
        # the path advances one step per step but the last; a foot placed at step k moves by
        # the path's advance since it was last placed: one step the first time, two after,
        # one on the last step (for the default gait: 0.125, 0.25, ..., 0.125 m)
        if footholds is None:
            advances = 1 if k in (1, steps) else 2
            feet[swing] = feet[swing] + _advance(forward, lateral, advances)
        else:
            feet[swing], orientation[swing] = footholds[swing][min(k, steps - 1)]
        t += single
        end = t + (gait.end_double_support if k == steps else double)
        both = tuple(
            Contact(name, tuple(feet[name]), orientation[name])
            for name in ("left_foot", "right_foot")
        )
        phases.append(ContactPhase(t, end, both))
        t = end
    total = t if duration is None else duration
    if duration is not None and duration > t:  # stand on at the end
        phases[-1] = ContactPhase(phases[-1].start, duration, phases[-1].contacts)
    return Scenario(
        name,
        total,
        Scene(),
        tuple(phases),
        model.robot.nominal_posture,
        swing_height=swing_height,
        goal_offset_world=tuple(float(v) for v in gait.goal_offset(scale)),
        goal_yaw=gait.goal_yaw(scale),
        gait=gait,
    )


def _footholds(
    gait: GaitCommand, scale: float, start: dict[str, Contact]
) -> dict[str, list[tuple[np.ndarray, tuple[float, float, float, float]]]]:
    """Per foot, its contact pose at each of the path's poses (`GaitCommand.path`): the foot
    keeps its standing offset from the feet's midpoint in the path's frame (across the path:
    half the step width), and the path's heading as its yaw."""
    middle = np.mean([np.array(c.position_world) for c in start.values()], axis=0)
    result = {}
    for name, contact in start.items():
        offset = np.array(contact.position_world) - middle
        if gait.step_width is not None:
            offset[1] = np.copysign(gait.step_width * scale / 2, offset[1])
        poses = []
        for position, heading in gait.path(scale):
            c, s = np.cos(heading), np.sin(heading)
            foot = middle + np.array(
                [
                    position[0] + c * offset[0] - s * offset[1],
                    position[1] + s * offset[0] + c * offset[1],
                    offset[2],
                ]
            )
            poses.append((foot, tuple(float(v) for v in heading_quaternion(heading))))
        result[name] = poses
    return result


def _advance(forward: float, lateral: float, steps: int) -> np.ndarray:
    """A foot's displacement [m] over `steps` of the path's advances (the default walk's
    stride / 2 and stride, computed as before: 0.25 / 2 and 0.25 at scale 1)."""
    stride = 2 * forward
    return np.array([stride / 2 if steps == 1 else stride, steps * lateral, 0.0])


def walk_side(model: RobotModel, duration: float | None = None, **_: object) -> Scenario:
    """`walk` with `WALK_SIDE_GAIT`: 10 steps to the left, 0.05 m each (0.45 m in all)."""
    return walk(model, duration, WALK_SIDE_GAIT, name="walk_side")


def walk_turn(model: RobotModel, duration: float | None = None, **_: object) -> Scenario:
    """`walk` with `WALK_TURN_GAIT`: 10 steps turning left 10 deg each (90 deg in all) while
    advancing 0.05 m per step, left foot first."""
    return walk(model, duration, WALK_TURN_GAIT, name="walk_turn")


SUPPORT_DIRECTIONS = ("inward", "outward", "forward", "backward")
"""Push directions relative to the support foot while walking (issue 21): inward (towards the
swing foot's side), outward (away from it), forward and backward along the support foot's
heading."""


def support_direction_deg(contact: Contact, name: str) -> float:
    """World direction [deg] (0 = +x, 90 = +y) of the push `name` (`SUPPORT_DIRECTIONS`)
    relative to the support foot `contact`: its heading is forward; outward is to its own
    side (left for the left foot), inward to the other."""
    if name not in SUPPORT_DIRECTIONS:
        raise ValueError(
            f"unknown push direction {name!r}; choose one of: {', '.join(SUPPORT_DIRECTIONS)}"
        )
    heading = np.rad2deg(yaw_of(contact.orientation_world))
    side = 90.0 if contact.limb.startswith("left") else -90.0  # outward from the support foot
    offset = {"forward": 0.0, "backward": 180.0, "outward": side, "inward": -side}[name]
    return float((heading + offset) % 360.0)


def walk_push(
    model: RobotModel,
    duration: float | None = None,
    push_impulse: float = 10.0,
    push_direction_deg: float = 90.0,
    push_step: int = 5,
    push_duration: float = 0.1,
    gait: GaitCommand = DEFAULT_GAIT,
    push_swing_fraction: float = 0.5,
    push_direction_name: str | None = None,
) -> Scenario:
    """`walk` pushed in single support `push_step`, the push centred at `push_swing_fraction`
    of it (0.5: the middle); towards `push_direction_deg`, or, when `push_direction_name` is
    given, towards that direction relative to the support foot (`support_direction_deg`)."""
    base = walk(model, duration, gait)
    single = [p for p in base.phases if len(p.contacts) == 1]
    if not 1 <= push_step <= len(single):
        raise ValueError(f"push_step must be 1..{len(single)} (the walk's steps), got {push_step}")
    if not 0.0 <= push_swing_fraction <= 1.0:
        raise ValueError(f"push_swing_fraction must be in [0, 1], got {push_swing_fraction}")
    phase = single[push_step - 1]
    if push_swing_fraction == 0.5:  # the middle, as computed before fractions existed
        centre = (phase.start + phase.end) / 2
    else:
        centre = phase.start + push_swing_fraction * (phase.end - phase.start)
    if push_direction_name is not None:
        push_direction_deg = support_direction_deg(phase.contacts[0], push_direction_name)
    impulse = _horizontal_impulse(push_impulse, push_direction_deg)
    push = PushEvent(centre - push_duration / 2, model.robot.torso_link, impulse, push_duration)
    return Scenario(
        "walk_push",
        base.duration,
        base.scene,
        base.phases,
        base.initial_posture,
        (push,),
        base.swing_height,
        base.goal_offset_world,
        base.goal_yaw,
        base.gait,
    )


SCENARIOS: dict[str, ScenarioSpec] = {
    "stand": ScenarioSpec("stand", stand, "double support on flat ground, 10 s"),
    "stand_push": ScenarioSpec(
        "stand_push", stand_push, "standing, one push to the torso at t = 2 s for 0.1 s", True
    ),
    "walk": ScenarioSpec("walk", walk, "10 straight steps, stride 0.25 m, 0.9 s per step"),
    "walk_push": ScenarioSpec(
        "walk_push", walk_push, "walk with a lateral push mid single support of step 5", True
    ),
    "walk_side": ScenarioSpec(
        "walk_side", walk_side, "10 steps to the left, 0.05 m each, left foot first"
    ),
    "walk_turn": ScenarioSpec(
        "walk_turn",
        walk_turn,
        "10 steps turning left 10 deg each (90 deg), 0.05 m forward",
        requires=WALKING,
    ),
    "reach": ScenarioSpec(
        "reach",
        reach,
        "Sherikov 2014 Test 1: right hand to a target 0.5 m ahead, moved at 4 s and 8 s, 12 s",
    ),
    "reach_push": ScenarioSpec(
        "reach_push",
        reach_push,
        "Sherikov 2014 Test 2: reach, pushed 15 N s for 0.1 s at 2.5 s (to +y), 7 s (to -x)",
    ),
    "moving_contacts": ScenarioSpec(
        "moving_contacts",
        moving_contacts_motion,
        "Murooka 2022 Fig. 4 (E): hands on two walls, balancing on moving floors and walls",
        requires=MULTI_CONTACT,
    ),
    "hand_wall": ScenarioSpec(
        "hand_wall",
        hand_wall_motion,
        "Murooka 2022 Fig. 4 (A): stepping over 25 deg scaffold boards, a hand on the wall",
        requires=MULTI_CONTACT,
    ),
    "handrail_stairs": ScenarioSpec(
        "handrail_stairs",
        handrail_stairs_motion,
        "Murooka 2022 Fig. 4 (B): climbing four 150 mm steps, hands grasping the handrails",
        requires=MULTI_CONTACT,
    ),
    "handrail_stairs_resting": ScenarioSpec(
        "handrail_stairs_resting",
        partial(handrail_stairs_motion, resting=True),
        "Murooka 2022 Fig. 4 (B), the hands resting on the rails (unilateral): Sec. V-G",
        requires=MULTI_CONTACT,
    ),
    "ladder": ScenarioSpec(
        "ladder",
        ladder_motion,
        "Murooka 2022 Fig. 4 (C): climbing a vertical ladder, 200 mm rungs, on the toes",
        requires=MULTI_CONTACT,
    ),
    "hand_supports": ScenarioSpec(
        "hand_supports",
        hand_supports_motion,
        "Murooka 2022 Fig. 4 (D): palms on two 500 mm supports, both feet swinging together",
        requires=MULTI_CONTACT,
    ),
}
WALKS_WITH_SPEED = ("walk", "walk_push")  # the scenarios whose forward speed can be set


def make_scenario(
    name: str,
    model: RobotModel,
    duration: float | None = None,
    push_impulse: float | None = None,
    push_direction_deg: float | None = None,
    push_time: float | None = None,
    push_step: int | None = None,
    friction: float | None = None,
    speed: float | None = None,
    steps: int | None = None,
    push_swing_fraction: float | None = None,
    push_direction_name: str | None = None,
) -> Scenario:
    """Build scenario `name` for `model`. Raises KeyError for an unknown name (listing the known
    ones) and ValueError for bad parameters. `push_time` [s] applies to `stand_push`,
    `push_step` (the single-support phase pushed in the middle, from 1) to `walk_push`;
    `friction` replaces the scene's Coulomb coefficient; `speed` [m/s] is the forward speed of
    `walk` and `walk_push` (`GaitCommand.speed`; None: their default step length) and `steps`
    their number of steps (`GaitCommand.steps`; None: 10)."""
    if name not in SCENARIOS:
        raise KeyError(f"unknown scenario {name!r}; choose one of: {', '.join(SCENARIOS)}")
    spec = SCENARIOS[name]
    kwargs: dict[str, float] = {}
    if duration is not None:
        if not duration > 0:
            raise ValueError(f"duration must be positive, got {duration}")
        kwargs["duration"] = duration
    if push_impulse is not None or push_direction_deg is not None:
        if not spec.takes_push:
            pushing = [s.name for s in SCENARIOS.values() if s.takes_push]
            raise ValueError(
                f"scenario {name!r} takes no push; scenarios with a push: {', '.join(pushing)}"
            )
        if push_impulse is not None:
            if not (np.isfinite(push_impulse) and push_impulse >= 0):
                raise ValueError(f"push impulse must be >= 0 N s, got {push_impulse}")
            kwargs["push_impulse"] = push_impulse
        if push_direction_deg is not None:
            kwargs["push_direction_deg"] = push_direction_deg
    if push_time is not None:
        if name != "stand_push":
            raise ValueError(f"push_time applies to stand_push, not to {name!r}")
        if not (np.isfinite(push_time) and push_time >= 0):
            raise ValueError(f"push_time must be >= 0 s, got {push_time}")
        kwargs["push_time"] = push_time
    for label, value in (
        ("push_step", push_step),
        ("push_swing_fraction", push_swing_fraction),
        ("push_direction_name", push_direction_name),
    ):
        if value is not None:
            if name != "walk_push":
                raise ValueError(f"{label} applies to walk_push, not to {name!r}")
            kwargs[label] = value
    if speed is not None:
        if name not in WALKS_WITH_SPEED:
            raise ValueError(f"speed applies to {', '.join(WALKS_WITH_SPEED)}, not to {name!r}")
        if not np.isfinite(speed):
            raise ValueError(f"speed must be a finite number of m/s, got {speed}")
        kwargs["gait"] = GaitCommand(speed=float(speed))
    if steps is not None:
        if name not in WALKS_WITH_SPEED:
            raise ValueError(f"steps applies to {', '.join(WALKS_WITH_SPEED)}, not to {name!r}")
        if (
            isinstance(steps, bool)
            or not isinstance(steps, int)
            or not 2 <= steps <= MAX_WALK_STEPS
        ):
            raise ValueError(f"steps must be an integer in [2, {MAX_WALK_STEPS}], got {steps!r}")
        kwargs["gait"] = replace(kwargs.get("gait", GaitCommand()), steps=steps)
    scenario = spec.build(model, **kwargs)
    if friction is not None:
        if not (np.isfinite(friction) and friction > 0):
            raise ValueError(f"friction must be a positive coefficient, got {friction}")
        scenario = replace(scenario, scene=replace(scenario.scene, friction=float(friction)))
    return scenario
