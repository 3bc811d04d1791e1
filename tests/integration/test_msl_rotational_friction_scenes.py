"""MSL's Rotational.Examples.Friction and .OneWayClutch rebuilt as scenes, against the
event-driven reference; the reference itself against closed forms of MSL's laws."""
import math

import numpy as np
import pytest

from assemblies import AssemblyError, run_scene
from assemblies.scenes.msl_rotational_friction_references import Friction, OneWayClutchExample


@pytest.mark.parametrize("name, expected", [
    ("rotational_friction", {"clutch_5", "brake_1", "phi1_end", "w3_end", "energy_balance"}),
    ("rotational_one_way_clutch", {"oneWayClutch_7", "w_out_end", "energy_balance"})])
def test_the_scene_meets_every_stick_slip_time_and_final_state_of_the_reference(name, expected):
    """Monolithic (the composite FMU in the engine) at MSL's parameters, tolerance 1e-8:
    every lock and break-away (and freewheel overrun) within 100 x tolerance of the
    reference, the final angles and speeds too, the energy balance within DRIFT x tol."""
    res = run_scene(name, mode="monolithic")
    figures = {f.name: f for f in res.figures}
    assert expected <= set(figures)
    assert all(f.passed for f in res.figures), [f for f in res.figures if not f.passed]


def test_friction_co_simulated_meets_every_figure_to_the_coupling_accuracy():
    """Co-simulated (adaptive, step tolerance 1e-5) the clutch's locks across FMUs hold to
    the communication step: every event and final figure states 100 x 1e-5 (scaled), not
    the FMUs' 1e-8, and meets it; the mode sequence is the reference's."""
    res = run_scene("rotational_friction", mode="cosim")
    figures = {f.name: f for f in res.figures}
    assert figures["w3_end"].accuracy == pytest.approx(100 * 1e-5 * abs(figures["w3_end"].reference))
    assert figures["clutch_events"].measured == figures["clutch_events"].reference
    assert all(f.passed for f in res.figures), [f for f in res.figures if not f.passed]


@pytest.mark.parametrize("engine", ["c", "fmpy"])
def test_one_way_clutch_co_simulated_meets_every_figure_to_the_coupling_accuracy(engine):
    """Co-simulated in both masters: the release when the pulse ends at 0.95 s (the
    normal force jumps to 0 at a communication point while the clutch is locked) is
    seen there, and every lock and overrun, final state and the energy balance meet
    the coupling's accuracy (100 x 1e-5)."""
    res = run_scene("rotational_one_way_clutch", mode="cosim", engine=engine, plot=False)
    # MSL's law in every row: forward, the clutch carries at most peak cgeo mu(0) fn (0
    # once the pulse has ended; the freewheel holds any backward torque)
    m = OneWayClutchExample()
    tau, fn = np.asarray(res["oneWayClutch.tau"]), np.asarray(res["oneWayClutch.fn"])
    limit = m.peak * 0.5 * fn  # mu_pos = [0, 0.5], cgeo = 1
    assert np.all(tau <= limit + 1e-9), [(t, a, b) for t, a, b in
                                         zip(np.asarray(res["time"]), tau, limit) if a > b + 1e-9]
    figures = {f.name: f for f in res.figures}
    assert figures["oneWayClutch_4"].description.startswith("oneWayClutch slides forward")
    assert figures["oneWayClutch_4"].reference == pytest.approx(0.95)
    assert figures["oneWayClutch_4"].accuracy == pytest.approx(100 * 1e-5)
    assert all(f.passed for f in res.figures), [f for f in res.figures if not f.passed]


@pytest.mark.parametrize("name, loop", [
    ("rotational_friction", "clutch.flange_a.tau => inertia3.flange_b.tau"),
    ("rotational_one_way_clutch", "oneWayClutch.flange_a.tau => inertiaIn.flange_b.tau")])
def test_the_engines_me_solves_the_loop_of_a_clutch_on_a_driven_inertia(name, loop):
    """The clutch carries its driven inertia, so its torque and the inertia's
    acceleration feed each other: the compiled engine's me solves that loop at every
    evaluation and meets every figure of the reference (stick/slip times, final states,
    energy balance) at the scene's accuracy, as monolithic. (It refused the loop before.)"""
    res = run_scene(name, mode="me", plot=False)
    assert res.settings["engine"] == "c"
    assert any(loop in named for named in res.settings["algebraic_loops"]), \
        res.settings["algebraic_loops"]
    assert all(f.passed for f in res.figures), [f for f in res.figures if not f.passed]


def test_the_one_way_clutch_reference_has_the_closed_form_freewheel_phases():
    """Before the pulse (0.3 s) the clutch is a bare freewheel: inertiaOut rests while
    inertiaIn, at w = -0.5 + 10/(6 pi) (1 - cos 6 pi t), catches up with it (lock at
    cos 6 pi t = 1 - 0.3 pi); then the pair turns as one under the motor torque until
    that torque changes sign at 1/6 s, where inertiaOut overruns (free again) and keeps
    the speed it had then, 5/(6 pi) (cos 6 pi t_lock + 1)."""
    m = OneWayClutchExample()
    ref = m.solve()
    t_lock = math.acos(1 - 0.3 * math.pi) / (6 * math.pi)
    assert ref.events[0][1:] == (0, 0) and abs(ref.events[0][0] - t_lock) < 1e-9
    assert ref.events[1][1:] == (0, 1) and abs(ref.events[1][0] - 1 / 6) < 1e-9
    # locked, each gets half the torque: w_out(1/6) = 5/(6 pi) (cos 6 pi t_lock - cos pi)
    w_release = 5 / (6 * math.pi) * (math.cos(6 * math.pi * t_lock) + 1)
    free = (ref.t > 1 / 6 + 1e-3) & (ref.t < 0.3)
    assert np.abs(ref.y[free, 3] - w_release).max() < 1e-9
    assert np.all(ref.y[ref.t < t_lock, 3] == 0.0)


def test_the_friction_reference_brakes_inertia1_at_the_brakes_torque_and_holds_it():
    """MSL's Friction after 0.5 s: the brake (800 N.m sliding, 800 N.m peak) stops
    inertia1 against a spring torque of at most |tau_s|, so within J1 w1(0.5) / (800 +-
    max |tau_s|), and holds it at rest to the end."""
    m = Friction()
    ref = m.solve()
    locks = [t for t, k, q in ref.events if k == 1 and q == 0]
    assert len(locks) == 1
    braking = (ref.t >= m.start_time) & (ref.t <= locks[0])
    phi, w = ref.y[braking, :3], ref.y[braking, 3:]
    tau_s = np.abs(m.c * (phi[:, 2] - phi[:, 1]) + m.d * (w[:, 2] - w[:, 1])).max()
    w1 = w[0, 2]
    brake = 0.5 * m.fn_brake
    assert m.J1 * w1 / (brake + tau_s) <= locks[0] - m.start_time <= m.J1 * w1 / (brake - tau_s)
    assert np.all(ref.y[ref.t > locks[0] + 1e-3, 5] == 0.0)
