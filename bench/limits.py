"""The valid ranges of what a user can ask for, shared by the command line (`bench.cli`) and
the sweep spec (`bench.sweep_spec`, `bench.push_protocol`), so that a value that would break
every episode (or the machine) is refused before anything runs, with the same bound in every
message.

Light on purpose (numpy and `robots.scene` only): the CLI's argument types import it.
"""

from __future__ import annotations

import re

from robots.scene import Scene

# The longest simulated episode [s]. The runner preallocates its trace (`bench.runner._Trace`:
# about 120 float64 columns per control period of 2 ms), so 600 s are some 300 MB; a
# duration of 1e12 s asked for petabytes and ended every episode in a MemoryError row.
MAX_EPISODE_SECONDS = 600.0
# One control period [s]: a shorter episode runs no period at all (and used to be reported
# "ok" with 0 s simulated).
CONTROL_PERIOD_S = Scene().control_dt
# numpy's seed range [0, 2**32): `np.random.seed` (the runner seeds the legacy API) refuses
# anything else, which failed every episode at setup.
SEED_LIMIT = 2**32
# Robot length scale (1 = 1.60 m): below 0.1 the smallest links' inertias fall under what
# MuJoCo accepts as positive definite; 10 (16 m, 58 t) is already far past any humanoid.
SCALE_RANGE = (0.1, 10.0)
# Total mass [kg] replacing the scaled one: the robot loads in pinocchio, MuJoCo and PyBullet
# from 1e-6 kg on at every scale in SCALE_RANGE (measured); 1 g ... 1000 t leaves margin.
MASS_RANGE_KG = (1e-3, 1e6)
# Coulomb friction coefficient of every contact: rubber on concrete is about 1; from 10 on the
# MuJoCo robot falls at once, and 1e300 makes its simulation unstable (measured).
FRICTION_MAX = 5.0
# Push velocity change dv = J / m [m/s]: the paper's levels are below 0.5; 100 m/s throws
# any robot away, and 1e307 overflowed the impulse to infinity.
MAX_PUSH_DV = 100.0
# Push impulse [N s] of `centrobench run` (the robot of about 58 kg): MAX_PUSH_DV x 100 kg.
MAX_PUSH_IMPULSE_NS = 10_000.0
# Pushes per level: the directions are drawn for all of them at once.
MAX_PUSH_COUNT = 10_000
# Episodes of one sweep: every one is listed (with its id) before the first runs.
MAX_EPISODES = 1_000_000
# linear_mpc horizon samples for `compare --horizons` (0.1 s each: 10 s of preview, longer
# than a walk); the condensed matrices grow with its square (200 took 100 s per update).
MAX_HORIZON = 100
# Local worker processes of a sweep: the pool starts every one of them at once.
MAX_WORKERS = 256
# Forward walking speed of a gait command [m/s], either way: at 1 m/s and 0.9 s per step a step
# is 0.9 m, past the reach of the humanoid's 0.72 m legs (faster asks nothing new).
MAX_WALK_SPEED = 1.0
# Steps of a walk's gait command: 200 steps of 0.9 s is 180 s, within MAX_EPISODE_SECONDS.
MAX_WALK_STEPS = 200
# An episode's wall-clock budget (`SweepSpec.wall_budget_s`): at most a day of base time and
# 1000 wall-clock seconds per simulated second (a controller 1000 times slower than real time).
TIMEOUT_BASE_MAX_S = 86_400.0
TIMEOUT_PER_SIM_MAX = 1_000.0
# A sweep's name names its result directory (results/NAME): one plain path component.
NAME_PATTERN = re.compile(r"[A-Za-z0-9_-][A-Za-z0-9._-]{0,99}")
NAME_RULE = "1 to 100 letters, digits, '-', '_' or '.', not starting with '.' and without '..'"


def valid_name(name: str) -> bool:
    """Whether `name` is a plain, identifier-like sweep name (see NAME_RULE)."""
    return NAME_PATTERN.fullmatch(name) is not None and ".." not in name
