"""Episode metrics computed from a trace (per-period DataFrame of `bench.runner`)."""

from __future__ import annotations

import numpy as np
import pandas as pd

MIN_SPEED = 1e-3  # [m/s] below this the reference does not walk: no walking quality


def walking_quality(
    trace: pd.DataFrame, plans_com_trajectory: bool = True
) -> dict[str, float | None]:
    """Ficht & Behnke eq. (18): the integral square errors of the horizontal CoM position,
    ZMP and CoM velocity against their references, normalised by the walking time t_w and
    the requested forward velocity v_g,x:

        e_* = 1 / (v_g,x t_w) * integral_0^t_w ||v_ref - v||^2 dt

    with v = [x y] of the CoM (e_c [m s]), [p_zx p_zy] of the ZMP (e_z [m s]) and [x' y'] of
    the CoM (e_v [m/s]). Adaptation: the references are the planner's plan (planned CoM,
    planned ZMP, planned CoM velocity: what the stabilizer is asked to track) and v_g,x is the
    mean forward speed of the plan over the episode (its displacement over the elapsed time);
    None when the plan does not move forward (standing). With `plans_com_trajectory` False (a
    planner whose plan's CoM is the state it was computed from: `Planner.plans_com_trajectory`)
    e_c and e_v would compare the state with itself and are None; e_z, the ZMP against the
    one the planner decided, stays.
    """
    empty = {"walk_speed_mps": None, "e_com": None, "e_zmp": None, "e_velocity": None}
    if len(trace) < 2 or "com_velocity_planned_x" not in trace:
        return empty
    time = trace["time"].to_numpy()
    dt = float(np.median(np.diff(time)))
    duration = dt * len(trace)
    displacement = trace["com_planned_x"].iloc[-1] - trace["com_planned_x"].iloc[0]
    speed = displacement / (time[-1] - time[0])
    if not speed > MIN_SPEED:
        return empty

    def ise(reference: str, actual: str, axes=("x", "y")) -> float:
        difference = (
            trace[[f"{reference}_{a}" for a in axes]].to_numpy()
            - trace[[f"{actual}_{a}" for a in axes]].to_numpy()
        )
        return float(np.nansum(difference**2) * dt / (speed * duration))

    return {
        "walk_speed_mps": float(speed),
        "e_com": ise("com_planned", "com_actual") if plans_com_trajectory else None,
        "e_zmp": ise("zmp_planned", "zmp_actual"),
        "e_velocity": (
            ise("com_velocity_planned", "com_velocity_actual") if plans_com_trajectory else None
        ),
    }


def feedback_magnitude(trace: pd.DataFrame) -> dict[str, float | None]:
    """Mean norms of the stabilizer's feedback wrench (desired minus planned resultant) [N],
    [N m], as in `bench.compare` (None when the stabilizer distributes no wrench)."""
    if "wrench_desired_fx" not in trace or not len(trace):
        return {"feedback_force_N": None, "feedback_moment_Nm": None}
    axes = ("fx", "fy", "fz", "mx", "my", "mz")
    desired = trace[[f"wrench_desired_{a}" for a in axes]].to_numpy()
    planned = trace[[f"wrench_projected_{a}" for a in axes]].to_numpy()
    difference = desired - planned
    return {
        "feedback_force_N": float(np.nanmean(np.linalg.norm(difference[:, :3], axis=1))),
        "feedback_moment_Nm": float(np.nanmean(np.linalg.norm(difference[:, 3:], axis=1))),
    }
