"""Automatic causality: profiles chosen from the connection graph, impossible graphs named."""
import pytest

from assemblies import Assembly, AssemblyError
from components import (AssumedModesBeam, Component, ConstantForce, ConstantSpeed, RigidBodyOnAxle,
                        SpringBlock)
from components.interfaces import FIXED, FORCE_IN, MOTION_IN, TRANSLATIONAL, Port, Profile
from components.sources.motion import SineMotion


class TwoPorts(Component):
    """Test double: p2 can be grounded only in the profile where p1 takes a motion."""
    ports = (Port("p1", TRANSLATIONAL, "first"), Port("p2", TRANSLATIONAL, "second"))
    profiles = (Profile("A", "p1 force, p2 motion", {"p1": FORCE_IN, "p2": MOTION_IN}),
                Profile("B", "p1 motion, p2 grounded", {"p1": MOTION_IN, "p2": FIXED}))

    def equations(self, e):  # pragma: no cover - never flattened here
        raise NotImplementedError


def test_a_free_block_gets_the_profile_its_connections_need():
    asm = Assembly("table")
    asm.add("drv", ConstantSpeed())
    asm.add("table", SineMotion())
    asm.add("block", SpringBlock())
    asm.connect("drv.flange", "block.flange_a")
    assert asm.resolve_causality()["block"] == "driven"  # its first profile fits
    asm.connect("table.flange", "block.support")
    assert asm.resolve_causality()["block"] == "driven_on_moving_support"
    # and the couplings follow: the table's motion feeds the support, the force goes back
    targets = {(c.target, c.source, c.gain) for c in asm.couplings()}
    assert (("block", "support.a"), ("table", "flange.a"), 1.0) in targets
    assert (("table", "flange.f"), ("block", "support.f"), -1.0) in targets


def test_two_rotating_bodies_get_one_motion_and_one_torque_side():
    asm = Assembly("pair")
    asm.add("a", RigidBodyOnAxle())
    asm.add("b", RigidBodyOnAxle())
    asm.connect("a.axle", "b.axle")
    assert asm.resolve_causality() == {"a": "driven_by_torque", "b": "driven_by_motion"}


def test_a_named_profile_is_kept():
    asm = Assembly("pair")
    asm.add("a", RigidBodyOnAxle(profile="driven_by_motion"))
    asm.add("b", RigidBodyOnAxle())
    asm.connect("a.axle", "b.axle")
    assert asm.resolve_causality() == {"a": "driven_by_motion", "b": "driven_by_torque"}
    both = Assembly("both")
    both.add("a", RigidBodyOnAxle(profile="driven_by_torque"))
    both.add("b", RigidBodyOnAxle(profile="driven_by_torque"))
    with pytest.raises(AssemblyError, match=r"a.axle \(force\) to b.axle \(force\)"):
        both.connect("a.axle", "b.axle")


def test_a_named_grounded_port_cannot_be_connected():
    asm = Assembly("grounded")
    asm.add("table", SineMotion())
    asm.add("block", SpringBlock(profile="driven"))
    with pytest.raises(AssemblyError, match=r"block.support is grounded in its profile"):
        asm.connect("table.flange", "block.support")


def test_a_cycle_of_three_bodies_is_impossible_and_the_closing_connection_is_named():
    asm = Assembly("triangle")
    for name in "abc":
        asm.add(name, RigidBodyOnAxle())
    asm.connect("a.axle", "b.axle")
    asm.connect("b.axle", "c.axle")
    asm.connect("c.axle", "a.axle")  # each pair alone fits; the three together cannot
    with pytest.raises(AssemblyError, match=r"connection c.axle - a.axle leaves no way .* together "
                                            r"with a.axle - b.axle, b.axle - c.axle"):
        asm.resolve_causality()


def test_a_dangling_motion_input_is_named():
    asm = Assembly("alone")
    asm.add("block", SpringBlock())
    with pytest.raises(AssemblyError, match=r"block.flange_a is a dangling required input"):
        asm.resolve_causality()
    pusher = Assembly("pusher")
    pusher.add("push", ConstantForce())
    with pytest.raises(AssemblyError, match=r"push.flange is a dangling required input"):
        pusher.couplings()


def test_an_unconnected_free_flange_is_allowed():
    asm = Assembly("beam")
    asm.add("beam", AssumedModesBeam())  # tip force in: an open tip is a free end, force 0
    assert asm.resolve_causality() == {"beam": "free_tip"}


def test_a_choice_that_fits_every_connection_but_leaves_an_input_open_is_named():
    asm = Assembly("open")
    asm.add("push", ConstantForce())     # motion in: p1 must compute the motion (profile A) ...
    asm.add("part", TwoPorts())          # ... and profile A leaves p2 a motion input
    asm.connect("push.flange", "part.p1")
    with pytest.raises(AssemblyError, match=r"leaves a required input dangling, e.g. part.p2 \(motion\)"):
        asm.resolve_causality()
    ok = Assembly("ok")
    ok.add("drv", ConstantSpeed())
    ok.add("part", TwoPorts())
    ok.connect("drv.flange", "part.p1")
    assert ok.resolve_causality()["part"] == "B"


def test_a_thousand_block_chain_resolves_without_a_deep_stack():
    """The search walks the instances in a loop: one stack frame per instance overflowed
    Python's stack (RecursionError) in an assembly of about a thousand instances."""
    from benchmarks.chain import friction_chain
    chosen = friction_chain(1000).resolve_causality()
    assert len(chosen) == 3001
    assert {chosen[f"block{i}"] for i in range(1, 1001)} == {"on_moving_support"}
    assert {chosen[f"link{i}"] for i in range(1, 1001)} == {"between_masses"}
