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


def test_rows_built_from_the_cache_are_the_bits_built_afresh(monkeypatch):
    """The planner keeps the scaled rows whose matrix is fixed by a key (`_Rows.add`, `key`)
    for the episode. Over a reach's standing start, walk start, swings and a held footstep,
    every period's three levels equal bit for bit the levels built without the cache (so the
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
    planner.reset(model, reach(model), state)
    end = planner.schedule.walk_start + 2 * planner.schedule.period_s
    for t in np.arange(0.0, end, 0.02):
        planner.plan(float(t), state)
    assert len(compared) == len(np.arange(0.0, end, 0.02))
    assert {"air", "footstep_box", "footstep_kept", "swing_xy", "cop_preview"} <= names
    assert compared[-1] >= 15  # keyed blocks: contacts, joints, steps, preview rows per axis
