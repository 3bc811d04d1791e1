"""The compiled engine's co-simulation master (assemblies/engine/c/cosim.c).

It is the fmpy-driven reference master's algorithm, so both must give the same numbers
(to round-off of the extrapolating polynomial's fit; the default scheme is compared in
test_fmpy_event_sync.py). Its default scheme (adaptive steps, linear extrapolation, event
synchronisation) is checked against independent references: the closed-form first
slip and sliding equilibrium of two_block_belt, the beam-with-tip-spring frequency of
beam_friction_damper, the exact solution of a block stuck on a beam tip (an algebraic
loop), and the monolithic model of moving_table.
"""
import dataclasses
import math
import signal

import numpy as np
import pytest

from assemblies.engine import cosim as engine_cosim
from assemblies.engine.cosim import DEFAULT_SCHEME, cosimulate
from assemblies.masters.cosim import cosimulate as reference_cosimulate
from assemblies.masters.monolithic import simulate_monolithic
from assemblies.scenes import scene
from assemblies.scenes.joined import belt_first_slip, belt_sliding_equilibrium

from test_loops import W0, _assembly as block_on_tip, _reference as block_on_tip_exact


def _both(name, stop, **options):
    sc = scene(name)
    runs = [master(sc.build(), stop, sc.step, sc.tolerance, record=sc.record, **options)
            for master in (reference_cosimulate, cosimulate)]
    return sc, runs


@pytest.mark.parametrize("name, stop, options", [
    ("stick_slip", 20.0, {}),
    ("moving_table", 3.0, {}),
    ("two_block_belt", 10.0, {"scheme": "gauss-seidel"}),
    ("two_block_belt", 10.0, {"scheme": "gauss-seidel", "extrapolation": 1}),
    ("moving_table", 3.0, {"extrapolation": 2}),
])
def test_a_fixed_step_is_the_reference_masters_algorithm(name, stop, options, monkeypatch):
    _, (ref, eng) = _both(name, stop, **options)
    assert ref.columns == eng.columns and len(ref) == len(eng)
    for column in ref.columns:
        assert np.max(np.abs(ref[column] - eng[column])) < 1e-9, column
    assert sorted(ref.events) == sorted(eng.events)
    for instance in ref.events:  # events inside steps, at the same times, same outputs
        for column in ref.events[instance].columns:
            assert np.max(np.abs(ref.events[instance][column] - eng.events[instance][column])) \
                < 1e-9, (instance, column)
    assert ref.settings["steps"] == eng.settings["steps"]
    # the members the engine evaluates itself (kinematic sources, springs: cosim.h
    # time_function / linear_map) are not stepped between rows (a recorded source is, once
    # per row: stick_slip's driver, whose steps are the rows); stepping every member, it
    # takes the reference's doSteps
    assert eng.settings["do_steps"] <= ref.settings["do_steps"]
    monkeypatch.setattr(engine_cosim, "EVALUATE_MEMBERS", False)
    _, (_, stepped) = _both(name, stop, **options)
    assert stepped.settings["do_steps"] == ref.settings["do_steps"]
    assert eng.settings["engine"] == "c"


def test_adaptive_meets_its_tolerance_against_the_monolithic_model():
    sc = scene("moving_table")
    stop, tol = 3.0, 1e-5
    # the joined model built into one FMU (no coupling error; solver error 1e-12)
    exact = simulate_monolithic(sc.build(), stop, sc.step, 1e-12, record=["block.s", "block.v"],
                                engine="fmu")
    # (zero-order hold is first order: the same tolerance takes 400 times the steps)
    res = cosimulate(sc.build(), stop, sc.step, 1e-12, record=["block.s", "block.v"],
                     adaptive=True, tol=tol, extrapolation=1)
    error = max(np.max(np.abs(res[c] - exact[c])) for c in ("block.s", "block.v"))
    assert error < tol and res.settings["error_ratio_max"] <= 1.0
    assert res.settings["h_min"] < res.settings["h_max"] <= sc.step
    # and it is not trivially so: a fixed step at the output interval misses by far more
    fixed = cosimulate(sc.build(), stop, sc.step, 1e-12, record=["block.v"])
    assert np.max(np.abs(fixed["block.v"] - exact["block.v"])) > 100 * tol


def test_an_event_where_the_half_steps_meet_does_not_keep_an_unjudged_step():
    """axle_motor with the communication step at its output grid (0.5 s, what the peers
    benchmark asks): the body's first slip fires where the two half steps of the first
    step meet. Kept unjudged, that first half (0.03 s) left the run 5e-3 off the
    composite model at every tolerance; judged like any step, the error falls with tol."""
    sc = scene("axle_motor")
    stop, record = 1.0, ["body.theta", "body.omega", "motor.phi", "motor.w"]
    exact = simulate_monolithic(sc.build(), stop, 0.5, 1e-12, record=record, engine="fmu")
    errors = []
    for tol in (1e-3, 1e-5):
        res = cosimulate(sc.build(), stop, 0.5, 1e-10, record=record,
                         **dict(DEFAULT_SCHEME, tol=tol))
        errors.append(max(np.max(np.abs(res[c] - exact[c])) / max(1.0, np.max(np.abs(exact[c])))
                          for c in record))
        # the slip is there, and the run steps to it: located at a step's start, or
        # (the motor's torque run along its polynomial) synchronised inside one
        assert res.settings["events_located"] + res.settings["events_synchronised"] >= 1
    assert errors[1] < 1e-5 and errors[1] < errors[0] / 10, errors


def test_unjudged_steps_follow_an_accepted_estimate():
    """Step doubling costs three doSteps per step; after an accepted estimate
    COAST_STEPS half steps are taken without one (cosim.c), so that on moving_table,
    whose steps stay about even, the doSteps per step and instance fall well below 3
    (with 4 unjudged steps after every estimate: 7/5). Its accuracy is checked above
    (test_adaptive_meets_its_tolerance_against_the_monolithic_model)."""
    sc = scene("moving_table")
    asm = sc.build()
    res = cosimulate(asm, 3.0, sc.step, sc.tolerance, record=["block.v"], **DEFAULT_SCHEME)
    s = res.settings
    per_step = s["do_steps"] / (s["steps"] + s["rejected"]) / len(asm.components)
    assert per_step < 2.0, per_step


def test_the_block_on_the_beam_tip_loop_converges_by_newton():
    stop, h = 4.0, 0.00625
    res = cosimulate(block_on_tip(), stop, h, 1e-12, record=["beam.tip.s", "block.mode"],
                     extrapolation=1)
    loops = res.settings["loops"]
    assert len(loops) == 1 and "beam.tip.a" in loops[0] and "block.support.f" in loops[0]
    assert res.settings["loop_residual"] < 1e-10
    # Newton on a linear loop: one iteration per communication point (+ the initial ones)
    assert res.settings["loop_iterations"] <= res.settings["steps"] + 4
    assert np.all(res["block.mode"] == 0)
    exact, _ = block_on_tip_exact(res["time"])
    # linear extrapolation is second order here: 2e-3 W0 at h = 0.00625 (test_loops)
    assert np.max(np.abs(res["beam.tip.s"] - exact)) < 2e-3 * W0
    # plain fixed-point iteration diverges (loop gain 5) and says which loop
    with pytest.raises(engine_cosim.EngineError, match=r"algebraic loop between FMUs beam, "
                                                       r"block did not converge in 20 "
                                                       r"fixed-point iterations.*beam.tip.a"):
        cosimulate(block_on_tip(), 1.0, 0.1, 1e-12, newton=False)


def test_default_two_block_belt_slips_on_time_and_settles_on_the_sliding_equilibrium():
    sc = scene("two_block_belt")
    asm = sc.build()
    res = cosimulate(asm, sc.stop_time, sc.step, sc.tolerance, record=sc.record, **DEFAULT_SCHEME)
    t_slip, first = belt_first_slip(asm)
    ev = res.events[first]
    slips = ev["time"][ev[f"{first}.mode"] != 0]
    assert abs(slips[0] - t_slip) < 1e-6  # (mu_s m g - d v) / (c v) = 0.641666...
    s_eq = belt_sliding_equilibrium(asm)
    assert abs(res["block1.s"][-1] - s_eq[0]) < 1e-3
    assert abs(res["block2.s"][-1] - s_eq[1]) < 1e-3
    # the run stepped to the slip: moved back to it (a force held over a step fires it
    # at the next step's start) or synchronised inside a step (the force run along its
    # polynomial fires it where it is)
    assert res.settings["events_located"] + res.settings["events_synchronised"] >= 1


def test_default_beam_friction_damper_sticks_for_good_at_the_tip_spring_frequency():
    sc = scene("beam_friction_damper")
    asm = sc.build()
    res = cosimulate(asm, sc.stop_time, sc.step, sc.tolerance, record=sc.record, **DEFAULT_SCHEME)
    figures = {f.name: f for f in sc.figures(res, asm)}
    assert res["pad.mode"][-1] == 0 and math.isfinite(figures["t_stick"].measured)
    assert figures["omega_stuck"].error < 1e-6, figures["omega_stuck"]
    assert figures["E_lost"].error < 1e-6 * figures["E_lost"].reference + 1e-7


def test_without_fmu_state_adaptive_falls_back_to_fixed_steps_and_says_so(monkeypatch):
    real = engine_cosim.prepared

    def stateless(component):
        fmu = real(component)
        return dataclasses.replace(fmu, can_get_set_state=False) if component.name == "block" \
            else fmu

    monkeypatch.setattr(engine_cosim, "prepared", stateless)
    sc = scene("stick_slip")
    with pytest.warns(engine_cosim.FixedStepFallback,
                      match=r"adaptive co-simulation rolls steps back, but FMU instance 'block' "
                            r"cannot get and set its state .*: ran fixed communication steps "
                            r"of 0.1 s without event synchronisation instead"):
        res = cosimulate(sc.build(), 1.0, sc.step, adaptive=True)
    assert not res.settings["adaptive"] and not res.settings["event_sync"]
    assert "instance 'block'" in res.settings["fallback"]
    fixed = cosimulate(sc.build(), 1.0, sc.step)
    assert np.array_equal(res["block.x"], fixed["block.x"])  # exactly the fixed-step run


def test_ctrl_c_stops_cleanly_and_keeps_what_was_computed():
    sc = scene("two_block_belt")
    calls = []

    def progress(t):
        calls.append(t)
        signal.raise_signal(signal.SIGINT)  # as if the user pressed Ctrl-C

    res = cosimulate(sc.build(), 1e5, sc.step, sc.tolerance, record=["block1.s"],
                     progress=progress, **DEFAULT_SCHEME)
    assert calls and "Ctrl-C" in res.settings["stopped"]
    assert 1 < len(res) < 1e6 and np.all(np.isfinite(res["block1.s"]))
    assert res["time"][-1] >= calls[0] - sc.step
