"""Which result rows say whether a controller came through its episode ("judged"), and how.

Judged: an episode that ended "ok" or "fell", and one whose controller failed: an exception
raised by the controller's own stages (its estimator, planner, stabilizer or whole-body layer;
status "error" with that `error_stage`), such as a solver that gives up on a robot it can no
longer hold. A controller failure counts as not survived: the controller did not bring the
robot through. Not judged: an error in the set-up, in the simulator or in a worker, and a
timeout (a wall-clock budget, which depends on the machine); they say nothing about the
controller and are shown as "not judged". (`sweep --resume --retry-errors` reruns every
"error" and "timeout" row, a controller's failure too, which is deterministic.)

A pushed episode that ended before its push came (the robot fell, or its controller failed,
earlier than `push_time_s`) is judged as an episode but says nothing of push recovery: the
push tables count it apart, "fell before the push" (`judged_push`), instead of as a push not
survived (until 2026-11-28 it was one: a controller that cannot stand read "0/20" beside the
others, and won or lost paired tests on pushes it never received).

Neither: an "n/a" row, an episode never run because the controller cannot run its scenario
(`bench.controllers.refusal`, the reason in `error`). It is no push, no walk and no failure:
the push and threshold tables leave it out, and the report lists it with its reason under
"Not run" (`refusal_reason`; until 2026-12-03 a refused controller's pushes read "10 not
judged" and "incomplete 10", the reason nowhere).

One definition for the result rows (`bench.dataset`) and every report table.
"""

from __future__ import annotations

import pandas as pd

ENDED = ("ok", "fell")  # statuses that end an episode the controller ran to its end
CONTROLLER_STAGES = ("estimator", "planner", "stabilizer", "whole_body")
"""The runner's stages (`error_stage`) that belong to the controller."""


def is_controller_failure(status: object, error_stage: object) -> bool:
    """One row: status "error" raised in one of `CONTROLLER_STAGES` (a missing stage, None
    or pandas' NA, is none of them)."""
    return status == "error" and isinstance(error_stage, str) and error_stage in CONTROLLER_STAGES


def controller_failed(rows: pd.DataFrame) -> pd.Series:
    """Per row: the controller failed (see the module)."""
    stage = rows["error_stage"] if "error_stage" in rows else pd.Series(None, index=rows.index)
    return (rows["status"] == "error") & stage.isin(CONTROLLER_STAGES)


def judged(rows: pd.DataFrame) -> pd.Series:
    """Per row: whether it says if the controller came through (see the module)."""
    return rows["status"].isin(ENDED) | controller_failed(rows)


def failure_label(error_stage: object, duration: object = None) -> str:
    """A controller failure in words: "<stage> failed[ at t s]" (t: the simulated time
    reached [s])."""
    stage = str(error_stage).replace("_", "-")
    if duration is None or pd.isna(duration):
        return f"{stage} failed"
    return f"{stage} failed at {float(duration):.1f} s"


def ended_before_push(rows: pd.DataFrame) -> pd.Series:
    """Per row: a pushed episode that fell (`fall_time`) or whose controller failed
    (`duration`, the simulated time reached) before its push (`push_time_s`) [s]; False for
    episodes without a push and for rows written without these columns."""
    if "push_time_s" not in rows:
        return pd.Series(False, index=rows.index)
    push = rows["push_time_s"]
    missing = pd.Series(float("nan"), index=rows.index)
    fell = (rows["status"] == "fell") & (rows.get("fall_time", missing) < push)
    failed = controller_failed(rows) & (rows.get("duration", missing) < push)
    return (fell | failed).fillna(False).astype(bool)


def judged_push(rows: pd.DataFrame) -> pd.Series:
    """Per row: judged (`judged`) and not ended before its push (`ended_before_push`): the
    episodes that say whether the controller came through its push."""
    return judged(rows) & ~ended_before_push(rows)


def ran(rows: pd.DataFrame) -> pd.DataFrame:
    """The rows of episodes that were run: without the "n/a" rows (see the module)."""
    return rows[rows["status"] != "n/a"]


def refusal_reason(error: object) -> str:
    """Why an "n/a" row was not run, from its `error` ("n/a: <reason>"); "" if none."""
    if not isinstance(error, str):
        return ""
    return error.removeprefix("n/a:").strip()
