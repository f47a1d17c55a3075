"""linear_mpc: the QP against an independent Riccati solution, the formulations against each
other, feasibility of the planned wrench, failures as data."""

from dataclasses import replace

import numpy as np
import pytest

from bench.scenarios import make_scenario
from centroidal.mpc import MpcModel, MpcProblem, MpcSolverError, MpcWeights, condensed, split
from centroidal.mpc_formulations import FORMULATIONS, make_formulation
from planners.linear_mpc import LinearMpcPlanner
from robots.humanoid import humanoid
from robots.limbs import PhaseContacts, limb_surfaces
from robots.model import RobotModel
from robots.scene import ContactPhase, Scenario


@pytest.fixture(scope="module")
def model():
    return RobotModel(humanoid())


def _state(model, com_offset=(0.0, 0.0, 0.0), velocity=(0.0, 0.0, 0.0)):
    state = model.standing_state()
    return replace(
        state,
        com_position_world=model.com_position_world(state) + np.array(com_offset),
        com_velocity_world=np.array(velocity, dtype=float),
    )


def _problem(model, scenario, t, horizon, x0, dtau=0.1, weights=None):
    """The MPC problem at time t built the planner's way (contacts per sample, c-hat = ref)."""
    robot = model.robot
    inertia = np.diag(model.constant_inertia())
    mpc = MpcModel(robot.total_mass, inertia, dtau, horizon, weights)
    phase_contacts = PhaseContacts(limb_surfaces(robot, scenario.scene.friction))
    generators = [phase_contacts(scenario.phase_at(t + k * dtau))[0].matrix for k in range(horizon)]
    points = np.tile(x0[:3], (horizon, 1))
    y_reference = np.zeros((horizon, 6))
    y_reference[:, :3] = x0[:3]
    maps = mpc.wrench_maps(generators, points)
    return mpc, MpcProblem(maps, x0, y_reference, generators=generators, points=points)


def _riccati_first_input(mpc: MpcModel, problem: MpcProblem) -> np.ndarray:
    """lambda_0 of the unconstrained problem by a backward Riccati recursion on the augmented
    state z = [x; 1] (time-varying input matrices B W_k): independent of the condensed QP."""
    n = mpc.horizon
    a_bar = np.zeros((13, 13))
    a_bar[:12, :12], a_bar[:12, 12], a_bar[12, 12] = mpc.a, mpc.e, 1.0
    q_out, r_in, u_ref = np.diag(mpc.q_output), np.diag(mpc.r_input), mpc.u_reference
    p_next = np.zeros((13, 13))
    gain_0 = None
    for k in reversed(range(n)):
        w = problem.maps[k]
        b_bar = np.zeros((13, w.shape[1]))
        b_bar[:12] = mpc.b @ w
        selector = np.zeros((6, 13))
        selector[:, :12], selector[:, 12] = mpc.c, -problem.y_reference[k]
        p_prime = p_next + selector.T @ q_out @ selector  # output cost on x_{k+1}
        e13 = np.zeros(13)
        e13[12] = 1.0
        cross = b_bar.T @ p_prime @ a_bar - np.outer(w.T @ r_in @ u_ref, e13)
        curvature = (
            b_bar.T @ p_prime @ b_bar + w.T @ r_in @ w + mpc.weights.ridge * np.eye(w.shape[1])
        )
        gain = np.linalg.solve(curvature, cross)
        p_next = (
            a_bar.T @ p_prime @ a_bar + (u_ref @ r_in @ u_ref) * np.outer(e13, e13) - cross.T @ gain
        )
        gain_0 = gain
    z0 = np.r_[problem.x0, 1.0]
    return -gain_0 @ z0


def test_unconstrained_first_input_equals_the_riccati_solution(model):
    """Standing on both feet, CoM 5 mm off its reference and moving: no ridge force reaches its
    bound, so the QP's first input is the unconstrained LQ optimum."""
    scenario = make_scenario("stand", model)
    state = _state(model, com_offset=(0.005, -0.003, 0.0), velocity=(0.02, 0.0, 0.0))
    x0 = np.r_[state.com_position_world, state.com_velocity_world, np.zeros(6)]
    x0_ref = x0.copy()
    x0_ref[:3] -= [0.005, -0.003, 0.0]
    mpc, problem = _problem(model, scenario, 0.0, 10, x0, weights=MpcWeights(ridge=1e-3))
    problem.y_reference[:, :3] = x0_ref[:3]
    lambdas = split(make_formulation("dense:daqp", mpc, 32).ridges(problem), problem.sizes)
    assert min(lam.min() for lam in lambdas) > 1e-3  # no bound active
    expected = _riccati_first_input(mpc, problem)
    np.testing.assert_allclose(lambdas[0], expected, rtol=1e-6, atol=1e-6)
    # and the same from the condensed system solved directly
    hessian, gradient = condensed(mpc, problem)
    direct = np.linalg.solve(hessian, -gradient)
    np.testing.assert_allclose(lambdas[0], direct[: problem.sizes[0]], rtol=1e-6, atol=1e-6)


@pytest.fixture(scope="module")
def walking_problem(model):
    """A problem across a contact switch: 6 samples of 0.1 s from t = 0.95 s of `walk`
    (double support, then the first single support), CoM 1 cm behind its reference."""
    scenario = make_scenario("walk", model)
    state = _state(model, com_offset=(-0.01, 0.0, 0.0))
    x0 = np.r_[state.com_position_world, state.com_velocity_world, np.zeros(6)]
    mpc, problem = _problem(model, scenario, 0.95, 6, x0)
    problem.y_reference[:, 1] = np.linspace(0.0, 0.06, 6)  # shift toward the support foot
    return mpc, problem


@pytest.mark.parametrize("name", FORMULATIONS)
def test_formulations_agree(walking_problem, name):
    mpc, problem = walking_problem
    assert len(set(problem.sizes)) == 2  # the horizon crosses a contact switch
    other = "dense:quadprog" if name != "dense:quadprog" else "sparse:clarabel"
    reference = make_formulation(other, mpc, 32).solve(problem)
    inputs = make_formulation(name, mpc, 32).solve(problem)
    assert inputs.shape == (mpc.horizon, 6)
    np.testing.assert_allclose(inputs[:, :3], reference[:, :3], atol=0.05)  # N, of ~570 N
    np.testing.assert_allclose(inputs[:, 3:], reference[:, 3:], atol=0.05)  # N m


@pytest.mark.parametrize("name", [f for f in FORMULATIONS if f.startswith("face:")])
def test_face_form_equals_ridge_form_where_the_cone_binds(walking_problem, name):
    """A reference 0.3 m to the side of the feet: the centre of pressure has to sit on the sole's
    edge, so faces are active; the wrenches still equal the ridge form's (eps ||lambda||^2, which
    the face form lacks, moves them by far less than the tolerance)."""
    mpc, problem = walking_problem
    problem = replace(problem, y_reference=problem.y_reference.copy())
    problem.y_reference[:, 1] += 0.3
    face = make_formulation(name, mpc, 32)
    inputs = face.solve(problem)
    reference = make_formulation("sparse:clarabel", mpc, 32).solve(problem)
    np.testing.assert_allclose(inputs[:, :3], reference[:, :3], atol=0.05)  # N
    np.testing.assert_allclose(inputs[:, 3:], reference[:, 3:], atol=0.05)  # N m
    about_origin = inputs.copy()
    about_origin[:, 3:] += np.cross(problem.points, inputs[:, :3])
    slack = [face.faces_of(g) @ w for g, w in zip(problem.generators, about_origin, strict=True)]
    assert max(s.max() for s in slack) < 1e-6  # feasible
    active = sum(
        int(np.sum(s > -1e-6 * np.abs(w).max())) for s, w in zip(slack, inputs, strict=True)
    )
    assert active >= 1  # and the cone binds


@pytest.mark.parametrize("shift", [0.0, 0.3])
def test_face_quadprog_working_set_gives_the_all_rows_answer(walking_problem, shift):
    """face:quadprog gives quadprog a working set of the faces, grown until no other face is
    violated: the same inputs as quadprog on every face, with and without binding faces (a
    reference 0.3 m to the side), from a cold start and from the last period's active set, and
    with fewer rows than all (measured: 5 and 21 of 192)."""
    mpc, problem = walking_problem
    problem = replace(problem, y_reference=problem.y_reference.copy())
    problem.y_reference[:, 1] += shift
    every = make_formulation("face:quadprog", mpc, 32)
    every.working_set = False
    reference = every.solve(problem)
    total = every.working_rows
    face = make_formulation("face:quadprog", mpc, 32)
    cold = face.solve(problem)
    assert face.working_rows < total
    warm = face.solve(problem)  # starts from the active faces of the solve before
    for inputs in (cold, warm):
        np.testing.assert_allclose(inputs, reference, rtol=0, atol=1e-9 * np.abs(reference).max())
    if shift:  # the cone binds: some faces are active, and they are in the working set
        assert face.working_rows >= 1


def test_face_form_refuses_points_of_the_wrong_shape(walking_problem):
    """One linearisation point per sample: anything else is a clear error (the compiled rows
    would read past the array)."""
    mpc, problem = walking_problem
    short = replace(problem, points=np.asarray(problem.points)[:-1])
    with pytest.raises(ValueError, match=r"points must be \(6, 3\)"):
        make_formulation("face:quadprog", mpc, 32).solve(short)


def test_face_form_refuses_ridge_bounds(model, walking_problem):
    mpc, problem = walking_problem
    bounded = replace(problem, upper=[np.full(n, 100.0) for n in problem.sizes])
    with pytest.raises(MpcSolverError, match="cannot bound ridge forces"):
        make_formulation("face:quadprog", mpc, 32).solve(bounded)
    with pytest.raises(ValueError, match="ridge_upper bounds ridge forces"):
        LinearMpcPlanner(0.002, formulation="face:quadprog", ridge_upper=100.0)


def test_no_support_is_a_recorded_failure_with_a_fallback(model):
    """A flight phase (no contact) in the middle of standing: the periods whose first sample
    has no contact fail, are counted, and plan the last feasible wrench; no exception."""
    stand = make_scenario("stand", model)
    (phase,) = stand.phases
    scenario = Scenario(
        "flight",
        1.0,
        stand.scene,
        (
            ContactPhase(0.0, 0.3, phase.contacts),
            ContactPhase(0.3, 0.5, ()),
            ContactPhase(0.5, 1.0, phase.contacts),
        ),
        stand.initial_posture,
    )
    planner = LinearMpcPlanner(0.002, horizon=5)
    state = _state(model)
    planner.reset(model, scenario, state)
    plans = [planner.plan(k * 0.002, state) for k in range(300)]
    failures = [p.solver_failures for p in plans]
    assert failures[149] == 0  # t < 0.3 s: supported
    assert failures[249] == 100  # every period of the flight, t in [0.3, 0.5)
    assert failures[-1] == 100  # solving resumes once the feet are back
    assert "no contact" in planner.last_error
    assert all(np.all(np.isfinite(p.wrench_planned_world)) for p in plans)
    assert all(np.all(np.isfinite(p.com_planned_world)) for p in plans)


@pytest.mark.slow
@pytest.mark.parametrize("sim", ["mujoco", "pybullet"])
def test_linear_mpc_walks_ten_steps(sim):
    from bench.runner import EpisodeSpec, run_episode

    summary = run_episode(EpisodeSpec("linear_mpc", "centroidal_feedback", sim, "walk")).summary
    assert summary["status"] == "ok", summary["error"] or summary["fall_reason"]
    assert summary["solver_failures"] == 0
    # feasible by construction: the projection of the planned wrench changes nothing
    assert summary["projection_error"]["planned_force_N"] < 1e-3
    assert summary["projection_error"]["planned_moment_Nm"] < 1e-3
    assert summary["zmp_margin_min_m"] > 0.0


def test_face_quadprog_does_not_cycle_at_friction_001():
    """Issue 14's reproduction: at friction 0.01 and scale 3 the face form's QP has a
    degenerate optimum, on which quadprog's active set cycled for ever (t = 0.006 s). Run in a
    subprocess with a timeout, so that a regression fails instead of hanging the suite."""
    import subprocess
    import sys

    code = (
        "from bench.runner import EpisodeSpec, run_episode\n"
        "r = run_episode(EpisodeSpec(planner='linear_mpc', stabilizer='centroidal_feedback', "
        "sim='mujoco', scenario='walk', duration=2.0, scale=3.0, friction=0.01))\n"
        "print(r.summary['status'], r.summary['duration'], r.summary['solver_failures'])\n"
    )
    result = subprocess.run(
        [sys.executable, "-c", code], capture_output=True, text=True, timeout=240, check=True
    )
    status, duration, failures = result.stdout.split()
    assert status in ("ok", "fell")  # the physics decides; a solver hang or error does not
    assert float(duration) > 0.05  # well past the period where it cycled
    assert int(failures) == 0


def test_face_form_with_grasps_everywhere_is_the_unconstrained_optimum():
    """With a grasp in every sample (its cone the whole space: no faces), the face form's QP
    has no constraint row and its solution is the unconstrained optimum, which the ridge form
    (a QP in the ridge forces, lambda >= 0, through qpsolvers) reaches too."""
    from dataclasses import replace

    from bench.scenarios import make_scenario
    from planners.linear_mpc import LinearMpcPlanner
    from robots.humanoid import humanoid
    from robots.model import RobotModel
    from robots.scene import Contact, ContactPhase

    model = RobotModel(humanoid())
    stand = make_scenario("stand", model)
    hand = Contact("left_hand", (0.3, 0.38, 1.1), grasp=True)
    phases = tuple(ContactPhase(p.start, p.end, (*p.contacts, hand)) for p in stand.phases)
    scenario = replace(stand, phases=phases)
    state = model.standing_state()
    state = replace(
        state,
        com_position_world=np.add(model.com_position_world(state), (0.03, 0.0, 0.0)),
        com_velocity_world=np.zeros(3),
    )
    plans = []
    for formulation in ("face:quadprog", "dense:daqp"):
        planner = LinearMpcPlanner(0.002, formulation=formulation)
        planner.reset(model, scenario, state)
        plans.append(planner.plan(0.0, state))
        assert plans[-1].grasp_limbs == ("left_hand",)
    np.testing.assert_allclose(
        plans[0].wrench_projected_world, plans[1].wrench_projected_world, atol=1e-3
    )
