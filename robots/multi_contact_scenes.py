"""The multi-contact scenes of Murooka et al. (Fig. 4 A-E, Sec. V-C), as boxes.

Each function takes the robot and returns a `robots.scene.Scene`; every simulator builds it
from the same boxes. The paper gives only a few dimensions (Fig. 4's caption: the 25 deg
scaffold boards, the four 150 mm steps, the ladder's 200 mm rung spacing and 75 mm rung depth,
the 500 mm hand supports, the 20 mm / 2 deg motion, the friction coefficient 0.6); every other
dimension is ours, chosen for the centrobench humanoid at scale 1 (1.60 m, 58 kg: hips 0.09 m
either side of the centre, legs of two 0.36 m segments, feet 0.22 m x 0.12 m, shoulders 0.21 m
either side and about 1.26 m above the ground when standing, arms 0.48 m to the palm) and
grouped under "ours" in the constants below. The paper's dimensions are used as printed at scale 1
(its robot, HRP-5P, is 1.8 m tall: the ladder's 75 mm rungs are less than half of either
robot's sole); every length is multiplied by the robot's `scale`, angles are not, and the
period of the moving scene scales as sqrt(scale) (Froude similarity, as the humanoid's joint
speed limits, `robots.humanoid`).

Frame: the robot starts standing at the origin facing +x (soles' centres at x = 0, y = +-0.09
m), the ground at z = 0 unless a scene says otherwise. A box's "top" is its +z face; a board
or rail is tilted about the world y axis only.
"""

from __future__ import annotations

import math
from collections.abc import Callable

from robots.scene import Box, MovingBox, Scene
from robots.similarity import froude_time_scale
from robots.spec import RobotDescription

# --------------------------------------------------------------------- the paper's numbers
PAPER_FRICTION = 0.6
"""Fig. 4's caption: "The friction coefficient is set to 0.6 for all environments"."""
PAPER_BOARD_INCLINE_RAD = math.radians(25.0)
"""Fig. 4 (A): "scaffold boards with 25 degree incline"."""
PAPER_STEP_COUNT = 4
PAPER_STEP_RISE_M = 0.150
"""Fig. 4 (B): "four steps of 150 mm height with handrails"."""
PAPER_RUNG_SPACING_M = 0.200
PAPER_RUNG_DEPTH_M = 0.075
"""Fig. 4 (C): "a vertical ladder with 200 mm steps. The depth of the ladder rungs is 75 mm,
which is less than half the depth of the robot's sole"."""
PAPER_SUPPORT_HEIGHT_M = 0.500
"""Fig. 4 (D): "both hands on the support surfaces at the height of 500 mm"."""
PAPER_MOTION_TRANSLATION_M = 0.020
PAPER_MOTION_ROTATION_RAD = math.radians(2.0)
"""Fig. 4 (E): floors and walls "move periodically in translation and rotation with an
amplitude of 20 mm and 2 degrees"."""

# ------------------------------------------------------------------ ours (scale 1, [m], [s])
WALL_INNER_FACE_Y = 0.45
"""(E): the walls' faces 0.45 m either side of the walkway's centre line: 0.24 m beyond
the shoulders, within the arm's 0.48 m reach with the elbow bent."""
WALL_WALK_FACE_Y = 0.40
"""(A): the walls' faces 0.40 m either side of the walkway's centre line (0.19 m beyond the
shoulders). From the kinematic check (`centrobench check --scenario hand_wall`): at (E)'s 0.45
m the arm of the palm on the wall straightened (the elbow at its limit) in the single
supports on the far foot, the body swaying 0.09 m away from the wall: in 7 of the motion's 78
phases with our lifted swing, none at 0.41 m (while (A) had three footholds down and 70 phases: 7 at
0.45 m, 2 at 0.41 m and 3 at 0.40 m; 0.38 m put the wrists at their limits). With the
authors' swing (`robots.swing`, 2026-11-27, session 25) 0.41 m left the left elbow at its
limit in the first step onto the board (1 of 78 phases; with our lifted swing it had been
within 0.01 rad of it there) and 0.40 m in none (0.39 m none either, the CoM 0.5 mm further
off)."""
WALL_THICKNESS = 0.10
WALL_HEIGHT = 2.0
BOARD_RUN = 0.60
"""(A): horizontal length of each inclined board (rise 0.60 tan 25 deg = 0.280 m)."""
BOARD_TOP_LENGTH = 0.40
"""(A): the flat board between the ascending and the descending one."""
BOARD_THICKNESS = 0.04
WALKWAY_WIDTH = 0.60
WALKWAY_START_X = 0.30
"""(A), (B): where the first board or step begins: 0.19 m beyond the toes (0.11 m ahead of
the soles' centres)."""
STEP_RUN = 0.30
"""(B): tread depth: the 0.22 m sole and 0.08 m to spare."""
LANDING_DEPTH = 0.60
"""(B): the fourth step's tread, deep enough for both feet side by side."""
STAIR_WIDTH = 0.70
HANDRAIL_Y = 0.38
"""(B): rail centre lines 0.38 m either side of the stairs' centre line, 0.03 m outside the
stairs' edges, 0.17 m beyond the shoulders (0.45 m, the first choice, left a palm 0.50 m from
its shoulder on the rail beside the robot: beyond the arm's 0.48 m)."""
HANDRAIL_HEIGHT = 0.85
"""(B): the rail's centre line 0.85 m above the stairs' pitch line (the line through the
steps' nosings): 0.925 m above a foot on a tread's centre, 0.26 m below the shoulders (which
(B)'s CoM height, `bench.motions.STAIRS_COM_HEIGHT`, keeps 1.18 m above the feet), so a palm
0.25 m ahead of or behind the shoulder reaches it with the elbow bent. From the kinematic check
(`centrobench check --scenario handrail_stairs`): 0.95 m, chosen when the CoM stayed at the
standing height, put the wrists at their pitch limits with the CoM 0.076 m lower (the CoM up to
77 mm from its reference in the double supports after a step up), 0.90 / 0.875 m up to 18 / 12
mm, 0.85 m 10 mm (0.83 m 11 mm), all at a CoM height of 0.75 m (13 mm at 0.74 m, the one kept);
0.80 m, a 0.9 m human handrail scaled, was out of reach at the standing height."""
HANDRAIL_HALF_SECTION = 0.02
"""(B): the rails are 0.04 m x 0.04 m bars (boxes: the scene has no cylinders)."""
HANDRAIL_RUNOUT = 0.40
"""(B): the rails' horizontal parts before the slope and after the last nosing."""
LADDER_X = 0.30
"""(C): the rungs' centres 0.30 m ahead of the soles' centres: 0.15 m beyond the toes."""
LADDER_RUNG_COUNT = 10
LADDER_RUNG_LENGTH = 0.50
"""(C): between the side rails; the feet (0.09 m either side) and the shoulders (0.21 m)
fit."""
LADDER_RUNG_THICKNESS = 0.03
LADDER_STILE_WIDTH = 0.04
LADDER_STILE_DEPTH = 0.075
SUPPORT_Y = 0.32
"""(D): the supports' centre lines 0.32 m either side, 0.11 m beyond the shoulders; their inner
edges (0.24 m) clear the soles' outer edges (0.15 m)."""
SUPPORT_WIDTH = 0.16
SUPPORT_FALL_HEIGHT = 0.30
"""(D): base height [m] below which the robot counts as fallen on the supports (ours): the
motion crouches on purpose to bring the palms to 0.5 m (base at about 0.45 m at scale 1, the
humanoid's own fall height), so the scene sets a lower one, two thirds of that crouch."""
SUPPORT_X_RANGE = (-0.30, 1.50)
"""(D): the supports run from beside the robot's start to 1.5 m ahead (the motion moves
forward along them)."""
MOTION_PERIOD_S = 8.0
"""(E): period of every moving floor and wall at scale 1 (x sqrt(scale)). The paper prints none.
Its damping control (eq. 15, Table II: K_d 10000 N s/m for a limb in contact) follows a surface
moving at speed v only with a force error K_d v, so the period decides whether contacts are
kept: at 20 mm amplitude the peak speed is 2 pi 0.02 / T, 63 mm/s at T = 2 s (630 N of force
error: more than a foot's load), 16 mm/s at 8 s. Measured with `preview_control` +
`centroidal_feedback` (MuJoCo / PyBullet, 10 s of motion, `bench.motions.moving_contacts`):
at 2 s the hands lose the walls and the robot falls at 11.5 s; at 4 s a foot unloads to 0 N;
at 8 s both feet keep more than 130 N and the hands are on the walls 88 % of the time."""
MOTION_RAMP_PERIODS = 0.5
"""(E): the motion's amplitude ramps in smoothly over the first half period
(`MovingBox.ramp_time`), so that the robot starts at rest on floors at their mean pose."""
FLOOR_PLATE_LENGTH = 0.80
FLOOR_PLATE_WIDTH = 0.40
FLOOR_PLATE_GAP = 0.01
FLOOR_PLATE_THICKNESS = 0.10
MOVING_WALL_LENGTH = 0.80
MOVING_WALL_HEIGHT = 1.80


def _pitch_quaternion(dx: float, dz: float) -> tuple[float, float, float, float]:
    """(w, x, y, z) of the rotation about the world y axis that turns +x to the direction
    (dx, 0, dz): an angle phi = atan2(-dz, dx), x axis (cos phi, 0, -sin phi)."""
    phi = math.atan2(-dz, dx)
    return (math.cos(0.5 * phi), 0.0, math.sin(0.5 * phi), 0.0)


def _bar(
    name: str, start: tuple[float, float], end: tuple[float, float], y: float, half_section
) -> Box:
    """A bar whose centre line runs from `start` to `end` ((x, z) [m]) in the plane at `y`,
    with half extents across the line `half_section` = (along y, along the bar's z) [m]."""
    dx, dz = end[0] - start[0], end[1] - start[1]
    return Box(
        name,
        (0.5 * (start[0] + end[0]), y, 0.5 * (start[1] + end[1])),
        (0.5 * math.hypot(dx, dz), half_section[0], half_section[1]),
        _pitch_quaternion(dx, dz),
    )


def _board(
    name: str,
    start: tuple[float, float],
    end: tuple[float, float],
    half_width: float,
    thickness: float,
) -> Box:
    """A board whose top face's centre line runs from `start` to `end` ((x, z) [m], in the
    plane y = 0): the centre lies half the thickness below it, along the board's normal."""
    dx, dz = end[0] - start[0], end[1] - start[1]
    length = math.hypot(dx, dz)
    # the board's normal (its z axis) is the direction rotated by +90 deg in the x-z plane
    nx, nz = -dz / length, dx / length
    mid_x, mid_z = 0.5 * (start[0] + end[0]), 0.5 * (start[1] + end[1])
    return Box(
        name,
        (mid_x - 0.5 * thickness * nx, 0.0, mid_z - 0.5 * thickness * nz),
        (0.5 * length, half_width, 0.5 * thickness),
        _pitch_quaternion(dx, dz),
    )


def _block(name: str, x_range, y_range, z_range) -> Box:
    """An axis-aligned box spanning the given (low, high) ranges [m]."""
    (x0, x1), (y0, y1), (z0, z1) = x_range, y_range, z_range
    return Box(
        name,
        (0.5 * (x0 + x1), 0.5 * (y0 + y1), 0.5 * (z0 + z1)),
        (0.5 * (x1 - x0), 0.5 * (y1 - y0), 0.5 * (z1 - z0)),
    )


def _side_walls(
    s: float, x_range: tuple[float, float], height: float, face_y: float = WALL_INNER_FACE_Y
) -> tuple[Box, Box]:
    """Walls `wall_left` (+y) and `wall_right` (-y) with their faces at +-face_y [m at scale
    1]."""
    face, thickness = face_y * s, WALL_THICKNESS * s
    return (
        _block("wall_left", x_range, (face, face + thickness), (0.0, height)),
        _block("wall_right", x_range, (-face - thickness, -face), (0.0, height)),
    )


def hand_wall(robot: RobotDescription) -> Scene:
    """Fig. 4 (A): scaffold boards inclined 25 deg (paper) with a vertical wall beside them.

    A walkway of three boards along +x, up then down (ours): `board_up` rises at 25 deg over a
    horizontal run of 0.60 m from x = 0.30 m (its top face starts at the ground) to a height of
    0.60 tan 25 deg = 0.280 m, `board_top` is flat and 0.40 m long at that height, `board_down`
    descends at 25 deg over 0.60 m back to the ground (x = 1.90 m); the boards are 0.60 m wide
    and 0.04 m thick, their top faces meeting edge to edge (ours). On a 25 deg slope the
    friction needed to stand, tan 25 deg = 0.47, is within the paper's 0.6.

    The paper's Fig. 5 has the left hand on the wall for 1-6 s and the right hand for 6-10 s
    (the motion switches hands), so there is a wall on each side (ours): `wall_left` and
    `wall_right`, faces at y = +-0.40 m (`WALL_WALK_FACE_Y`), 0.10 m thick, 2.0 m high, from
    0.5 m behind the start to 0.5 m beyond the last board. Every length x robot.scale; the
    angle is not scaled."""
    s = robot.scale
    x0, run, top = WALKWAY_START_X * s, BOARD_RUN * s, BOARD_TOP_LENGTH * s
    rise = run * math.tan(PAPER_BOARD_INCLINE_RAD)
    half_width, thickness = 0.5 * WALKWAY_WIDTH * s, BOARD_THICKNESS * s
    x1, x2, x3 = x0 + run, x0 + run + top, x0 + 2 * run + top
    boards = (
        _board("board_up", (x0, 0.0), (x1, rise), half_width, thickness),
        _board("board_top", (x1, rise), (x2, rise), half_width, thickness),
        _board("board_down", (x2, rise), (x3, 0.0), half_width, thickness),
    )
    walls = _side_walls(s, (-0.5 * s, x3 + 0.5 * s), WALL_HEIGHT * s, WALL_WALK_FACE_Y)
    return Scene(boxes=boards + walls, friction=PAPER_FRICTION)


def handrail_stairs(robot: RobotDescription) -> Scene:
    """Fig. 4 (B): four steps of 150 mm rise (paper) with a handrail on each side.

    Steps (ours but the rise): solid blocks `step_1` ... `step_4` from the ground, step k's
    tread at k x 0.150 m, treads 0.30 m deep starting at x = 0.30 m, the fourth a 0.60 m
    landing, 0.70 m wide. Handrails (ours): 0.04 m square bars with centre lines at y = +-0.38 m
    and 0.85 m above the pitch line (`HANDRAIL_HEIGHT`; the pitch line runs through the
    nosings, slope 0.150 / 0.30, 26.6 deg, and meets the ground at the robot's start, x = 0),
    each rail in three pieces:
    `rail_<side>_bottom` horizontal over the 0.40 m before the slope, `rail_<side>_slope`
    along the stairs up to the last nosing, `rail_<side>_top` horizontal for 0.40 m beyond it.
    The rails float (a static box needs no post). Every length x robot.scale."""
    s = robot.scale
    x0, run, rise = WALKWAY_START_X * s, STEP_RUN * s, PAPER_STEP_RISE_M * s
    half_width = 0.5 * STAIR_WIDTH * s
    steps = []
    for k in range(1, PAPER_STEP_COUNT + 1):
        front = x0 + (k - 1) * run
        back = front + (LANDING_DEPTH * s if k == PAPER_STEP_COUNT else run)
        steps.append(_block(f"step_{k}", (front, back), (-half_width, half_width), (0, k * rise)))
    height = HANDRAIL_HEIGHT * s
    foot_of_slope = x0 - run  # where the pitch line meets the ground
    last_nosing = x0 + (PAPER_STEP_COUNT - 1) * run
    top_height = height + PAPER_STEP_COUNT * rise
    runout = HANDRAIL_RUNOUT * s
    section = (HANDRAIL_HALF_SECTION * s, HANDRAIL_HALF_SECTION * s)
    rails = []
    for side, y in (("left", HANDRAIL_Y * s), ("right", -HANDRAIL_Y * s)):
        rails += [
            _bar(
                f"rail_{side}_bottom",
                (foot_of_slope - runout, height),
                (foot_of_slope, height),
                y,
                section,
            ),
            _bar(
                f"rail_{side}_slope", (foot_of_slope, height), (last_nosing, top_height), y, section
            ),
            _bar(
                f"rail_{side}_top",
                (last_nosing, top_height),
                (last_nosing + runout, top_height),
                y,
                section,
            ),
        ]
    return Scene(boxes=tuple(steps) + tuple(rails), friction=PAPER_FRICTION)


def ladder(robot: RobotDescription) -> Scene:
    """Fig. 4 (C): a vertical ladder with rungs 200 mm apart and 75 mm deep (paper).

    Rungs `rung_01` ... `rung_10` (ours but the spacing and depth): 0.075 m deep along x,
    0.03 m thick, 0.50 m long, centred at x = 0.30 m, their top faces at 0.20, 0.40, ...,
    2.00 m; the 75 mm depth is less than half the 0.22 m sole (0.11 m), so a foot on a rung
    stands on its toes. Side rails `stile_left` and `stile_right` (ours): 0.04 m x 0.075 m
    bars either side of the rungs, from the ground to one spacing above the top rung. Every
    length x robot.scale."""
    s = robot.scale
    x, depth, spacing = LADDER_X * s, PAPER_RUNG_DEPTH_M * s, PAPER_RUNG_SPACING_M * s
    half_length, thickness = 0.5 * LADDER_RUNG_LENGTH * s, LADDER_RUNG_THICKNESS * s
    rungs = tuple(
        _block(
            f"rung_{k:02d}",
            (x - 0.5 * depth, x + 0.5 * depth),
            (-half_length, half_length),
            (k * spacing - thickness, k * spacing),
        )
        for k in range(1, LADDER_RUNG_COUNT + 1)
    )
    stile_depth, stile_width = LADDER_STILE_DEPTH * s, LADDER_STILE_WIDTH * s
    height = (LADDER_RUNG_COUNT + 1) * spacing
    x_range = (x - 0.5 * stile_depth, x + 0.5 * stile_depth)
    stiles = (
        _block("stile_left", x_range, (half_length, half_length + stile_width), (0.0, height)),
        _block("stile_right", x_range, (-half_length - stile_width, -half_length), (0.0, height)),
    )
    return Scene(boxes=rungs + stiles, friction=PAPER_FRICTION)


def hand_supports(robot: RobotDescription) -> Scene:
    """Fig. 4 (D): two support surfaces at 500 mm for the hands (paper).

    `support_left` and `support_right` (ours but the height): solid blocks from the ground to
    0.500 m, 0.16 m wide, centred at y = +-0.32 m, from x = -0.30 m (beside the robot's start)
    to 1.50 m. At scale 1 the palms are at 0.79 m in the standing posture: reaching 0.5 m
    takes a crouch or a forward lean, as for the paper's 1.8 m robot; the scene's fall height
    is `SUPPORT_FALL_HEIGHT` for that crouch. Every length x robot.scale."""
    s = robot.scale
    x_range = (SUPPORT_X_RANGE[0] * s, SUPPORT_X_RANGE[1] * s)
    y, half_width, top = SUPPORT_Y * s, 0.5 * SUPPORT_WIDTH * s, PAPER_SUPPORT_HEIGHT_M * s
    return Scene(
        boxes=(
            _block("support_left", x_range, (y - half_width, y + half_width), (0.0, top)),
            _block("support_right", x_range, (-y - half_width, -y + half_width), (0.0, top)),
        ),
        friction=PAPER_FRICTION,
        fall_height=SUPPORT_FALL_HEIGHT * s,
    )


def moving_contacts(robot: RobotDescription) -> Scene:
    """Fig. 4 (E): floors and walls moving periodically, 20 mm and 2 deg amplitude (paper).

    No ground (ours): the robot stands on two moving floor plates, `floor_left` and
    `floor_right`, 0.80 m x 0.40 m x 0.10 m, one under each foot with a 0.01 m gap between them,
    their top faces at z = 0 in their mean pose (where the robot starts). Two moving walls,
    `wall_left` and `wall_right`, faces at y = +-0.45 m, 0.80 m long, 0.10 m thick, from z = 0 to
    1.80 m. The motions (ours but the amplitudes), with period T = `MOTION_PERIOD_S` (8 s) x
    sqrt(scale) and their amplitude ramping in over the first half period
    (`MovingBox.ramp_time`, so everything starts at rest in its mean pose):
    - floors: 20 mm vertically (along their normal) and 2 deg about the world y axis (pitch)
      through their centres; the right floor in antiphase to the left (phase pi);
    - walls: 20 mm along y (their normal) and 2 deg about the world x axis (leaning toward and
      away from the robot) through their centres; phases pi/2 (left) and 3 pi/2 (right).
    Translations x robot.scale; angles not scaled."""
    s = robot.scale
    period = MOTION_PERIOD_S * froude_time_scale(s)
    ramp = MOTION_RAMP_PERIODS * period
    amplitude, angle = PAPER_MOTION_TRANSLATION_M * s, PAPER_MOTION_ROTATION_RAD
    half_length, half_width = 0.5 * FLOOR_PLATE_LENGTH * s, 0.5 * FLOOR_PLATE_WIDTH * s
    half_thickness, y = 0.5 * FLOOR_PLATE_THICKNESS * s, 0.5 * FLOOR_PLATE_GAP * s + half_width
    floors = tuple(
        MovingBox(
            name,
            (0.0, sign * y, -half_thickness),
            (half_length, half_width, half_thickness),
            translation_amplitude_world=(0.0, 0.0, amplitude),
            rotation_axis_world=(0.0, 1.0, 0.0),
            rotation_amplitude=angle,
            period=period,
            phase=phase,
            ramp_time=ramp,
        )
        for name, sign, phase in (("floor_left", 1.0, 0.0), ("floor_right", -1.0, math.pi))
    )
    face, half_wall = WALL_INNER_FACE_Y * s, 0.5 * WALL_THICKNESS * s
    half_wall_length, half_height = 0.5 * MOVING_WALL_LENGTH * s, 0.5 * MOVING_WALL_HEIGHT * s
    walls = tuple(
        MovingBox(
            name,
            (0.0, sign * (face + half_wall), half_height),
            (half_wall_length, half_wall, half_height),
            translation_amplitude_world=(0.0, amplitude, 0.0),
            rotation_axis_world=(1.0, 0.0, 0.0),
            rotation_amplitude=angle,
            period=period,
            phase=phase,
            ramp_time=ramp,
        )
        for name, sign, phase in (
            ("wall_left", 1.0, 0.5 * math.pi),
            ("wall_right", -1.0, 1.5 * math.pi),
        )
    )
    return Scene(moving_boxes=floors + walls, friction=PAPER_FRICTION, ground=False)


MULTI_CONTACT_SCENES: dict[str, Callable[[RobotDescription], Scene]] = {
    "hand_wall": hand_wall,
    "handrail_stairs": handrail_stairs,
    "ladder": ladder,
    "hand_supports": hand_supports,
    "moving_contacts": moving_contacts,
}
"""Fig. 4's scenes (A)-(E) by the issue's scenario names."""
