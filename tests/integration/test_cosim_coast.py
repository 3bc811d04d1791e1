"""The compiled master's runs of unjudged steps (cosim.c COAST_STEPS .. COAST_MAX) and
the coupling defect that guards them: the error estimate that costs no doStep.

Step doubling costs three doSteps to advance two half steps. After an accepted
estimate the master takes a run of steps without one; a run grows (4, 8, 16, 32) while
each estimate keeps the step where it was, and every step of it compares the held
couplings' extrapolation with what their sources returned at its end (the coupling
defect). A defect grown past twice the one the last estimate saw rejects the step and
estimates again. Both are checked against independent references: a closed form (two
masses and a spring) and the monolithic model of moving_table.
"""
import math

import numpy as np
import pytest

import assemblies.engine.cosim as engine_cosim
from assemblies.assembly import Assembly
from assemblies.engine.cosim import DEFAULT_SCHEME, cosimulate
from assemblies.masters.adaptive import COAST_STEPS
from assemblies.masters.cosim import cosimulate as reference_cosimulate
from assemblies.masters.monolithic import simulate_monolithic
from assemblies.scenes import scene
from components import Mass, Spring


@pytest.fixture
def every_member_stepped(monkeypatch):
    """The doSteps counted here are the estimate's cost per FMU: the engine steps the
    spring too (it would take it as a linear map, with no doStep at all, which would
    hide the count), as the reference master does."""
    monkeypatch.setattr(engine_cosim, "EVALUATE_MEMBERS", False)

M1, M2, K = 1.0, 0.5, 4.0       # kg, kg, N/m
X0, V0 = 0.1, 0.05              # b starts X0 ahead of a; a starts at V0
RECORD = ["a.s", "b.s", "a.v", "b.v"]


def _two_masses() -> Assembly:
    asm = Assembly("bfd27_two_masses")
    asm.add("a", Mass(m=M1, s=0.0, v=V0))
    asm.add("b", Mass(m=M2, s=X0, v=0.0))
    asm.add("k", Spring(c=K))
    asm.connect("a.flange_b", "k.flange_a")
    asm.connect("k.flange_b", "b.flange_a")
    return asm


def _closed_form(t: np.ndarray) -> dict:
    """The centre of mass moves uniformly; the stretch d = s_b - s_a oscillates at
    sqrt(K / reduced mass)."""
    total = M1 + M2
    w = math.sqrt(K * total / (M1 * M2))
    d = X0 * np.cos(w * t) - V0 / w * np.sin(w * t)
    dd = -X0 * w * np.sin(w * t) - V0 * np.cos(w * t)
    centre, v_centre = M2 * X0 / total + M1 * V0 / total * t, M1 * V0 / total
    return {"a.s": centre - M2 / total * d, "b.s": centre + M1 / total * d,
            "a.v": v_centre - M2 / total * dd, "b.v": v_centre + M1 / total * dd}


@pytest.mark.parametrize("tol", [1e-3, 1e-4, 1e-5])
def test_runs_of_unjudged_steps_keep_two_masses_and_a_spring_within_the_tolerance(
        tol, every_member_stepped):
    """22 periods of the stretch at an output interval of 0.5 s (a third of a period:
    a fixed step there is far off). The controller's promise is the global error
    within about tol (local errors within tol per unit step: adaptive.py); measured
    err/tol 1.69 / 1.73 / 1.70 here, the same as with a run of 4 after every estimate
    (1.71 / 1.69 / 1.70). Most steps go unjudged: doSteps per step and instance
    1.26 / 1.14 / 1.09, where runs of 4 cost (3 + 4) / 5 = 1.4 (measured 1.46 / 1.43 /
    1.41: the assertion fails without the longer runs). The band is 2 tol, not tol,
    because the controller bounds the sum of local errors, and an undamped oscillation
    does not merely add them: an error made in one state rotates into the other, which
    the weighing by each state's own units measures differently (the same 1.7 tol with
    the runs of 4 before this change, so the bound checks that longer runs lose
    nothing, not a promise of the method's)."""
    res = cosimulate(_two_masses(), 40.0, 0.5, 1e-10, record=RECORD,
                     **dict(DEFAULT_SCHEME, tol=tol))
    exact = _closed_form(np.asarray(res["time"]))
    error = max(float(np.max(np.abs(np.asarray(res[c]) - exact[c]))) for c in RECORD)
    s = res.settings
    assert error < 2.0 * tol, (tol, error)
    per_step = s["do_steps"] / (s["steps"] + s["rejected"]) / 3
    assert per_step < 1.32, per_step
    assert s["h_max"] < 0.5 / 4  # the error, not the output interval, set the step


def test_the_default_keeps_moving_table_within_the_tolerance():
    """A block sliding on a shaken table: the error of a step depends on the table's
    phase, and an estimate taken where it is small could let a run of 32 cross the
    phase where it is large. Against the monolithic model (one FMU, tolerance 1e-12),
    block position and velocity: err/tol 0.071 / 0.64 / 0.57 at tol 1e-2 / 1e-3 / 1e-4.
    With the table's acceleration held at its step mean the coupling defect's check
    decided it (2.6 / 0.49 / 0.38 switched off, over the tolerance at 1e-2); run along
    its cubic, the fmpy master with the check switched off (COAST_DEFECT_GROWTH
    infinite) ends 0.19 / 0.15 / 0.16 off, so here the check is no longer what keeps
    the error within tol (on conveyor at tol 1e-3 it still is: 2.3e-6 with it, 1.6e-5
    without, benchmarks.joined's measure)."""
    sc = scene("moving_table")
    record = ["block.s", "block.v"]
    exact = simulate_monolithic(sc.build(), sc.stop_time, sc.step, 1e-12, record=record,
                                engine="fmu")
    for tol in (1e-2, 1e-3, 1e-4):
        res = cosimulate(sc.build(), sc.stop_time, sc.step, sc.tolerance, record=record,
                         **dict(DEFAULT_SCHEME, tol=tol))
        error = max(float(np.max(np.abs(res[c] - exact[c]))) for c in record)
        assert error < tol, (tol, error)


@pytest.mark.parametrize("step", [0.3, 0.25, 0.2])
def test_runs_of_unjudged_steps_grow_where_the_steps_do_not_divide_the_output_interval(
        step, every_member_stepped):
    """The two masses at tol 1e-2 with output intervals that the steps the error allows
    (about 0.06-0.17 s) do not divide. Steps fit the output grid (cosim.c cells): the
    steps between two output points are equal, and an estimate whose two halves do not
    fit before an output point is put off to it. Before, the last step before each
    output point was what was left of the interval, an estimate taken on it set the
    run's steps to half of it and the run back to COAST_STEPS: doSteps per step and
    instance 1.28 / 1.20 / 1.26 at step 0.3 / 0.25 / 0.2 (with the forces held at their
    step mean). Now, with the forces run along their cubic (a coupling of order 3 to
    step doubling), 1.11 / 1.24 / 1.34: fewer steps (736 / 709 / 712, against 1465 /
    1469 / 1515 held at the mean), so an estimate and its rejections weigh more on each;
    in all 835 / 927 / 1024 doSteps per instance (1615 / 1598 / 1695 held), err/tol 0.70
    / 0.76 / 0.69 against the closed form (1.19 / 1.20 / 1.12), within the 2 tol the
    first test of this file allows (its docstring says why 2). The bound is what runs of
    COAST_STEPS after every estimate cost in that test, (3 + 4) / 5."""
    tol = 1e-2
    res = cosimulate(_two_masses(), 40.0, step, 1e-10, record=RECORD,
                     **dict(DEFAULT_SCHEME, tol=tol))
    exact = _closed_form(np.asarray(res["time"]))
    error = max(float(np.max(np.abs(np.asarray(res[c]) - exact[c]))) for c in RECORD)
    s = res.settings
    per_step = s["do_steps"] / (s["steps"] + s["rejected"]) / 3
    assert error < 2.0 * tol, (step, error)
    assert per_step < (3 + COAST_STEPS) / (1 + COAST_STEPS), (step, per_step)
    assert s["do_steps"] / 3 < 1100, s["do_steps"]


def test_the_reference_master_fits_the_output_grid_as_the_engine_does(every_member_stepped):
    """The fmpy-driven master (assemblies/masters/cosim.py) takes the same steps as the
    engine where the steps do not divide the output interval (runs put off to an output
    point, runs the coupling defect ended): the same counts, the same values."""
    options = dict(DEFAULT_SCHEME, tol=1e-2)
    runs = [master(_two_masses(), 12.0, 0.25, 1e-10, record=RECORD, **options)
            for master in (reference_cosimulate, cosimulate)]
    ref, eng = runs
    assert eng.settings["engine"] == "c" and "engine" not in ref.settings
    for key in ("steps", "rejected", "do_steps"):
        assert ref.settings[key] == eng.settings[key], key
    for column in RECORD:
        assert np.max(np.abs(np.asarray(ref[column]) - np.asarray(eng[column]))) < 1e-9, column
