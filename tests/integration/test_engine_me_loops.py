"""Algebraic loops in the compiled engine's Model Exchange master (c/me.c, c/loop.c).

Two handmade affine blocks fed from each other, y = a u + b and x' = y
(tests/handmade/ml2_affine), form a linear loop with a closed-form solution:
y_p = (a_p b_q + b_p) / (1 - a_p a_q), y_q = a_q y_p + b_q, and x = y t. With
a_p a_q = 1 the matrix I - dy/du is singular and no consistent input exists.
"""
from __future__ import annotations

import numpy as np
import pytest
from fmpy.validation import validate_fmu

from assemblies import FMU, Assembly, EngineError
from assemblies.engine.me import simulate_me
from handmade_fmus import handmade_fmu


def pair(name: str, a_p: float, b_p: float, a_q: float, b_q: float, **values) -> Assembly:
    asm = Assembly("affine_loop")
    asm.add("p", FMU(handmade_fmu(name), a=a_p, b=b_p, **values))
    asm.add("q", FMU(handmade_fmu(name), a=a_q, b=b_q, **values))
    asm.connect("p.y", "q.u")
    asm.connect("q.y", "p.u")
    return asm


@pytest.mark.parametrize("name", ["ml2_affine", "ml2_affine_fd"])
def test_the_affine_blocks_are_valid(name):
    assert validate_fmu(str(handmade_fmu(name))) == []


@pytest.mark.parametrize("method", ["DOPRI5", "DOP853", "RODAS3"])
@pytest.mark.parametrize("name", ["ml2_affine", "ml2_affine_fd"])
def test_a_linear_loop_is_solved_to_round_off(name, method):
    """Loop gain a_p a_q = -1.5: plain fixed-point iteration diverges, Newton takes one
    step from the matrix of the blocks' directional derivatives (ml2_affine) or of
    differences (ml2_affine_fd), kept from one evaluation to the next. The outputs are
    the closed form to round-off at every row, the states its integral."""
    a_p, b_p, a_q, b_q = 0.5, 1.0, -3.0, 2.0
    y_p = (a_p * b_q + b_p) / (1.0 - a_p * a_q)
    y_q = a_q * y_p + b_q
    result = simulate_me(pair(name, a_p, b_p, a_q, b_q), 2.0, 0.1, tolerance=1e-8,
                         method=method, record=["p.y", "q.y", "p.x", "q.x", "p.u"])
    t = result["time"]
    assert len(t) == 21
    np.testing.assert_allclose(result["p.y"], y_p, rtol=0, atol=1e-14)
    np.testing.assert_allclose(result["q.y"], y_q, rtol=0, atol=1e-14)
    np.testing.assert_allclose(result["p.u"], y_q, rtol=0, atol=1e-14)
    # the explicit methods integrate a constant exactly; RODAS3 too on the exact Jacobian
    # (0), but its differences see the loop's round-off over sqrt(eps): within the
    # tolerance then
    atol = 1e-8 if method == "RODAS3" else 1e-13
    np.testing.assert_allclose(result["p.x"], y_p * t, rtol=1e-8 if atol > 1e-13 else 0,
                               atol=atol)
    np.testing.assert_allclose(result["q.x"], y_q * t, rtol=1e-8 if atol > 1e-13 else 0,
                               atol=atol)
    s = result.settings
    assert s["algebraic_loops"] == ["between FMUs p, q: p.y => q.u -> q.y => p.u"]
    assert s["jacobian"] == "finite differences"
    # the factors are reused: a new matrix at initialisation and where the integrator's
    # Jacobian asks for one, not at every evaluation
    assert 1 <= s["loop_matrices"] <= 2 + s["jacobians"]
    assert s["loop_iterations"] >= s["rhs_calls"]


def test_a_singular_loop_is_named_in_one_line():
    """a_p a_q = 1: I - dy/du = [[1, -2], [-0.5, 1]] has no inverse."""
    with pytest.raises(EngineError) as caught:
        simulate_me(pair("ml2_affine", 2.0, 1.0, 0.5, 1.0), 1.0, 0.1)
    line = str(caught.value)
    assert "\n" not in line
    assert ("algebraic loop between FMUs p, q: p.y => q.u -> q.y => p.u: the matrix "
            "I - dy/du is singular") in line


def test_a_loop_that_does_not_converge_is_named_in_one_line():
    """Directional derivatives that say 0 (dd_factor 0) make Newton a fixed-point
    iteration, which diverges on a loop gain of -1.5: bounded, and named."""
    with pytest.raises(EngineError) as caught:
        simulate_me(pair("ml2_affine", 0.5, 1.0, -3.0, 2.0, dd_factor=0.0), 1.0, 0.1)
    line = str(caught.value)
    assert "\n" not in line
    assert ("algebraic loop between FMUs p, q: p.y => q.u -> q.y => p.u: Newton did not "
            "converge in 20 iterations at t = 0") in line


def test_the_exact_jacobian_is_refused_through_a_loop():
    with pytest.raises(EngineError, match=r"jacobian='exact': the couplings form an algebraic "
                                          r"loop \(between FMUs p, q"):
        simulate_me(pair("ml2_affine", 0.5, 1.0, -3.0, 2.0), 1.0, 0.1, jacobian="exact")


@pytest.mark.parametrize("fmi", [2, 3])
def test_an_assembly_fmu_in_mode_me_solves_the_loop(tmp_path, fmi):
    """Exported in mode 'me', the loop travels in the FMU's configuration (its groups)
    and the engine inside it solves it: fmpy stepping the FMU (Co-Simulation: the
    engine's own integrator in doStep) and integrating it (Model Exchange: fmpy's) both
    give the closed form, the outputs to round-off, the states to the tolerance."""
    from fmpy import simulate_fmu

    from assemblies import export_fmu
    a_p, b_p, a_q, b_q = 0.5, 1.0, -3.0, 2.0
    y_p = (a_p * b_q + b_p) / (1.0 - a_p * a_q)
    path = export_fmu(pair("ml2_affine", a_p, b_p, a_q, b_q), tmp_path / f"loop{fmi}.fmu",
                      fmi=fmi, mode="me", outputs=["p.y", "p.x"], stop_time=1.0, step=0.1,
                      tolerance=1e-10)
    assert validate_fmu(str(path)) == []
    for fmi_type in ("CoSimulation", "ModelExchange"):
        res = simulate_fmu(str(path), fmi_type=fmi_type, stop_time=1.0, output_interval=0.1,
                           relative_tolerance=1e-10, record_events=False)
        np.testing.assert_allclose(res["p.y"], y_p, rtol=0, atol=1e-14)
        np.testing.assert_allclose(res["p.x"], y_p * res["time"], rtol=0, atol=1e-8)
