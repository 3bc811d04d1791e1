"""The beam in modal coordinates (coordinates='modal') against the seed's formulation,
the closed-form motion of one mode, and the static flexibility that n_modes='auto' keeps."""
import math

import numpy as np
import pytest
from fmpy import simulate_fmu
from scipy.integrate import solve_ivp
from scipy.linalg import eigh

from components import flatten
from components.bodies.beam import AssumedModesBeam
from fmus import build_fmu
from fmus.codegen import directional_jacobian

EVERYTHING = dict(EI=2.0, L=1.3, m=0.7, k_tip=3.0, alpha=0.1, beta=0.01, zeta=0.05)


def _tip_history(beam, force, times):
    """w_tip(t) of the flattened (SX) equations under a constant tip force, by scipy."""
    model = flatten(beam)
    f = model.functions()
    x0, q0, _, p = model.start_vectors()
    if model.q.numel():  # the start event: amplitudes into the frame of t = 0
        x0 = np.array(f["jump"](0.0, x0, q0, [force], p)[0]).ravel()
        q0 = np.ones_like(q0)
    tip = [v.name for v in model.outputs].index("w_tip")
    sol = solve_ivp(lambda t, x: np.array(f["ode"](t, x, q0, [force], p)).ravel(), (0, times[-1]),
                    x0, t_eval=times, rtol=1e-11, atol=1e-13, method="DOP853")
    return np.array([float(f["out"](t, x, q0, [force], p)[tip]) for t, x in zip(sol.t, sol.y.T)])


@pytest.mark.parametrize("basis, n", [("poly2", 1), ("sine", 3)])
def test_modal_coordinates_are_the_same_physics(basis, n):
    """Released from a static shape, damped, tip spring, and pushed: the two formulations'
    tip motions agree to the integrator's tolerance."""
    times = np.linspace(0.0, 1.5, 31)
    histories = [_tip_history(AssumedModesBeam(basis=basis, n_modes=n, coordinates=c,
                                               w_tip0=0.05, **EVERYTHING), 0.4, times)
                 for c in ("assumed", "modal")]
    assert np.abs(histories[0]).max() > 0.04
    np.testing.assert_allclose(histories[1], histories[0], atol=1e-9, rtol=0)


def test_vectorised_functions_equal_the_flattened_ones():
    """The MX functions compiled into the FMU against CasADi's own SX derivatives."""
    beam = AssumedModesBeam(n_modes=3, coordinates="modal", **EVERYTHING)
    model = flatten(beam)
    reference = {**model.functions(), "dd": directional_jacobian(model)}
    vectorised = beam.vectorised_functions(model)
    x = np.random.default_rng(7).normal(size=model.x.numel())
    for q in (0.0, 1.0):
        args = (0.37, x, [q], [0.3], model.start_vectors()[3])
        for key, function in vectorised.items():
            for got, want in zip(function.call(list(args)), reference[key].call(list(args))):
                np.testing.assert_allclose(np.array(got), np.array(want), rtol=1e-13,
                                           atol=1e-13 * np.abs(np.array(want)).max(), err_msg=key)


def test_generated_code_does_not_grow_with_the_modes():
    """Loops over constant data: the same instructions for 17 modes as for 65."""
    counts = {n: {k: f.n_instructions()
                  for k, f in AssumedModesBeam(n_modes=n, coordinates="modal")
                  .vectorised_functions(flatten(AssumedModesBeam(n_modes=n, coordinates="modal")))
                  .items()}
              for n in (16, 64)}
    assert counts[16] == counts[64]


def test_one_mode_vibrates_at_its_frequency_from_any_start_time(tmp_path):
    """The beam released in its second mode shape: w_tip = w0 cos(ω2 (t - t0)) with ω2 from
    the seed's eigenproblem K u = ω² M u (scipy), for a run that starts at t0 = 1.3 s."""
    beam = AssumedModesBeam(n_modes=4, coordinates="modal", EI=2.0, m=3.0)
    mass, stiffness = beam.matrices()
    eigenvalues, modes = eigh(stiffness, mass)
    shape = modes[:, 1] * (0.02 / (beam.basis().tip_value @ modes[:, 1]))
    for name, value in zip(beam.basis().names, shape):
        beam.set(name, value)
    beam.validate()
    t0, omega = 1.3, math.sqrt(eigenvalues[1])
    res = simulate_fmu(str(build_fmu(beam)), fmi_type="CoSimulation", start_time=t0,
                       stop_time=t0 + 2.0, output_interval=0.01, relative_tolerance=1e-6,
                       start_values=dict(beam.starts), output=["w_tip", "E"])
    np.testing.assert_allclose(res["w_tip"], 0.02 * np.cos(omega * (res["time"] - t0)),
                               atol=1e-12, rtol=0)
    # the energy of a mode: ω² (w0 / ψ)² / 2 with ψ the tip value of the M-normalised mode
    psi = beam.basis().tip_value @ modes[:, 1]
    assert res["E"] == pytest.approx(np.full(len(res), (omega * 0.02 / psi)**2 / 2), rel=1e-12)


@pytest.mark.parametrize("accuracy", [1e-3, 1e-6])
def test_auto_keeps_the_modes_that_carry_the_static_tip_deflection(accuracy):
    """The static tip deflection of the kept modes (modal flexibilities) against the full
    model's K⁻¹ in the seed's coordinates: off by at most `accuracy`, and by more with
    one mode fewer."""
    beam = AssumedModesBeam(n_modes="auto", coordinates="modal", accuracy=accuracy)
    full = beam.static_tip_deflection(1.0)  # EI = L = 1: in units of L³/EI
    flexibility = beam.modal().static_flexibility()
    kept = beam.kept_modes()
    assert 1 - flexibility[:kept].sum() / full <= accuracy * (1 + 1e-9)
    assert 1 - flexibility[:kept - 1].sum() / full > accuracy
    assert len(beam.states) == 2 * kept and kept < 129


def test_release_from_static_shape_starts_at_rest_with_the_tip_deflection():
    beam = AssumedModesBeam(n_modes=8, coordinates="modal", w_tip0=0.05, EI=3.0)
    model = flatten(beam)
    x0, q0, u0, p = model.start_vectors()
    out = dict(zip([v.name for v in model.outputs],
                   np.array(model.functions()["out"](0.0, x0, q0, u0, p)).ravel()))
    assert out["w_tip"] == pytest.approx(0.05, rel=1e-12)
    assert out["tip.v"] == 0.0
    # at rest in the static shape under F = 3 EI w0 / L³ (K a = φ F): strain energy w0 F / 2
    force = 0.05 / beam.static_tip_deflection(1.0)
    assert out["E"] == pytest.approx(0.05 * force / 2, rel=1e-12)


def test_modal_coordinates_are_the_default():
    """Every integer n_modes keeps every mode: the default is the exact change of basis."""
    beam = AssumedModesBeam(n_modes=5)
    assert beam.option("coordinates") == "modal" and beam.kept_modes() == 6
    assert [s.name for s in beam.states][:2] == ["mode1_c", "mode2_c"]


def _columns(beam, force, times):
    """Every state and mode of the flattened (SX) equations over `times`, by name, with
    the start event applied as the FMU applies it (scipy, constant tip force)."""
    model = flatten(beam)
    f = model.functions()
    x0, q0, _, p = model.start_vectors()
    if model.q.numel():
        x0 = np.array(f["jump"](0.0, x0, q0, [force], p)[0]).ravel()
        q0 = np.ones_like(q0)
    sol = solve_ivp(lambda t, x: np.array(f["ode"](t, x, q0, [force], p)).ravel(),
                    (0, times[-1]), x0, t_eval=times, rtol=1e-12, atol=1e-14, method="DOP853")
    columns = dict(zip([s.name for s in model.states], sol.y))
    columns.update({m.name: np.full(len(times), q) for m, q in zip(beam.modes, q0)})
    return columns


def test_assumed_motion_gives_the_seeds_coordinates_from_either_coordinates():
    """a(t), a'(t) read off a modal run (AssumedModesBeam.assumed_motion, what the scenes'
    figures use) against the assumed coordinates integrated directly: damped, tip spring,
    pushed, started from arbitrary a, a'."""
    times = np.linspace(0.0, 1.2, 25)
    starts = dict(zip(["a0", "a1", "a2", "a3", "a0_dot", "a1_dot", "a2_dot", "a3_dot"],
                      np.random.default_rng(3).normal(scale=0.01, size=8)))
    motions = []
    for coordinates in ("assumed", "modal"):
        beam = AssumedModesBeam(n_modes=3, coordinates=coordinates, **EVERYTHING, **starts)
        columns = _columns(beam, 0.4, times)
        motions.append(beam.assumed_motion(columns.__getitem__, times))
    assert np.abs(motions[0][0][:, 0] - [starts[f"a{i}"] for i in range(4)]).max() < 1e-15
    for assumed, modal in zip(*motions):
        np.testing.assert_allclose(modal, assumed, atol=1e-9 * np.abs(assumed).max(), rtol=0)
    # a row at the start time before the start event (frame 0): the amplitudes are η, η'/ω
    beam = AssumedModesBeam(n_modes=3, **EVERYTHING, **starts)
    a, a_dot = beam.assumed_motion(lambda n: [beam.starts.get(n, 0.0)], [0.7])
    np.testing.assert_allclose(a[:, 0], [starts[f"a{i}"] for i in range(4)], rtol=1e-12)
    np.testing.assert_allclose(a_dot[:, 0], [starts[f"a{i}_dot"] for i in range(4)], rtol=1e-12)


def test_what_show_lists_is_what_a_default_beam_has():
    """`mechfmu show` reads the class: its states and modes are a default instance's
    (COMPONENTS[name]() built a modal beam with the assumed states once), and it names
    the start values the beam converts (w_tip0, the a_i)."""
    from components.listing import sheet
    beam = AssumedModesBeam()
    assert [s.name for s in AssumedModesBeam.states] == [s.name for s in beam.states]
    assert [m.name for m in AssumedModesBeam.modes] == [m.name for m in beam.modes]
    text = sheet(AssumedModesBeam)
    assert "w_tip0" in text and "a0_dot" in text
