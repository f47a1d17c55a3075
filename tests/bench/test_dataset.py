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


def test_every_scalar_summary_field_reaches_its_typed_column():
    """Each field of the runner's summary that is not a table of its own (latency, projection
    error, versions: flattened into other columns) is a `ROW_SCHEMA` column with a dtype, and
    the row holds its value; here for `reach`, whose hand error (0.51 m: the target starts
    0.5 m ahead of the palm) must not be dropped on the way to the result file."""
    import pyarrow as pa

    from bench.dataset import ROW_SCHEMA
    from bench.runner import EpisodeSpec, run_episode, summary_json_ready

    result = run_episode(EpisodeSpec("hold", "posture", "mujoco", "reach", duration=0.1))
    summary = summary_json_ready(result.summary)
    assert summary["status"] == "ok"
    labels = {"episode_id": "x", "controller": "hold+posture"}
    row = summary_row(labels, result.summary, result.trace, 0.1, 1.0)
    table = pa.Table.from_pylist([row], schema=ROW_SCHEMA)
    for key, value in summary.items():
        if isinstance(value, dict):
            continue
        assert key in ROW_SCHEMA.names, key
        assert table.column(key)[0].as_py() == value, key
    assert table.schema.field("hand_error_final_m").type == pa.float64()
    assert 0.5 < table.column("hand_error_final_m")[0].as_py() < 0.52


def test_a_replicas_row_has_its_own_push_time():
    """A replica's push starts up to 20 ms earlier or later than its protocol's
    (`bench.runner.replica_changes`): its row's `push_time_s` is its own, so that "fell before
    the push" is judged against the push it got; replica 0's is the protocol's."""
    from bench.runner import EpisodeSpec, replica_changes, run_episode
    from robots.model import cached_model
    from robots.robot_registry import make_robot

    standing = cached_model(make_robot()).standing_state()
    for replica in (0, 3):
        result = run_episode(
            EpisodeSpec("hold", "posture", "mujoco", "stand_push", duration=0.05, replica=replica)
        )
        _, shift = replica_changes(standing, 0, replica)
        assert result.summary["push_shift_s"] == shift
        row = summary_row({"push_time_s": 1.5}, result.summary, result.trace, 0.05, 1.0)
        assert row["push_time_s"] == pytest.approx(1.5 + shift, abs=1e-12)
        assert (shift == 0.0) == (replica == 0)


@pytest.mark.parametrize(
    ("stage", "survived"),
    [("planner", False), ("estimator", False), ("sim", None), ("setup", None)],
)
def test_a_push_whose_controller_failed_is_not_survived(stage, survived):
    """`reports.outcomes`: an error raised by the controller's own stages ends the push as
    not survived; an error of the set-up or the simulator says nothing (None)."""
    labels = {"push_phase": "standing", "episode_id": "x", "controller": "c"}
    summary = {"status": "error", "error_stage": stage, "duration": 3.9}
    row = summary_row(labels, summary, None, 5.0, 1.0)
    assert row["survived"] is survived


def test_scanning_a_results_folder_keeps_every_row_in_order_and_says_what_it_left_out(tmp_path):
    """`scan_episodes` reads the files on a few threads and skips the cast of a file already
    in `ROW_SCHEMA`: the rows come back in file order, each as `pq.read_table` and the cast
    would give it; a file of an older centrobench lacking a column is read with it null; an
    unreadable file, a file with a column of another type and a file of another episode are
    left out with their reason, in file order."""
    import pyarrow as pa
    import pyarrow.parquet as pq

    from bench.dataset import ROW_SCHEMA, scan_episodes

    folder = tmp_path / "episodes"
    folder.mkdir()
    summary = {"status": "ok", "duration": 1.0}

    def row(episode: str) -> pa.Table:
        labels = {"episode_id": episode, "controller": "c", "sim": "mujoco"}
        return pa.Table.from_pylist([summary_row(labels, summary, None, 1.0, 1.0)], ROW_SCHEMA)

    names = [f"{k:02d}" for k in range(12)]
    for name in names:
        pq.write_table(row(name), folder / f"{name}.parquet")
    pq.write_table(row("old").drop_columns(["torque_share_max"]), folder / "old.parquet")
    wrong = row("typed")
    index = wrong.schema.get_field_index("fall_time")
    pq.write_table(
        wrong.set_column(index, "fall_time", pa.array(["soon"])), folder / "typed.parquet"
    )
    pq.write_table(row("someone"), folder / "other.parquet")
    (folder / "broken.parquet").write_bytes(b"not parquet")
    table, bad = scan_episodes(tmp_path)
    assert table.column("episode_id").to_pylist() == [*names, "old"]
    expected = pa.concat_tables(
        [pq.read_table(folder / f"{name}.parquet").cast(ROW_SCHEMA) for name in names]
    )
    assert table.slice(0, len(names)).equals(expected)
    assert table.column("torque_share_max")[len(names)].as_py() is None
    assert [(path.name, why.split(" (")[0]) for path, why in bad] == [
        ("broken.parquet", "not a readable Parquet file"),
        ("other.parquet", "1 rows, not the one row of episode other"),
        ("typed.parquet", "columns of the wrong type"),
    ]
