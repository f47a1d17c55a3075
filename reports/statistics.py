"""How sure a number is: intervals on survival fractions, robust push thresholds from replicas,
paired comparisons between controllers on the same pushes, and the band between simulators.

- `wilson_interval`: the 95 % Wilson score interval of k successes out of n (Wilson 1927;
  scipy's `binomtest(...).proportion_ci(method="wilson")`), which, unlike the normal
  approximation, stays inside [0, 1] and is informative at k = 0 and k = n (20/20 pushes
  survived is 0.84-1.00, not "100 %").
- `robust_threshold`: the largest push level survived in at least `required` of the replicas
  at that level and at every level below it (DESIGN.md, reference figures: "a push threshold
  from one trial per magnitude misleads; replicate each magnitude"; 4 of 5 by default).
- `paired_test`: two controllers pushed with the same pushes (same level, direction, replica):
  the pushes one survives and the other does not, and the exact two-sided McNemar test on them
  (a binomial test of the discordant pairs at p = 1/2: under the null hypothesis that both
  controllers survive equally, each discordant push is equally likely to go either way).
- `simulator_band`: a number measured in both simulators as its range [low, high] (the two
  point estimates, not an interval), which the report shows in its headline §1 (push
  survival) and §5 (where the simulators disagree), not on the cost or the speed tables.
- `median_interval`: the distribution-free 95 % interval of a median from its sample's order
  statistics (scipy's `quantile_test(...).confidence_interval()`: the interval between the
  order statistics that the binomial distribution of the count below the median brackets
  with at least 95 %), for numbers such as per-period times that are not normal and vary
  with the machine's load.
"""

from __future__ import annotations

import math
from collections.abc import Iterable, Mapping, Sequence

import numpy as np
import pandas as pd
from scipy import stats

CONFIDENCE = 0.95
ROBUST_REQUIRED = 4  # replicas survived at a level ...
ROBUST_REPLICAS = 5  # ... out of this many (DESIGN.md)


def robust_required(replicas: int) -> int:
    """How many of `replicas` replicas a level must survive for the robust threshold: DESIGN's
    4 of 5, and for another count the same fraction rounded up (8 of 10, 3 of 3, 1 of 1)."""
    if replicas < 1:
        raise ValueError(f"replicas must be at least 1, got {replicas}")
    return math.ceil(ROBUST_REQUIRED * replicas / ROBUST_REPLICAS - 1e-9)


def wilson_interval(
    survived: int, trials: int, confidence: float = CONFIDENCE
) -> tuple[float, float]:
    """The Wilson score interval (low, high) of the fraction `survived` / `trials`; (nan, nan)
    without trials. Counts must be whole numbers (ValueError otherwise)."""
    if survived != int(survived) or trials != int(trials):
        raise ValueError(f"counts must be whole numbers, got {survived} of {trials}")
    if trials <= 0:
        return (math.nan, math.nan)
    if not 0 <= survived <= trials:
        raise ValueError(f"survived must be in [0, {trials}], got {survived}")
    interval = stats.binomtest(int(survived), int(trials)).proportion_ci(
        confidence_level=confidence, method="wilson"
    )
    return (float(interval.low), float(interval.high))


def robust_threshold(
    survived_by_level: Mapping[float, Sequence[bool]],
    required: int = ROBUST_REQUIRED,
    replicas: int = ROBUST_REPLICAS,
) -> float | None:
    """The largest level (a velocity change [m/s], an impulse...) such that at it and at every
    lower level at least `required` of the replicas survived; None when the lowest level is
    not survived so. Every level must have exactly `replicas` judged trials (a level with
    fewer cannot say "4 of 5": ValueError naming it)."""
    threshold = None
    for level in sorted(survived_by_level):
        outcomes = list(survived_by_level[level])
        if len(outcomes) != replicas:
            raise ValueError(
                f"level {level:g} has {len(outcomes)} judged replicas; the robust threshold "
                f"takes {required} of {replicas}"
            )
        if sum(bool(x) for x in outcomes) < required:
            break
        threshold = level
    return threshold


def paired_test(survived_a: Iterable[bool], survived_b: Iterable[bool]) -> dict[str, float | int]:
    """The exact McNemar test of two controllers on the same pushes (element k of each is the
    same push): `only_a` (pushes A survived and B did not), `only_b`, `both`, `neither`, and
    the two-sided p-value of `only_a` out of `only_a + only_b` discordant pushes at p = 1/2
    (1.0 without discordant pushes)."""
    a = np.asarray(list(survived_a), dtype=bool)
    b = np.asarray(list(survived_b), dtype=bool)
    if a.shape != b.shape:
        raise ValueError(f"paired outcomes differ in length: {a.size} and {b.size}")
    only_a, only_b = int(np.sum(a & ~b)), int(np.sum(~a & b))
    discordant = only_a + only_b
    p_value = 1.0 if discordant == 0 else float(stats.binomtest(only_a, discordant).pvalue)
    return {
        "only_a": only_a,
        "only_b": only_b,
        "both": int(np.sum(a & b)),
        "neither": int(np.sum(~a & ~b)),
        "p_value": p_value,
    }


def simulator_band(values: Mapping[str, float]) -> tuple[float, float]:
    """(low, high) of one number measured in several simulators (finite values only; nan, nan
    when none is)."""
    finite = [float(v) for v in values.values() if v is not None and math.isfinite(float(v))]
    if not finite:
        return (math.nan, math.nan)
    return (min(finite), max(finite))


def median_interval(values: Iterable[float], confidence: float = CONFIDENCE) -> tuple[float, float]:
    """The distribution-free `confidence` interval (low, high) of the median of `values`
    (finite values only): two of the sample's order statistics (scipy's `quantile_test` at
    p = 1/2). (nan, nan) with fewer than 6 values, which cannot bracket a median with 95 %
    (2 / 2^5 = 6.25 % of samples have every value on one side of it)."""
    sample = np.asarray([float(v) for v in values], dtype=float)
    sample = sample[np.isfinite(sample)]
    if sample.size == 0:
        return (math.nan, math.nan)
    test = stats.quantile_test(sample, q=float(np.median(sample)), p=0.5)
    interval = test.confidence_interval(confidence_level=confidence)
    return (float(interval.low), float(interval.high))


MIN_RATE_TRIALS = 10
"""Below this many episodes a cell states its count, not a rate: no interval and no "half at"
(a robustness walk is one episode per magnitude: a fall is a finding, not a rate)."""


def _percent_bound(bound: float, upper: bool) -> str:
    """A Wilson bound [0, 1] in percent: to the nearest whole percent, but within 1 % of 0 or
    100 (and not 0 or 100 itself) to a tenth, rounded outward, so that only k = 0 prints a
    0 and only k = n prints 100 (99 of 100 is 95-99.9 %, not 95-100 %)."""
    percent = 100.0 * bound
    if 0.0 < percent < 1.0 or 99.0 < percent < 100.0:
        tenths = math.ceil(10.0 * percent) if upper else math.floor(10.0 * percent)
        return f"{min(max(tenths, 1), 999) / 10:.1f}"
    return f"{percent:.0f}"


def fraction_cell(survived: int, trials: int) -> str:
    """ "k/n (low-high %)" with the 95 % Wilson interval in whole percent, rounded to the
    nearest (so a printed bound may lie up to half a percent inside the computed one), but to
    a tenth near 0 and 100 % (`_percent_bound`); "0/0" without trials."""
    if trials <= 0:
        return "0/0"
    low, high = wilson_interval(survived, trials)
    return (
        f"{survived}/{trials} ({_percent_bound(low, upper=False)}-"
        f"{_percent_bound(high, upper=True)} %)"
    )


def count_cell(survived: int, trials: int) -> str:
    """`fraction_cell` from MIN_RATE_TRIALS trials on, else the bare count "k/n"."""
    if trials < MIN_RATE_TRIALS:
        return f"{survived}/{trials}"
    return fraction_cell(survived, trials)


def paired_table(
    outcomes: pd.DataFrame, pair_keys: Sequence[str], by: Sequence[str] = ("sim",)
) -> pd.DataFrame:
    """Every pair of controllers, per group of `by`, on the pushes both were judged on:
    `outcomes` has columns controller, survived (bool), the `by` columns and the `pair_keys`
    that identify one push (phase, level, direction, replica...). Columns: the `by` columns,
    controller A, controller B, pushes (paired), only A, only B, p (exact McNemar). A pair
    without a push in common (two robots' controllers, whose pushes differ) is no comparison
    and has no row."""
    rows = []
    for group_key, group in outcomes.groupby(list(by), sort=True):
        group_key = group_key if isinstance(group_key, tuple) else (group_key,)
        wide = group.pivot_table(
            index=list(pair_keys), columns="controller", values="survived", aggfunc="first"
        )
        controllers = sorted(wide.columns)
        for i, first in enumerate(controllers):
            for second in controllers[i + 1 :]:
                both = wide[[first, second]].dropna()
                if both.empty:
                    continue
                test = paired_test(both[first].astype(bool), both[second].astype(bool))
                rows.append(
                    {
                        **dict(zip(by, group_key, strict=True)),
                        "controller A": first,
                        "controller B": second,
                        "pushes": len(both),
                        "only A": test["only_a"],
                        "only B": test["only_b"],
                        "p": test["p_value"],
                    }
                )
    columns = [*by, "controller A", "controller B", "pushes", "only A", "only B", "p"]
    return pd.DataFrame(rows, columns=columns)
