"""Hierarchical least squares (centroidal.hierarchy): DAQP's hierarchical mode against the QP
cascade on controller-size problems, hand-solved examples, warm start and bad input."""

import numpy as np
import pytest

from centroidal import hierarchy
from centroidal.hierarchy import SOLVERS, HierarchyError, Level, solve_hierarchy

N = 85  # the controller's variable count


def _rows(rng, m, n):
    """Gaussian rows with norms spread over a factor 10, so that row scaling matters."""
    return rng.normal(size=(m, n)) * rng.uniform(0.3, 3.0, size=(m, 1))


def _inequalities(rng, a, value, half_width, one_sided):
    lower, upper = value - half_width, value + half_width
    lower[:one_sided] = -np.inf
    upper[one_sided : 2 * one_sided] = np.inf
    return Level(a, lower, upper)


def controller_levels(seed, feasible, n=N):
    """Level 1: 60 equalities + 60 inequalities, feasible. Level 2: 2 equalities, in conflict
    with level 1 unless `feasible`. Level 3: 60 equalities + 20 inequalities (more than the
    degrees of freedom left, so infeasible unless `feasible`). Row norms vary over 10x."""
    rng = np.random.default_rng(seed)
    x0 = rng.normal(size=n)
    eq1, in1 = _rows(rng, 60, n), _rows(rng, 60, n)
    first = _inequalities(rng, in1, in1 @ x0, rng.uniform(0.0, 1.0, 60), 20)
    # The first level-2 row lies in the span of level 1's equalities, so level 1 pins its value.
    a2 = np.vstack([rng.normal(size=60) @ eq1 / np.sqrt(60), _rows(rng, 1, n)])
    t2 = a2 @ x0 + (0.0 if feasible else rng.normal(scale=5.0, size=2))
    eq3, in3 = _rows(rng, 60, n), _rows(rng, 20, n)
    t3 = eq3 @ x0 + (0.0 if feasible else rng.normal(scale=2.0, size=60))
    centre = in3 @ x0 + (0.0 if feasible else rng.normal(scale=3.0, size=20))
    third = _inequalities(rng, in3, centre, rng.uniform(0.0, 0.5, 20), 5)
    return [
        Level(
            np.vstack([eq1, in1]),
            np.concatenate([eq1 @ x0, first.lower]),
            np.concatenate([eq1 @ x0, first.upper]),
            name="contacts",
        ),
        Level(a2, t2, t2, name="com"),
        Level(
            np.vstack([eq3, in3]),
            np.concatenate([t3, third.lower]),
            np.concatenate([t3, third.upper]),
            name="posture",
        ),
    ]


def underdetermined_levels(seed, n=30):
    """15 equalities in 30 variables: the least-norm tie-break decides x."""
    rng = np.random.default_rng(seed)
    x0 = rng.normal(size=n)
    eq1, in1, a2, eq3, in3 = (_rows(rng, m, n) for m in (5, 10, 4, 6, 5))
    first = _inequalities(rng, in1, in1 @ x0, rng.uniform(0.0, 0.3, 10), 3)
    t2 = a2 @ x0 + rng.normal(size=4)
    t3 = eq3 @ x0 + rng.normal(size=6)
    third = _inequalities(rng, in3, in3 @ x0 + rng.normal(size=5), np.full(5, 0.1), 2)
    return [
        Level(
            np.vstack([eq1, in1]),
            np.concatenate([eq1 @ x0, first.lower]),
            np.concatenate([eq1 @ x0, first.upper]),
        ),
        Level(a2, t2, t2),
        Level(
            np.vstack([eq3, in3]),
            np.concatenate([t3, third.lower]),
            np.concatenate([t3, third.upper]),
        ),
    ]


@pytest.mark.parametrize("feasible", [False, True])
@pytest.mark.parametrize("seed", [0, 1, 2, 3])
def test_daqp_equals_cascade_on_controller_size(seed, feasible):
    levels = controller_levels(seed, feasible)
    assert sum(level.a.shape[0] for level in levels) == 202
    daqp = solve_hierarchy(levels, N)
    cascade = solve_hierarchy(levels, N, solver="cascade")
    assert daqp.exitflag in (1, 2)
    assert daqp.polished  # the exact active-set polish was kept
    # one QP when levels 1-2 can be met, else two: levels 1-2, then all with level 2 held
    assert daqp.qps == (1 if feasible else 2)
    assert daqp.single_qp == feasible
    np.testing.assert_allclose(daqp.violation_norm, cascade.violation_norm, rtol=0, atol=1e-6)
    np.testing.assert_allclose(daqp.x, cascade.x, rtol=0, atol=1e-6)
    for solution in (daqp, cascade):
        for level, r, norm in zip(levels, solution.violation, solution.violation_norm, strict=True):
            np.testing.assert_array_equal(r, level.violation(solution.x))
            assert norm == pytest.approx(np.linalg.norm(r), abs=1e-12)
    if feasible:
        assert max(cascade.violation_norm) < 1e-6
    else:  # the conflicts the problem was built with are real
        assert cascade.violation_norm[0] < 1e-6
        assert min(cascade.violation_norm[1:]) > 0.1


@pytest.mark.parametrize("solver", SOLVERS)
@pytest.mark.parametrize("seed", [4, 5])
def test_infeasible_level_2_leaves_level_1_and_level_3_leaves_level_2(seed, solver):
    levels = controller_levels(seed, feasible=False)
    alone = solve_hierarchy([levels[1]], N, solver=solver)
    assert alone.violation_norm[0] < 1e-8  # level 2 by itself is feasible...
    full = solve_hierarchy(levels, N, solver=solver)
    assert full.violation_norm[0] < 1e-7  # ...but level 1 keeps its rows satisfied
    assert full.violation_norm[1] > 0.1
    two = solve_hierarchy(levels[:2], N, solver=solver)
    assert full.violation_norm[0] == pytest.approx(two.violation_norm[0], abs=1e-7)
    assert full.violation_norm[1] == pytest.approx(two.violation_norm[1], abs=1e-6)
    assert full.violation_norm[2] > 1.0  # level 3 is not satisfied either: it had to yield


@pytest.mark.parametrize("solver", SOLVERS)
def test_hand_solved_three_levels(solver):
    # |x1 + x2| <= 1, then |x1 - x2| <= 3, then x1 = 5. Adding the two upper bounds gives
    # x1 <= 2, so x1 = 2 (level 3 off by 3) and both bounds are tight: x2 = -1.
    levels = [
        Level(np.array([[1.0, 1.0]]), np.array([-1.0]), np.array([1.0])),
        Level(np.array([[1.0, -1.0]]), np.array([-3.0]), np.array([3.0])),
        Level(np.array([[1.0, 0.0]]), np.array([5.0]), np.array([5.0])),
    ]
    solution = solve_hierarchy(levels, 2, solver=solver)
    np.testing.assert_allclose(solution.x, [2.0, -1.0], atol=1e-8)
    np.testing.assert_allclose(solution.violation_norm, [0.0, 0.0, 3.0], atol=1e-8)
    np.testing.assert_allclose(solution.violation[2], [-3.0], atol=1e-8)


@pytest.mark.parametrize("solver", SOLVERS)
def test_hand_solved_conflicting_top_level_and_tie_break(solver):
    # Level 1: x1 >= 3 and x1 <= 1 conflict: least squares splits them, x1 = 2, r = (-1, 1).
    # Level 2: x2 >= 7 (one-sided); least norm then takes x2 = 7, x3 = 0.
    levels = [
        Level(
            np.array([[1.0, 0, 0], [1.0, 0, 0]]), np.array([3.0, -np.inf]), np.array([np.inf, 1])
        ),
        Level(np.array([[0, 1.0, 0]]), np.array([7.0]), np.array([np.inf])),
    ]
    solution = solve_hierarchy(levels, 3, solver=solver)
    np.testing.assert_allclose(solution.x, [2.0, 7.0, 0.0], atol=1e-8)
    np.testing.assert_allclose(solution.violation[0], [-1.0, 1.0], atol=1e-8)
    assert solution.violation_norm[1] == pytest.approx(0.0, abs=1e-8)


@pytest.mark.parametrize("solver", SOLVERS)
def test_rows_of_unequal_norm_are_weighed_by_their_plain_residual(solver):
    # x1 = 0 and 100 x1 = 100 conflict: min x1^2 + (100 x1 - 100)^2 at x1 = 10000 / 10001.
    # (A row-normalised least squares, DAQP's native weighting, would give x1 = 0.5.)
    level = Level(np.array([[1.0, 0.0], [100.0, 0.0]]), np.array([0.0, 100]), np.array([0.0, 100]))
    solution = solve_hierarchy([level], 2, solver=solver)
    np.testing.assert_allclose(solution.x, [10000 / 10001, 0.0], rtol=0, atol=1e-9)
    assert solution.violation_norm[0] == pytest.approx(100 / np.sqrt(10001), abs=1e-9)


@pytest.mark.parametrize("solver", SOLVERS)
def test_regularization_breaks_ties(solver):
    # x1 + x2 = 2: least norm gives (1, 1); least x1^2 + 4 x2^2 gives x1 = 4 x2, (1.6, 0.4).
    level = Level(np.array([[1.0, 1.0]]), np.array([2.0]), np.array([2.0]))
    plain = solve_hierarchy([level], 2, solver=solver)
    weighted = solve_hierarchy([level], 2, solver=solver, regularization=np.diag([1.0, 4.0]))
    np.testing.assert_allclose(plain.x, [1.0, 1.0], atol=1e-8)
    np.testing.assert_allclose(weighted.x, [1.6, 0.4], atol=1e-8)


@pytest.mark.parametrize("seed", [0, 1])
def test_daqp_equals_cascade_when_the_tie_break_decides(seed):
    levels = underdetermined_levels(seed)
    rng = np.random.default_rng(100 + seed)
    b = rng.normal(size=(30, 30))
    hess = b @ b.T / 30 + 0.1 * np.eye(30)
    for regularization in (None, hess):
        daqp = solve_hierarchy(levels, 30, regularization=regularization)
        cascade = solve_hierarchy(levels, 30, solver="cascade", regularization=regularization)
        np.testing.assert_allclose(daqp.violation_norm, cascade.violation_norm, atol=1e-6)
        np.testing.assert_allclose(daqp.x, cascade.x, atol=1e-6)
    plain = solve_hierarchy(levels, 30)
    weighted = solve_hierarchy(levels, 30, regularization=hess)
    for solution in (plain, weighted):  # one QP, its tie-break polished exact
        assert solution.single_qp
        assert solution.polished
    assert np.abs(plain.x - weighted.x).max() > 1e-3  # the tie-break really chose x
    assert weighted.x @ hess @ weighted.x < plain.x @ hess @ plain.x


@pytest.mark.parametrize("last_equalities_only", [False, True])
@pytest.mark.parametrize("seed", [8, 9])
def test_one_qp_equals_the_level_by_level_solve(seed, last_equalities_only, monkeypatch):
    """When levels 1-2 can be met exactly, the one QP (the last level as its cost) and DAQP's
    hierarchical mode give the same x; the one QP is taken without being forced."""
    levels = controller_levels(seed, feasible=True)
    if last_equalities_only:  # the controller's case: level 3 is objectives only
        third = levels[2]
        rng = np.random.default_rng(1000 + seed)  # not controller_levels' draws
        target = third.a[:60] @ rng.normal(size=N)  # not met: level 3 is infeasible
        levels[2] = Level(third.a[:60], target, target)
    one = solve_hierarchy(levels, N)
    assert one.single_qp
    assert one.polished
    monkeypatch.setattr(hierarchy, "_solve_single_qp", lambda *args: None)
    by_level = solve_hierarchy(levels, N)
    assert not by_level.single_qp
    np.testing.assert_allclose(one.violation_norm, by_level.violation_norm, rtol=0, atol=1e-7)
    np.testing.assert_allclose(one.x, by_level.x, rtol=0, atol=1e-7)
    if last_equalities_only:
        assert one.violation_norm[2] > 0.1


@pytest.mark.parametrize("seed", [14, 15, 16])
def test_qps_in_sequence_equal_the_level_by_level_solve(seed, monkeypatch):
    """Level 2 in conflict with level 1 (one of its rows pinned by level 1's equalities, held
    as an equality again all the same): levels 1-2 as one QP, then all three with level 2's
    violated rows held at their values, give DAQP's hierarchical mode's x, and the cascade's;
    with a fourth level below (a range per variable) level 3, not met, is held in turn: the
    sequence recurses (3 QPs)."""
    levels = controller_levels(seed, feasible=False)
    rng = np.random.default_rng(3000 + seed)  # not controller_levels' draws
    low = rng.normal(size=N)
    fourth = Level(np.eye(N), low, low + 1.0)  # x_i in a range
    for stack, qps in ((levels, 2), ([*levels[:2], levels[2], fourth], 3)):
        sequence = solve_hierarchy(stack, N)
        assert sequence.qps == qps
        assert sequence.polished
        assert min(sequence.violation_norm[1:3]) > 0.1  # levels 2 and 3 really are not met
        with monkeypatch.context() as patch:
            patch.setattr(hierarchy, "_solve_qp_sequence", lambda *args: None)
            by_level = solve_hierarchy(stack, N)
        assert by_level.qps == 0
        cascade = solve_hierarchy(stack, N, solver="cascade")
        for other in (by_level, cascade):
            np.testing.assert_allclose(
                sequence.violation_norm, other.violation_norm, rtol=0, atol=1e-6
            )
            np.testing.assert_allclose(sequence.x, other.x, rtol=0, atol=1e-6)


def _level(a, lower, upper):
    return Level(
        np.array(a, dtype=float), np.array(lower, dtype=float), np.array(upper, dtype=float)
    )


@pytest.mark.parametrize(
    "levels",
    [
        # x0 = 0 pins level 2's row but for 1e-7 x2: level 2 chooses x2 = +10 (0.999999 left),
        # level 3's x2 = -10 must not undo that (a version that freed pinned rows gave -10)
        [
            _level([[1, 0, 0], [0, 0, 1]], [0, -10], [0, 10]),
            _level([[1, 0, 1e-7]], [1], [1]),
            _level([[0, 0, 1], [0, 1, 0]], [-10, 1], [-10, 1]),
        ],
        # x0 <= 0 against x0 >= 1, and 1e-4 x1 = 5e-4 with x1 <= 5 - 1e-6: level 2 wants x1 at
        # its bound; level 3's x1 = 0 must not pull it back (a version that held the unpolished
        # answer of levels 1-2 gave x1 = 4.5455)
        [
            _level([[1, 0], [0, 1]], [-np.inf, -np.inf], [0, 5 - 1e-6]),
            _level([[1, 0], [0, 1e-4]], [1, 5e-4], [np.inf, 5e-4]),
            _level([[0, 1]], [0], [0]),
        ],
    ],
    ids=["nearly_pinned_row", "answer_not_polished"],
)
def test_qps_in_sequence_on_a_review_s_edge_cases(levels, monkeypatch):
    """Two hierarchies a review built against the sequence of QPs: the backend's answer is the
    hierarchical mode's (whichever path it takes) and, within the cascade's own accuracy, the
    cascade's."""
    n = levels[0].a.shape[1]
    answer = solve_hierarchy(levels, n)
    with monkeypatch.context() as patch:
        patch.setattr(hierarchy, "_solve_qp_sequence", lambda *args: None)
        by_level = solve_hierarchy(levels, n)
    cascade = solve_hierarchy(levels, n, solver="cascade")
    np.testing.assert_allclose(answer.x, by_level.x, rtol=0, atol=1e-7)
    np.testing.assert_allclose(answer.violation_norm, by_level.violation_norm, rtol=0, atol=1e-9)
    np.testing.assert_allclose(answer.x, cascade.x, rtol=0, atol=1e-4)


@pytest.mark.parametrize("seed", [10, 11])
def test_one_qp_with_the_last_levels_inequalities_violated(seed):
    """Levels 1-2 met, level 3 (equalities and inequalities) not: the one QP's slacks carry the
    violated inequality rows, and the answer is the cascade's."""
    levels = controller_levels(seed, feasible=True)
    levels[2] = controller_levels(seed, feasible=False)[2]
    one = solve_hierarchy(levels, N)
    cascade = solve_hierarchy(levels, N, solver="cascade")
    assert one.single_qp
    third = levels[2]
    inequality = third.lower != third.upper
    assert np.abs(one.violation[2][inequality]).max() > 1e-3  # some slack is really used
    np.testing.assert_allclose(one.violation_norm, cascade.violation_norm, rtol=0, atol=1e-6)
    np.testing.assert_allclose(one.x, cascade.x, rtol=0, atol=1e-6)


def test_one_qp_is_exact_whatever_the_scale_of_the_last_level_or_h():
    """x >= 2.9 at level 1, x = 3 at level 2: x = 3 whatever the rows' or the regularization's
    scale (with the tie-break weighed against unscaled rows, a regularization of 1e8 or a last
    level of norm 1e-4 put x on the level-1 bound, 2.9, with `polished` set)."""
    first = Level(np.array([[1.0]]), np.array([2.9]), np.array([np.inf]))
    for second, hess in (
        (Level(np.array([[1.0]]), np.array([3.0]), np.array([3.0])), np.array([[1e8]])),
        (Level(np.array([[1e-4]]), np.array([3e-4]), np.array([3e-4])), None),
    ):
        solution = solve_hierarchy([first, second], 1, regularization=hess)
        assert solution.single_qp
        assert solution.x[0] == pytest.approx(3.0, abs=1e-9)


@pytest.mark.parametrize("seed", [12, 13])
def test_one_qp_equals_the_cascade_with_a_small_last_level_and_a_large_h(seed):
    levels = controller_levels(seed, feasible=True)
    third = levels[2]
    rng = np.random.default_rng(2000 + seed)
    target = third.a[:60] @ rng.normal(size=N)  # level 3 not met
    small = Level(1e-4 * third.a[:60], 1e-4 * target, 1e-4 * target)
    for last, hess in ((small, None), (Level(third.a[:60], target, target), 1e8 * np.eye(N))):
        hierarchy_levels = [*levels[:2], last]
        one = solve_hierarchy(hierarchy_levels, N, regularization=hess)
        cascade = solve_hierarchy(hierarchy_levels, N, solver="cascade", regularization=hess)
        assert one.single_qp
        np.testing.assert_allclose(one.violation_norm, cascade.violation_norm, atol=1e-6)
        np.testing.assert_allclose(one.x, cascade.x, rtol=0, atol=1e-6)


@pytest.mark.parametrize("seed", [0, 1, 2])
def test_row_pinned_by_equalities_above(seed):
    # A level-2 row in the span of level 1's equalities: given to DAQP 0.11 as is, it makes the
    # level-3 answer wrong (nonzero on this feasible hierarchy) in most draws.
    rng = np.random.default_rng(seed)
    n = 10
    x0 = rng.normal(size=n)
    eq1, in1 = rng.normal(size=(3, n)), rng.normal(size=(3, n))
    first = _inequalities(rng, in1, in1 @ x0, rng.uniform(0.0, 1.0, 3), 0)
    a2 = np.vstack([rng.normal(size=3) @ eq1, rng.normal(size=n)])
    eq3 = rng.normal(size=(5, n))
    levels = [
        Level(
            np.vstack([eq1, in1]),
            np.concatenate([eq1 @ x0, first.lower]),
            np.concatenate([eq1 @ x0, first.upper]),
        ),
        Level(a2, a2 @ x0, a2 @ x0),
        Level(eq3, eq3 @ x0, eq3 @ x0),
    ]
    daqp = solve_hierarchy(levels, n)
    cascade = solve_hierarchy(levels, n, solver="cascade")
    np.testing.assert_allclose(daqp.violation_norm, 0.0, atol=1e-8)
    np.testing.assert_allclose(daqp.x, cascade.x, atol=1e-7)


@pytest.mark.parametrize("solver", SOLVERS)
def test_empty_level_and_zero_row(solver):
    # The three-level example with an empty level inserted, and a zero row that no x satisfies.
    levels = [
        Level(np.array([[1.0, 1.0], [0.0, 0.0]]), np.array([-1.0, 1]), np.array([1.0, 2])),
        Level(np.zeros((0, 2)), np.zeros(0), np.zeros(0), name="empty"),
        Level(np.array([[1.0, -1.0]]), np.array([-3.0]), np.array([3.0])),
        Level(np.array([[1.0, 0.0]]), np.array([5.0]), np.array([5.0])),
    ]
    solution = solve_hierarchy(levels, 2, solver=solver)
    np.testing.assert_allclose(solution.x, [2.0, -1.0], atol=1e-8)
    np.testing.assert_allclose(solution.violation[0], [0.0, -1.0], atol=1e-8)
    assert solution.violation[1].shape == (0,)
    assert solution.violation_norm[3] == pytest.approx(3.0, abs=1e-8)


def test_daqp_refuses_row_norms_it_cannot_weigh():
    # Rows of norm 1 and 1e6 in one level: DAQP's soft trade-off cannot weigh them; the cascade
    # gives min x1^2 + (1e6 x1 - 1e6)^2 at x1 = 1e12 / (1e12 + 1).
    level = Level(np.array([[1.0, 0.0], [1e6, 0.0]]), np.array([0.0, 1e6]), np.array([0.0, 1e6]))
    with pytest.raises(HierarchyError, match="rescale rows"):
        solve_hierarchy([level], 2)
    solution = solve_hierarchy([level], 2, solver="cascade")
    np.testing.assert_allclose(solution.x, [1e12 / (1e12 + 1), 0.0], atol=1e-9)


@pytest.mark.parametrize("feasible", [False, True])
@pytest.mark.parametrize("seed", [6, 7])
def test_warm_start_repeats_the_cold_solution_in_no_more_iterations(seed, feasible):
    levels = controller_levels(seed, feasible)
    cold = solve_hierarchy(levels, N)
    assert cold.active.shape == (202,)
    warm = solve_hierarchy(levels, N, warm_start=cold.active)
    assert warm.iterations <= cold.iterations
    np.testing.assert_allclose(warm.x, cold.x, rtol=0, atol=1e-9)
    # A slightly moved problem, warm-started from the old solution: same answer as cold.
    rng = np.random.default_rng(seed)
    moved = []
    for level in levels:
        shift = rng.normal(scale=1e-3, size=level.a.shape[0])
        moved.append(Level(level.a, level.lower + shift, level.upper + shift))
    moved_cold = solve_hierarchy(moved, N)
    moved_warm = solve_hierarchy(moved, N, warm_start=cold.active)
    assert moved_warm.iterations <= moved_cold.iterations
    np.testing.assert_allclose(moved_warm.x, moved_cold.x, rtol=0, atol=1e-9)


@pytest.mark.parametrize("seed", [14, 15])
def test_one_qp_warm_started_on_moved_bounds_repeats_the_cold_solution(seed):
    """The controller's period to period: levels 1-2 met, level 3 not; the inequality bounds
    of level 1 and the targets of level 3 moved by 1e-3 (level 2 kept: moving it would
    contradict its row pinned by level 1). Warm-started from the last active set, the one QP
    takes fewer iterations than cold (measured: 1 against 42-50) and gives the same x."""
    levels = controller_levels(seed, feasible=True)
    rng = np.random.default_rng(3000 + seed)
    third = levels[2]
    target = third.a[:60] @ rng.normal(size=N)
    levels[2] = Level(third.a[:60], target, target)
    last = solve_hierarchy(levels, N)
    first = levels[0]
    shift = np.where(first.lower == first.upper, 0.0, rng.normal(scale=1e-3, size=len(first.lower)))
    moved_target = target + rng.normal(scale=1e-3, size=60)
    moved = [
        Level(first.a, first.lower + shift, first.upper + shift),
        levels[1],
        Level(third.a[:60], moved_target, moved_target),
    ]
    cold = solve_hierarchy(moved, N)
    warm = solve_hierarchy(moved, N, warm_start=last.active)
    assert cold.single_qp
    assert warm.single_qp
    assert warm.iterations < cold.iterations
    np.testing.assert_allclose(warm.x, cold.x, rtol=0, atol=1e-9)


def _one_line_value_error(make, match):
    with pytest.raises(ValueError, match=match) as error:
        make()
    assert "\n" not in str(error.value)


@pytest.mark.parametrize(
    ("make", "match"),
    [
        (lambda: Level(np.ones(3), np.zeros(3), np.ones(3)), "must be 2-D"),
        (lambda: Level(np.ones((3, 2)), np.zeros(2), np.ones(3)), r"shape \(3,\)"),
        (lambda: Level(np.ones((2, 2)), np.array([0.0, 2]), np.array([1.0, 1])), "lower > upper"),
        (lambda: Level(np.array([[np.nan, 1]]), np.zeros(1), np.ones(1)), "NaN"),
        (lambda: Level(np.ones((1, 2)), np.array([np.nan]), np.ones(1)), "NaN"),
        (lambda: Level(np.ones((1, 2)), np.array([np.inf]), np.array([np.inf])), r"\+inf"),
    ],
)
def test_bad_level_raises_one_line_value_error(make, match):
    _one_line_value_error(make, match)


def test_bad_solve_arguments_raise_one_line_value_error():
    level = Level(np.ones((1, 2)), np.zeros(1), np.ones(1))
    _one_line_value_error(lambda: solve_hierarchy([level], 3), "2 columns, not 3")
    _one_line_value_error(lambda: solve_hierarchy([], 2), "non-empty")
    _one_line_value_error(lambda: solve_hierarchy([level], 2, solver="lexls"), "daqp, cascade")
    _one_line_value_error(
        lambda: solve_hierarchy([level], 2, regularization=np.diag([1.0, -1.0])),
        "positive definite",
    )
    _one_line_value_error(
        lambda: solve_hierarchy([level], 2, warm_start=np.zeros(2, dtype=np.intc)), "1 rows"
    )


@pytest.mark.parametrize("shape", [(82, 28), (54, 2), (52, 97), (30, 30), (1, 5), (7, 1)])
def test_the_polish_s_lapack_calls_are_scipy_s_bit_for_bit(shape):
    """The polish calls LAPACK itself (`_qr_pivoted`, `_solve_triangular`) to save
    scipy.linalg's wrappers: the same routines, with the same workspace and the same flags, so
    the same bits as scipy.linalg.qr(pivoting=True) and solve_triangular, whether the matrix is
    wide or tall, C- or Fortran-ordered (a changed bit would change the hierarchy's episodes,
    which are chaotic)."""
    import scipy.linalg

    rng = np.random.default_rng(sum(shape))
    a = rng.normal(size=shape) * rng.uniform(0.01, 100.0, size=(shape[0], 1))
    a[:, 0] = 0.0  # a rank deficiency, and zeros of both signs
    a[-1, :] *= -0.0
    for matrix in (a, np.asfortranarray(a)):
        q, packed, perm = hierarchy._qr_pivoted(matrix)
        q_ref, r_ref, perm_ref = scipy.linalg.qr(matrix, pivoting=True)
        np.testing.assert_array_equal(q, q_ref)
        np.testing.assert_array_equal(np.triu(packed), r_ref)
        np.testing.assert_array_equal(np.diag(packed), np.diag(r_ref))
        np.testing.assert_array_equal(perm, perm_ref)
    k = min(shape)
    triangle = np.triu(rng.normal(size=(k, k))) + 3.0 * np.eye(k)
    rhs = rng.normal(size=k)
    for matrix in (triangle, triangle.T, np.asfortranarray(triangle), triangle.T.copy()):
        lower = bool(np.allclose(matrix, np.tril(matrix)))
        np.testing.assert_array_equal(
            hierarchy._solve_triangular(matrix, rhs, lower=lower),
            scipy.linalg.solve_triangular(matrix, rhs, lower=lower),
        )
