"""The friction chain of the scaling benchmark (benchmarks/chain.py) does the physics it
claims: its first slip and its sliding equilibrium against closed forms (the `me`
master: all states in one integrator, events located to the solver tolerance)."""
import numpy as np
import pytest

from assemblies.masters.me import simulate_me
from benchmarks.chain import (chain_first_slip, chain_sliding_equilibrium, friction_chain,
                              positions)

N = 3
# d = 2 damps the slowest sliding mode (K eigenvalue 4 sin^2(pi/14) = 0.198) at
# d lambda / 2m = 0.198 /s: the 0.9 m transient is below 1e-6 m by t = 80 s
PARAMS = dict(d=2.0, belt_speed=0.1)
STOP, STEP, TOL = 80.0, 0.5, 1e-9


@pytest.fixture(scope="module")
def run():
    asm = friction_chain(N, **PARAMS)
    modes = [f"block{i}.mode" for i in range(1, N + 1)]
    return asm, simulate_me(asm, STOP, STEP, TOL, record=positions(N) + modes)


def _first_slip_is_the_closed_form(asm, res):
    t_slip = chain_first_slip(asm)  # (mu_s m g - d v) / (c v) = 2 s here
    assert t_slip == pytest.approx(2.0)
    first = {}
    for i in range(1, N + 1):
        ev = res.events.get(f"block{i}")
        slips = [] if ev is None else [t for t, m in zip(ev["time"], ev[f"block{i}.mode"]) if m != 0]
        first[i] = slips[0] if slips else np.inf
    assert abs(first[1] - t_slip) < 1e-8  # an event time: located to the solver tolerance
    # the wall pulls block1 back: it slides backward relative to the belt
    ev = res.events["block1"]
    assert ev["block1.mode"][list(ev["time"]).index(first[1])] == -1
    # the links between riding blocks stay at rest until block1 moves
    assert min(first[2], first[3]) > t_slip + 0.1


def _settles_to_the_sliding_equilibrium(asm, res):
    s_eq = chain_sliding_equilibrium(asm)  # K s = mu_k m g: 0.9, 1.5, 1.8 m
    np.testing.assert_allclose(s_eq, [0.9, 1.5, 1.8], rtol=1e-12)
    s_end = np.array([res[c][-1] for c in positions(N)])
    np.testing.assert_allclose(s_end, s_eq, rtol=0, atol=1e-5)
    # and every block slides backward on the belt at the end (kinetic friction holds it)
    assert all(res[f"block{i}.mode"][-1] == -1 for i in range(1, N + 1))


def test_block1_slips_first_when_its_wall_link_reaches_the_static_limit(run):
    _first_slip_is_the_closed_form(*run)


def test_chain_settles_to_the_sliding_equilibrium(run):
    _settles_to_the_sliding_equilibrium(*run)


def test_the_composite_of_member_maps_does_the_same_physics(monkeypatch):
    """The composite FMU whose functions are maps over member kinds (what a chain beyond
    FLAT_LIMIT gets, forced here at N = 3) validates with fmpy and, run by the engine,
    meets the same closed forms."""
    from fmpy.validation import validate_fmu

    from assemblies.engine import simulate_monolithic
    from assemblies.masters import composite_code
    from assemblies.masters.monolithic import composite
    from fmus import build_fmu
    monkeypatch.setattr(composite_code, "FLAT_LIMIT", 0)
    asm = friction_chain(N, **PARAMS)
    asm.name = "chain_of_member_maps"  # its own recipe: never the flattened composite's
    assert validate_fmu(str(build_fmu(composite(asm)))) == []
    modes = [f"block{i}.mode" for i in range(1, N + 1)]
    res = simulate_monolithic(asm, STOP, STEP, TOL, record=positions(N) + modes)
    _first_slip_is_the_closed_form(asm, res)
    _settles_to_the_sliding_equilibrium(asm, res)


def test_bad_size_is_refused_with_its_name():
    with pytest.raises(ValueError, match="n must be an integer >= 1"):
        friction_chain(0)


def test_event_location_per_instance_finds_the_same_events(monkeypatch):
    """The engine's me master locating each instance's events alone (what a chain of 16
    blocks and more gets, forced here at N = 3) meets the closed forms, and finds the
    same events as the look at the whole assembly."""
    from assemblies.engine import me as engine_me
    modes = [f"block{i}.mode" for i in range(1, N + 1)]
    runs = {}
    for name, local_from in (("chain_whole_look", 10**9), ("chain_local_look", 1)):
        monkeypatch.setattr(engine_me, "LOCAL_EVENTS_FROM", local_from)
        asm = friction_chain(N, **PARAMS)
        asm.name = name  # a plan of its own
        runs[name] = asm, engine_me.simulate_me(asm, STOP, STEP, TOL, record=positions(N) + modes)
    asm, res = runs["chain_local_look"]
    _first_slip_is_the_closed_form(asm, res)
    _settles_to_the_sliding_equilibrium(asm, res)
    whole = runs["chain_whole_look"][1]
    assert (res.settings["event_location"], whole.settings["event_location"]) == \
        ("per instance", "whole assembly")
    assert res.settings["events"] == whole.settings["events"]
    for i in range(1, N + 1):
        np.testing.assert_allclose(res.events[f"block{i}"]["time"],
                                   whole.events[f"block{i}"]["time"], rtol=0, atol=1e-12)


def test_indicator_couplings_out_of_range_are_refused_before_the_run(monkeypatch):
    """The C checks the per-instance lists before it sizes anything by them."""
    import ctypes

    from assemblies.engine import EngineError
    from assemblies.engine import me as engine_me
    monkeypatch.setattr(engine_me, "LOCAL_EVENTS_FROM", 1)
    asm = friction_chain(2, **PARAMS)
    asm.name = "chain_hostile_indicator_plan"
    # twice: the first call's plan is keyed before the causality is resolved
    engine_me.simulate_me(asm, 1.0, 0.5, 1e-6)
    engine_me.simulate_me(asm, 1.0, 0.5, 1e-6)
    plan = list(engine_me._plans.values())[-1]
    assert plan.indicator_start is not None and "block2" in plan.names
    n = plan.indicator_start[len(plan.names)]
    plan.indicator_coupling = plan.keep.array(ctypes.c_int, [10**6] * n)
    plan.spec = None  # the plan's MeSpec, made once from its fields, is made again
    with pytest.raises(EngineError, match="indicator_coupling: couplings out of range"):
        engine_me.simulate_me(asm, 1.0, 0.5, 1e-6)
