"""The report's figures (matplotlib, Agg backend; PNG files)."""

from __future__ import annotations

from collections.abc import Mapping
from pathlib import Path

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt
import pandas as pd

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


def walk_plot(traces: Mapping[str, pd.DataFrame], path: str | Path) -> Path:
    """Murooka Fig. 3 style: the CoM (reference, planned, actual) and the ZMP (planned,
    actual) along x and y against time, one row per controller."""
    path = Path(path)
    n = max(len(traces), 1)
    figure, axes = plt.subplots(n, 2, figsize=(10, 2.6 * n), squeeze=False, sharex=True)
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
            axis.set_title(f"{label}: {axis_name}", fontsize=9)
            axis.grid(alpha=0.3)
    axes[0][0].legend(fontsize=7, loc="upper left")
    for axis in axes[-1]:
        axis.set_xlabel("time [s]")
    figure.tight_layout()
    figure.savefig(path, dpi=100)
    plt.close(figure)
    return path
