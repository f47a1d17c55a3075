"""The report's robustness tables (issue 21), from a sweep's episode rows: which episodes are the
nominal protocol, how survival and tracking degrade along each robustness dimension, robust
push thresholds from replicas, paired comparisons between controllers, survival by push timing
and direction, and every headline survival number with its interval and simulator band.

Column meanings follow `bench.dataset.ROW_SCHEMA`: `perturbation` is "nominal" or
"dimension=magnitude" (null in result files written before robustness existed: nominal);
`replica` 0 (or null) is the protocol's own push, > 0 a replica of it.
"""

from __future__ import annotations

import math

import numpy as np
import pandas as pd

from reports.statistics import (
    fraction_cell,
    paired_table,
    robust_threshold,
    simulator_band,
    wilson_interval,
)

KEYS = ["controller", "sim"]
JUDGED = ("ok", "fell")


def perturbation_labels(episodes: pd.DataFrame) -> pd.Series:
    """Each row's perturbation label ("nominal" for the rows of older files)."""
    if "perturbation" not in episodes:
        return pd.Series("nominal", index=episodes.index)
    return episodes["perturbation"].fillna("nominal")


def nominal(episodes: pd.DataFrame) -> pd.DataFrame:
    """The nominal episodes: no perturbation, replica 0 (the protocol's own)."""
    mask = perturbation_labels(episodes) == "nominal"
    if "replica" in episodes:
        mask &= episodes["replica"].fillna(0) == 0
    return episodes[mask]


def protocol_pushes(episodes: pd.DataFrame, phase: str) -> pd.DataFrame:
    """The pushes of the Ficht & Behnke protocol in `phase`: nominal, replica 0, random
    directions, in the middle of the swing (walking)."""
    rows = nominal(episodes)
    rows = rows[rows["push_phase"] == phase]
    if "push_direction_name" in rows:
        rows = rows[rows["push_direction_name"].isna()]
    if "push_swing_fraction" in rows:
        fraction = rows["push_swing_fraction"]
        rows = rows[fraction.isna() | (fraction == 0.5)]
    return rows


def _survived(rows: pd.DataFrame) -> pd.Series:
    """Whether each judged row survived: a push its `survived`, a plain episode no fall."""
    pushed = rows["push_phase"].notna()
    plain = rows["status"] == "ok"
    return np.where(pushed, rows["survived"].fillna(False).astype(bool), plain)


def protocol_of(rows: pd.DataFrame) -> pd.Series:
    """What an episode measures: "standing push", "walking push", or its scenario."""
    return (
        rows["push_phase"].map(lambda p: f"{p} push", na_action="ignore").fillna(rows["scenario"])
    )


def degradation_table(episodes: pd.DataFrame) -> pd.DataFrame:
    """Per controller x simulator x protocol x dimension x magnitude (the nominal episodes as
    magnitude 0 or 1, whichever the dimension leaves unchanged, of every dimension): survival
    k/n with its 95 % Wilson interval (rate, low, high) over the judged episodes and the
    median CoM tracking error [mm]. Empty without robustness episodes."""
    labels = perturbation_labels(episodes)
    if (labels == "nominal").all():
        return pd.DataFrame()
    rows = episodes[episodes["status"].isin(JUDGED)].copy()
    if "replica" in rows:
        rows = rows[rows["replica"].fillna(0) == 0]
    if "push_direction_name" in rows:
        rows = rows[rows["push_direction_name"].isna()]
    rows["label"] = perturbation_labels(rows)
    rows["protocol"] = protocol_of(rows)
    rows["alive"] = _survived(rows)
    single = rows["label"].str.fullmatch(r"[a-z_]+=[-0-9.e+]+")
    perturbed = rows[single].copy()
    perturbed[["dimension", "magnitude"]] = perturbed["label"].str.split("=", expand=True)
    perturbed["magnitude"] = perturbed["magnitude"].astype(float)
    baseline = rows[rows["label"] == "nominal"]
    parts = [perturbed]
    keys = [*KEYS, "protocol"]
    for dimension, tested in perturbed.groupby("dimension", sort=True):
        # the nominal point of the curves that this dimension was tested on
        which = tested[keys].drop_duplicates()
        points = baseline.merge(which, on=keys)
        parts.append(points.assign(dimension=dimension, magnitude=NOMINAL_MAGNITUDE[dimension]))
    table = pd.concat(parts, ignore_index=True)
    grouped = table.groupby([*KEYS, "protocol", "dimension", "magnitude"], sort=True)
    result = grouped.agg(
        survived=("alive", "sum"),
        episodes=("alive", "size"),
        com_rms_mm=("com_error_rms_m", lambda s: 1e3 * s.median()),
    ).reset_index()
    intervals = [
        wilson_interval(int(k), int(n))
        for k, n in zip(result["survived"], result["episodes"], strict=True)
    ]
    result["rate"] = result["survived"] / result["episodes"]
    result["low"] = [low for low, _ in intervals]
    result["high"] = [high for _, high in intervals]
    result["survival"] = [
        fraction_cell(int(k), int(n))
        for k, n in zip(result["survived"], result["episodes"], strict=True)
    ]
    return result


NOMINAL_MAGNITUDE = {
    "noise": 0.0,
    "noise_encoders": 0.0,
    "noise_imu": 0.0,
    "noise_ft": 0.0,
    "noise_bias": 0.0,
    "delay": 0.0,
    "command_delay": 0.0,
    "sensor_delay": 0.0,
    "payload_kg": 0.0,
    "com_offset_m": 0.0,
    "mass_error": 0.0,
    "torque_scale": 1.0,
    "gain_scale": 1.0,
    "ground_height_m": 0.0,
    "slope_deg": 0.0,
}
"""Each dimension's nominal magnitude (`robots.perturbation.Perturbation`'s defaults)."""


def half_survival_table(degradation: pd.DataFrame) -> pd.DataFrame:
    """Per controller x simulator x protocol x dimension: the nominal survival rate and the
    first magnitude (moving away from the nominal one) at which the rate is at most half of
    it ("beyond" the largest tested when none is; "-" when the nominal rate is 0)."""
    rows = []
    if degradation.empty:
        return pd.DataFrame(columns=[*KEYS, "protocol", "dimension", "nominal", "half at"])
    groups = degradation.groupby([*KEYS, "protocol", "dimension"], sort=True)
    for (controller, sim, protocol, dimension), group in groups:
        base = NOMINAL_MAGNITUDE[dimension]
        start = group[group["magnitude"] == base]
        if start.empty:
            continue
        rate = float(start["rate"].iloc[0])
        order = group.assign(distance=(group["magnitude"] - base).abs()).sort_values("distance")
        order = order[order["magnitude"] != base]
        if order.empty:
            continue
        if rate == 0:
            half = "-"
        else:
            lost = order[order["rate"] <= rate / 2]
            tested = order["magnitude"].abs().max() if len(order) else base
            half = f"{lost['magnitude'].iloc[0]:g}" if len(lost) else f"beyond {tested:g}"
        rows.append(
            {
                "controller": controller,
                "sim": sim,
                "protocol": protocol,
                "dimension": dimension,
                "nominal": fraction_cell(
                    int(start["survived"].iloc[0]), int(start["episodes"].iloc[0])
                ),
                "half at": half,
            }
        )
    return pd.DataFrame(rows)


def robust_threshold_table(episodes: pd.DataFrame) -> pd.DataFrame:
    """Per controller x simulator x phase x push (a random direction by its index, or a
    support-relative direction at a swing fraction), with replicas: the robust threshold
    (`reports.statistics.robust_threshold`: the largest dv [m/s] survived in 4 of 5 replicas
    at it and every level below), summarised per controller x simulator x phase x direction
    kind as median, min and max over the pushes. Empty without 5 judged replicas per push."""
    rows = episodes[
        (perturbation_labels(episodes) == "nominal")
        & episodes["push_phase"].notna()
        & episodes["status"].isin(JUDGED)
    ]
    if "replica" not in rows or rows["replica"].fillna(0).max() < 1:
        return pd.DataFrame()
    rows = rows.assign(
        direction=(
            rows["push_direction_name"].fillna("random")
            if "push_direction_name" in rows
            else "random"
        ),
        fraction=rows["push_swing_fraction"].fillna(0.5) if "push_swing_fraction" in rows else 0.5,
        push=rows["push_index"].fillna(-1),
        alive=rows["survived"].fillna(False).astype(bool),
    )
    result = []
    keys = [*KEYS, "push_phase", "direction", "fraction"]
    for key, group in rows.groupby(keys, sort=True):
        thresholds, incomplete = [], 0
        for _, push in group.groupby("push"):
            levels = {dv: list(g["alive"]) for dv, g in push.groupby("push_dv_mps")}
            if any(len(v) != 5 for v in levels.values()):
                incomplete += 1
                continue
            value = robust_threshold(levels)
            thresholds.append(0.0 if value is None else value)
        if not thresholds:
            continue
        values = np.array(thresholds)
        result.append(
            {
                **dict(zip(keys, key, strict=True)),
                "pushes": len(values),
                "median dv m/s": float(np.median(values)),
                "min dv m/s": float(values.min()),
                "max dv m/s": float(values.max()),
                "incomplete": incomplete,
            }
        )
    return pd.DataFrame(result)


def paired_comparisons(episodes: pd.DataFrame, phase: str) -> pd.DataFrame:
    """Every pair of controllers per simulator on the protocol pushes of `phase` both were
    judged on (same level, direction and replica): the pushes one survived and the other did
    not, and the exact McNemar p-value (`reports.statistics.paired_table`), most significant
    first."""
    rows = protocol_pushes(episodes, phase)
    rows = rows[rows["status"].isin(JUDGED)]
    if rows["controller"].nunique() < 2:
        return pd.DataFrame()
    outcomes = rows.assign(
        survived=rows["survived"].fillna(False).astype(bool),
        push=rows["push_index"].fillna(-1),
    )
    keys = ["push_dv_mps", "push"]
    if "robot" in outcomes and outcomes["robot"].nunique() > 1:
        keys.append("robot")
    table = paired_table(outcomes, pair_keys=keys, by=("sim",))
    return table.sort_values(["p", "sim"], kind="stable").reset_index(drop=True)


def headline_survival(episodes: pd.DataFrame) -> pd.DataFrame:
    """Per controller x push phase: the protocol pushes survived over all levels in each
    simulator, k/n with the 95 % Wilson interval, and the band between the simulators' rates
    [%] (low-high)."""
    result = []
    for phase in ("standing", "walking"):
        rows = protocol_pushes(episodes, phase)
        rows = rows[rows["status"].isin(JUDGED)]
        for controller, group in rows.groupby("controller", sort=True):
            row = {"controller": controller, "phase": phase}
            rates = {}
            for sim, runs in group.groupby("sim", sort=True):
                alive = runs["survived"].fillna(False).astype(bool)
                row[sim] = fraction_cell(int(alive.sum()), len(alive))
                rates[sim] = float(alive.mean()) if len(alive) else math.nan
            low, high = simulator_band(rates)
            row["band %"] = "" if math.isnan(low) else f"{100 * low:.0f}-{100 * high:.0f}"
            result.append(row)
    return pd.DataFrame(result)


def direction_table(episodes: pd.DataFrame) -> pd.DataFrame:
    """Walking pushes by timing and direction: per controller x simulator x swing fraction x
    direction (support-relative, or "random" for the uniform ones), survival over the levels
    and replicas as k/n with its 95 % Wilson interval. Empty without support-relative
    pushes or several swing fractions."""
    rows = episodes[perturbation_labels(episodes) == "nominal"]  # every replica
    rows = rows[(rows["push_phase"] == "walking") & rows["status"].isin(JUDGED)]
    if rows.empty or "push_direction_name" not in rows:
        return pd.DataFrame()
    rows = rows.assign(
        direction=rows["push_direction_name"].fillna("random"),
        fraction=rows["push_swing_fraction"].fillna(0.5),
        alive=rows["survived"].fillna(False).astype(bool),
    )
    if rows["direction"].eq("random").all() and rows["fraction"].nunique() == 1:
        return pd.DataFrame()
    table = (
        rows.groupby([*KEYS, "fraction", "direction"], sort=True)["alive"]
        .agg(["sum", "size"])
        .reset_index()
    )
    table["survival"] = [
        fraction_cell(int(k), int(n)) for k, n in zip(table["sum"], table["size"], strict=True)
    ]
    return table.drop(columns=["sum", "size"]).rename(columns={"fraction": "swing fraction"})


REPLAY_FOLDER = "replays"  # in the report's folder: <episode_id>.html (`centrobench replay`)


def replay_choices(episodes: pd.DataFrame) -> pd.DataFrame:
    """The episodes the report offers replays of: per controller, one nominal walk (MuJoCo's
    when there is one) and its first fall (the nominal episode that fell at the lowest push
    level, then the lowest push index, MuJoCo first; a plain scenario's fall counts before
    any push). Columns: controller, what, sim, episode_id, and the result directory when the
    report reads several."""
    rows = nominal(episodes)
    result = []
    for controller, group in rows.groupby("controller", sort=True):
        walks = group[(group["scenario"] == "walk") & group["push_phase"].isna()]
        walks = walks.sort_values(["sim", "episode_id"])
        if len(walks):
            result.append({"controller": controller, "what": "walk", **_choice(walks.iloc[0])})
        falls = group[group["status"] == "fell"]
        falls = falls.assign(
            level=falls["push_dv_mps"].fillna(-1.0), index=falls["push_index"].fillna(-1)
        )
        falls = falls.sort_values(["level", "index", "sim", "episode_id"])
        if len(falls):
            first = falls.iloc[0]
            what = (
                f"first fall ({first['scenario']}"
                + (
                    f", dv {first['push_dv_mps']:g} m/s"
                    if first["push_dv_mps"] == first["push_dv_mps"]
                    else ""
                )
                + ")"
            )
            result.append({"controller": controller, "what": what, **_choice(first)})
    return pd.DataFrame(result, columns=["controller", "what", "sim", "episode_id", "results_dir"])


def _choice(row: pd.Series) -> dict:
    return {
        "sim": row["sim"],
        "episode_id": row["episode_id"],
        "results_dir": row.get("results_dir"),
    }
