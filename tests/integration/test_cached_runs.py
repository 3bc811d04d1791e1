"""A cached scene costs nothing before it starts: a second run in a process reuses the
loaded FMUs, and a run in a fresh process finds them by recipe (no flattening, no code
generation, no extraction)."""
from __future__ import annotations

import numpy as np
import pytest

import assemblies.engine.me as engine_me
import assemblies.engine.prepare as prepare
import assemblies.pruning as pruning
import fmus.build as build
import fmus.recipe as recipe
from assemblies.run import run_scene


def _forbid_building(monkeypatch):
    def refuse(*args, **kwargs):
        raise AssertionError("a cached run flattened, generated or extracted a model")
    for module, name in ((build, "flatten"), (build, "generate_c"), (build, "_compile"),
                         (prepare, "_read")):
        monkeypatch.setattr(module, name, refuse)


def _forget_the_process(monkeypatch):
    """What a new process would not have: the in-process memos."""
    monkeypatch.setattr(prepare, "_by_key", {})
    monkeypatch.setattr(engine_me, "_plans", {})
    monkeypatch.setattr(recipe, "_closures", {})
    monkeypatch.setattr(recipe, "_module_digests", {})
    monkeypatch.setattr(pruning, "_ends_run", {})
    monkeypatch.setattr(recipe, "_digests", {})
    prepare.prepared_path.cache_clear()


@pytest.mark.parametrize("name", ["stick_slip", "resonance_below"])  # cosim, me
def test_a_second_run_in_a_process_builds_nothing_and_repeats_the_first(name, monkeypatch):
    first = run_scene(name)
    _forbid_building(monkeypatch)
    second = run_scene(name)
    assert second.columns == first.columns
    for column in first.columns:
        np.testing.assert_array_equal(second[column], first[column])
    assert all(f.passed for f in second.figures)


def test_a_run_in_a_fresh_process_finds_its_fmus_by_recipe(monkeypatch):
    first = run_scene("stick_slip")  # now on disk, recipes filed
    _forget_the_process(monkeypatch)
    _forbid_building(monkeypatch)
    again = run_scene("stick_slip")
    np.testing.assert_array_equal(again["block.x"], first["block.x"])


def test_new_values_are_set_at_run_time_without_a_rebuild(monkeypatch):
    run_scene("stick_slip")
    _forget_the_process(monkeypatch)
    _forbid_building(monkeypatch)
    # mu_s = 0.5: first slip when k v t = mu_s m g, t1 = 0.5 / 0.05 = 10 s (seed 9.2)
    slipped = run_scene("stick_slip", params={"block.mu_s": 0.5})
    t1 = next(f for f in slipped.figures if f.name == "t1")
    assert t1.reference == pytest.approx(10.0)
    assert t1.passed


def test_a_composite_in_a_fresh_process_is_not_joined_again(monkeypatch):
    first = run_scene("stick_slip", mode="monolithic")
    _forget_the_process(monkeypatch)
    _forbid_building(monkeypatch)
    import assemblies.masters.monolithic as monolithic
    monkeypatch.setattr(monolithic, "join", lambda *a: (_ for _ in ()).throw(
        AssertionError("a cached composite was joined again")))
    again = run_scene("stick_slip", mode="monolithic")
    np.testing.assert_array_equal(again["block.x"], first["block.x"])
