"""Which instances a run may leave out: only those with no path of couplings to a
recorded one (assemblies.pruning). Direction matters: a signal carries influence one
way, a flange both ways."""
from __future__ import annotations

from assemblies import Assembly
from assemblies.pruning import needed_instances, prune_unrecorded
from components import ConstantSpeed, SpringBlock
from components.sensors.translational import PositionSensor
from components.sources.translational import Position
from conftest import drop_component


def _chain() -> Assembly:
    """driver <-> sensor -> position source <-> block: the sensor's signal drives the
    position source, which drags the block; nothing flows back through the signal."""
    asm = Assembly("chain")
    asm.add("driver", ConstantSpeed(v=0.1))
    asm.add("sensor", PositionSensor())
    asm.add("source", Position())
    asm.add("block", SpringBlock())
    asm.connect("driver.flange", "sensor.flange")
    asm.connect("sensor.s", "source.s_ref")
    asm.connect("source.flange", "block.flange_a")
    return asm


def test_what_feeds_a_recorded_instance_is_kept_upstream_to_the_first_source():
    # block is recorded; source drags it, the sensor's signal drives source, the driver
    # moves the sensor: every instance influences block.x
    assert needed_instances(_chain(), ["block.x"]) == ["driver", "sensor", "source", "block"]


def test_what_only_receives_from_a_recorded_instance_is_left_out():
    # the sensor is recorded; source and block hang off its signal and feed nothing back
    asm = _chain()
    assert needed_instances(asm, ["sensor.s"]) == ["driver", "sensor"]
    pruned, left_out = prune_unrecorded(asm, ["sensor.s"])
    assert left_out == ["source", "block"]
    assert list(pruned.components) == ["driver", "sensor"]
    assert [(c.a, c.b) for c in pruned.connections] == [("driver.flange", "sensor.flange")]
    assert pruned.components["sensor"] is asm.components["sensor"]  # values stay the user's


def test_a_flange_carries_influence_both_ways():
    # recording only the driver still needs the sensor: it sends the driver a force back
    assert needed_instances(_chain(), ["driver.flange.f"]) == ["driver", "sensor"]


def test_everything_recorded_or_an_unknown_instance_prunes_nothing():
    asm = _chain()
    assert prune_unrecorded(asm, None) == (asm, [])
    assert prune_unrecorded(asm, ["nosuch.x"]) == (asm, [])  # the master names the error


def test_an_instance_that_can_end_the_run_is_kept():
    asm = _chain()
    asm.add("drop", drop_component()())
    assert "drop" in needed_instances(asm, ["sensor.s"])
