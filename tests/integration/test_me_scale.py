"""The engine's Model Exchange master at scale: what grows with the number of instances
does so linearly (issue 27). Counted, never timed: each test asserts how many FMU calls
a run makes, against what the FMI rules and the assembly's structure require."""
import numpy as np
import pytest
from fmpy.validation import validate_fmu

from assemblies import FMU, Assembly, simulate_me

from handmade_fmus import handmade_fmu

RELAYS = 40


def relay_chain(n: int) -> Assembly:
    """n relays y = u + 1, each feeding the next, in causal order: r_k.y = k at t = 0."""
    asm = Assembly(f"sp_relays_{n}")
    path = handmade_fmu("sp_relay")
    for k in range(1, n + 1):
        asm.add(f"r{k}", FMU(path))
    for k in range(1, n):
        asm.connect(f"r{k}.y", f"r{k + 1}.u")
    return asm


def test_relay_fmu_is_valid():
    assert validate_fmu(str(handmade_fmu("sp_relay"))) == []


def test_initialization_settles_a_causal_chain_in_a_few_passes():
    """Before the run, the master propagates the couplings until the chain's outputs
    settle. A chain in causal order settles in one pass; the next pass sees nothing
    change and is the last (it did n passes, setting every input n times: n^2 calls).
    The values must still reach the chain's end: y_k = k, x = exp(-t)."""
    res = simulate_me(relay_chain(RELAYS), 0.5, 0.25,
                      record=[f"r{k}.{v}" for k in range(1, RELAYS + 1)
                              for v in ("y", "init_sets", "x")])
    for k in range(1, RELAYS + 1):
        assert res[f"r{k}.y"][0] == k
        np.testing.assert_allclose(res[f"r{k}.x"], np.exp(-res["time"]), rtol=1e-6)
    sets = [res[f"r{k}.init_sets"][0] for k in range(2, RELAYS + 1)]
    # one pass that sets, one that confirms: two sets of each coupled input
    assert max(sets) <= 2, sets


# --- the Jacobian's column groups (c/jacobian.c) ---------------------------------------

def stiff_chain_run(n: int, jacobian: str, stop: float = 20.0):
    """The benchmark's friction chain (started at rest) under RODAS3, so that every step
    takes a Jacobian."""
    from benchmarks.chain import friction_chain, positions
    asm = friction_chain(n, d=2.0, belt_speed=0.1)
    return simulate_me(asm, stop, 0.5, 1e-8, method="RODAS3", jacobian=jacobian,
                       record=positions(n))


@pytest.mark.parametrize("n", [3, 12])
def test_grouped_jacobian_gives_the_solution_of_differences(n):
    """Columns seeded together (no two of a group reach the same derivative) give the
    Jacobian that forward differences of the right-hand side give column by column,
    and the banded factorisation the chain's pattern allows (n = 12: a band of 10
    diagonals among 37 states) solves what the dense one solves: the same RODAS3 run,
    step for step."""
    from benchmarks.chain import positions
    grouped, differences = stiff_chain_run(n, "exact"), stiff_chain_run(n, "fd")
    assert grouped.settings["jacobian"] == "directional derivatives"
    assert differences.settings["jacobian"] == "finite differences"
    assert grouped.settings["jacobians"] > 100
    assert differences.settings["jacobian_band"] == 0  # no pattern: dense
    assert (grouped.settings["jacobian_band"] > 0) == (n == 12)
    # a Jacobian wrong in any entry that matters would change the steps RODAS3 takes
    for k in ("steps", "rejected", "jacobians"):
        assert grouped.settings[k] == differences.settings[k]
    for c in positions(n):
        np.testing.assert_allclose(grouped[c], differences[c], rtol=0, atol=1e-7)


def test_a_chain_takes_as_many_propagations_per_jacobian_whatever_its_length():
    """A chain couples each block to its neighbours only: its Jacobian is banded, and
    the column groups that cover it do not grow with the chain (2n + n + 1 states),
    nor do the directional-derivative calls per instance and Jacobian (counted)."""
    per_instance, groups = {}, {}
    for n in (4, 16):
        res = stiff_chain_run(n, "exact", stop=4.0)
        s = res.settings
        n_states, n_instances = 3 * n + 1, 3 * n + 1  # 2 per block, 1 per belt and the wall
        groups[n] = s["jacobian_groups"]
        per_instance[n] = s["jacobian_evaluations"] / s["jacobians"] / n_instances
        assert 1 <= groups[n] < n_states
        # 16 blocks: a band of a few diagonals, factored as one (4: dense is as cheap)
        assert (0 < s["jacobian_band"] <= 12) if n == 16 else s["jacobian_band"] == 0
    assert groups[4] == groups[16] < (3 * 16 + 1) / 4
    # each group evaluates each instance about once: about `groups` calls per instance
    assert per_instance[16] <= groups[16] + 1
    assert per_instance[16] <= per_instance[4] * 1.25


def test_a_fully_coupled_model_gets_one_group_per_column():
    """Robertson's kinetics: every derivative depends on every state (one instance),
    so no two columns can share a propagation: three groups for three states, the
    column-by-column Jacobian, factored dense, and the published solution at t = 40."""
    asm = Assembly("robertson")
    asm.add("rob", FMU(handmade_fmu("me_robertson")))
    res = simulate_me(asm, 40.0, 4.0, tolerance=1e-6, jacobian="exact", method="RODAS3")
    assert res.settings["jacobian_groups"] == 3
    assert res.settings["jacobian_band"] == 0
    assert res.settings["jacobian_evaluations"] == 3 * res.settings["jacobians"]
    assert [res[f"rob.y{k}"][-1] for k in (1, 2, 3)] == pytest.approx(
        [0.7158, 9.185e-6, 0.2842], rel=2e-3)


def test_the_jacobian_is_planned_only_when_a_run_needs_one():
    """The plan follows every state's reach through the couplings (for a composite FMU,
    whose derivatives each depend on every state, quadratic in its states: a tenth of a
    256-block chain's monolithic run). A run whose explicit steps never ask for a
    Jacobian plans none (no column groups), though it reports the directional
    derivatives it would take; the same run under RODAS3 plans it at its first step and
    gets the run that finite differences give (the solution does not depend on when
    the plan was made)."""
    from assemblies.engine import simulate_monolithic
    from benchmarks.chain import bench_chain, positions
    for run in (simulate_me, simulate_monolithic):
        explicit = run(bench_chain(4), 10.0, 0.1, 1e-6, record=positions(4))
        s = explicit.settings
        assert s["jacobians"] == 0 and s["jacobian"] == "directional derivatives"
        assert s["jacobian_groups"] == 0 and s["jacobian_evaluations"] == 0
        implicit = run(bench_chain(4), 2.0, 0.1, 1e-6, method="RODAS3", record=positions(4))
        fd = run(bench_chain(4), 2.0, 0.1, 1e-6, method="RODAS3", jacobian="fd",
                 record=positions(4))
        assert implicit.settings["jacobian_groups"] > 0 and implicit.settings["jacobians"] > 0
        for c in positions(4):
            np.testing.assert_allclose(implicit[c], fd[c], rtol=0, atol=1e-6)
