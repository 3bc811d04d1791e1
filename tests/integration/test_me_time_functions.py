"""Members the engine's me evaluates itself between events (issue 27).

A kinematic source such as ConstantSpeed (travel' = v, s = s0 + travel) is not called
between events: its coupled outputs are its values at the last event plus their rates
times the time since (eng_me_spec.time_function). A spring is a fixed linear map from the
motions it is given to its forces: they are its values at the last event plus its
directional derivatives times the inputs' change since (eng_me_spec.linear_map). Checked
against closed forms (s0 + v t; a mass hung on a belt by a spring), and against the
composite FMU, which joins the same equations, integrates the sources' travel as states
and evaluates the springs' forces itself.
"""
import numpy as np
import pytest

from assemblies.engine.me import (is_linear_map, is_time_function, linear_outputs, simulate_me,
                                  simulate_monolithic)
from assemblies.scenes import scene
from assemblies import Assembly
from components import ConstantSpeed, Mass, MassWithFriction, PositionSensor, Spring
from components.sources.motion import SineMotion

EPS = np.finfo(float).eps


def _belt_with_sensor(v=0.37, s0=1.5):
    """two_block_belt, plus a third constant-speed source read by a position sensor: the
    sensor's output is the coupled value itself."""
    asm = scene("two_block_belt").build()
    asm.add("drive", ConstantSpeed(v=v, s0=s0))
    asm.add("sensor", PositionSensor())
    asm.connect("drive.flange", "sensor.flange")
    return asm


def test_a_constant_speed_source_is_evaluated_from_time_exactly():
    v, s0, stop = 0.37, 1.5, 1000.0
    asm = _belt_with_sensor(v, s0)
    result = simulate_me(asm, stop, 0.5, 1e-9, record=["sensor.s", "block1.s"])
    assert "drive" in result.settings["evaluated_from_time"]
    assert result.settings["events"] >= 4  # the blocks' slips re-read the source each time
    t = result["time"]
    exact = s0 + v * t
    # s0 + travel_event + v (t - t_event): a few roundings of the largest value, over a
    # run of thousands of steps (integrated, travel would gather one per step)
    np.testing.assert_allclose(result["sensor.s"], exact, rtol=0, atol=8 * EPS * exact.max())


def test_only_affine_state_free_of_inputs_sources_qualify():
    assert is_time_function(ConstantSpeed(v=0.3))
    assert not is_time_function(Spring())
    assert not is_time_function(SineMotion())  # time in its outputs: evaluated as usual
    assert not is_time_function(MassWithFriction())  # indicators, inputs
    assert not is_time_function(Mass())
    # a recorded source is evaluated as usual: a column reads the FMU itself
    result = simulate_me(scene("two_block_belt").build(), 5.0, 0.5, 1e-8,
                         record=["belt_1.flange.s", "block1.s"])
    assert "belt_1" not in result.settings["evaluated_from_time"]
    assert "belt_2" in result.settings["evaluated_from_time"]
    np.testing.assert_allclose(result["belt_1.flange.s"], 0.3 * result["time"], rtol=0,
                               atol=1e-14)


def _mode_changes(result, instance):
    """(time, mode) of each event of `instance` that changed its mode."""
    mode, changes = result[f"{instance}.mode"][0], []
    for t, m in zip(result.events[instance]["time"], result.events[instance][f"{instance}.mode"]):
        if m != mode:
            changes.append((float(t), float(m)))
            mode = m
    return changes


@pytest.mark.parametrize("method", ["DOPRI5", "RODAS3"])
def test_the_belt_in_me_follows_its_composite_fmu(method):
    """The composite integrates the sources' travel and evaluates the springs; me takes
    the sources from time and the springs' forces from their linear maps. With the
    sources' states kept in the one integrator, DOPRI5 takes the composite's steps (a
    rounding may tip one) and the two differ by rounding; RODAS3's matrix loses the
    sources' columns (their time dependence is its df/dt), so its steps may differ within
    the tolerance. coupling.f is recorded: the linear map's FMU is given its inputs
    before each row."""
    sc = scene("two_block_belt")
    tol = 1e-8
    me = simulate_me(sc.build(), 60.0, 0.1, tol, record=sc.record, method=method)
    composite = simulate_monolithic(sc.build(), 60.0, 0.1, tol, record=sc.record,
                                    method=method)
    assert me.settings["evaluated_from_time"] == ["wall_a", "wall_b", "belt_1", "belt_2"]
    assert me.settings["evaluated_as_linear_maps"] == ["spring1", "coupling", "spring2"]
    assert composite.settings["events"] >= 2
    # the same method at the same tolerance: the two differ by rounding and, where a
    # rounding tips a step or an event, by that step's local error, at most tol (measured
    # 2.4e-14 with DOPRI5 and 8.8e-12 with RODAS3, 4805 steps each)
    atol = tol
    if method == "DOPRI5":
        assert abs(me.settings["steps"] - composite.settings["steps"]) <= 2
        assert me.settings["events"] == composite.settings["events"]
    # RODAS3 may locate a slip a rounding early, where the mode machine still holds the
    # block: an event that changes nothing, then the slip. The changes are the composite's.
    for n in composite.events:
        ours, theirs = _mode_changes(me, n), _mode_changes(composite, n)
        assert [m for _, m in ours] == [m for _, m in theirs], n
        np.testing.assert_allclose([t for t, _ in ours], [t for t, _ in theirs], rtol=0,
                                   atol=1e-9)
    for c in sc.record:
        if c.endswith(".mode"):
            np.testing.assert_array_equal(me[c], composite[c], err_msg=c)
        else:
            np.testing.assert_allclose(me[c], composite[c], rtol=0, atol=atol, err_msg=c)


def test_a_spring_is_a_linear_map_by_its_forces_not_its_energy():
    linear = set(linear_outputs(Spring(c=3.0)))
    assert {"flange_a.f", "flange_b.f", "f", "s_rel"} <= linear and "E" not in linear
    assert is_linear_map(Spring(c=3.0), {"flange_a.f", "flange_b.f"})
    assert not is_linear_map(Spring(c=3.0), {"flange_a.f", "E"})  # E = c s_rel^2 / 2
    assert not linear_outputs(Mass())  # states


def test_the_belt_scene_figures_keep_their_accuracy_in_me():
    sc = scene("two_block_belt")
    result = simulate_me(sc.build(), sc.stop_time, sc.step, 1e-9, record=sc.record)
    assert result.settings["evaluated_from_time"]
    for figure in sc.figures(result, sc.build()):
        assert figure.passed, figure


def test_a_spring_on_a_belt_follows_the_closed_form():
    """A mass hung on a moving belt by a spring: the belt is taken from time, the spring's
    force from its linear map of the two flanges' motion. Relative to
    the belt the mass oscillates freely: y = s - v t, y'' = -(c/m) y, y(0) = a,
    y'(0) = -v, so y = a cos(w t) - (v/w) sin(w t), w = sqrt(c/m)."""
    v, m, c, a = 0.5, 2.0, 8.0, 0.2
    asm = Assembly("hung")
    asm.add("belt", ConstantSpeed(v=v))
    asm.add("spring", Spring(c=c))
    asm.add("mass", Mass(m=m))
    asm.connect("belt.flange", "spring.flange_a")
    asm.connect("spring.flange_b", "mass.flange_a")
    asm.component("mass").set("s", a)
    result = simulate_me(asm, 30.0, 0.05, 1e-10, record=["mass.s"])
    assert result.settings["evaluated_from_time"] == ["belt"]
    assert result.settings["evaluated_as_linear_maps"] == ["spring"]
    t, w = result["time"], np.sqrt(c / m)
    exact = v * t + a * np.cos(w * t) - v / w * np.sin(w * t)
    np.testing.assert_allclose(result["mass.s"], exact, rtol=0, atol=1e-7)
