"""Couplings set at events only (assemblies/engine/liveness.py).

Between events the `me` engine sets only the couplings that the state derivatives, the
event indicators or the recorded columns depend on, read from each FMU's
ModelStructure. In two_block_belt that leaves out the reaction forces sent back to the
walls and belts, the accelerations sent to the springs and the velocities sent to the
undamped spring between the blocks: none of them moves anything the integrator needs.
"""
import numpy as np
import pytest

from assemblies.engine import liveness
from assemblies.engine.me import simulate_me
from assemblies.engine.prepare import prepared, record_columns
from assemblies.masters.loops import loop_order
from assemblies.pruning import prune_unrecorded
from assemblies.scenes import scene
from components import SpringBlock

STOP = 20.0  # the first slips and re-sticks of both blocks


def _belt(record=None):
    sc = scene("two_block_belt")
    asm, _ = prune_unrecorded(sc.build(), sc.record)
    return asm, record or sc.record


def test_two_block_belt_defers_the_reactions_and_what_no_spring_force_reads():
    asm, record = _belt()
    deferred = set(simulate_me(asm, 1.0, 0.1, 1e-6, record=record).settings["set_at_events_only"])
    for flange in ("wall_a", "wall_b", "belt_1", "belt_2"):
        assert any(d.endswith(f"-> {flange}.flange.f") for d in deferred), flange
    for spring, port in (("spring1", "flange_a"), ("spring1", "flange_b"),
                         ("spring2", "flange_a"), ("spring2", "flange_b"),
                         ("coupling", "flange_a"), ("coupling", "flange_b")):
        assert any(d.endswith(f"-> {spring}.{port}.a") for d in deferred), (spring, port)
    # a position and a velocity every spring force needs (the coupling spring has no
    # damper, so its velocities wait too)
    assert not any(d.endswith(".s") for d in deferred)
    assert any(d.endswith("-> coupling.flange_a.v") for d in deferred)
    assert not any(d.endswith("-> spring1.flange_b.v") for d in deferred)  # damped
    # what the blocks read is set at every evaluation: their forces and their belts
    assert not any("-> block" in d for d in deferred)


def test_a_recorded_input_is_set_between_events_and_balances_the_spring_force():
    """Recording the wall's reaction makes its coupling needed: at every output row the
    force on the wall is the spring's force at that end, reversed (Newton's third law)."""
    asm, record = _belt(["wall_a.flange.f", "spring1.flange_a.f", "block1.v"])
    res = simulate_me(asm, STOP, 0.1, 1e-8, record=record)
    assert not any(d.endswith("-> wall_a.flange.f") for d in res.settings["set_at_events_only"])
    f_wall, f_spring = np.asarray(res["wall_a.flange.f"]), np.asarray(res["spring1.flange_a.f"])
    assert np.ptp(f_spring) > 0.1  # the spring is loaded and unloaded
    np.testing.assert_allclose(f_wall, -f_spring, rtol=0, atol=1e-12)


def test_deferring_changes_no_value(monkeypatch):
    """What waits for the next event cannot move the derivatives, indicators or record:
    the run is the same to the last bit with every coupling set at every evaluation."""
    asm, record = _belt()
    deferring = simulate_me(asm, STOP, 0.1, 1e-8, record=record)
    monkeypatch.setattr("assemblies.engine.me.continuous_couplings",
                        lambda fmus, couplings, recorded: [True] * len(couplings))
    asm.name = "two_block_belt_all_couplings"  # another plan, not the memoised one
    every = simulate_me(asm, STOP, 0.1, 1e-8, record=record)
    assert every.settings["set_at_events_only"] == []
    assert deferring.settings["steps"] == every.settings["steps"]
    for column in record:
        np.testing.assert_array_equal(deferring[column], every[column], err_msg=column)


@pytest.mark.parametrize("fmi_version", [2, 3])
def test_unlisted_dependencies_mean_every_input(fmi_version):
    """FMI 2 does not list the event indicators' dependencies: a block's indicators then
    depend on all its inputs. FMI 3 lists them: the acceleration of the support is not
    among them."""
    fmu = prepared(SpringBlock(name="block"), fmi_version)
    assert fmu.derivatives_depend == {"flange_a.s", "flange_a.v"}
    expected = set(fmu.inputs) if fmi_version == 2 else {"flange_a.s", "flange_a.v"}
    assert fmu.indicators_depend == expected
    assert liveness.needed_inputs({"block": fmu}, [], [])["block"] == expected


def test_an_output_row_sets_only_what_the_recorded_columns_read(monkeypatch):
    """The blocks' positions depend on their own states and on the travel of their
    belts, their velocities on the belt (relative) on their states alone: a row
    recording them sets the two travel couplings on the four instances involved, and
    its values equal, to the last bit, those of a row that sets the whole assembly
    first. (The scene's own record, with the friction and spring forces, needs every
    coupling the integrator does.)"""
    asm, record = _belt(["block1.s", "block1.v", "block2.s"])
    couplings = asm.couplings()  # resolves the causality profiles, which shape the FMUs
    fmus = {name: prepared(c) for name, c in asm.components.items()}
    ordered, _ = loop_order(couplings, fmus)
    rows = liveness.row_couplings(fmus, ordered, record_columns(fmus, record))
    assert sorted(".".join(c.target) for c, needed in zip(ordered, rows) if needed) == \
        ["block1.support.s", "block2.support.s"]
    partial = simulate_me(asm, STOP, 0.1, 1e-8, record=record)
    monkeypatch.setattr("assemblies.engine.me.row_couplings", lambda *args: None)
    asm.name = "two_block_belt_whole_rows"  # another plan, not the memoised one
    whole = simulate_me(asm, STOP, 0.1, 1e-8, record=record)
    assert partial.settings["steps"] == whole.settings["steps"]
    for column in record:
        assert np.ptp(whole[column]) > 0.1, column  # the blocks move
        np.testing.assert_array_equal(partial[column], whole[column], err_msg=column)
