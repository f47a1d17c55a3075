"""The report's figures (matplotlib, Agg backend; PNG files)."""

from __future__ import annotations

import textwrap
from collections.abc import Mapping, Sequence
from pathlib import Path

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt
import numpy as np
import pandas as pd
from matplotlib.patches import Polygon

# the trace columns `walk_plot` draws
WALK_COLUMNS = (
    "time",
    *(
        f"{quantity}_{axis}"
        for axis in ("x", "y")
        for quantity in ("zmp_planned", "zmp_actual", "com_ref", "com_planned", "com_actual")
    ),
)


def survival_plot(rates: pd.DataFrame, path: str | Path) -> Path:
    """Survival rate against the velocity change dv [m/s] (Ficht & Behnke Table 2 as a plot),
    one line per controller x simulator; `rates` from `reports.tables.survival_rates`."""
    path = Path(path)
    figure, axis = plt.subplots(figsize=(7, 4.2))
    styles = {"mujoco": "-o", "pybullet": "--s"}
    for (controller, sim), group in rates.groupby(["controller", "sim"], sort=True):
        axis.plot(
            group["push_dv_mps"],
            group["rate"],
            styles.get(sim, "-x"),
            label=f"{controller} ({sim})",
        )
    axis.set_xlabel("velocity change dv = J / m [m/s]")
    axis.set_ylabel("pushes survived (fraction)")
    axis.set_ylim(-0.05, 1.05)
    axis.grid(alpha=0.3)
    axis.legend(fontsize=7, loc="lower left")
    figure.tight_layout()
    figure.savefig(path, dpi=110)
    plt.close(figure)
    return path


def degradation_plot(degradation: pd.DataFrame, dimension: str, path: str | Path) -> Path:
    """One robustness dimension (`reports.robustness.degradation_table`): survival against
    the magnitude with its 95 % Wilson interval as error bars, and the median CoM tracking
    error, one line per controller x simulator x protocol."""
    path = Path(path)
    rows = degradation[degradation["dimension"] == dimension]
    figure, (survival, tracking) = plt.subplots(1, 2, figsize=(11, 4.2))
    styles = {"mujoco": "-o", "pybullet": "--s"}
    for (controller, sim, protocol), group in rows.groupby(
        ["controller", "sim", "protocol"], sort=True
    ):
        group = group.sort_values("magnitude")
        label = f"{controller} ({sim}, {protocol})"
        # no bar where a magnitude has too few episodes for an interval (`MIN_RATE_TRIALS`)
        errors = np.nan_to_num(
            np.vstack([group["rate"] - group["low"], group["high"] - group["rate"]])
        )
        survival.errorbar(
            group["magnitude"],
            group["rate"],
            yerr=errors,
            fmt=styles.get(sim, "-x"),
            capsize=3,
            label=label,
        )
        tracking.plot(group["magnitude"], group["com_rms_mm"], styles.get(sim, "-x"), label=label)
    survival.set_xlabel(dimension)
    survival.set_ylabel("survived (fraction, 95 % Wilson interval)")
    survival.set_ylim(-0.05, 1.05)
    tracking.set_xlabel(dimension)
    tracking.set_ylabel("CoM tracking error, median RMS [mm]")
    for axis in (survival, tracking):
        axis.grid(alpha=0.3)
    survival.legend(fontsize=6, loc="lower left")
    figure.tight_layout()
    figure.savefig(path, dpi=110)
    plt.close(figure)
    return path


PLANNED_MARGIN_M = 0.1
"""[m] how far beyond the planned range `walk_plot` draws (an actual ZMP that runs 5 m away
as the robot falls would otherwise flatten every planned line)."""


def planned_limits(trace: pd.DataFrame, axis_name: str) -> tuple[float, float] | None:
    """(low, high) [m] of the reference and planned CoM and planned ZMP along `axis_name`,
    widened by `PLANNED_MARGIN_M`; None when they have no finite value."""
    columns = [f"{q}_{axis_name}" for q in ("com_ref", "com_planned", "zmp_planned")]
    values = trace[[c for c in columns if c in trace.columns]].to_numpy(dtype=float).ravel()
    values = values[np.isfinite(values)]
    if not len(values):
        return None
    return float(values.min()) - PLANNED_MARGIN_M, float(values.max()) + PLANNED_MARGIN_M


def walk_plot(traces: Mapping[str, pd.DataFrame], path: str | Path) -> Path:
    """Murooka Fig. 3 style: the CoM (reference, planned, actual) and the ZMP (planned,
    actual) along x and y against time, one row per controller."""
    path = Path(path)
    n = max(len(traces), 1)
    figure, axes = plt.subplots(n, 2, figsize=(10, 2.9 * n), squeeze=False, sharex=True)
    for row, (label, trace) in enumerate(traces.items()):
        for column, axis_name in enumerate(("x", "y")):
            axis = axes[row][column]
            time = trace["time"]
            axis.plot(
                time, trace[f"zmp_planned_{axis_name}"], color="C1", lw=0.8, label="ZMP planned"
            )
            axis.plot(
                time,
                trace[f"zmp_actual_{axis_name}"],
                color="C1",
                lw=0.5,
                alpha=0.5,
                label="ZMP actual",
            )
            axis.plot(time, trace[f"com_ref_{axis_name}"], "k:", lw=0.8, label="CoM reference")
            axis.plot(
                time, trace[f"com_planned_{axis_name}"], color="C0", lw=1.0, label="CoM planned"
            )
            axis.plot(
                time,
                trace[f"com_actual_{axis_name}"],
                color="C2",
                lw=1.0,
                ls="--",
                label="CoM actual",
            )
            axis.set_ylabel(f"{axis_name} [m]")
            # two columns of long labels ("controller [estimator] @ robot (sim, status)"):
            # wrapped, or the neighbours' titles overlap
            axis.set_title(textwrap.fill(f"{label}: {axis_name}", 60), fontsize=8)
            axis.grid(alpha=0.3)
            limits = planned_limits(trace, axis_name)
            if limits is not None:
                axis.set_ylim(*limits)
    axes[0][0].legend(fontsize=7, loc="upper left")
    for axis in axes[-1]:
        axis.set_xlabel("time [s]")
    figure.tight_layout()
    figure.savefig(path, dpi=100)
    plt.close(figure)
    return path


# the trace columns `motion_plot` needs (a hand's columns are drawn when the trace has them)
MOTION_COLUMNS = (
    "time",
    "contacts_planned",
    *(f"{quantity}_{axis}" for axis in "xyz" for quantity in ("com_ref", "com_planned")),
    *(f"com_{kind}_{axis}" for axis in "xyz" for kind in ("true", "velocity_true")),
    *(f"wrench_{kind}_f{axis}" for axis in "xyz" for kind in ("projected", "desired")),
)
MOTION_HANDS = ("left_hand", "right_hand")
ACTUAL_FORCE_SMOOTHING_S = 0.01
"""[s] the moving average over which `actual_resultant_force` smooths the differentiated
ground-truth CoM velocity (a 2 ms difference of a simulated velocity chatters at contacts)."""


def actual_resultant_force(trace: pd.DataFrame, mass_kg: float) -> np.ndarray:
    """(n, 3) [N] the actual resultant force, gravity apart (m c'', the convention of the
    plan's w-bar), from the ground-truth CoM velocity differentiated over the trace's periods
    and averaged over `ACTUAL_FORCE_SMOOTHING_S`. By Newton's law it is the sum of the measured
    contact forces minus m g (Murooka Fig. 5 B's "actual", from w^a_i) whenever no other force
    acts, i.e. outside pushes."""
    time = trace["time"].to_numpy(dtype=float)
    velocity = trace[[f"com_velocity_true_{axis}" for axis in "xyz"]].to_numpy(dtype=float)
    if len(time) < 2:
        return np.full((len(time), 3), np.nan)
    acceleration = np.gradient(velocity, time, axis=0)
    window = max(1, round(ACTUAL_FORCE_SMOOTHING_S / float(np.median(np.diff(time)))))
    kernel = np.ones(window) / window
    smooth = np.column_stack(
        [np.convolve(acceleration[:, k], kernel, mode="same") for k in range(3)]
    )
    return mass_kg * smooth


def motion_plot(trace: pd.DataFrame, mass_kg: float, path: str | Path, title: str = "") -> Path:
    """Murooka Figs. 5-7 style, for one multi-contact motion: (A) the CoM reference, planned
    and actual (ground truth) along x, y, z; (B) the resultant force, gravity apart, reference
    (zero: "we always set the reference force to zero", Sec. III-B), planned (w-bar^p',
    projected), desired (w-bar^d) and actual (`actual_resultant_force`) along x, y, z; (C) each
    hand's contact force desired (w^d_i) and measured (w^a_i) in its contact frame, and the
    number of planned contacts. Columns: `MOTION_COLUMNS`, and the hands' when present."""
    path = Path(path)
    figure, axes = plt.subplots(3, 3, figsize=(13, 8.5), sharex=True)
    time = trace["time"].to_numpy(dtype=float)
    actual = actual_resultant_force(trace, mass_kg)
    for k, axis_name in enumerate("xyz"):
        com = axes[0][k]
        com.plot(time, trace[f"com_ref_{axis_name}"], "k:", lw=0.8, label="reference")
        com.plot(time, trace[f"com_planned_{axis_name}"], color="C0", lw=1.0, label="planned")
        com.plot(time, trace[f"com_true_{axis_name}"], color="C2", lw=1.0, ls="--", label="actual")
        com.set_title(f"(A) CoM {axis_name}", fontsize=9)
        com.set_ylabel("[m]")
        force = axes[1][k]
        force.axhline(0.0, color="k", ls=":", lw=0.8, label="reference")
        force.plot(
            time, trace[f"wrench_projected_f{axis_name}"], color="C0", lw=0.9, label="planned"
        )
        force.plot(time, trace[f"wrench_desired_f{axis_name}"], color="C1", lw=0.7, label="desired")
        force.plot(time, actual[:, k], color="C2", lw=0.6, alpha=0.8, label="actual")
        force.set_title(f"(B) resultant force {axis_name}, gravity apart", fontsize=9)
        force.set_ylabel("[N]")
    for k, hand in enumerate(MOTION_HANDS):
        axis = axes[2][k]
        axis.set_title(f"(C) {hand.replace('_', ' ')} force, contact frame", fontsize=9)
        axis.set_ylabel("[N]")
        columns = [f"wrench_{kind}_{hand}_f{a}" for kind in ("desired", "measured") for a in "xyz"]
        if not all(c in trace.columns for c in columns):
            axis.text(0.5, 0.5, "not recorded", ha="center", transform=axis.transAxes)
            continue
        for j, a in enumerate("xyz"):
            axis.plot(
                time,
                trace[f"wrench_desired_{hand}_f{a}"],
                color=f"C{j}",
                lw=0.9,
                label=f"f{a} desired",
            )
            axis.plot(
                time,
                trace[f"wrench_measured_{hand}_f{a}"],
                color=f"C{j}",
                lw=0.6,
                ls="--",
                alpha=0.8,
                label=f"f{a} actual",
            )
        axis.legend(fontsize=6, loc="upper left", ncol=2)
    contacts = axes[2][2]
    contacts.step(time, trace["contacts_planned"].to_numpy(dtype=float), where="post", color="k")
    contacts.set_title("contacts planned", fontsize=9)
    for row in axes:
        for axis in row:
            axis.grid(alpha=0.3)
    axes[0][0].legend(fontsize=7, loc="upper left")
    axes[1][0].legend(fontsize=7, loc="upper left")
    for axis in axes[-1]:
        axis.set_xlabel("time [s]")
    if title:
        figure.suptitle(title, fontsize=10)
    figure.tight_layout()
    figure.savefig(path, dpi=90)
    plt.close(figure)
    return path


PAPER_SOLVE_MEAN_MS = 0.92
"""Sherikov, Dimitrov & Wieber 2014, Sec. VII-B (Fig. 2): "The average time required for
solution of the optimization problem is equal to 0.92 (ms), when the solver is executed on
Intel Core i5-3360M (2.80GHz) CPU"."""
HIERARCHY_TIME_COLUMN = "t_hierarchy_us"  # the hierarchy solve per period (the runner's)
FOOT_STYLES = {"left_foot": ("tab:green", "left foot"), "right_foot": ("tab:purple", "right foot")}


def _xy(trace: pd.DataFrame, prefixes: tuple[str, ...]) -> tuple[np.ndarray, np.ndarray] | None:
    """The x and y columns of the first prefix the trace has, as float arrays; None if none."""
    for prefix in prefixes:
        if f"{prefix}_x" in trace.columns and f"{prefix}_y" in trace.columns:
            return (
                trace[f"{prefix}_x"].to_numpy(dtype=float),
                trace[f"{prefix}_y"].to_numpy(dtype=float),
            )
    return None


def _sole(x: float, y: float, yaw: float, half_extents, color: str, dashed: bool = False):
    """The sole's rectangle centred at (x, y) [m], turned by yaw [rad]."""
    hx, hy = half_extents
    corners = np.array([(hx, hy), (-hx, hy), (-hx, -hy), (hx, -hy)])
    c, s = np.cos(yaw), np.sin(yaw)
    corners = corners @ np.array([[c, s], [-s, c]]) + (x, y)
    return Polygon(
        corners,
        closed=True,
        fill=True,
        facecolor=color,
        alpha=0.35,
        edgecolor=color,
        linestyle="--" if dashed else "-",
        linewidth=1.0,
    )


def top_view_plot(
    trace: pd.DataFrame,
    footsteps: pd.DataFrame | None,
    sole_half_extents: tuple[float, float],
    path: str | Path,
    title: str = "",
    pushes: Sequence[float] = (),
    initial_feet: Mapping[str, tuple[float, float, float]] | None = None,
) -> Path:
    """Sherikov et al. 2014 Fig. 3 style top view (x forward, y left, equal axes): the steps
    taken (`bench.footsteps` rows: limb, x_m, y_m, yaw_rad at touchdown) as sole rectangles
    (`sole_half_extents` (x, y) [m]; left and right feet in their own colours), the feet
    standing at the start if `initial_feet` gives them (limb -> (x, y, yaw), dashed), the CoM
    path in black (the ground truth `com_true_*` when the trace has it, else `com_actual_*`),
    the hand path dashed blue (`hand_actual_*`), the target path dotted red (`hand_target_*`,
    NaN while none is active: gaps) with each position it takes marked (a target that jumps
    between fixed points, as `reach`'s, draws no path of its own), and the CoM at each time in
    `pushes` [s] marked."""
    path = Path(path)
    figure, axis = plt.subplots(figsize=(7, 5.5))
    labelled: set[str] = set()

    def add_foot(limb: str, x: float, y: float, yaw: float, dashed: bool) -> None:
        if not all(np.isfinite((x, y, yaw))):
            return
        color, label = FOOT_STYLES.get(limb, ("tab:gray", str(limb)))
        patch = _sole(x, y, yaw, sole_half_extents, color, dashed)
        if dashed:
            label = f"{label} (start)"
        if label not in labelled:
            patch.set_label(label)
            labelled.add(label)
        axis.add_patch(patch)

    for limb, (x, y, yaw) in (initial_feet or {}).items():
        add_foot(limb, x, y, yaw, dashed=True)
    if footsteps is not None and len(footsteps):
        for row in footsteps.itertuples(index=False):
            add_foot(str(row.limb), float(row.x_m), float(row.y_m), float(row.yaw_rad), False)
    com = _xy(trace, ("com_true", "com_actual"))
    if com is not None:
        axis.plot(*com, color="black", lw=1.2, label="CoM")
        times = trace["time"].to_numpy(dtype=float) if "time" in trace.columns else None
        if times is not None and len(times):
            instants = [t for t in pushes if times[0] <= t <= times[-1]]
            if instants:
                axis.plot(
                    np.interp(instants, times, com[0]),
                    np.interp(instants, times, com[1]),
                    "o",
                    color="tab:orange",
                    markeredgecolor="black",
                    ms=7,
                    label="push",
                    zorder=5,
                )
    hand = _xy(trace, ("hand_actual",))
    if hand is not None:
        axis.plot(*hand, color="blue", ls="--", lw=1.0, label="hand")
    target = _xy(trace, ("hand_target",))
    if target is not None and np.isfinite(target[0]).any():
        axis.plot(*target, color="red", ls=":", lw=2.0, label="target")
        # a target that jumps or stands still is no visible path: its positions marked too
        x, y = target
        finite = np.isfinite(x) & np.isfinite(y)
        x, y = x[finite], y[finite]
        held = np.r_[True, (np.diff(x) != 0) | (np.diff(y) != 0)]
        axis.plot(x[held], y[held], "x", color="red", ms=8, mew=2, label="target positions")
    axis.set_aspect("equal", adjustable="datalim")
    axis.autoscale_view()
    axis.set_xlabel("x [m] (forward)")
    axis.set_ylabel("y [m] (left)")
    axis.set_title(title or "top view", fontsize=9)
    axis.grid(alpha=0.3)
    if axis.get_legend_handles_labels()[0]:
        axis.legend(fontsize=7, loc="best")
    figure.tight_layout()
    figure.savefig(path, dpi=100)
    plt.close(figure)
    return path


def solve_time_plot(trace: pd.DataFrame, path: str | Path, title: str = "") -> Path:
    """Sherikov et al. 2014 Fig. 2 style: the hierarchy's solve time per control period [ms]
    (`HIERARCHY_TIME_COLUMN`, above) and the solver's active-set iterations
    (`solver_iterations`, below) against time, with the paper's mean (`PAPER_SOLVE_MEAN_MS`,
    measured on its CPU) dashed; the time axis is logarithmic when the longest solve is over
    20 times the median (and the paper's mean). A missing column leaves its axis empty."""
    path = Path(path)
    figure, (above, below) = plt.subplots(2, 1, figsize=(8, 5), sharex=True)
    time = trace["time"].to_numpy(dtype=float) if "time" in trace.columns else None
    solve_ms = None
    if time is not None and HIERARCHY_TIME_COLUMN in trace.columns:
        solve_ms = trace[HIERARCHY_TIME_COLUMN].to_numpy(dtype=float) / 1e3
        above.plot(time, solve_ms, color="C0", lw=0.7, label="solve time (this machine)")
        if np.isfinite(solve_ms).any():
            above.axhline(
                float(np.nanmean(solve_ms)),
                color="C0",
                ls=":",
                lw=1.0,
                label=f"mean {np.nanmean(solve_ms):.2f} ms (this machine)",
            )
    else:
        above.text(0.5, 0.5, "no solve times recorded", ha="center", transform=above.transAxes)
    above.axhline(
        PAPER_SOLVE_MEAN_MS,
        color="red",
        ls="--",
        lw=1.0,
        label=f"paper's mean {PAPER_SOLVE_MEAN_MS} ms (Intel Core i5-3360M)",
    )
    above.set_ylabel("solve time [ms]")
    finite = solve_ms[np.isfinite(solve_ms) & (solve_ms > 0)] if solve_ms is not None else []
    if len(finite) and finite.max() > 20 * max(np.median(finite), PAPER_SOLVE_MEAN_MS):
        above.set_yscale("log")  # rare long solves would flatten the rest and the paper's line
    else:
        above.set_ylim(bottom=0.0)
    above.grid(alpha=0.3)
    above.legend(fontsize=7, loc="upper right")
    above.set_title(title or "hierarchy solve", fontsize=9)
    if time is not None and "solver_iterations" in trace.columns:
        below.step(
            time, trace["solver_iterations"].to_numpy(dtype=float), where="post", color="C1", lw=0.7
        )
    else:
        below.text(0.5, 0.5, "no iterations recorded", ha="center", transform=below.transAxes)
    below.set_ylabel("solver iterations")
    below.set_xlabel("time [s]")
    below.grid(alpha=0.3)
    figure.tight_layout()
    figure.savefig(path, dpi=100)
    plt.close(figure)
    return path
