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
from scipy import stats

from reports.outcomes import ended_before_push, judged, judged_push, ran
from reports.statistics import (
    MIN_RATE_TRIALS,
    count_cell,
    fraction_cell,
    paired_table,
    robust_required,
    robust_threshold,
    simulator_band,
    wilson_interval,
)

KEYS = ["controller", "sim"]
EPISODE_KEYS = (
    "scenario",
    "speed",
    "push_phase",
    "push_dv_mps",
    "push_index",
    "push_direction_deg",
    "push_swing_fraction",
    "push_direction_name",
    "seed",
    "scale",
    "friction",
    "robot",
)
"""What makes two controllers' (or a perturbed and a nominal) episodes the same test: the
scenario and its push (level, index and world direction, timing), seed, scale, friction and
robot."""


def episode_key(rows: pd.DataFrame, without: tuple[str, ...] = ()) -> pd.Series:
    """One string per row from its `EPISODE_KEYS` (but `without`; missing columns and nulls
    count as empty), to group or pair on (null-safe, unlike pandas' own keys)."""
    names = [name for name in EPISODE_KEYS if name not in without and name in rows]
    if not names:
        return pd.Series("", index=rows.index)
    parts = rows[names].astype(object).where(rows[names].notna(), "")
    return parts.astype(str).agg("|".join, axis=1)


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
    directions, in the middle of the swing (walking); not the "n/a" rows, never run
    (`reports.outcomes.ran`)."""
    rows = nominal(ran(episodes))
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
    pushed = rows["push_phase"].map(lambda p: f"{p} push", na_action="ignore").astype(object)
    return pushed.where(pushed.notna(), rows["scenario"])


def degradation_table(episodes: pd.DataFrame) -> pd.DataFrame:
    """Per controller x simulator x protocol x dimension x magnitude (the nominal episodes as
    magnitude 0 or 1, whichever the dimension leaves unchanged, of every dimension): survival
    k/n over the judged episodes, with its 95 % Wilson interval (rate, low, high) from
    MIN_RATE_TRIALS episodes on (a count alone below: `count_cell`), and the median CoM
    tracking error [mm]. A pushed episode that fell before its push counts as not survived here
    (unlike the push tables: under a perturbation, not standing until the push is part of what
    the dimension degrades); `before_push` says how many of them there are. A controller's own
    failure is judged (not survived, `reports.outcomes`); a simulator's or worker's error or a
    timeout is not, and `not_judged` counts them; n/a rows are left out. Empty without
    robustness episodes."""
    labels = perturbation_labels(episodes)
    if (labels == "nominal").all():
        return pd.DataFrame()
    rows = ran(episodes).copy()
    rows["is_judged"] = judged(rows).to_numpy()
    if "replica" in rows:
        rows = rows[rows["replica"].fillna(0) == 0]
    if "push_direction_name" in rows:
        rows = rows[rows["push_direction_name"].isna()]
    rows["label"] = perturbation_labels(rows)
    rows["protocol"] = protocol_of(rows)
    rows["alive"] = _survived(rows) & rows["is_judged"]
    rows["early"] = ended_before_push(rows) & rows["is_judged"]
    rows["com_judged"] = rows["com_error_rms_m"].where(rows["is_judged"])
    single = rows["label"].str.fullmatch(r"[A-Za-z0-9_]+=[-0-9.e+]+")
    perturbed = rows[single].copy()
    perturbed[["dimension", "magnitude"]] = perturbed["label"].str.split("=", expand=True)
    perturbed["magnitude"] = perturbed["magnitude"].astype(float)
    baseline = rows[rows["label"] == "nominal"]
    baseline = baseline.assign(
        twin=baseline["controller"] + "|" + baseline["sim"] + "|" + episode_key(baseline)
    )
    parts = [perturbed]
    for dimension, tested in perturbed.groupby("dimension", sort=True):
        # the nominal point: the nominal twins of the episodes perturbed (same controller,
        # simulator, scenario and push, seed, scale, friction, robot), not every nominal
        # episode (a report over several sweeps has others)
        twins = set(tested["controller"] + "|" + tested["sim"] + "|" + episode_key(tested))
        points = baseline[baseline["twin"].isin(twins)].drop(columns="twin")
        parts.append(points.assign(dimension=dimension, magnitude=nominal_magnitude(dimension)))
    table = pd.concat(parts, ignore_index=True)
    grouped = table.groupby([*KEYS, "protocol", "dimension", "magnitude"], sort=True)
    result = grouped.agg(
        survived=("alive", "sum"),
        episodes=("is_judged", "sum"),
        not_judged=("is_judged", lambda judged_rows: int((~judged_rows).sum())),
        before_push=("early", "sum"),
        com_rms_mm=("com_judged", lambda s: 1e3 * s.median()),
    ).reset_index()
    result = result[result["episodes"] > 0].reset_index(drop=True)
    intervals = [
        wilson_interval(int(k), int(n)) if n >= MIN_RATE_TRIALS else (math.nan, math.nan)
        for k, n in zip(result["survived"], result["episodes"], strict=True)
    ]
    result["rate"] = result["survived"] / result["episodes"]
    result["low"] = [low for low, _ in intervals]
    result["high"] = [high for _, high in intervals]
    result["survival"] = [
        count_cell(int(k), int(n))
        for k, n in zip(result["survived"], result["episodes"], strict=True)
    ]
    return result


NOMINAL_MAGNITUDE = {"torque_scale": 1.0, "gain_scale": 1.0}
"""Each dimension's nominal magnitude (`robots.perturbation.Perturbation`'s defaults) where
it is not 0."""


def nominal_magnitude(dimension: str) -> float:
    """The magnitude of `dimension` that leaves an episode nominal: 1 for the scale factors,
    0 for every other (the noise channels in SI units too)."""
    return NOMINAL_MAGNITUDE.get(dimension, 0.0)


def half_survival_table(degradation: pd.DataFrame) -> pd.DataFrame:
    """Per controller x simulator x protocol x dimension: the nominal survival rate and the
    first magnitude (moving away from the nominal one) at which the rate is at most half of
    it ("beyond" the largest tested when none is; "-" when the nominal rate is 0; "n < 10"
    when a magnitude has fewer than MIN_RATE_TRIALS episodes, as a robustness walk's one)."""
    rows = []
    if degradation.empty:
        return pd.DataFrame(columns=[*KEYS, "protocol", "dimension", "nominal", "half at"])
    groups = degradation.groupby([*KEYS, "protocol", "dimension"], sort=True)
    for (controller, sim, protocol, dimension), group in groups:
        base = nominal_magnitude(dimension)
        start = group[group["magnitude"] == base]
        if start.empty:
            continue
        rate = float(start["rate"].iloc[0])
        order = group.assign(distance=(group["magnitude"] - base).abs()).sort_values("distance")
        order = order[order["magnitude"] != base]
        if order.empty:
            continue
        if min(group["episodes"]) < MIN_RATE_TRIALS:
            half = f"n < {MIN_RATE_TRIALS}"
        elif rate == 0:
            half = "-"
        else:
            lost = order[order["rate"] <= rate / 2]
            farthest = order["magnitude"].iloc[-1]  # the tested magnitude farthest out, signed
            half = f"{lost['magnitude'].iloc[0]:g}" if len(lost) else f"beyond {farthest:g}"
        rows.append(
            {
                "controller": controller,
                "sim": sim,
                "protocol": protocol,
                "dimension": dimension,
                "nominal": count_cell(
                    int(start["survived"].iloc[0]), int(start["episodes"].iloc[0])
                ),
                "half at": half,
            }
        )
    return pd.DataFrame(rows)


def robust_threshold_table(episodes: pd.DataFrame) -> pd.DataFrame:
    """Per controller x simulator x phase x push (a world direction, and for walking pushes a
    swing fraction, with its seed, scale, friction and robot) that has replicas: the robust
    threshold (`reports.statistics.robust_threshold`: the largest dv [m/s] survived by
    `robust_required(R)` of its R replicas, 4 of 5, at it and at every level below) over
    every level the push was run at, summarised per controller x simulator x phase x
    direction kind x swing fraction over the pushes that have one: the lower median (a
    level that was run; "< lowest" when a push does not survive its lowest level so; those
    pushes count, as below every level), min and max, as text. Pushes counted apart, with no
    threshold: `incomplete`, a level without R judged replicas (an error, a timeout, or a
    level run without its replicas); `before push`, a replica that fell, or whose controller
    failed, before its push came (`reports.outcomes.ended_before_push`: it says nothing of
    push recovery). Empty without replicas."""
    if "replica" not in episodes or episodes["replica"].fillna(0).max() < 1:
        return pd.DataFrame()
    episodes = ran(episodes)  # an "n/a" row is no push: it was "incomplete"
    rows = episodes[(perturbation_labels(episodes) == "nominal") & episodes["push_phase"].notna()]
    if rows.empty:
        return pd.DataFrame()
    rows = rows.assign(
        direction=rows["push_direction_name"].fillna("random")
        if "push_direction_name" in rows
        else "random",
        fraction=rows["push_swing_fraction"].fillna(0.5) if "push_swing_fraction" in rows else 0.5,
        push=episode_key(rows, without=("push_dv_mps",)),
        replica=rows["replica"].fillna(0).astype(int),
        judged=judged(rows),
        early=ended_before_push(rows),
        alive=rows["survived"].fillna(False).astype(bool),
    )
    result = []
    keys = [*KEYS, "push_phase", "direction", "fraction"]
    for key, group in rows.groupby(keys, sort=True):
        thresholds, incomplete, before = [], 0, 0
        lowest = math.inf
        for _, push in group.groupby("push", sort=True):
            replicas = int(push["replica"].max()) + 1
            if replicas < 2:
                continue  # a push of a protocol without replicas
            if push["early"].any():
                before += 1
                continue
            levels = {
                dv: list(push.loc[(push["push_dv_mps"] == dv) & push["judged"], "alive"])
                for dv in sorted(set(push["push_dv_mps"]))
            }
            lowest = min(lowest, min(levels))
            if any(len(outcomes) != replicas for outcomes in levels.values()):
                incomplete += 1
                continue
            value = robust_threshold(levels, robust_required(replicas), replicas)
            thresholds.append(-math.inf if value is None else value)
        if not thresholds and not incomplete and not before:
            continue
        values = sorted(thresholds)
        median, low, high = (
            (values[(len(values) - 1) // 2], values[0], values[-1]) if values else (None,) * 3
        )
        result.append(
            {
                **dict(zip(keys, key, strict=True)),
                "pushes": len(values),
                "median dv m/s": _threshold_cell(median, lowest),
                "min dv m/s": _threshold_cell(low, lowest),
                "max dv m/s": _threshold_cell(high, lowest),
                "incomplete": incomplete,
                "before push": before,
            }
        )
    return pd.DataFrame(result)


def _threshold_cell(value: float | None, lowest: float) -> str:
    """A robust threshold [m/s] as printed: "< lowest" below every level (-inf), "–" none."""
    if value is None:
        return "–"
    return f"< {lowest:g}" if value == -math.inf else f"{value:g}"


def paired_comparisons(episodes: pd.DataFrame, phase: str) -> pd.DataFrame:
    """Every pair of controllers per simulator on the protocol pushes of `phase` (nominal,
    replica 0) both were judged on, a push being the same test (`EPISODE_KEYS`: level, world
    direction, timing, seed, scale, friction, robot): the pushes one survived and the other
    did not, and the exact McNemar p-value (`reports.statistics.paired_table`) with the
    Benjamini-Hochberg q-value over the table's tests (scipy's `false_discovery_control`: many
    pairs are tested at once), most significant first. A push that either controller fell
    before is no comparison of push recovery (`reports.outcomes.judged_push`)."""
    rows = protocol_pushes(episodes, phase)
    rows = rows[judged_push(rows)]
    if rows["controller"].nunique() < 2:
        return pd.DataFrame()
    outcomes = rows.assign(
        survived=rows["survived"].fillna(False).astype(bool), push=episode_key(rows)
    )
    table = paired_table(outcomes, pair_keys=["push"], by=("sim",))
    if len(table):
        table["q (BH)"] = stats.false_discovery_control(table["p"].to_numpy(), method="bh")
    return table.sort_values(["p", "sim"], kind="stable").reset_index(drop=True)


def headline_survival(episodes: pd.DataFrame) -> pd.DataFrame:
    """Per controller x push phase: the protocol pushes survived over all levels in each
    simulator, k/n with the 95 % Wilson interval, and the band between the simulators' rates
    [%] (low-high), and the protocol's levels (`levels_cell`: dv and the impulse for the
    robot). Episodes that fell before their push are not pushes
    (`reports.outcomes.judged_push`): a cell says how many ("20 fell before the push"), and
    how many ended in an error or a timeout that says nothing of the controller ("1 not
    judged", `reports.outcomes.judged`)."""
    result = []
    for phase in ("standing", "walking"):
        pushed = protocol_pushes(episodes, phase)
        for controller, group in pushed.groupby("controller", sort=True):
            row = {"controller": controller, "phase": phase, "levels": levels_cell(group)}
            rates = {}
            for sim, runs in group.groupby("sim", sort=True):
                unjudged = int((~judged(runs)).sum())
                runs = runs[judged(runs)]
                early = ended_before_push(runs)
                before = int(early.sum())
                runs = runs[~early]
                alive = runs["survived"].fillna(False).astype(bool)
                cell = fraction_cell(int(alive.sum()), len(alive)) if len(alive) else ""
                notes = (
                    f"{before} fell before the push" if before else "",
                    f"{unjudged} not judged" if unjudged else "",
                )
                row[sim] = ", ".join(part for part in (cell, *notes) if part)
                rates[sim] = float(alive.mean()) if len(alive) else math.nan
            low, high = simulator_band(rates)
            row["band %"] = "" if math.isnan(low) else f"{100 * low:.0f}-{100 * high:.0f}"
            result.append(row)
    return pd.DataFrame(result)


def levels_cell(pushes: pd.DataFrame) -> str:
    """The push levels of one controller's protocol pushes: "0.35 m/s (20.4 N s)" for one
    level (dv and the impulse J = m dv the robot was given), "3 levels, 0.18-0.42 m/s" for
    several."""
    levels = sorted(set(pushes["push_dv_mps"].dropna()))
    if len(levels) == 1:
        impulse = pushes["push_impulse_Ns"].dropna()
        given = f" ({impulse.median():.1f} N s)" if len(impulse) else ""
        return f"{levels[0]:g} m/s{given}"
    if not levels:
        return ""
    return f"{len(levels)} levels, {levels[0]:g}-{levels[-1]:g} m/s"


def direction_table(episodes: pd.DataFrame) -> pd.DataFrame:
    """Walking pushes by timing and direction: per controller x simulator x swing fraction x
    direction (support-relative, or "random" for the uniform ones), one column per level
    ("dv 0.2 m/s"): the pushes survived out of the pushes run, a push with replicas counting
    as survived when `robust_required(R)` of its R replicas survived (4 of 5), without an
    interval: the replicas of one push differ only by a small seeded change of the initial
    state and the push time, so they are not independent trials, and each named direction is
    one push. Pushes with a replica that fell before the push came
    (`reports.outcomes.judged_push`) or that was not judged (an error, a timeout) are not
    counted; "left out" says how many per row. Empty without support-relative pushes or
    several swing fractions."""
    episodes = ran(episodes)
    rows = episodes[perturbation_labels(episodes) == "nominal"]  # every replica
    rows = rows[rows["push_phase"] == "walking"]
    if rows.empty or "push_direction_name" not in rows:
        return pd.DataFrame()
    rows = rows.assign(
        direction=rows["push_direction_name"].fillna("random"),
        fraction=rows["push_swing_fraction"].fillna(0.5),
        alive=rows["survived"].fillna(False).astype(bool),
        replica=rows["replica"].fillna(0).astype(int) if "replica" in rows else 0,
        push=episode_key(rows),
        is_judged=judged_push(rows).to_numpy(),
    )
    if rows["direction"].eq("random").all() and rows["fraction"].nunique() == 1:
        return pd.DataFrame()
    keys = [*KEYS, "fraction", "direction", "push_dv_mps"]
    # R from every replica run, the judged or not (a push whose last replica timed out has
    # R - 1 judged ones and is left out, not judged "4 of 4")
    replicas = rows.groupby([*keys, "push"], sort=True)["replica"].max() + 1
    rows = rows[rows["is_judged"]]
    if rows.empty:
        return pd.DataFrame()
    pushes = (
        rows.groupby([*keys, "push"], sort=True)
        .agg(alive=("alive", "sum"), judged=("alive", "size"))
        .reset_index()
    )
    pushes["replicas"] = replicas.loc[pd.MultiIndex.from_frame(pushes[[*keys, "push"]])].to_numpy()
    pushes = pushes[pushes["judged"] == pushes["replicas"]]
    required = [robust_required(int(r)) for r in pushes["replicas"]]
    pushes["survived"] = pushes["alive"] >= required
    counts = pushes.groupby(keys, sort=True)["survived"].agg(["sum", "size"]).reset_index()
    counts["cell"] = [
        f"{int(k)}/{int(n)}" for k, n in zip(counts["sum"], counts["size"], strict=True)
    ]
    counts["level"] = [f"dv {dv:g} m/s" for dv in counts["push_dv_mps"]]
    table = counts.pivot_table(
        index=[*KEYS, "fraction", "direction"], columns="level", values="cell", aggfunc="first"
    )
    levels = sorted(set(counts["push_dv_mps"]))
    table = table[[f"dv {dv:g} m/s" for dv in levels]].fillna("")
    # the pushes run but not counted, over the row's levels: shown, not silently dropped
    row_keys = [*KEYS, "fraction", "direction"]
    run = replicas.groupby(row_keys, sort=True).size()
    counted = pushes.groupby(row_keys, sort=True).size().reindex(run.index, fill_value=0)
    table = table.reindex(run.index, fill_value="")
    table["left out"] = [int(n) or "" for n in run - counted]
    table = table.reset_index()
    table.columns.name = None
    return table.rename(columns={"fraction": "swing fraction"})


REPLAY_FOLDER = "replays"  # in the report's folder: <episode_id>.html (`centrobench replay`)


def replay_choices(episodes: pd.DataFrame) -> pd.DataFrame:
    """The episodes the report offers replays of: per controller, one nominal walk (MuJoCo's
    when there is one) and its first fall (the episode that fell at the lowest push level,
    then the lowest push index, MuJoCo first, a plain scenario's fall before any push; a
    nominal one if any fell, else a perturbed one, named with its perturbation). Columns:
    controller, what, sim, episode_id, and the result directory when the report reads
    several."""
    everything = episodes.assign(label=perturbation_labels(episodes))
    if "replica" in everything:
        everything = everything[everything["replica"].fillna(0) == 0]
    result = []
    for controller, group in everything.groupby("controller", sort=True):
        walks = group[
            (group["scenario"] == "walk")
            & group["push_phase"].isna()
            & (group["label"] == "nominal")
        ]
        walks = walks.sort_values(["sim", "episode_id"])
        if len(walks):
            result.append({"controller": controller, "what": "walk", **_choice(walks.iloc[0])})
        falls = group[group["status"] == "fell"]
        falls = falls.assign(
            perturbed=falls["label"] != "nominal",
            level=falls["push_dv_mps"].fillna(-1.0),
            index=falls["push_index"].fillna(-1),
        )
        falls = falls.sort_values(["perturbed", "level", "index", "label", "sim", "episode_id"])
        if len(falls):
            first = falls.iloc[0]
            what = f"first fall ({first['scenario']}"
            if first["push_dv_mps"] == first["push_dv_mps"]:  # not nan: a push
                what += f", dv {first['push_dv_mps']:g} m/s"
            if first["label"] != "nominal":
                what += f", {first['label']}"
            what += ")"
            result.append({"controller": controller, "what": what, **_choice(first)})
    return pd.DataFrame(result, columns=["controller", "what", "sim", "episode_id", "results_dir"])


def _choice(row: pd.Series) -> dict:
    return {
        "sim": row["sim"],
        "episode_id": row["episode_id"],
        "results_dir": row.get("results_dir"),
    }
