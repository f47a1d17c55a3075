"""Rows of the capturability hierarchy (issue 18) that the closed-loop tests do not isolate."""

import numpy as np
import pytest

from bench.runner import cached_model, humanoid
from bench.scenarios import reach
from planners.capturability_hierarchy import ADAPTATION_BLOCK_S, CapturabilityHierarchyPlanner


def test_a_footstep_held_near_touchdown_replaces_its_rectangle():
    """In the last `ADAPTATION_BLOCK_S` of a swing the next footstep is held where the last
    period put it (the paper's workaround), and its rectangle (eq. 12) leaves the hierarchy:
    together with the held value it made the rows degenerate (DAQP exitflag 3 and every
    cascade QP solver failing, measured in `reach_push`). The second footstep keeps its
    rectangle, and the held step comes out of the solve unchanged."""
    model = cached_model(humanoid(1.0))
    state = model.standing_state()
    planner = CapturabilityHierarchyPlanner(0.002)
    planner.reset(model, reach(model), state)
    swing_start = planner.schedule.walk_start
    end = swing_start + planner.schedule.single_s
    before = end - ADAPTATION_BLOCK_S - 0.01  # still adapting
    planner.plan(before, state)
    first = list(planner.row_names[0])
    assert planner.last_phase.swing is not None
    assert first.count("footstep_box") == 4
    assert "footstep_kept" not in first
    held = planner.last_step.copy()
    planner.plan(end - ADAPTATION_BLOCK_S / 2, state)
    first = list(planner.row_names[0])
    assert first.count("footstep_kept") == 2
    assert first.count("footstep_box") == 2  # the second footstep's rectangle only
    np.testing.assert_allclose(planner.last_step, held, atol=1e-9)


def test_a_hierarchy_no_solver_solves_holds_the_last_answer_a_few_periods(monkeypatch):
    """When DAQP and the reference cascade both fail, the last period's answer (same rows) is
    held, counted as a solver failure, for at most `HOLD_PERIODS_MAX` periods in a row; then
    the failure ends the episode (HierarchyError). A solve that succeeds resets the count."""
    import planners.capturability_hierarchy as module
    from centroidal.hierarchy import HierarchyError

    model = cached_model(humanoid(1.0))
    state = model.standing_state()
    planner = CapturabilityHierarchyPlanner(0.002)
    planner.reset(model, reach(model), state)
    solved = planner.plan(0.0, state)
    solve = module.solve_hierarchy

    def failing(*args, **kwargs):
        raise HierarchyError("no solution (test)")

    monkeypatch.setattr(module, "solve_hierarchy", failing)
    for k in range(module.HOLD_PERIODS_MAX):
        held = planner.plan(0.002 * (k + 1), state)
        np.testing.assert_array_equal(
            held.generalized_acceleration, solved.generalized_acceleration
        )
        assert planner.solver_failures == k + 1
    with pytest.raises(HierarchyError):
        planner.plan(0.002 * (module.HOLD_PERIODS_MAX + 1), state)
    monkeypatch.setattr(module, "solve_hierarchy", solve)
    planner.plan(0.02, state)
    assert planner.held == 0


@pytest.mark.parametrize("scenario", ["reach", "walk"])
def test_rows_built_from_the_cache_are_the_bits_built_afresh(monkeypatch, scenario):
    """The planner keeps the scaled rows whose matrix is fixed by a key (`_Rows.add`, `key`)
    for the episode. Over a reach's standing start, walk start, swings and a held footstep,
    and over a walk's last two steps and its end (the samples after it on both feet), every
    period's three levels equal bit for bit the levels built without the cache (so the
    cache changes no episode), and the cache is used (it holds the keyed blocks)."""
    original = CapturabilityHierarchyPlanner._levels
    compared, names = [], set()

    def checked(self, *args):
        levels, context = original(self, *args)
        cache, self._row_cache = self._row_cache, None
        try:
            fresh, fresh_context = original(self, *args)
        finally:
            self._row_cache = cache
        np.testing.assert_array_equal(context, fresh_context)
        for level, afresh in zip(levels, fresh, strict=True):
            for field in ("a", "lower", "upper"):
                np.testing.assert_array_equal(getattr(level, field), getattr(afresh, field))
        names.update(self.row_names[0])
        compared.append(len(cache))
        return levels, context

    monkeypatch.setattr(CapturabilityHierarchyPlanner, "_levels", checked)
    model = cached_model(humanoid(1.0))
    state = model.standing_state()
    planner = CapturabilityHierarchyPlanner(0.002)
    if scenario == "reach":
        planner.reset(model, reach(model), state)
        start, end = 0.0, planner.schedule.walk_start + 2 * planner.schedule.period_s
    else:
        from bench.scenarios import walk

        planner.reset(model, walk(model), state)
        schedule = planner.schedule
        end = schedule.walk_start + schedule.steps * schedule.period_s + 0.1
        start = end - 2 * schedule.period_s - 0.1
    times = np.arange(start, end, 0.02)
    for t in times:
        planner.plan(float(t), state)
    assert len(compared) == len(times)
    assert {"air", "footstep_box", "footstep_kept", "swing_xy", "cop_preview"} <= names
    if scenario == "walk":
        assert "cop_after_walk" in names
    assert compared[-1] >= 15  # keyed blocks: contacts, joints, steps, preview rows per axis


def _levels_at(planner, t, state):
    """The three levels the planner solves at t (its `_levels`, captured)."""
    captured = {}
    original = planner._levels

    def capture(*args):
        captured["result"] = original(*args)
        return captured["result"]

    planner._levels = capture
    try:
        planner.plan(t, state)
    finally:
        del planner._levels
    return captured["result"][0]


def _walk_planner():
    from bench.scenarios import walk

    model = cached_model(humanoid(1.0))
    state = model.standing_state()
    planner = CapturabilityHierarchyPlanner(0.002)
    planner.reset(model, walk(model), state)
    schedule = planner.schedule
    return planner, state, schedule.walk_start + schedule.steps * schedule.period_s


def test_after_a_walk_the_preview_stands_on_both_feet():
    """In the last double support of a walk, standing at rest on both feet between them (the
    standing state), the samples after the walk's end are on both feet: the previewed CoP
    stays in the middle of the feet (within 1 cm), instead of moving onto the landed foot
    alone (its box and eq. 21's target until 2026-12-04, which on JVRC-1 held the CoP at the
    sole's edge after the walk and tipped it over in PyBullet)."""
    planner, state, end = _walk_planner()
    planner.plan(end - 0.05, state)
    assert planner.last_phase.swing is None
    assert planner.last_phase.step >= 0
    lay = planner.layout
    x = planner.last_solution[1].x
    cop = np.stack([x[lay.cop(0)], x[lay.cop(1)]], axis=1)
    middle = (planner.foothold["left_foot"] + planner.foothold["right_foot"]) / 2
    np.testing.assert_allclose(cop, np.tile(middle, (lay.samples, 1)), atol=0.01)
    landed = planner.foothold[planner.last_phase.stance]
    assert np.all(np.abs(cop[:, 1] - landed[1]) > planner.cop_extents[1])  # off the last sole


@pytest.mark.parametrize("last_steps", [2, 1])
def test_after_a_walk_the_preview_cop_is_bounded_by_both_soles(last_steps):
    """In the single support of the next-to-last step (the left foot swings) the samples
    after the walk's end stand on the two footsteps still to come (j = 1, 2); in the last
    one's (the right foot swings) on the stance foot and the next footstep (j = 0, 1).
    Eq. 11's rows there (`cop_after_walk`) hold a CoP between the soles laterally and within
    both soles' x extents, and refuse one a few millimetres beyond either sole's outer edge
    or behind the front sole's heel; eq. 21 centres it on their midpoint. Checked on the
    rows at chosen footsteps and CoPs."""
    planner, state, end = _walk_planner()
    t = end - (last_steps - 1) * planner.schedule.period_s - 0.3
    levels = _levels_at(planner, t, state)
    lay = planner.layout
    after = planner.schedule.samples_after_walk(t, planner.period_s, lay.samples)
    assert after.any()
    assert not after.all()
    names = np.array(planner.row_names[0])
    first = levels[0]
    rows = names == "cop_after_walk"
    assert rows.sum() == 2 * 2 * after.sum()  # two soles, two axes, per sample after the end
    half_x, half_y = planner.cop_extents
    x = np.zeros(lay.size)
    if last_steps == 2:
        assert planner.last_phase.swing == "left_foot"
        stance = planner.foothold["right_foot"]
        left = stance + np.array([0.10, 0.18])  # footstep 1
        right = left + np.array([0.10, -0.18])  # footstep 2
        x[lay.step(1)] = left - stance
        x[lay.step(2)] = right - left
    else:
        assert planner.last_phase.swing == "right_foot"
        left = planner.foothold["left_foot"]  # the stance foot, j = 0
        right = left + np.array([0.10, -0.18])  # footstep 1
        x[lay.step(1)] = right - left
        x[lay.step(2)] = np.array([0.3, 0.3])  # no part of these rows

    def holds(cop):
        x[lay.cop(0).start + np.flatnonzero(after)] = cop[0]
        x[lay.cop(1).start + np.flatnonzero(after)] = cop[1]
        value = first.a[rows] @ x
        return bool(np.all(value >= first.lower[rows] - 1e-9)) and bool(
            np.all(value <= first.upper[rows] + 1e-9)
        )

    middle = (left + right) / 2
    assert holds(middle)
    assert holds([right[0] - half_x + 0.001, right[1] - half_y + 0.001])  # inside the right sole
    assert holds([left[0] + half_x - 0.001, left[1] + half_y - 0.001])  # inside the left sole
    assert not holds([middle[0], right[1] - half_y - 0.005])  # beyond its outer edge
    assert not holds([middle[0], left[1] + half_y + 0.005])  # beyond the left one's
    assert not holds([right[0] - half_x - 0.005, middle[1]])  # behind the front sole's heel
    assert not holds([left[0] + half_x + 0.005, middle[1]])  # beyond the rear sole's toe
    # eq. 21 (level 3, rows "cop"): zero residual at the midpoint for the samples after the end
    third, names_3 = levels[2], np.array(planner.row_names[2])
    holds(middle)
    residual = third.a[names_3 == "cop"] @ x - third.lower[names_3 == "cop"]
    cop_rows = np.flatnonzero(np.tile(after, 2))
    np.testing.assert_allclose(residual[cop_rows], 0.0, atol=1e-9)
