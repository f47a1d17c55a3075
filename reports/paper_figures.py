"""The papers' own figures that the report sets beside ours (reports/ reads result files and
these constants only)."""

from __future__ import annotations

PAPER_TABLE_IV_US: dict[str, dict[str, float]] = {
    "hand_wall": {
        "centroidal_control": 124.0,
        "reference": 22.0,
        "preview": 9.0,
        "projection": 29.0,
        "distribution": 28.0,
    },
    "handrail_stairs": {
        "centroidal_control": 186.0,
        "reference": 22.0,
        "preview": 10.0,
        "projection": 56.0,
        "distribution": 56.0,
    },
    "ladder": {
        "centroidal_control": 409.0,
        "reference": 22.0,
        "preview": 9.0,
        "projection": 165.0,
        "distribution": 162.0,
    },
}
"""Murooka et al. 2022, Table IV: computation time per control cycle [µs] of the proposed
centroidal control (preview control with wrench projection and distribution, not the
whole-body IK; C++ on an i7-9750H) for the motions of Fig. 4: (A) walking on scaffold boards
with a hand on the wall (`hand_wall`), (B) climbing handrail stairs (`handrail_stairs`), (C)
climbing a vertical ladder (`ladder`). Rows: total control, calculate reference, preview
control, project planned wrench, distribute desired wrench (our trace's stage names)."""

MOTION_LABELS = {
    "hand_wall": "(A) hand on wall",
    "handrail_stairs": "(B) handrail stairs",
    "ladder": "(C) ladder",
}
"""The scenarios of Murooka et al.'s Fig. 4 (A)-(C), where Table IV and Sec. V-G are measured."""

PAPER_SCENARIO = {"handrail_stairs_resting": "handrail_stairs"}
"""Our variants of the paper's motions and the motion whose published numbers they are set
beside ((B) with the hands resting on the rails instead of grasping them)."""

VARIANT_LABELS = {"handrail_stairs_resting": "(B) handrail stairs, hands resting (ours)"}
"""How the report names the variants of `PAPER_SCENARIO`, set beside the paper's figures of
the motion they vary."""

MOTION_FIGURES = {
    "hand_wall": "Fig. 5",
    "handrail_stairs": "Fig. 6",
    "handrail_stairs_resting": "Fig. 6",
    "ladder": "Fig. 7",
    "hand_supports": "Figs. 5-7 style, Fig. 4 (D)",
    "moving_contacts": "Figs. 5-7 style, Fig. 4 (E)",
}
"""The multi-contact motions of Murooka et al.'s Fig. 4 and the paper's figure of results for
each ((D) and (E) have none: drawn in the same style); the report draws one per episode with a
trace (`reports.plots.motion_plot`)."""

PAPER_SEC_V_G: dict[tuple[str, str], dict[str, float]] = {
    ("handrail_stairs", "preview_control"): {
        "planned_force_N": 2.2,
        "planned_moment_Nm": 4.4,
        "desired_force_N": 3.7,
        "desired_moment_Nm": 4.7,
    },
    ("handrail_stairs", "linear_mpc"): {
        "planned_force_N": 0.0,
        "planned_moment_Nm": 0.0,
        "desired_force_N": 0.42,
        "desired_moment_Nm": 0.52,
    },
    ("ladder", "preview_control"): {
        "planned_force_N": 0.0,
        "planned_moment_Nm": 0.0,
        "desired_force_N": 9.0,
        "desired_moment_Nm": 8.7,
    },
    ("ladder", "linear_mpc"): {
        "planned_force_N": 0.0,
        "planned_moment_Nm": 0.0,
        "desired_force_N": 9.3,
        "desired_moment_Nm": 9.1,
    },
}
"""Murooka et al. 2022, Sec. V-G (HRP-5P in Choreonoid): the mean projection errors of the
planned resultant wrench (||w-bar^p - w-bar^p'||) and of the desired one, for climbing the
handrail stairs (Fig. 4 B) and the ladder (C), with the proposed preview control and with the
linear MPC of its ref. [5]; "no significant differences were found in the scale of feedback
wrench (11), CoM acceleration, and angular momentum" (no numbers printed)."""
