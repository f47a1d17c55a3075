"""The scenario library: named experiments built as data (`robots.scene.Scenario`).

- `stand`: double support on flat ground, 10 s.
- `stand_push`: `stand` with one push to the torso at t = 2 s lasting 0.1 s; impulse [N s]
  (default 20) and horizontal direction [deg] (0 = +x, forward; 90 = +y, left; default 0).
"""

from __future__ import annotations

from collections.abc import Callable
from dataclasses import dataclass

import numpy as np

from robots.model import RobotModel
from robots.scene import Contact, ContactPhase, PushEvent, Scenario, Scene


@dataclass(frozen=True)
class ScenarioSpec:
    name: str
    build: Callable[..., Scenario]
    description: str
    takes_push: bool = False


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


def stand_push(
    model: RobotModel,
    duration: float = 10.0,
    push_impulse: float = 20.0,
    push_direction_deg: float = 0.0,
    push_time: float = 2.0,
    push_duration: float = 0.1,
) -> Scenario:
    angle = np.deg2rad(push_direction_deg)
    impulse = (push_impulse * np.cos(angle), push_impulse * np.sin(angle), 0.0)
    base = stand(model, duration)
    push = PushEvent(push_time, model.robot.base_link, impulse, push_duration)
    return Scenario("stand_push", duration, base.scene, base.phases, base.initial_posture, (push,))


SCENARIOS: dict[str, ScenarioSpec] = {
    "stand": ScenarioSpec("stand", stand, "double support on flat ground, 10 s"),
    "stand_push": ScenarioSpec(
        "stand_push", stand_push, "standing, one push to the torso at t = 2 s for 0.1 s", True
    ),
}


def make_scenario(
    name: str,
    model: RobotModel,
    duration: float | None = None,
    push_impulse: float | None = None,
    push_direction_deg: float | None = None,
) -> Scenario:
    """Build scenario `name` for `model`. Raises KeyError for an unknown name (listing the known
    ones) and ValueError for bad parameters."""
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
    return spec.build(model, **kwargs)
