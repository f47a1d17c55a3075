"""Result rows: whether a push was survived."""

import pytest

from bench.dataset import summary_row
from bench.limits import CONTROL_PERIOD_S


@pytest.mark.parametrize(
    ("status", "duration", "survived"),
    [
        ("ok", 6.232, True),  # round(6.2325 / 0.002) periods: half a period short, complete
        ("ok", 6.2325, True),
        ("ok", 6.2325 - CONTROL_PERIOD_S, False),  # a whole period short: not complete
        ("fell", 4.1, False),
    ],
)
def test_a_walking_push_that_ran_its_periods_is_survived(status, duration, survived):
    """The walking pushes request 6.2325 s (push at 3.1325 s + 0.1 s + 3 s), no whole number
    of 2 ms periods; the runner runs 3116 of them (6.232 s). Before this was accepted, every
    walking push that ended ok was counted as a fall."""
    labels = {"push_phase": "walking", "episode_id": "x", "controller": "c"}
    row = summary_row(labels, {"status": status, "duration": duration}, None, 6.2325, 1.0)
    assert row["survived"] is survived
