"""Members the co-simulation master evaluates itself instead of stepping (issue 27).

A kinematic source whose outputs are exact functions of time (ConstantSpeed: travel' = v,
s = s0 + travel) is taken from its value at the start plus its rate times the time since;
a member with no states, indicators or time whose coupled outputs are affine in its inputs
(a spring, a position sensor) from its value at the start plus its directional derivatives
times the change of its inputs (cosim.h, eng_cosim_spec.time_function / .linear_map).
Neither is stepped between the points that need its FMU: a row that records it, a
rollback. Checked against closed forms, and against the same master stepping every
member (cosim.EVALUATE_MEMBERS = False): in exact arithmetic the two are one computation.
"""
import numpy as np
import pytest

import assemblies.engine.cosim as engine_cosim
from assemblies import Assembly
from assemblies.engine.cosim import cosimulate
from assemblies.scenes import scene
from components import ConstantSpeed, Mass, PositionSensor, Spring

EPS = np.finfo(float).eps
TOL = 1e-4


def _run(asm, stop, step, record, evaluate, monkeypatch, **kw):
    monkeypatch.setattr(engine_cosim, "EVALUATE_MEMBERS", evaluate)
    options = dict(adaptive=True, tol=TOL, extrapolation=2)
    options.update(kw)
    return cosimulate(asm, stop, step, 1e-10, record=record, **options)


@pytest.mark.parametrize("name, stop, from_time, linear", [
    ("two_block_belt", 60.0, ["wall_a", "wall_b", "belt_1", "belt_2"],
     ["spring1", "coupling", "spring2"]),
    ("moving_table", None, ["anchor"], [])])
def test_evaluated_members_give_the_stepped_result(name, stop, from_time, linear, monkeypatch):
    """Adaptive steps with event synchronisation (rollbacks of rejected steps, events
    located by bisection through rollback): the same run with every member stepped.
    The blocks have indicators and states, the table (SineMotion) has time in its
    outputs: they are stepped. A stepped ConstantSpeed adds h v to its travel each step
    (a rounding of s per step) where the map takes s0 + v t, and a held input's
    quadratic through the points of an event's settle steps (1e-8 s apart) carries such a
    rounding into the next held value many times over; a rounding may also tip a
    step-size decision, which moves the result by at most that step's local error, within
    tol. Measured 6.3e-9 on the belt over 60 s (6960 steps either way), 5.7e-9 over 300 s
    (28624 / 28621 steps), and 0 on the table (its anchor stands still: v = 0)."""
    sc = scene(name)
    stop = sc.stop_time if stop is None else stop
    stepped = _run(sc.build(), stop, sc.step, sc.record, False, monkeypatch)
    mapped = _run(sc.build(), stop, sc.step, sc.record, True, monkeypatch)
    assert stepped.settings["evaluated_from_time"] == []
    assert stepped.settings["evaluated_as_linear_maps"] == []
    assert mapped.settings["evaluated_from_time"] == from_time
    assert mapped.settings["evaluated_as_linear_maps"] == linear
    assert stepped.settings["rejected"] > 0  # rollbacks were exercised
    assert stepped.settings["events_synchronised"] + stepped.settings["events_located"] > 0
    # the members taken as maps are not stepped between rows: fewer doSteps per step
    per_step = {r: r.settings["do_steps"] / (r.settings["steps"] + r.settings["rejected"])
                for r in (stepped, mapped)}
    n = len(sc.build().components)
    assert per_step[mapped] < per_step[stepped] * (n - len(from_time) - len(linear) + 0.5) / n
    assert abs(mapped.settings["steps"] - stepped.settings["steps"]) <= 0.01 * stepped.settings["steps"]
    for c in sc.record:
        if c.endswith(".mode"):
            np.testing.assert_array_equal(mapped[c], stepped[c], err_msg=c)
        else:
            np.testing.assert_allclose(mapped[c], stepped[c], rtol=0, atol=TOL, err_msg=c)
    for n_ in stepped.events:
        np.testing.assert_allclose(mapped.events[n_]["time"], stepped.events[n_]["time"],
                                   rtol=0, atol=1e-6, err_msg=n_)


def _hung(v=0.5, m=2.0, c=8.0, a=0.2, s0=1.5):
    """A mass hung on a moving belt by a spring, and a second drive read by a position
    sensor."""
    asm = Assembly("hung")
    asm.add("belt", ConstantSpeed(v=v))
    asm.add("spring", Spring(c=c))
    asm.add("mass", Mass(m=m))
    asm.add("drive", ConstantSpeed(v=0.37, s0=s0))
    asm.add("sensor", PositionSensor())
    asm.connect("belt.flange", "spring.flange_a")
    asm.connect("spring.flange_b", "mass.flange_a")
    asm.connect("drive.flange", "sensor.flange")
    asm.component("mass").set("s", a)
    return asm


@pytest.mark.parametrize("kw", [dict(), dict(adaptive=False, event_sync=True),
                                dict(adaptive=False, event_sync=False, scheme="gauss-seidel")])
def test_recorded_evaluated_members_are_right_at_every_row(kw, monkeypatch):
    """Each recorded column of an evaluated member is read from its FMU brought up to date
    at the row: the drive's and the belt's positions are s0 + v t (a time function's FMU
    steps once over the time it lagged: its travel gathers a rounding per row, not per
    communication step), the sensor's output too (from s0 + v (t - t0), the master's),
    the spring's force c (s_mass - s_belt) from the recorded positions (its inputs set
    before the row). The mass follows the master stepping every member, and with adaptive
    steps the closed form of a free oscillation relative to the belt, y = a cos(w t) -
    (v/w) sin(w t), to the tolerance. Adaptive with rollbacks, fixed steps, and the
    Gauss–Seidel sweep (a source stepped already is read at the step's end)."""
    v, m, c, a, s0 = 0.5, 2.0, 8.0, 0.2, 1.5
    record = ["belt.flange.s", "drive.flange.s", "sensor.s", "spring.f", "spring.flange_b.s",
              "mass.s"]
    result = _run(_hung(v, m, c, a, s0), 30.0, 0.05, record, True, monkeypatch,
                  **kw)
    assert result.settings["evaluated_from_time"] == ["belt", "drive"]
    # under Gauss–Seidel a linear member stepped in the sweep is read at the step's end,
    # where its FMU extrapolates its chained inputs (s with v): it is stepped there
    gauss_seidel = kw.get("scheme") == "gauss-seidel"
    assert result.settings["evaluated_as_linear_maps"] == ([] if gauss_seidel
                                                           else ["spring", "sensor"])
    t = result["time"]
    np.testing.assert_allclose(result["belt.flange.s"], v * t, rtol=0, atol=len(t) * EPS * 15)
    np.testing.assert_allclose(result["drive.flange.s"], s0 + 0.37 * t, rtol=0,
                               atol=len(t) * EPS * 15)
    # the sensor reads the master's s0 + v (t - t0): a few roundings of the largest value
    np.testing.assert_allclose(result["sensor.s"], s0 + 0.37 * t, rtol=0,
                               atol=8 * EPS * (s0 + 0.37 * t[-1]))
    # the spring's force from its own inputs at the row (flange_b.s is the mass's)
    np.testing.assert_allclose(result["spring.f"],
                               c * (result["spring.flange_b.s"] - result["belt.flange.s"]),
                               rtol=0, atol=1e-12)
    np.testing.assert_allclose(result["spring.flange_b.s"], result["mass.s"], rtol=0, atol=1e-12)
    # the same master stepping every member: fixed steps take the same steps, and differ
    # by the roundings of a stepped travel (h v added per step)
    stepped = _run(_hung(v, m, c, a, s0), 30.0, 0.05, record, False, monkeypatch, **kw)
    np.testing.assert_allclose(result["mass.s"], stepped["mass.s"], rtol=0,
                               atol=1e-12 if kw else TOL)
    if not kw:  # adaptive, to tol: the closed form
        w = np.sqrt(c / m)
        exact = v * t + a * np.cos(w * t) - v / w * np.sin(w * t)
        np.testing.assert_allclose(result["mass.s"], exact, rtol=0, atol=5 * TOL)


def test_members_with_states_or_indicators_are_never_evaluated(monkeypatch):
    """The mass has states that move with its inputs, the belt's blocks have event
    indicators, the table's outputs follow time through a sine: each is stepped, whatever
    its coupling."""
    result = _run(_hung(), 2.0, 0.05, ["mass.s"], True, monkeypatch)
    assert "mass" not in result.settings["evaluated_from_time"] + \
        result.settings["evaluated_as_linear_maps"]
    belt = _run(scene("two_block_belt").build(), 2.0, 0.1, ["block1.s"], True, monkeypatch)
    taken = belt.settings["evaluated_from_time"] + belt.settings["evaluated_as_linear_maps"]
    assert "block1" not in taken and "block2" not in taken
    table = _run(scene("moving_table").build(), 1.0, scene("moving_table").step, ["block.s"],
                 True, monkeypatch)
    assert "table" not in table.settings["evaluated_from_time"]
    assert "block" not in table.settings["evaluated_from_time"] + \
        table.settings["evaluated_as_linear_maps"]


@pytest.mark.parametrize("kw", [dict(extrapolation=0),
                                dict(adaptive=False, event_sync=True, extrapolation=0)])
def test_a_recorded_source_survives_the_rollbacks(kw, monkeypatch):
    """two_block_belt, its belts recorded: each row brings the belts' FMUs to the row's
    time, and an event found at the start of a later step is moved back into the step
    before it, restoring every FMU to a point before rows already taken (cosim.c
    locate_start_event; the rows are taken again). A belt's FMU then stands where the
    snapshot left it, or its recorded position would run ahead of its time: belt_1.flange.s
    = belt_2.flange.s = 0.3 t at every row, to the roundings of one doStep per row. With
    fixed steps of the output interval every step starts at a row, so every event moved
    back restores the belts from beyond a row. Held constant (extrapolation 0), the
    springs' forces jump at communication points and fire such events (3 and 16 in 60
    s); extrapolated, the blocks take them as polynomials, and they fire none."""
    sc = scene("two_block_belt")
    record = ["block1.s", "belt_1.flange.s", "belt_2.flange.s"]
    result = _run(sc.build(), 60.0, sc.step, record, True, monkeypatch, **kw)
    assert result.settings["events_located"] >= 1
    assert result.settings["rejected"] > 0 or not result.settings["adaptive"]
    assert "belt_1" in result.settings["evaluated_from_time"]
    t = result["time"]
    for column, v in (("belt_1.flange.s", 0.3), ("belt_2.flange.s", 0.3)):
        np.testing.assert_allclose(result[column], v * t, rtol=0, atol=len(t) * EPS * v * t[-1],
                                   err_msg=column)
