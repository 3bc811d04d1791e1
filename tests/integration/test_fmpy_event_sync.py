"""Event synchronisation in the fmpy-driven co-simulation master (assemblies/masters).

The master rolls every FMU back and retakes a step so that it ends at the first event
an FMU locates inside it, and moves an event that an FMU handles at the start of a
step (its inputs crossed a switching condition during the step before) back to where
the coupled system crossed, by bisecting that step. Checked against independent
references: the closed-form first slip of two_block_belt, (mu_s m g - d v) / (c v),
and the exact break-away times of the short-slip fixture (event-driven exact solution,
tests/short_slip.py); and against the compiled engine, which implements the same
scheme, event for event.
"""
import numpy as np
import pytest

from assemblies.engine import cosim as engine_cosim
from assemblies.engine.cosim import EVENT_TOL as ENGINE_EVENT_TOL
from assemblies.engine.cosim import cosimulate as engine_cosimulate
from assemblies.experiment import FixedStepFallback
from assemblies.masters import cosim as fmpy_master
from assemblies.masters.cosim import cosimulate
from assemblies.masters.events import EVENT_TOL
from assemblies.run import cosim_scheme, run_scene_full
from assemblies.scenes import scene
from assemblies.scenes.joined import belt_first_slip
from short_slip import (SHORT_SLIP_STOP, exact_short_slip_phases, mode_changes,
                        short_slip_assembly)

BELT_STOP = 3.0  # past the first slip (0.64 s) and a few more events; the scene runs 300 s


def _same_events(a, b):
    """The two results have the same events, at the same times and outputs (to round-off
    of the extrapolating polynomial's fit, which numpy and the engine do differently)."""
    assert sorted(a.events) == sorted(b.events)
    for instance in a.events:
        assert len(a.events[instance]) == len(b.events[instance]), instance
        for column in a.events[instance].columns:
            assert np.max(np.abs(a.events[instance][column] - b.events[instance][column])) \
                < 1e-9, (instance, column)


@pytest.fixture(scope="module")
def belt():
    """two_block_belt in the default co-simulation (adaptive, linear extrapolation, event
    synchronisation), in the fmpy master and in the compiled engine stepping every member
    as the fmpy master does (STEPPED)."""
    with pytest.MonkeyPatch.context() as mp:
        STEPPED(mp)
        return {engine: run_scene_full("two_block_belt", stop_time=BELT_STOP,
                                       engine=engine).result for engine in ("fmpy", "c")}


def STEPPED(monkeypatch):
    """The engine steps every member, as the fmpy master does: the members it evaluates
    itself otherwise (engine_cosim.EVALUATE_MEMBERS: the belts from time, the springs as
    linear maps) give the same values to rounding, but a held input's history keeps the
    points of the settle steps after an event (1e-8 s apart), and its quadratic through
    them carries a rounding of 1e-17 into the next step's held force at 3e-5, so the runs
    part by 1e-7 after the first slip: the same algorithm, not the same roundings
    (test_cosim_evaluated compares the two engine paths to tol)."""
    monkeypatch.setattr(engine_cosim, "EVALUATE_MEMBERS", False)


def test_the_default_cosim_slips_at_the_closed_form_time(belt):
    res = belt["fmpy"]
    t_slip, first = belt_first_slip(scene("two_block_belt").build())
    ev = res.events[first]
    slips = ev["time"][ev[f"{first}.mode"] != 0]
    # (mu_s m g - d v) / (c v) = 0.641666...: the block runs the spring force along its
    # extrapolating polynomial and lets go inside a step, where the master stops every
    # FMU (held constant, it let go at a communication point, which the master moved
    # back to where the coupled system crossed)
    assert abs(slips[0] - t_slip) < 1e-6, (slips[0], t_slip)
    s = res.settings
    assert s["engine"] == "fmpy" and s["adaptive"] and s["event_sync"]
    assert s["events_located"] + s["events_synchronised"] >= 1
    # without the synchronisation the block still lets go on time where it runs the
    # force along its polynomial (it finds its own slip inside its step: measured 6e-14
    # off); held constant over fixed steps of the output interval (extrapolation 0) it
    # lets go at the communication point after the crossing, 0.058 s late
    sc = scene("two_block_belt")
    for adaptive, on_time in ((None, True), (False, False)):
        alone = cosimulate(sc.build(), 1.0, sc.step, sc.tolerance, record=["block1.s"],
                           event_sync=False, **cosim_scheme(adaptive, None))
        ev = alone.events[first]
        assert not alone.settings["event_sync"] and alone.settings["events_located"] == 0
        error = abs(ev["time"][ev[f"{first}.mode"] != 0][0] - t_slip)
        assert error < 1e-6 if on_time else error > 1e-2, (adaptive, error)


def test_the_default_cosim_is_the_engines_step_for_step(belt):
    ref, eng = belt["fmpy"], belt["c"]
    assert ref.columns == eng.columns and len(ref) == len(eng)
    for column in ref.columns:
        assert np.max(np.abs(ref[column] - eng[column])) < 1e-9, column
    _same_events(ref, eng)
    for key in ("steps", "rejected", "do_steps", "events_synchronised", "events_located"):
        assert ref.settings[key] == eng.settings[key], key


@pytest.mark.parametrize("extrapolation", [0, 1, 3])
def test_fixed_steps_find_each_break_away_exactly_and_agree_with_the_engine(extrapolation,
                                                                            monkeypatch):
    # A block stuck on a shaken table lets go when the table's acceleration passes
    # mu_s g. Held over a step (extrapolation 0), the block lets go at the communication
    # point after the crossing; bisecting the step before (every retaken step sets the
    # input at its end exactly) finds the crossing to EVENT_TOL. Sticking again is an
    # event inside a step, from the block's states, which the held acceleration makes
    # late by the coupling error. Extrapolated, the block runs the acceleration along
    # its polynomial (the rate inputs) and meets every event inside a step, off by how
    # far the polynomial misses the table's acceleration: O(h^(p+1)) in a, divided by
    # the rate a crosses at. Measured, worst of the 8 events: 1.9e-3 (p = 1) and
    # 1.9e-7 (p = 3) at h = 0.01.
    h = 0.01
    options = dict(adaptive=False, event_sync=True, extrapolation=extrapolation)
    res = cosimulate(short_slip_assembly(), SHORT_SLIP_STOP, h, 1e-10, **options)
    ev = res.events["block"]
    found = mode_changes(ev["time"], ev["block.mode"])
    exact = exact_short_slip_phases()
    assert [q for _, q in found] == [q for _, q in exact], found
    errors = np.array([t - te for (t, _), (te, _) in zip(found, exact)])
    if extrapolation == 0:  # every break-away (phases 0, 2, ...) to the bracket's width
        assert res.settings["events_located"] == 4
        assert np.max(np.abs(errors[0::2])) < 1e-9, errors
        assert np.max(np.abs(errors)) < h, errors
    else:
        assert res.settings["events_located"] == 0
        assert res.settings["events_synchronised"] == len(exact)
        assert np.max(np.abs(errors)) < {1: h / 4, 3: 1e-6}[extrapolation], errors
    # the same scheme as the compiled engine: the same events, steps and retakes
    STEPPED(monkeypatch)
    eng = engine_cosimulate(short_slip_assembly(), SHORT_SLIP_STOP, h, 1e-10, **options)
    _same_events(res, eng)
    for key in ("steps", "do_steps", "events_synchronised", "events_located"):
        assert res.settings[key] == eng.settings[key], key


def test_without_synchronisation_a_fixed_step_finds_the_break_away_late():
    # the reference for the test above: the block lets go at the communication point
    # after the crossing, up to one step late
    h = 0.01
    res = cosimulate(short_slip_assembly(), SHORT_SLIP_STOP, h, 1e-10)
    assert not res.settings["event_sync"] and res.settings["events_located"] == 0
    ev = res.events["block"]
    found = mode_changes(ev["time"], ev["block.mode"])
    exact = exact_short_slip_phases()
    late = np.array([t - te for (t, _), (te, _) in zip(found[0::2], exact[0::2])])
    assert np.all(late > 1e-6) and np.all(late < h), late


def test_event_sync_is_on_with_adaptive_steps_and_its_bracket_is_the_engines():
    assert EVENT_TOL == ENGINE_EVENT_TOL
    res = cosimulate(short_slip_assembly(), 0.5, 0.1, 1e-10, adaptive=True, extrapolation=1,
                     tol=1e-3)
    assert res.settings["event_sync"]
    res = cosimulate(short_slip_assembly(), 0.5, 0.1, 1e-10, adaptive=True, extrapolation=1,
                     tol=1e-3, event_sync=False)
    assert not res.settings["event_sync"] and res.settings["events_synchronised"] == 0


def test_without_fmu_state_rollback_falls_back_to_fixed_steps_as_the_engine_does(monkeypatch):
    load = fmpy_master._Instance._load

    def stateless(self, name, component):
        out = load(self, name, component)
        if name == "block":
            self.can_get_set_state = False
        return out

    monkeypatch.setattr(fmpy_master._Instance, "_load", stateless)
    with pytest.warns(FixedStepFallback, match=r"event-synchronised co-simulation rolls steps "
                                               r"back, but FMU instance 'block' cannot get and "
                                               r"set its state .*: ran fixed communication "
                                               r"steps of 0.01 s without event "
                                               r"synchronisation instead"):
        res = cosimulate(short_slip_assembly(), 0.1, 0.01, 1e-10, event_sync=True)
    assert not res.settings["event_sync"] and "instance 'block'" in res.settings["fallback"]
    # exactly the fixed-step run, which never rolls back
    fixed = cosimulate(short_slip_assembly(), 0.1, 0.01, 1e-10)
    assert len(fixed) == 11 and fixed.settings["fallback"] is None
    assert np.array_equal(res["block.x"], fixed["block.x"])
