"""The benchmark suite's plumbing: one tiny sweep, its JSON schema, and that its errors are
measured against the independent reference (the full sweeps live in benchmarks/, not here)."""
from __future__ import annotations

import json
import math

import numpy as np
import pytest

from benchmarks import scenes
from benchmarks.runners import max_error
from benchmarks.suite import FIELDS, run_scene, write_json
from benchmarks.references import coulomb_drag


@pytest.fixture(scope="module")
def stick_slip_case():
    return scenes.stick_slip()


@pytest.fixture(scope="module")
def records(stick_slip_case):
    return run_scene("stick_slip", log=lambda *_: None, case=stick_slip_case,
                     methods=("fmu_cs_dopri5", "scipy_LSODA"), tolerances=(1e-6,))


def test_reference_is_the_analytic_piecewise_solution(stick_slip_case):
    """The benchmark's reference is the piecewise solution, which meets the seed's numbers."""
    phases, x_of_t = coulomb_drag(1, 1, 1, 0.3, 0.4, 0.05, 100.0)
    assert np.max(np.abs(stick_slip_case.reference - x_of_t(stick_slip_case.times))) < 1e-12
    (_, _, t1), (_, _, t2) = phases[0], phases[1]  # stuck until t1, sliding until t2
    assert abs(t1 - 8.0) < 1e-12 and abs(t2 - 12.0689) < 5e-5  # seed 9.2
    assert abs(float(x_of_t(np.array([t2]))[0]) - 0.40344) < 5e-6


def test_json_records_have_the_schema(records, tmp_path):
    path = tmp_path / "bench.json"
    write_json(records, path)
    loaded = json.loads(path.read_text())
    # the pairs a target compares run first (suite.run_scene), so sorted: the schema
    assert sorted(r["method"] for r in loaded) == ["fmu_cs_dopri5", "scipy_LSODA"]
    for r in loaded:
        assert tuple(r) == FIELDS
        assert r["scene"] == "stick_slip" and r["tolerance"] == 1e-6
        assert r["error"] >= 0 and r["wall_s"] > 0
        assert isinstance(r["rhs_evals"], int) and isinstance(r["steps"], int)
    # our FMU's counts come from its logSolver lines: at least one step per doStep
    fmu = next(r for r in loaded if r["method"] == "fmu_cs_dopri5")
    assert fmu["steps"] >= len(scenes.output_times("stick_slip")) - 1


def test_errors_are_against_the_reference(records, stick_slip_case):
    _, x_of_t = coulomb_drag(1, 1, 1, 0.3, 0.4, 0.05, 100.0)
    exact = x_of_t(stick_slip_case.times)
    for r in records:
        values, _, _ = stick_slip_case.methods[r["method"]](r["tolerance"], False)
        assert math.isclose(r["error"], max_error(values, exact), rel_tol=1e-6, abs_tol=1e-14)
        # a rerun against a shifted reference would differ: the error is not a constant
        assert max_error(values, exact + 1e-3) > r["error"]


def test_coin_baseline_agrees_with_the_component_and_with_lagrange():
    """The hand-written numpy coin (Newton–Euler about C, one 3x3 solve) gives the same
    eight derivatives as the library's CasADi component and the same Euler accelerations as
    the independent Lagrange-multiplier model in tests/coin_reference.py."""
    from benchmarks.baselines import coin_derivatives
    from coin_reference import accelerations
    from components.dae import flatten
    from components.bodies.rolling_coin import RollingCoin

    m, R, g = 1.3, 0.7, 9.0
    model = flatten(RollingCoin(m=m, R=R, g=g))
    ode = model.functions()["ode"]
    _, q, u, p = model.start_vectors()
    rng = np.random.default_rng(7)
    for _ in range(20):
        state = np.concatenate([rng.uniform(-1, 1, 2), [rng.uniform(-3, 3),
                                rng.uniform(0.15, math.pi - 0.15), rng.uniform(-3, 3)],
                                rng.uniform(-6, 6, 3)])
        mine = coin_derivatives(state, m, R, g)
        theirs = np.array(ode(0.0, state, q, u, p)).ravel()
        scale = max(1.0, np.abs(theirs).max())
        assert np.abs(mine - theirs).max() < 1e-10 * scale
        lagrange, _ = accelerations(state[2:], m, R, g)
        assert np.abs(mine[5:] - lagrange).max() < 1e-10 * scale


def test_a_flat_curve_is_followed_until_the_tolerance_binds(stick_slip_case):
    """Stepped once per 0.1 s output interval, the CS FMU's DOPRI5 meets 1e-6 and 1e-8 with
    one step per doStep (the same error and work at both: one point); the sweep goes on to
    1e-10, where the tolerance binds, and the work–precision curve moves."""
    lines = []
    records = run_scene("stick_slip", log=lines.append, case=stick_slip_case,
                        methods=("fmu_cs_dopri5",), tolerances=(1e-6, 1e-8))
    assert [r["tolerance"] for r in records] == [1e-6, 1e-8, 1e-10]
    loose, tight = records[1], records[2]
    assert (records[0]["error"], records[0]["steps"]) == (loose["error"], loose["steps"])
    # one step per doStep, plus the steps that end at the run's stick and slip events
    assert loose["steps"] < 1.05 * (len(stick_slip_case.times) - 1)
    assert tight["steps"] > 1.2 * loose["steps"] and tight["rhs_evals"] > loose["rhs_evals"]
    assert tight["error"] < loose["error"] / 5
    # measured against the exact piecewise solution, not against each other
    _, x_of_t = coulomb_drag(1, 1, 1, 0.3, 0.4, 0.05, 100.0)
    assert tight["error"] == pytest.approx(
        max_error(stick_slip_case.methods["fmu_cs_dopri5"](1e-10, False)[0],
                  x_of_t(stick_slip_case.times)), rel=1e-6)
    assert any("did not bind" in line for line in lines)
    # a curve that moves is not extended
    moving = run_scene("stick_slip", log=lambda *_: None, case=stick_slip_case,
                       methods=("fmu_cs_dopri5",), tolerances=(1e-8, 1e-10))
    assert [r["tolerance"] for r in moving] == [1e-8, 1e-10]
