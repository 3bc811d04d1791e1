"""The beam's FMU in time: fmpy ME and CS, energy conservation, and the two beam scenes."""
import math

import numpy as np
import pytest
from fmpy import simulate_fmu
from scipy.linalg import eigh

from assemblies.scenes.beam import BEAM_SCENES
from assemblies.masters.cosim import cosimulate
from assemblies.run import run_scene_full
from components.bodies.beam import AssumedModesBeam
from fmus import build_fmu

from conftest import simulate_in_fmpy

EI, L, M_TOTAL = 2.0, 1.5, 3.0


def _seed_free_vibration(a0, t):
    """w(L, t) for poly2 released at rest from a0, by modal superposition of the seed's M, K."""
    mass = M_TOTAL * np.array([[1 / 5, 1 / 6], [1 / 6, 1 / 7]])
    e = EI / L**3
    stiffness = np.array([[4 * e, 6 * e], [6 * e, 12 * e]])
    eigenvalues, modes = eigh(stiffness, mass)
    amplitudes = modes.T @ mass @ a0  # modal coordinates at t = 0, at rest
    a = modes @ (amplitudes[:, None] * np.cos(np.sqrt(eigenvalues)[:, None] * t))
    return a.sum(axis=0)  # φ(L) = (1, 1)


@pytest.mark.parametrize("fmi_type, atol", [("CoSimulation", 1e-9), ("ModelExchange", 1e-5)])
def test_poly2_free_vibration_in_fmpy_is_the_seeds_modal_solution(fmi_type, atol):
    a0 = np.array([0.02, -0.005])
    beam = AssumedModesBeam(basis="poly2", EI=EI, L=L, m=M_TOTAL, a1=a0[0], a2=a0[1])
    res = simulate_in_fmpy(beam, fmi_type, stop_time=10.0, output_interval=0.01, output=["w_tip"])
    np.testing.assert_allclose(res["w_tip"], _seed_free_vibration(a0, res["time"]), atol=atol, rtol=0)


@pytest.mark.parametrize("fmi_type", ["CoSimulation", "ModelExchange"])
def test_sine_beam_runs_in_fmpy_and_settles_under_a_tip_force(fmi_type):
    """tip.f set as the input's start value: the static deflection of the discretised model."""
    beam = AssumedModesBeam(basis="sine", n_modes=4, zeta=0.5)
    res = simulate_fmu(str(build_fmu(beam)), fmi_type=fmi_type, stop_time=20.0, output_interval=0.1,
                       relative_tolerance=1e-10, start_values={"tip.f": 0.2}, output=["w_tip"])
    assert res["w_tip"][-1] == pytest.approx(beam.static_tip_deflection(0.2), rel=1e-6)


def test_free_vibration_conserves_energy_to_the_solver_tolerance():
    """100 periods of ω1: the drift is the integrator's, shrinking with its tolerance (in the
    assumed coordinates: a free modal beam's states are constant, its drift round-off)."""
    beam = AssumedModesBeam(basis="sine", n_modes=4, w_tip0=0.1, coordinates="assumed")
    period = 2 * math.pi / beam.natural_frequencies()[0]
    drift = {}
    for tolerance in (1e-8, 1e-10):
        res = simulate_in_fmpy(beam, "CoSimulation", stop_time=100 * period, output_interval=period / 20,
                               tolerance=tolerance, output=["E"])
        drift[tolerance] = np.abs(res["E"] - res["E"][0]).max() / res["E"][0]
        assert drift[tolerance] < 1e4 * tolerance
    assert drift[1e-10] < drift[1e-8] / 30


def _run(name, **params):
    scene = BEAM_SCENES[name]
    asm = scene.build()
    for key, value in params.items():
        asm.set(key, value)
    res = cosimulate(asm, scene.stop_time, scene.step, scene.tolerance, record=scene.record)
    return res, {f.name: f for f in scene.figures(res, asm)}


@pytest.mark.parametrize("params", [{}, {"beam.n_modes": 8}, {"beam.basis": "poly2"},
                                    {"beam.k_tip": 10.0}, {"beam.coordinates": "assumed"},
                                    {"beam.coordinates": "assumed", "beam.k_tip": 10.0}])
def test_free_vibration_scene_measures_the_discretised_frequency(params):
    res, figures = _run("beam_free_vibration", **params)
    assert figures["omega1"].error < 1e-9 * figures["omega1"].reference
    # against the exact beam, only the discretisation error remains: positive and small
    exact = figures["omega1_EB"].reference
    assert 0 < figures["omega1_EB"].measured / exact - 1 < 0.02
    assert figures["E_drift"].measured < 1e-6
    assert res["beam.w_tip"][0] == pytest.approx(0.1, rel=1e-14)
    assert all(f.passed for f in figures.values()), figures


def test_both_coordinates_measure_the_same_frequency():
    """The scene's figures read the beam's motion in either coordinates (a modal run
    ended in KeyError 'beam.a0'); the two formulations are one model: their ω1 agree with
    each other as with scipy's eigensolution."""
    measured = [_run("beam_free_vibration", **{"beam.coordinates": c, "beam.k_tip": 2.0})[1]
                ["omega1"].measured for c in ("assumed", "modal")]
    assert measured[1] == pytest.approx(measured[0], rel=1e-9)


def test_sixty_four_modes_run_in_the_default_coordinates_within_two_seconds():
    """Issue 26: N = 64 took 57 s to simulate 2 s in the assumed coordinates (the solver
    steps through ω_65 ≈ 4e4 rad/s); modal, the whole scene's 40 s take a fraction of a
    second, and every figure passes (omega1_EB against N = 128)."""
    run = run_scene_full("beam_free_vibration", params={"beam.n_modes": 64})
    assert run.result.settings["wall_s"] < 2.0
    assert run.passed, run.table()


def test_tip_force_scene_settles_at_the_static_deflection():
    errors = {}
    # the scene's assumed coordinates come to rest: poly2's settled deflection is then the
    # cubic's to round-off; a modal beam's amplitudes keep turning at rest, so its settled
    # value carries the solver's error (within w_static's accuracy)
    for params in ({"beam.basis": "poly2"}, {"beam.basis": "poly2", "beam.coordinates": "modal"},
                   {"beam.n_modes": 4}, {"beam.n_modes": 8},
                   {"beam.n_modes": 4, "beam.coordinates": "modal"}):
        _, figures = _run("beam_tip_force", **params)
        assert figures["w_static"].error < 1e-9 * figures["w_static"].reference
        assert all(f.passed for f in figures.values()), figures
        errors[tuple(params.values())] = figures["w_EB"].error / figures["w_EB"].reference
    assert errors[("poly2",)] < 1e-12  # the exact static shape is a cubic
    assert 0 < errors[(8,)] < errors[(4,)] < 0.02
    assert errors[(4, "modal")] == pytest.approx(errors[(4,)], rel=1e-6)


def test_tip_spring_acts_in_parallel():
    res, figures = _run("beam_tip_force", **{"beam.basis": "poly2", "beam.k_tip": 7.0})
    assert figures["w_EB"].reference == pytest.approx(0.1 / (3 + 7.0))
    assert figures["w_EB"].error < 1e-12
    assert res["load.flange.f"][-1] == -0.1
