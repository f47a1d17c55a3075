"""Seeing an episode (issue 21): `centrobench replay RESULTS EPISODE_ID --out FILE`.

A sweep keeps a summary row for every episode and a trace only for some, and no trace holds
the robot's configuration, so a replay runs the episode again from the sweep's record
(`sweep.json`: the spec, and from it the episode by its id; episodes are deterministic: the
same seed gives the same trace) with the ground-truth configuration recorded every control
period, and checks that it ended as the recorded one did (status and fall time) before it
draws anything.

Drawing: PyBullet's CPU renderer (TinyRenderer, no OpenGL needed) draws the simulated robot
and scene at each frame's configuration from a camera that follows the centre of mass, with
markers for the centre of mass (green) and the measured ZMP (red) on the ground and one bar
per limb along its measured contact force (blue, 1 mm per N); matplotlib puts beside it the
time, the status and the CoM and ZMP along x and y over the whole episode with a cursor, and
writes the frames as a self-contained HTML page with a player (`Animation.to_jshtml`: the
frames as embedded JPEG images, play / pause / step / slider; opens in any browser without a
server or network) or as an animated GIF (Pillow). Both libraries are dependencies already.
The page also embeds every recorded period's data (time, base pose, joint positions, CoM,
ZMP, contact forces) as JSON in a `<script type="application/json" id="episode-trace">`.

Chosen over meshcat (a 3-D viewer in the browser, interactive): its Python package imports a
ZeroMQ server, IPython, tornado and pyngrok, six dependencies more; PyBullet's renderer and
matplotlib are dependencies already. Measured (a 12 s walk, 5682 periods, run in 4.1 s): a
frame renders in 47 ms; at 10 frames per simulated second the replay's 115 frames take 21 s
to draw and compose and the page is 12 MB (docs/robustness.md).
"""

from __future__ import annotations

import json
import math
from dataclasses import replace
from pathlib import Path
from typing import Any

import numpy as np
import pandas as pd

DEFAULT_FPS = 10.0  # frames per simulated second
IMAGE_SIZE = (480, 360)  # [px] width, height of the rendered view
FORCE_SCALE_M_PER_N = 1e-3  # a contact force's bar: 1 mm per N
FIGURE_DPI = 80  # the page's frames: 880 x 352 px
EMBED_LIMIT_MB = 1000.0  # matplotlib's default (20 MB) would drop the frames past it


class ReplayError(ValueError):
    """The episode cannot be replayed (one line that says why)."""


def find_episode(results: str | Path, episode_id: str):
    """(the sweep's `Episode` of `episode_id`, its recorded summary row or None): from the
    result directory's sweep record. ReplayError when there is no record or no such id."""
    from bench.sweep_spec import SpecError, spec_from_mapping

    root = Path(results)
    record_path = root / "sweep.json"
    if not record_path.exists():
        raise ReplayError(f"{root} has no sweep.json: not a sweep's result directory")
    try:
        record = json.loads(record_path.read_text())
        if not isinstance(record, dict) or "spec" not in record:
            raise SpecError("it has no 'spec' table")  # a list's record["spec"]: Python's words
        spec = spec_from_mapping(record["spec"])
    except (OSError, ValueError, KeyError, TypeError, SpecError) as exc:
        raise ReplayError(f"{record_path} is not a readable sweep record: {exc}") from None
    for episode in spec.episodes():
        if episode.episode_id == episode_id:
            break
    else:
        raise ReplayError(f"episode {episode_id!r} is not in the sweep recorded in {root}")
    row = None
    path = root / "episodes" / f"{episode_id}.parquet"
    if path.exists():
        row = pd.read_parquet(path).iloc[0].to_dict()
    return episode, row


def run_with_configuration(run) -> Any:
    """Run the episode `run` (an `EpisodeSpec`) with the ground-truth configuration in its
    trace (`bench.runner.run_episode`'s `record_configuration`)."""
    from bench.runner import run_episode

    return run_episode(run, record_configuration=True)


def check_same_ending(summary: dict, row: dict | None) -> None:
    """ReplayError when the run again ended otherwise than the recorded episode (status or
    fall time): the replay would show another episode (another machine's arithmetic, or a
    changed centrobench)."""
    if row is None or row["status"] not in ("ok", "fell"):
        return  # an error or a timeout: nothing to compare the run with
    if summary["status"] != row["status"]:
        raise ReplayError(
            f"the episode ran again ended {summary['status']!r}, recorded {row['status']!r}: "
            "not the same episode (another centrobench or machine)"
        )
    recorded, again = row.get("fall_time"), summary.get("fall_time")
    fell = recorded is not None and not (isinstance(recorded, float) and math.isnan(recorded))
    if fell and (again is None or abs(again - recorded) > 1e-9):
        raise ReplayError(
            f"the episode ran again fell at {again} s, recorded {recorded} s: not the same "
            "episode (another centrobench or machine)"
        )


def frame_rows(trace: pd.DataFrame, fps: float) -> np.ndarray:
    """The trace rows drawn as frames: one per 1 / fps simulated seconds, and the last."""
    time = trace["time"].to_numpy()
    if len(time) == 0:
        return np.zeros(0, dtype=int)
    times = np.arange(time[0], time[-1] + 1e-9, 1.0 / fps)
    rows = np.unique(np.searchsorted(time, times - 1e-9).clip(0, len(time) - 1))
    return np.unique(np.append(rows, len(time) - 1))


def trace_json(trace: pd.DataFrame, limbs: tuple[str, ...], joints: tuple[str, ...]) -> str:
    """Every recorded period's data as JSON: time, base pose, joint positions, CoM, ZMP and
    the measured contact forces (columns with their values)."""
    columns = ["time"]
    columns += [f"base_position_true_{a}" for a in "xyz"]
    columns += [f"base_orientation_true_{a}" for a in "wxyz"]
    columns += [f"q_true_{joint}" for joint in joints]
    columns += [f"com_true_{a}" for a in "xyz"] + [f"zmp_actual_{a}" for a in "xy"]
    columns += [f"wrench_measured_{limb}_f{a}" for limb in limbs for a in "xyz"]
    data = trace.reindex(columns=columns)
    return json.dumps(
        {
            "columns": columns,
            "rows": np.where(np.isfinite(data.to_numpy()), data.to_numpy(), None).tolist(),
        },
        allow_nan=False,
    )


class _Renderer:
    """PyBullet's CPU renderer on a simulator loaded with the episode's robot and scene."""

    def __init__(self, run) -> None:
        import pybullet as pb

        from bench.scenarios import make_scenario
        from robots.model import RobotModel
        from robots.perturbation import NOMINAL, simulated_robot, simulated_scene
        from robots.robot_registry import make_robot
        from sims.base import make_simulator

        self.pb = pb
        perturbation = run.perturbation or NOMINAL
        nominal = make_robot(run.robot, run.scale)
        self.robot = simulated_robot(nominal, perturbation, run.seed)
        model = RobotModel(nominal)
        scenario = make_scenario(  # as the runner builds it (`bench.runner.run_episode`)
            run.scenario,
            model,
            run.duration,
            run.push_impulse,
            run.push_direction_deg,
            run.push_time,
            run.push_step,
            run.friction,
            run.speed,
            run.steps,
            run.push_swing_fraction,
            run.push_direction_name,
        )
        scene = simulated_scene(scenario.scene, perturbation, run.seed, run.scale)
        self.sim = make_simulator("pybullet")
        # no grasps (a replay sets configurations, it does not simulate); moving boxes are
        # put where they are at each frame's time
        self.sim.reset(self.robot, replace(scene, grasps=()), model.standing_state())
        c = self.client = self.sim.client
        self.markers = {
            name: pb.createMultiBody(
                baseMass=0,
                baseCollisionShapeIndex=-1,
                baseVisualShapeIndex=pb.createVisualShape(
                    pb.GEOM_SPHERE, radius=0.03 * run.scale, rgbaColor=colour, physicsClientId=c
                ),
                physicsClientId=c,
            )
            for name, colour in (("com", [0.1, 0.8, 0.2, 1]), ("zmp", [0.9, 0.1, 0.1, 1]))
        }
        self.model = RobotModel(self.robot)
        self.forces: list[int] = []  # this frame's force bars (made again every frame)

    def close(self) -> None:
        self.sim.close()

    def draw(self, row: pd.Series) -> np.ndarray:
        """The view of one trace row: an (h, w, 3) uint8 image."""
        from robots.types import RobotState

        pb, c = self.pb, self.client
        q = np.array([row[f"q_true_{j}"] for j in self.robot.joint_names])
        state = RobotState.at_rest(
            np.array([row[f"base_position_true_{a}"] for a in "xyz"]),
            np.array([row[f"base_orientation_true_{a}"] for a in "wxyz"]),
            q,
        )
        self.sim.set_state(state)
        if self.sim.scene.moving_boxes:
            self.sim._move_boxes(float(row["time"]))
        com = np.array([row[f"com_true_{a}"] for a in "xyz"])
        zmp = [row.get("zmp_actual_x", np.nan), row.get("zmp_actual_y", np.nan)]
        hidden = [0.0, 0.0, -10.0]
        pb.resetBasePositionAndOrientation(
            self.markers["com"], com.tolist(), [0, 0, 0, 1], physicsClientId=c
        )
        ground = [zmp[0], zmp[1], 0.005] if np.all(np.isfinite(zmp)) else hidden
        pb.resetBasePositionAndOrientation(
            self.markers["zmp"], ground, [0, 0, 0, 1], physicsClientId=c
        )
        for body in self.forces:
            pb.removeBody(body, physicsClientId=c)
        self.forces = [
            bar
            for limb in self.robot.limbs
            if (bar := self._force_bar(limb, row, state)) is not None
        ]
        width, height = IMAGE_SIZE
        view = pb.computeViewMatrixFromYawPitchRoll(
            cameraTargetPosition=[com[0], com[1], 0.6 * com[2]],
            distance=3.0 * self.robot.scale,
            yaw=50.0,
            pitch=-20.0,
            roll=0.0,
            upAxisIndex=2,
        )
        projection = pb.computeProjectionMatrixFOV(45.0, width / height, 0.05, 20.0)
        image = pb.getCameraImage(
            width,
            height,
            view,
            projection,
            renderer=pb.ER_TINY_RENDERER,
            physicsClientId=c,
        )[2]
        return np.reshape(np.asarray(image, dtype=np.uint8), (height, width, 4))[:, :, :3]

    def _force_bar(self, limb, row: pd.Series, state) -> int | None:
        """A bar along the limb's measured contact force from its contact frame (1 mm per
        N); None when the limb carries less than 1 N."""
        pb, c = self.pb, self.client
        force_limb = np.array([row.get(f"wrench_measured_{limb.name}_f{a}", 0.0) for a in "xyz"])
        origin, rotation = self.model.frame_pose(state, limb.contact_frame)
        force = rotation @ np.nan_to_num(force_limb)
        magnitude = float(np.linalg.norm(force))
        if magnitude < 1.0:
            return None
        length = FORCE_SCALE_M_PER_N * magnitude
        direction = force / magnitude
        axis = np.cross([0.0, 0.0, 1.0], direction)
        angle = math.acos(float(np.clip(direction[2], -1.0, 1.0)))
        axis = axis / np.linalg.norm(axis) if np.linalg.norm(axis) > 1e-9 else np.array([1.0, 0, 0])
        shape = pb.createVisualShape(
            pb.GEOM_BOX,
            halfExtents=[0.008, 0.008, length / 2],
            rgbaColor=[0.1, 0.3, 0.9, 1],
            physicsClientId=c,
        )
        return pb.createMultiBody(
            baseMass=0,
            baseCollisionShapeIndex=-1,
            baseVisualShapeIndex=shape,
            basePosition=(np.asarray(origin) + direction * length / 2).tolist(),
            baseOrientation=[*(math.sin(angle / 2) * axis), math.cos(angle / 2)],  # x y z w
            physicsClientId=c,
        )


def replay(results: str | Path, episode_id: str, out: str | Path, fps: float = DEFAULT_FPS) -> Path:
    """Run `episode_id` of the sweep in `results` again and write its replay to `out` (.html:
    a page with a player; .gif: an animated image). Returns `out`."""
    out = Path(out)
    if out.suffix.lower() not in (".html", ".gif"):
        raise ReplayError(f"--out {out}: give a .html or .gif file")
    episode, row = find_episode(results, episode_id)
    if episode.refused is not None:
        raise ReplayError(f"episode {episode_id} was not run: n/a ({episode.refused})")
    result = run_with_configuration(episode.run)
    check_same_ending(result.summary, row)
    return write_replay(result, episode, out, fps)


def write_replay(result, episode, out: Path, fps: float = DEFAULT_FPS) -> Path:
    """Draw `result` (a run with the configuration recorded) of `episode` into `out`."""
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
    from matplotlib import animation

    trace = result.trace
    joints = _joint_names(episode.run)
    if trace.empty or f"q_true_{joints[0]}" not in trace:
        raise ReplayError("the episode recorded no period to draw")
    renderer = _Renderer(episode.run)
    try:
        rows = frame_rows(trace, fps)
        images = [renderer.draw(trace.iloc[k]) for k in rows]
    finally:
        renderer.close()
    matplotlib.rcParams["animation.embed_limit"] = EMBED_LIMIT_MB  # else frames are dropped
    matplotlib.rcParams["animation.frame_format"] = "jpeg"  # a third of PNG's size
    figure = plt.figure(figsize=(11, 4.4), dpi=FIGURE_DPI)
    view = figure.add_axes([0.0, 0.0, 0.52, 0.92])
    view.set_axis_off()
    picture = view.imshow(images[0])
    title = figure.suptitle("", fontsize=9, x=0.02, ha="left")
    plots = [figure.add_axes([0.58, 0.56, 0.4, 0.36]), figure.add_axes([0.58, 0.1, 0.4, 0.36])]
    time = trace["time"].to_numpy()
    cursors = []
    for axis, name in zip(plots, "xy", strict=True):
        axis.plot(time, trace[f"com_true_{name}"], "g-", lw=1, label=f"CoM {name}")
        if f"zmp_actual_{name}" in trace:
            axis.plot(time, trace[f"zmp_actual_{name}"], "r-", lw=0.6, label=f"ZMP {name}")
        axis.set_ylabel(f"{name} [m]")
        axis.legend(fontsize=7, loc="upper left")
        axis.grid(alpha=0.3)
        cursors.append(axis.axvline(time[0], color="k", lw=0.8))
    plots[1].set_xlabel("time [s]")
    summary = result.summary
    label = f"{episode.controller} | {episode.run.sim} | {episode.run.scenario}"
    limbs = _limb_names(trace)

    def show(index: int):
        k = rows[index]
        picture.set_data(images[index])
        forces = ", ".join(
            f"{limb} {trace[f'wrench_measured_{limb}_fz'].iloc[k]:.0f} N"
            for limb in limbs
            if f"wrench_measured_{limb}_fz" in trace
        )
        title.set_text(
            f"{label} | t = {time[k]:.3f} s of {time[-1]:.3f} s | {summary['status']}"
            f"{' at ' + format(summary['fall_time'], '.3f') + ' s' if summary['fall_time'] else ''}"
            f"\nnormal forces: {forces}"
        )
        for cursor in cursors:
            cursor.set_xdata([time[k], time[k]])
        return [picture, title, *cursors]

    player = animation.FuncAnimation(figure, show, frames=len(rows), interval=1000.0 / fps)
    out.parent.mkdir(parents=True, exist_ok=True)
    if out.suffix.lower() == ".gif":
        player.save(out, writer=animation.PillowWriter(fps=fps))
    else:
        page = player.to_jshtml(fps=fps, default_mode="once")
        data = trace_json(trace, tuple(limbs), joints)
        out.write_text(
            "<!DOCTYPE html>\n<html><head><meta charset='utf-8'>"
            f"<title>centrobench replay {episode.episode_id}</title></head><body>\n"
            f"<p>{label}: {len(trace)} control periods, {len(rows)} frames at {fps:g} per "
            "simulated second.</p>\n"
            f"{page}\n<script type='application/json' id='episode-trace'>{data}</script>\n"
            "</body></html>\n"
        )
    plt.close(figure)
    return out


def _joint_names(run) -> tuple[str, ...]:
    from robots.robot_registry import make_robot

    return make_robot(run.robot, run.scale).joint_names


def _limb_names(trace: pd.DataFrame) -> list[str]:
    return [c.removeprefix("contact_") for c in trace.columns if c.startswith("contact_")]
