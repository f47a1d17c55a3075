"""The report's statistics against values computed by hand (and scipy's exact test)."""

from __future__ import annotations

import math

import numpy as np
import pandas as pd
import pytest
from scipy import stats

from reports.statistics import (
    fraction_cell,
    paired_table,
    paired_test,
    robust_required,
    robust_threshold,
    simulator_band,
    wilson_interval,
)

Z = 1.959963984540054  # the 97.5 % normal quantile


@pytest.mark.parametrize(
    ("survived", "trials", "low", "high"),
    [
        # p = 0.7, z^2 = 3.8415: centre (0.7 + 0.09604) / 1.19207 = 0.66777, half-width
        # 1.95996 sqrt(0.0105 + 0.0024009) / 1.19207 = 0.18675
        (14, 20, 0.48102718, 0.85452276),
        (20, 20, 20 / (20 + Z**2), 1.0),  # k = n: low = n / (n + z^2)
        (0, 20, 0.0, Z**2 / (20 + Z**2)),  # k = 0: high = z^2 / (n + z^2)
        (3, 5, 0.23072428, 0.88237923),
    ],
)
def test_wilson_interval_equals_the_hand_computed_one(survived, trials, low, high):
    assert wilson_interval(survived, trials) == pytest.approx((low, high), abs=5e-9)


def test_wilson_interval_without_trials_is_nan_and_bad_counts_are_refused():
    assert all(math.isnan(x) for x in wilson_interval(0, 0))
    with pytest.raises(ValueError, match="survived must be in"):
        wilson_interval(21, 20)
    with pytest.raises(ValueError, match="whole numbers"):
        wilson_interval(2.7, 10)  # not truncated to 2


@pytest.mark.parametrize(("replicas", "required"), [(5, 4), (10, 8), (3, 3), (2, 2), (1, 1)])
def test_the_robust_share_is_4_of_5_for_any_replica_count(replicas, required):
    assert robust_required(replicas) == required


def test_fraction_cell_shows_the_interval_in_percent():
    assert fraction_cell(14, 20) == "14/20 (48-85 %)"
    assert fraction_cell(20, 20) == "20/20 (84-100 %)"
    assert fraction_cell(0, 0) == "0/0"


def _wilson_closed_form(k: int, n: int, z: float = 1.959963984540054) -> tuple[float, float]:
    """Wilson 1927: (p + z^2 / 2n -+ z sqrt(p (1 - p) / n + z^2 / 4n^2)) / (1 + z^2 / n)."""
    p = k / n
    centre, spread = p + z * z / (2 * n), z * math.sqrt(p * (1 - p) / n + z * z / (4 * n * n))
    return (centre - spread) / (1 + z * z / n), (centre + spread) / (1 + z * z / n)


def test_near_0_and_100_percent_a_bound_is_printed_to_a_tenth_rounded_outward():
    """99 of 100 survived: the upper bound is 99.82 %, printed 99.9 (not "100", which only k = n
    may show); 1 of 20: the lower bound 0.89 % is printed 0.8 (not "0", only k = 0's)."""
    low, high = _wilson_closed_form(99, 100)
    assert 99.8 < 100 * high < 99.9
    assert round(100 * low) == 95
    assert fraction_cell(99, 100) == "99/100 (95-99.9 %)"
    low, high = _wilson_closed_form(1, 20)
    assert 0.8 < 100 * low < 0.9
    assert round(100 * high) == 24
    assert fraction_cell(1, 20) == "1/20 (0.8-24 %)"


def test_below_ten_trials_a_cell_is_a_count_without_a_rate():
    from reports.statistics import MIN_RATE_TRIALS, count_cell

    assert MIN_RATE_TRIALS == 10
    assert count_cell(1, 1) == "1/1"
    assert count_cell(0, 9) == "0/9"
    assert count_cell(6, 10) == fraction_cell(6, 10)


def test_robust_threshold_is_the_last_level_before_the_first_with_fewer_than_4_of_5():
    T, F = True, False
    levels = {
        0.2: [T, T, T, T, T],
        0.3: [T, T, T, T, F],  # 4 of 5: still robust
        0.4: [T, T, F, F, T],  # 3 of 5: the threshold stops below
        0.5: [T, T, T, T, T],  # survived again, but above a failed level
    }
    assert robust_threshold(levels) == 0.3
    assert robust_threshold({0.2: [T, F, F, T, T], 0.3: [T] * 5}) is None
    assert robust_threshold({0.2: [T] * 5, 0.3: [T] * 5}) == 0.3
    with pytest.raises(ValueError, match=r"level 0\.3 has 4 judged replicas"):
        robust_threshold({0.2: [T] * 5, 0.3: [T] * 4})


def test_paired_test_counts_the_discordant_pushes_and_equals_scipys_exact_test():
    a = [True] * 9 + [False] * 3
    b = [True, True] + [False] * 7 + [True, False, False]
    result = paired_test(a, b)
    assert (result["only_a"], result["only_b"], result["both"], result["neither"]) == (7, 1, 2, 2)
    # by hand: 2 (C(8,7) + C(8,8)) / 2^8 = 18 / 256
    assert result["p_value"] == pytest.approx(18 / 256, rel=1e-12)
    assert result["p_value"] == pytest.approx(stats.binomtest(7, 8, 0.5).pvalue, rel=1e-12)
    assert paired_test([True, False], [True, False])["p_value"] == 1.0
    with pytest.raises(ValueError, match="differ in length"):
        paired_test([True], [True, False])


def test_paired_table_pairs_only_the_pushes_both_controllers_were_judged_on():
    rows = []
    for push in range(6):
        rows.append({"sim": "mujoco", "controller": "a", "push": push, "survived": True})
        if push < 5:  # b has no judged episode for push 5
            rows.append({"sim": "mujoco", "controller": "b", "push": push, "survived": push < 2})
    table = paired_table(pd.DataFrame(rows), pair_keys=["push"])
    assert len(table) == 1
    row = table.iloc[0]
    assert (row["controller A"], row["controller B"], row["pushes"]) == ("a", "b", 5)
    assert (row["only A"], row["only B"]) == (3, 0)
    assert row["p"] == pytest.approx(2 / 8)  # 2 x (1/2)^3


def test_paired_table_leaves_out_pairs_without_a_push_in_common():
    """Two robots' controllers are pushed differently (their pushes' keys differ): pairing
    them compares nothing, so there is no row (the main job's report had 112 such rows, every
    one 0 pushes and p = 1, beside the 100 real ones)."""
    rows = []
    for push in range(4):
        for controller in ("a @ humanoid", "b @ humanoid"):
            rows.append({"sim": "mujoco", "controller": controller, "push": push, "survived": True})
        rows.append({"sim": "mujoco", "controller": "a @ jvrc1", "push": 10 + push, "survived": 0})
    table = paired_table(pd.DataFrame(rows), pair_keys=["push"])
    assert list(zip(table["controller A"], table["controller B"], strict=True)) == [
        ("a @ humanoid", "b @ humanoid")
    ]
    assert table.iloc[0]["pushes"] == 4


def test_simulator_band_spans_the_finite_values():
    assert simulator_band({"mujoco": 0.7, "pybullet": 0.55}) == (0.55, 0.7)
    assert simulator_band({"mujoco": 0.7, "pybullet": float("nan")}) == (0.7, 0.7)
    assert all(math.isnan(x) for x in simulator_band({"mujoco": None}))


def test_median_interval_is_the_binomial_order_statistics():
    """For n values the interval is (x_(k), x_(n+1-k)) with k the largest count for which
    P(Bin(n, 1/2) < k) <= 2.5 %: at n = 21, P(X <= 5) = 1.3 % and P(X <= 6) = 3.9 %, so the
    6th and the 16th of the sorted values."""
    from reports.statistics import median_interval

    n = 21
    assert stats.binom.cdf(5, n, 0.5) < 0.025 < stats.binom.cdf(6, n, 0.5)
    values = np.random.default_rng(3).permutation(np.arange(1.0, n + 1) * 10)  # unsorted
    assert median_interval(values) == (60.0, 160.0)
    assert median_interval([*values, math.nan]) == (60.0, 160.0)  # NaN left out


def test_median_interval_needs_six_values():
    """With 5 values the sample's extremes bracket the median with 1 - 2 / 32 = 93.75 %, less
    than 95 %: no interval; with 6, the extremes' 96.9 %."""
    from reports.statistics import median_interval

    assert all(math.isnan(v) for v in median_interval([1.0, 2.0, 3.0, 4.0, 5.0]))
    assert median_interval([6.0, 1.0, 2.0, 3.0, 4.0, 5.0]) == (1.0, 6.0)
    assert all(math.isnan(v) for v in median_interval([]))
