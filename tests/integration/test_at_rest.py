"""No work while nothing moves (issue 13): once every state's derivative is exactly zero
in an assembly of autonomous instances, the run takes no more steps and the remaining
rows repeat that point.

The reference is seed 9.4's exact motion (benchmarks.references via the scene): the
block stops for good at its last turning point, 5 pi / omega here, at x = -0.55, and
stays there. A run to 1000 s must take exactly the steps a run to 20 s takes, find the
rest at that time (the event where the block sticks, located to 1e-6 s), and hold the exact position to the
solver's accuracy in every later row. Where something keeps moving (a driver) or time
enters a model explicitly (a shaken table), the run never rests.
"""
import math

import numpy as np
import pytest

from assemblies.run import run_scene_full
from assemblies.scenes import scene
from assemblies.scenes.references import friction_damping_turning_points
from short_slip import SHORT_SLIP_STEP, short_slip_assembly

MODES = ("cosim", "me", "monolithic")


def _work(settings: dict) -> int:
    return settings["do_steps"] if "do_steps" in settings else settings["steps"]


@pytest.mark.parametrize("mode", MODES)
def test_friction_damping_stops_stepping_once_the_block_sticks_for_good(mode):
    asm = scene("friction_damping").build()
    block = asm.component("block")
    p = block.values
    turning = friction_damping_turning_points(p["m"], p["k"], p["g"], p["mu_k"],
                                              block.starts["x"])
    t_rest, x_rest = turning[-1]
    short, long_ = (run_scene_full("friction_damping", stop_time=T, mode=mode).result
                    for T in (20.0, 1000.0))
    # the same steps: none after the rest (1000 s would otherwise take 50x more)
    assert _work(long_.settings) == _work(short.settings)
    found = long_.settings["at_rest_from"]
    assert abs(found - t_rest) <= 1e-6, (found, t_rest)
    after = long_["time"] >= found
    assert after.sum() > 9000
    x_after = np.asarray(long_["block.x"])[after]
    assert np.all(x_after == x_after[0])  # repeated, not recomputed
    assert abs(x_after[0] - x_rest) < 1e-8, (x_after[0], x_rest)
    assert np.all(np.asarray(long_["block.v"])[after] == 0.0)
    # the run to 20 s agrees row for row where both have rows
    n = len(short["time"])
    assert np.array_equal(np.asarray(long_["block.x"])[:n], np.asarray(short["block.x"]))


@pytest.mark.parametrize("mode", ("cosim", "me"))
def test_a_moving_driver_never_rests(mode):
    """stick_slip: the block sticks, but the driver's travel keeps moving (its
    derivative is its speed), so every stick ends in a slip and nothing may stop."""
    result = run_scene_full("stick_slip", mode=mode).result
    assert result.settings["at_rest_from"] is None
    assert sum(np.diff(np.asarray(result["block.mode"])) != 0) >= 4  # it slips again


def test_a_model_written_in_time_never_rests():
    """The short-slip table moves as sin(t), written in time: while the block sticks,
    its states stand still, yet the table will tear it loose again, so no run may stop
    stepping (the engine sees the table is not autonomous)."""
    from assemblies.engine.me import simulate_me
    result = simulate_me(short_slip_assembly(), 4 * math.pi, SHORT_SLIP_STEP, 1e-10)
    assert result.settings["at_rest_from"] is None
    assert result.settings["steps"] > 10


def _stick_slip_beside(rest_block: dict | None):
    """stick_slip, and beside it (coupled to nothing of it) a block held by a wall."""
    asm = scene("stick_slip").build()
    if rest_block is not None:
        from components import ConstantSpeed, SpringBlock
        asm.add("wall", ConstantSpeed(v=0.0))
        asm.add("held", SpringBlock(m=1, k=1, g=1, mu_k=0.6, mu_s=0.6, **rest_block))
        asm.connect("wall.flange", "held.flange_a")
    return asm


def test_a_decoupled_group_at_rest_sleeps_while_the_rest_moves():
    """Beside stick_slip, a block held by static friction from the start (x = 0.3 inside
    the band |x| <= mu m g / k = 0.6) rests for good: it sleeps at the first step, so
    the run costs what stick_slip alone costs plus that step, and stick_slip's columns
    are those of its run alone (a resting group adds nothing to the error control)."""
    from assemblies.engine.cosim import cosimulate
    sc = scene("stick_slip")
    record = ["block.x", "block.v", "block.mode", "held.x", "held.v"]
    alone = cosimulate(_stick_slip_beside(None), sc.stop_time, sc.step, sc.tolerance,
                       record=record[:3])
    both = cosimulate(_stick_slip_beside({"x": 0.3}), sc.stop_time, sc.step, sc.tolerance,
                      record=record)
    assert set(both.settings["asleep"]) == {"wall", "held"}
    assert max(both.settings["asleep"].values()) <= sc.step  # at its first step
    assert both.settings["at_rest_from"] is None  # stick_slip never rests
    for column in record[:3]:
        assert np.array_equal(np.asarray(both[column]), np.asarray(alone[column])), column
    assert np.all(np.asarray(both["held.x"]) == 0.3) and np.all(np.asarray(both["held.v"]) == 0)
    # stepped once or twice before it slept: 2 FMUs x a few doSteps, not twice the run's
    assert both.settings["do_steps"] - alone.settings["do_steps"] <= 24, (
        both.settings["do_steps"], alone.settings["do_steps"])


def test_a_decoupled_group_at_rest_sleeps_under_one_integrator_too():
    """me: the held block's group falls asleep at the first step (no more evaluations of
    its FMUs, its derivatives zero), stick_slip runs on and passes its figures."""
    from assemblies.engine.me import simulate_me
    from assemblies.scenes.friction import _stick_slip_figures
    sc = scene("stick_slip")
    asm = _stick_slip_beside({"x": 0.3})
    result = simulate_me(asm, sc.stop_time, sc.step, sc.tolerance,
                         record=["block.x", "block.v", "block.mode", "held.x", "held.v"])
    assert set(result.settings["asleep"]) == {"wall", "held"}
    assert result.settings["at_rest_from"] is None
    assert np.all(np.asarray(result["held.x"]) == 0.3)
    assert all(f.passed for f in _stick_slip_figures(result, asm))
