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
