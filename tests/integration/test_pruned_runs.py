"""A scene runs only what its record needs (assemblies.pruning): a component beside it
that feeds nothing recorded changes nothing, in every mode, and is named as pruned."""
from __future__ import annotations

import dataclasses

import numpy as np
import pytest

from assemblies.run import run_scene
from assemblies.scenes import SCENES
from components import ConstantSpeed, SpringBlock


def _stick_slip_beside_a_second_chain():
    asm = SCENES["stick_slip"].build()
    asm.add("driver2", ConstantSpeed(v=0.2))
    asm.add("block2", SpringBlock(m=2.0, mu_k=0.1, mu_s=0.2))
    asm.connect("driver2.flange", "block2.flange_a")
    return asm


@pytest.fixture
def beside(monkeypatch):
    scene = dataclasses.replace(SCENES["stick_slip"], name="stick_slip_beside",
                                build=_stick_slip_beside_a_second_chain)
    monkeypatch.setitem(SCENES, "stick_slip_beside", scene)
    return "stick_slip_beside"


@pytest.mark.parametrize("mode", ["cosim", "me", "monolithic"])
def test_an_unrecorded_chain_is_pruned_and_changes_nothing(beside, mode):
    alone = run_scene("stick_slip", mode=mode)
    with_chain = run_scene(beside, mode=mode)
    assert with_chain.settings["pruned"] == ["driver2", "block2"]
    assert alone.settings["pruned"] == []
    assert with_chain.columns == alone.columns
    for column in alone.columns:
        np.testing.assert_array_equal(with_chain[column], alone[column])
    # and the run is the seed's: first slip at t1 = 8 s (seed 9.2, closed form)
    assert with_chain.figures[0].passed


def test_without_pruning_the_chain_runs_and_shares_the_error_control(beside):
    """The control: with every instance run, the second chain's states join the shared
    step control (me: one integrator), so the recorded columns differ in their last
    digits; the pruned run above is therefore not the same run by accident."""
    alone = run_scene("stick_slip", mode="me")
    everything = run_scene(beside, mode="me", prune=False)
    assert everything.settings["pruned"] == []
    assert not np.array_equal(everything["block.x"], alone["block.x"])
    np.testing.assert_allclose(everything["block.x"], alone["block.x"], atol=1e-7)
