"""The report's robustness sections on a hand-made fixture: degradation with intervals, where
half the survival is lost, robust thresholds from 5 replicas, paired comparisons (scipy's
exact test), walking pushes by timing and direction, the simulator band; and perturbed
episodes stay out of the nominal tables."""

from __future__ import annotations

import json
from pathlib import Path

import pandas as pd
import pytest
from scipy import stats

from bench.dataset import ResultStore
from reports import robustness, tables
from reports.build import build_report
from reports.statistics import fraction_cell
from tests.reports.rows import result_row

LEVELS = (0.2, 0.3, 0.4)
# replicas survived out of 5, per controller and level, for push 0 (push 1: all survive)
REPLICAS = {"a+x": (5, 4, 2), "b+y": (5, 5, 4)}
# standing pushes survived out of 10 per controller at noise 0 (nominal), 1 and 2
NOISE = {"a+x": (10, 6, 2), "b+y": (10, 9, 8)}


def _row(**values) -> dict:
    row = result_row(mass_kg=50.0, status="ok", fell=False, com_error_rms_m=0.004)
    row.update(values)
    row["episode_id"] = "e" + str(abs(hash(json.dumps(values, sort_keys=True, default=str))))
    return row


def _push(controller, sim, dv, index, alive, **values) -> dict:
    return _row(
        controller=controller,
        sim=sim,
        scenario="stand_push",
        push_phase="standing",
        push_dv_mps=dv,
        push_index=index,
        push_impulse_Ns=50.0 * dv,
        status="ok" if alive else "fell",
        fell=not alive,
        survived=alive,
        **values,
    )


def fixture_rows() -> list[dict]:
    rows = []
    for controller in REPLICAS:
        for sim in ("mujoco", "pybullet"):
            for level, survived in zip(LEVELS, REPLICAS[controller], strict=True):
                for replica in range(5):
                    rows.append(
                        _push(controller, sim, level, 0, replica < survived, replica=replica)
                    )
                    rows.append(_push(controller, sim, level, 1, True, replica=replica))
        for magnitude, survived in zip((1, 2), NOISE[controller][1:], strict=True):
            for index in range(10):
                rows.append(
                    _push(
                        controller,
                        "mujoco",
                        0.2,
                        100 + index,
                        index < survived,
                        perturbation=f"noise={magnitude}",
                        noise_encoders=magnitude,
                        noise_imu=magnitude,
                        noise_ft=magnitude,
                        com_error_rms_m=0.004 * (1 + magnitude),
                    )
                )
        for index in range(10):  # the nominal pushes of the noise curve
            rows.append(_push(controller, "mujoco", 0.2, 100 + index, True))
        for index in range(10):  # one channel's noise in SI units: 3 of 10 survive
            rows.append(
                _push(
                    controller,
                    "mujoco",
                    0.2,
                    100 + index,
                    index < 3,
                    perturbation="noise_force_N=0.5",
                    noise_force_N=0.5,
                )
            )
        for name, alive in (("inward", False), ("outward", True)):
            rows.append(
                _row(
                    controller=controller,
                    sim="mujoco",
                    scenario="walk_push",
                    push_phase="walking",
                    push_dv_mps=0.3,
                    push_direction_name=name,
                    push_swing_fraction=0.2,
                    status="ok" if alive else "fell",
                    survived=alive,
                )
            )
    return rows


@pytest.fixture(scope="module")
def episodes() -> pd.DataFrame:
    return pd.DataFrame(fixture_rows())


def test_degradation_has_intervals_and_the_nominal_point(episodes):
    table = robustness.degradation_table(episodes)
    assert set(table["sim"]) == {"mujoco"}  # the only simulator with noise episodes
    noise = table[(table["controller"] == "a+x") & (table["dimension"] == "noise")]
    noise = noise[noise["protocol"] == "standing push"].sort_values("magnitude")
    assert list(noise["magnitude"]) == [0.0, 1.0, 2.0]
    # nominal: the perturbed pushes' nominal twins only (the same 10 pushes unperturbed),
    # not the other nominal pushes of the sweep
    assert list(noise["episodes"]) == [10, 10, 10]
    assert list(noise["survived"]) == [10, 6, 2]
    assert noise.iloc[1]["survival"] == fraction_cell(6, 10)
    assert noise.iloc[2]["com_rms_mm"] == pytest.approx(12.0)


def test_a_channels_noise_in_si_units_is_a_dimension_of_its_own(episodes):
    table = robustness.degradation_table(episodes)
    force = table[(table["controller"] == "a+x") & (table["dimension"] == "noise_force_N")]
    assert list(force["magnitude"]) == [0.0, 0.5]  # [N], with the nominal twins at 0
    assert list(force["survived"]) == [10, 3]


def test_half_survival_is_the_first_magnitude_at_half_the_nominal_rate(episodes):
    half = robustness.half_survival_table(robustness.degradation_table(episodes))
    rows = half[(half["dimension"] == "noise") & (half["protocol"] == "standing push")]
    by_controller = dict(zip(rows["controller"], rows["half at"], strict=True))
    assert by_controller == {"a+x": "2", "b+y": "beyond 2"}  # 2/10 <= 1/2; 8/10 > 1/2


def test_robust_thresholds_take_4_of_5_replicas_at_every_level(episodes):
    table = robustness.robust_threshold_table(episodes)
    table = table[table["sim"] == "mujoco"].set_index("controller")
    # a+x push 0: 5, 4, 2 of 5 -> 0.3; push 1 all -> 0.4: lower median 0.3 (a level run,
    # not the 0.35 between them), min 0.3
    assert table.loc["a+x", "min dv m/s"] == "0.3"
    assert table.loc["a+x", "max dv m/s"] == "0.4"
    assert table.loc["a+x", "median dv m/s"] == "0.3"
    # b+y push 0: 5, 5, 4 of 5 -> 0.4
    assert table.loc["b+y", "min dv m/s"] == "0.4"
    assert table.loc["a+x", "pushes"] == 2


def _replicated(controller, levels, survived, replicas=5, index=0, **values):
    """Push `index` at each level with `replicas` replicas, the first survived[level] of
    which survive."""
    return [
        _push(controller, "mujoco", level, index, replica < k, replica=replica, **values)
        for level, k in zip(levels, survived, strict=True)
        for replica in range(replicas)
    ]


def test_a_push_below_its_lowest_level_is_below_every_level_not_zero():
    """Thresholds {below 0.2, 0.4}: the median is the lower one, "< 0.2", not the mean of
    0 and 0.4 (a level never run); min "< 0.2", max 0.4."""
    rows = _replicated("a+x", LEVELS, (3, 5, 5), index=0)
    rows += _replicated("a+x", LEVELS, (5, 5, 5), index=1)
    row = robustness.robust_threshold_table(pd.DataFrame(rows)).iloc[0]
    assert (row["pushes"], row["median dv m/s"]) == (2, "< 0.2")
    assert (row["min dv m/s"], row["max dv m/s"]) == ("< 0.2", "0.4")


def test_a_push_fallen_before_it_came_has_no_threshold():
    """Every replica fell at 0.7 s, before its 1.5 s push: counted under "before push", not
    as a push below its lowest level (it was never pushed)."""
    rows = _replicated("a+x", LEVELS, (0, 0, 0), push_time_s=1.5, fall_time=0.7)
    row = robustness.robust_threshold_table(pd.DataFrame(rows)).iloc[0]
    assert (row["pushes"], row["before push"], row["incomplete"]) == (0, 1, 0)
    assert row["median dv m/s"] == "–"


def test_a_level_run_without_its_replicas_makes_the_push_incomplete():
    """0.3 m/s has only replica 0 (an interrupted sweep), which fell: the push has no
    threshold (before, the level was skipped and the threshold read 0.4)."""
    rows = [
        row
        for row in _replicated("a+x", LEVELS, (5, 0, 5))
        if row["push_dv_mps"] != 0.3 or row["replica"] == 0
    ]
    row = robustness.robust_threshold_table(pd.DataFrame(rows)).iloc[0]
    assert (row["pushes"], row["incomplete"]) == (0, 1)


@pytest.mark.parametrize(("replicas", "survived", "threshold"), [(10, 8, "0.4"), (10, 7, "< 0.2")])
def test_another_replica_count_takes_the_same_fraction(replicas, survived, threshold):
    """10 replicas: 8 of 10 (80 %, as 4 of 5) makes a level; 7 does not."""
    rows = _replicated("a+x", LEVELS, (survived,) * 3, replicas=replicas)
    row = robustness.robust_threshold_table(pd.DataFrame(rows)).iloc[0]
    assert (row["pushes"], row["incomplete"], row["median dv m/s"]) == (1, 0, threshold)


def test_paired_comparison_equals_scipys_exact_test(episodes):
    table = robustness.paired_comparisons(episodes, "standing")
    row = table[table["sim"] == "mujoco"].iloc[0]
    assert (row["controller A"], row["controller B"]) == ("a+x", "b+y")
    # the protocol pushes (replica 0, nominal): every one survived by both -> no discordant
    assert (row["only A"], row["only B"], row["p"]) == (0, 0, 1.0)
    perturbed = pd.DataFrame(fixture_rows())
    perturbed = perturbed[perturbed["perturbation"] == "noise=2"].assign(perturbation="nominal")
    table = robustness.paired_comparisons(perturbed, "standing")
    row = table.iloc[0]
    assert (row["only A"], row["only B"]) == (0, 6)  # b+y survives 8, a+x the first 2 of them
    assert row["p"] == pytest.approx(stats.binomtest(0, 6).pvalue)


def test_direction_table_and_the_simulator_band(episodes):
    directions = robustness.direction_table(episodes)
    cells = directions.set_index(["controller", "direction"])["dv 0.3 m/s"]
    assert cells[("a+x", "inward")] == "0/1"
    assert cells[("a+x", "outward")] == "1/1"
    headline = robustness.headline_survival(episodes).set_index("controller")
    # a+x protocol pushes (replica 0): mujoco 6 + 10 nominal noise-curve pushes all survived
    assert headline.loc["a+x", "mujoco"] == fraction_cell(16, 16)
    assert headline.loc["a+x", "pybullet"] == fraction_cell(6, 6)
    assert headline.loc["a+x", "band %"] == "100-100"


def test_perturbed_episodes_stay_out_of_the_nominal_tables(episodes):
    table = tables.survival_rates(episodes, "standing")
    row = table[(table["controller"] == "a+x") & (table["sim"] == "mujoco")]
    # level 0.2: 2 protocol pushes + the 10 nominal pushes of the noise curve, no replicas
    assert list(row["pushes"]) == [12, 2, 2]


def test_report_has_every_robustness_section(tmp_path: Path):
    root = tmp_path / "results"
    store = ResultStore(root)
    store.prepare({"name": "robust"}, "digest", resume=False, overwrite=False)
    for row in fixture_rows():
        store.write(row, None)
    paths = build_report(root, tmp_path / "report")
    markdown = (tmp_path / "report" / "report.md").read_text()
    for title in (
        "1. Which pushes each controller survives",
        "Robust push thresholds",
        "Paired comparisons, standing pushes",
        "Walking pushes by timing and direction",
        "Degradation along the robustness dimensions",
        "Where each controller loses half of its survival",
    ):
        assert f"## {title}" in markdown, title
    assert "degradation_noise.png" in {p.name for p in paths}


def test_replays_offered_are_one_walk_and_the_first_fall_per_controller(tmp_path: Path):
    records = [
        _row(controller="a+x", sim="pybullet", scenario="walk", seed=2),
        _row(controller="a+x", sim="mujoco", scenario="walk", seed=1),
        _push("a+x", "mujoco", 0.4, 3, False),
        _push("a+x", "pybullet", 0.3, 7, False),  # the lowest level that fell
        _push("a+x", "mujoco", 0.3, 9, False),
        _push("a+x", "mujoco", 0.2, 1, False, perturbation="noise=2"),  # not nominal
        _push("b+y", "mujoco", 0.2, 0, True),
        _push("c+z", "mujoco", 0.2, 0, True),
        _push("c+z", "mujoco", 0.2, 0, False, perturbation="delay=3"),
    ]
    rows = pd.DataFrame(records)
    choices = robustness.replay_choices(rows)
    a = choices[choices["controller"] == "a+x"].set_index("what")
    assert a.loc["walk", "sim"] == "mujoco"
    first = a.loc["first fall (stand_push, dv 0.3 m/s)"]
    assert (first["sim"], first["episode_id"]) == ("pybullet", rows.iloc[3]["episode_id"])
    # b+y: no walk, no fall; c+z: only a perturbed fall, named with its perturbation
    assert list(choices["controller"]) == ["a+x", "a+x", "c+z"]
    assert choices.iloc[2]["what"] == "first fall (stand_push, dv 0.2 m/s, delay=3)"
    # the report lists them, with the file where one was made
    root = tmp_path / "results"
    store = ResultStore(root)
    store.prepare({"name": "replays"}, "d", resume=False, overwrite=False)
    for row in records:
        store.write(row, None)
    made = tmp_path / "report" / "replays" / f"{rows.iloc[1]['episode_id']}.html"
    made.parent.mkdir(parents=True)
    made.write_text("<html></html>")
    build_report(root, tmp_path / "report")
    markdown = (tmp_path / "report" / "report.md").read_text()
    assert "## Replays" in markdown
    assert f"replays/{rows.iloc[1]['episode_id']}.html" in markdown


def test_a_level_whose_replicas_all_failed_to_run_leaves_the_push_without_a_threshold():
    rows = []
    for level in (0.3, 0.35, 0.4):
        for replica in range(5):
            row = _push("a+x", "mujoco", level, 0, True, replica=replica)
            if level == 0.35:
                row.update(status="error", survived=None)
            rows.append(row)
    table = robustness.robust_threshold_table(pd.DataFrame(rows))
    assert table.iloc[0]["pushes"] == 0
    assert table.iloc[0]["incomplete"] == 1


def test_replicas_whose_controller_failed_count_as_not_surviving_the_level():
    """`reports.outcomes`: at 0.35 m/s two of the five replicas end in the planner's failure
    (judged, not survived: 3 of 5 < 4), so the robust threshold is 0.3 m/s, where before the
    push was left without one (the level had 3 judged replicas, "incomplete")."""
    rows = []
    for level in (0.3, 0.35, 0.4):
        for replica in range(5):
            row = _push("a+x", "mujoco", level, 0, True, replica=replica)
            if level == 0.35 and replica < 2:
                row.update(status="error", error_stage="planner", survived=None)
            rows.append(row)
    table = robustness.robust_threshold_table(pd.DataFrame(rows))
    assert (table.iloc[0]["pushes"], table.iloc[0]["incomplete"]) == (1, 0)
    assert table.iloc[0]["min dv m/s"] == "0.3"


def test_pushes_are_paired_by_seed_too():
    rows = []
    for seed, winner in ((0, "a+x"), (1, "b+y")):
        for index in range(3):
            for controller in ("a+x", "b+y"):
                rows.append(
                    _push(controller, "mujoco", 0.3, index, controller == winner, seed=seed)
                )
    table = robustness.paired_comparisons(pd.DataFrame(rows), "standing")
    row = table.iloc[0]
    assert (row["pushes"], row["only A"], row["only B"]) == (6, 3, 3)
    assert row["p"] == pytest.approx(1.0)


def _pushes_with_an_early_fall() -> pd.DataFrame:
    """Two controllers on 6 standing pushes at 1.5 s: "steady" survives 4; "shaky" falls
    before the push in 3 (at 0.7 s) and survives 1 of the 3 it receives."""
    rows = []
    for index in range(6):
        rows.append(_push("steady", "mujoco", 0.3, index, index < 4, push_time_s=1.5))
        early = index < 3
        row = _push(
            "shaky",
            "mujoco",
            0.3,
            index,
            index == 3,
            push_time_s=1.5,
            fall_time=0.7 if early else (None if index == 3 else 2.4),
        )
        rows.append(row)
    return pd.DataFrame(rows)


def test_a_robot_that_fell_before_its_push_is_not_counted_as_a_push_not_survived():
    """A controller that cannot stand to the push says nothing of push recovery: its early
    falls are counted apart in the survival tables and left out of the paired tests (before
    2026-11-28 they read 0/20 and won the other controllers significant paired tests)."""
    episodes = _pushes_with_an_early_fall()
    rates = tables.survival_rates(episodes, "standing").set_index("controller")
    assert (rates.loc["shaky", "survived"], rates.loc["shaky", "pushes"]) == (1, 3)
    assert rates.loc["shaky", "before_push"] == 3
    assert (rates.loc["steady", "survived"], rates.loc["steady", "pushes"]) == (4, 6)
    table = tables.survival_table(episodes, "standing").set_index("controller")
    assert table.loc["shaky", "fell before the push"] == 3
    assert table.loc["steady", "fell before the push"] == ""
    headline = robustness.headline_survival(episodes).set_index("controller")
    assert headline.loc["shaky", "mujoco"] == fraction_cell(1, 3) + ", 3 fell before the push"
    paired = robustness.paired_comparisons(episodes, "standing").iloc[0]
    assert (paired["pushes"], paired["only A"], paired["only B"]) == (3, 0, 0)  # 3, 4, 5


def test_paired_comparisons_give_the_false_discovery_rate_of_the_tables_tests():
    """q (Benjamini-Hochberg) is at least p, and is scipy's over all of the table's p."""
    table = robustness.paired_comparisons(pd.DataFrame(fixture_rows()), "standing")
    assert len(table) > 1
    assert (table["q (BH)"] >= table["p"] - 1e-15).all()
    expected = stats.false_discovery_control(table["p"].to_numpy(), method="bh")
    assert table["q (BH)"].to_numpy() == pytest.approx(expected)


def test_the_false_discovery_rate_on_a_hand_case():
    """Benjamini-Hochberg by hand: p = (0.01, 0.04, 0.03) of 3 tests gives q = min over the
    larger ranks of p m / rank = (0.03, 0.04, 0.04). Three controllers on the same 10 pushes:
    a survives every one, b loses the first 2, c the first 6."""
    assert stats.false_discovery_control([0.01, 0.04, 0.03], method="bh") == pytest.approx(
        [0.03, 0.04, 0.04]
    )
    rows = []
    for index in range(10):
        for controller, lost in (("a+x", 0), ("b+y", 2), ("c+z", 6)):
            rows.append(_push(controller, "mujoco", 0.3, index, index >= lost))
    table = robustness.paired_comparisons(pd.DataFrame(rows), "standing")
    p = {
        (a, b): value
        for a, b, value in zip(
            table["controller A"], table["controller B"], table["p"], strict=True
        )
    }
    # exact McNemar: d discordant pushes all one way give p = 2 / 2^d
    assert p[("a+x", "b+y")] == pytest.approx(2 / 2**2)
    assert p[("a+x", "c+z")] == pytest.approx(2 / 2**6)
    assert p[("b+y", "c+z")] == pytest.approx(2 / 2**4)
    pairs = list(zip(table["controller A"], table["controller B"], strict=True))
    q = dict(zip(pairs, table["q (BH)"], strict=True))
    # sorted p: 1/32 (rank 1), 1/8 (rank 2), 1/2 (rank 3): q = 3/32, 3/16, 1/2
    assert q[("a+x", "c+z")] == pytest.approx(3 / 32)
    assert q[("b+y", "c+z")] == pytest.approx(3 / 16)
    assert q[("a+x", "b+y")] == pytest.approx(1 / 2)


def test_a_levels_impulse_is_the_robots_or_the_range_over_the_robots():
    """J = m dv differs between robots of different mass: one robot, its J; several, their
    range (the header gave their mean before 2026-11-28, no robot's impulse)."""
    assert tables.level_label(0.35, 20.44) == "0.35 m/s (20.4 N s)"
    assert tables.level_label(0.35, 20.44, 21.84) == "0.35 m/s (20.4-21.8 N s)"
    assert tables.level_label(0.35, 20.44, 20.44) == "0.35 m/s (20.4 N s)"
    rows = [_push("a", "mujoco", 0.35, 0, True, robot="h"), _push("a @ j", "mujoco", 0.35, 0, True)]
    rows[0]["push_impulse_Ns"], rows[1]["push_impulse_Ns"] = 20.44, 21.84
    table = tables.survival_table(pd.DataFrame(rows), "standing")
    assert "0.35 m/s (20.4-21.8 N s)" in table.columns


def test_a_controller_given_another_estimator_says_so_in_its_label():
    """The hierarchy runs with a perfect state, Ficht & Behnke with their own filter: the
    report's tables name that estimator beside the controller; the default one is not named."""
    from estimators import DEFAULT_ESTIMATOR
    from reports.build import label_estimators, label_robots

    rows = pd.DataFrame(
        [
            _push("capturability_hierarchy", "mujoco", 0.3, 0, True, estimator="ground_truth"),
            _push("preview_control+x", "mujoco", 0.3, 0, True, estimator=DEFAULT_ESTIMATOR),
            _push("preview_control+x", "mujoco", 0.3, 1, True, estimator="ground_truth"),
        ]
    )
    labels = list(label_robots(label_estimators(rows))["controller"])
    assert labels == [
        "capturability_hierarchy [ground_truth]",
        "preview_control+x",
        "preview_control+x [ground_truth]",
    ]
    headline = robustness.headline_survival(label_estimators(rows))
    assert set(headline["controller"]) == {
        "capturability_hierarchy [ground_truth]",
        "preview_control+x",
        "preview_control+x [ground_truth]",
    }


def test_the_headline_survival_counts_the_unjudged_episodes_and_names_the_level():
    """An episode that ended in a simulator error says nothing of the controller: the headline
    cell leaves it out of k/n and says how many there were; the level column gives dv and the
    impulse the robot was given."""
    rows = [_push("a+x", "mujoco", 0.3, index, True) for index in range(4)]
    rows[3].update(status="error", error_stage="sim", survived=None)
    episodes = pd.DataFrame(rows)
    headline = robustness.headline_survival(episodes).set_index("controller")
    assert headline.loc["a+x", "mujoco"] == fraction_cell(3, 3) + ", 1 not judged"
    impulse = float(episodes["push_impulse_Ns"].iloc[0])
    assert headline.loc["a+x", "levels"] == f"0.3 m/s ({impulse:.1f} N s)"


def _walking_push(level: float, direction: str, replica: int, status: str) -> dict:
    """A walking push of "a+x" in MuJoCo, 0.2 into the swing, survived when `status` is ok."""
    return _row(
        controller="a+x",
        sim="mujoco",
        scenario="walk_push",
        push_phase="walking",
        push_dv_mps=level,
        push_direction_name=direction,
        push_swing_fraction=0.2,
        replica=replica,
        status=status,
        survived=status == "ok",
    )


def test_the_direction_table_counts_pushes_not_replicas():
    """One inward push at three levels with 5 replicas each (4, 5 and 2 survived): per level
    1/1, 1/1, 0/1 pushes (4 of 5 replicas make a push survived), not "11/15" pooled with an
    interval as if the replicas were independent trials."""
    rows = []
    for level, k in zip(LEVELS, (4, 5, 2), strict=True):
        for replica in range(5):
            for name in ("inward", "outward"):
                alive = replica < k if name == "inward" else True
                rows.append(_walking_push(level, name, replica, "ok" if alive else "fell"))
    table = robustness.direction_table(pd.DataFrame(rows)).set_index("direction")
    assert list(table.loc["inward", ["dv 0.2 m/s", "dv 0.3 m/s", "dv 0.4 m/s"]]) == [
        "1/1",
        "1/1",
        "0/1",
    ]
    assert list(table.loc["outward", ["dv 0.2 m/s", "dv 0.3 m/s", "dv 0.4 m/s"]]) == ["1/1"] * 3


def test_a_push_whose_last_replica_was_not_judged_is_left_out_of_the_direction_table():
    """Replicas 0-2 and 4 survived, replica 3 fell: 4 of 5, survived (1/1). With replica 4 a
    timeout instead (not judged), the push has 4 judged replicas of 5 and is left out; it is
    not judged on 3 of 4, nor on the 4 left "of 4" when the missing one is the last; its
    row says so ("left out": 1), where it vanished from the table until 2026-12-03."""

    def push(status_of):
        rows = []
        for replica in range(5):
            status = status_of(replica)
            for name in ("inward", "outward"):
                rows.append(_walking_push(0.3, name, replica, status if name == "inward" else "ok"))
        return robustness.direction_table(pd.DataFrame(rows)).set_index("direction")

    complete = push(lambda r: "fell" if r == 3 else "ok")
    assert complete.loc["inward", "dv 0.3 m/s"] == "1/1"
    for missing in (3, 4):
        table = push(lambda r, m=missing: "timeout" if r == m else "ok")
        assert table.loc["inward", "dv 0.3 m/s"] == ""  # its only push: not counted ...
        assert table.loc["inward", "left out"] == 1  # ... and said to be left out
        assert table.loc["outward", "dv 0.3 m/s"] == "1/1"
        assert table.loc["outward", "left out"] == ""


def test_robustness_walks_of_one_episode_are_counts_without_a_rate():
    """A robustness walk is one episode per magnitude: its cell is "0/1", with no interval and
    no "half at" (a fall is a finding, not a rate)."""
    rows = [
        _row(controller="a+x", sim="mujoco", scenario="walk", status="ok", survived=None),
        _row(
            controller="a+x",
            sim="mujoco",
            scenario="walk",
            status="fell",
            survived=None,
            perturbation="slope_deg=-4",
            slope_deg=-4.0,
        ),
    ]
    table = robustness.degradation_table(pd.DataFrame(rows)).set_index("magnitude")
    assert list(table["survival"]) == ["0/1", "1/1"]
    assert table["low"].isna().all()
    assert table["high"].isna().all()
    half = robustness.half_survival_table(robustness.degradation_table(pd.DataFrame(rows)))
    assert list(half["half at"]) == ["n < 10"]


def test_the_degradation_table_counts_what_it_does_not_judge():
    """Of 10 perturbed pushes, one ended in a simulator error: 9 judged, 1 not judged; one
    more ended in a planner error, judged and not survived."""
    rows = []
    for index in range(10):
        rows.append(_push("a+x", "mujoco", 0.3, index, True, push_time_s=1.5))
        status, stage = ("error", "sim") if index == 0 else ("ok", None)
        if index == 1:
            status, stage = "error", "planner"
        row = _push(
            "a+x",
            "mujoco",
            0.3,
            index,
            status == "ok",
            push_time_s=1.5,
            perturbation="payload_kg=10",
            payload_kg=10.0,
        )
        row.update(status=status, error_stage=stage, duration=3.0)
        rows.append(row)
    table = robustness.degradation_table(pd.DataFrame(rows)).set_index("magnitude")
    assert table.loc[10.0, "episodes"] == 9
    assert table.loc[10.0, "not_judged"] == 1
    assert table.loc[10.0, "survived"] == 8


def test_the_degradation_table_says_how_many_fell_before_their_push():
    """A payload that fells the robot at 0.8 s, before its 1.5 s push, in 10 of 10 episodes:
    not survived (not standing is part of the degradation), and counted under before_push."""
    rows = []
    for index in range(10):
        rows.append(_push("a+x", "mujoco", 0.3, index, True, push_time_s=1.5))
        rows.append(
            _push(
                "a+x",
                "mujoco",
                0.3,
                index,
                False,
                push_time_s=1.5,
                fall_time=0.8,
                perturbation="payload_kg=10",
                payload_kg=10.0,
            )
        )
    table = robustness.degradation_table(pd.DataFrame(rows)).set_index("magnitude")
    assert (table.loc[10.0, "survived"], table.loc[10.0, "before_push"]) == (0, 10)
    assert (table.loc[0.0, "survived"], table.loc[0.0, "before_push"]) == (10, 0)


def test_a_controller_of_ours_is_tagged_in_the_report():
    """Our variants of Ficht & Behnke's method (not rows of the paper's Table 1) carry "(ours)"
    in every table; the paper's rows and the other methods keep their names."""
    from bench.controllers import OURS_CONTROLLERS
    from reports.build import label_estimators, label_ours

    assert "direct_centroidal/bent_no_inertia" in OURS_CONTROLLERS
    assert "direct_centroidal/no_inertia" not in OURS_CONTROLLERS  # Table 1's last row
    rows = pd.DataFrame(
        [
            _push("direct_centroidal/bent_no_inertia", "mujoco", 0.3, 0, True),
            _push("direct_centroidal/no_inertia", "mujoco", 0.3, 0, True),
            _push("direct_centroidal", "mujoco", 0.3, 0, True, estimator="five_mass_kalman"),
            _push(
                "direct_centroidal/lagged_inertia",
                "mujoco",
                0.3,
                0,
                True,
                estimator="five_mass_kalman",
            ),
        ]
    )
    assert list(label_estimators(label_ours(rows))["controller"]) == [
        "direct_centroidal/bent_no_inertia (ours)",
        "direct_centroidal/no_inertia",
        "direct_centroidal [five_mass_kalman]",
        "direct_centroidal/lagged_inertia (ours) [five_mass_kalman]",
    ]


def test_a_controller_refused_the_pushes_is_under_not_run_and_in_no_push_table():
    """An "n/a" row is never run: until 2026-12-03 a refused controller's pushes read
    "10 not judged" in section 1 and Table 2 and "incomplete 10" in the thresholds, and the
    reason was nowhere in the report."""
    reason = "hold+posture cannot run with the estimator x: it reads tilt"
    refused = []
    for index in range(10):
        for replica in range(5):
            row = _push("hold+posture", "mujoco", 0.3, index, False, replica=replica)
            row.update(status="n/a", fell=None, survived=None, error=f"n/a: {reason}")
            refused.append(row)
    ran = [_push("a+x", "mujoco", 0.3, index, index < 7, replica=r)
           for index in range(10) for r in range(5)]  # fmt: skip
    episodes = pd.DataFrame(ran + refused)
    headline = robustness.headline_survival(episodes)
    assert list(headline["controller"]) == ["a+x"]
    assert headline.loc[0, "mujoco"] == fraction_cell(7, 10)  # nothing "not judged" in it
    assert list(tables.survival_table(episodes)["controller"]) == ["a+x"]
    thresholds = robustness.robust_threshold_table(episodes)
    assert list(thresholds["controller"]) == ["a+x"]
    assert list(thresholds["incomplete"]) == [0]
    not_run = tables.refusal_table(episodes)
    assert not_run.to_dict("records") == [
        {
            "controller": "hold+posture",
            "reason": reason,
            "scenarios": "stand_push",
            "sims": "mujoco",
            "episodes": 50,
        }
    ]
    assert tables.refusal_table(pd.DataFrame(ran)).empty
