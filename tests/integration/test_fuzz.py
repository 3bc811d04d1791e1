"""Random call sequences through fmpy's low-level API: no FMU of ours takes its host down.

Short walks of benchmarks/fuzz.py (its docstring says what a walk does and counts) over
SpringBlock for each FMI version and interface, the RollingCoin in one cell per version,
and an assembly FMU (a block pushed by the FMU's input) exported in mode 'cosim' and in
mode 'me' for FMI 2 and 3, each walk in a child process: a crash, a call that takes
longer than 10 s, an illegal status, a non-finite value read with status OK, or a fresh
instance that answers differently after the walk's misuse fails the test. The long run
is the benchmark: `python -m benchmarks.fuzz --calls 100000`. MECHFMU_FUZZ_CALLS
sets the calls per walk here (default 2000; a third of that for an assembly FMU, whose
every instantiation loads its members).
"""
import os

import pytest

from benchmarks.fuzz import cells, run_walk

CALLS = int(os.environ.get("MECHFMU_FUZZ_CALLS", "2000"))
COMPONENT_CELLS = ["SpringBlock-fmi2-CoSimulation", "SpringBlock-fmi2-ModelExchange",
                   "SpringBlock-fmi3-CoSimulation", "SpringBlock-fmi3-ModelExchange",
                   "RollingCoin-fmi3-CoSimulation", "RollingCoin-fmi2-ModelExchange"]
ASSEMBLY_CELLS = ["assembly_cosim-fmi2-CoSimulation", "assembly_cosim-fmi3-CoSimulation",
                  "assembly_me-fmi2-CoSimulation", "assembly_me-fmi2-ModelExchange",
                  "assembly_me-fmi3-CoSimulation", "assembly_me-fmi3-ModelExchange"]


@pytest.fixture(scope="module")
def fuzzed_fmus(tmp_path_factory):
    return {name: (path, version, kind)
            for name, path, version, kind in cells(tmp_path_factory.mktemp("fuzz"))}


@pytest.mark.parametrize("cell", COMPONENT_CELLS + ASSEMBLY_CELLS)
def test_random_call_sequences_get_legal_answers(fuzzed_fmus, cell):
    calls = CALLS if cell in COMPONENT_CELLS else max(1, CALLS // 3)
    outcome, seen, tail = run_walk(*fuzzed_fmus[cell], 12345, calls)
    assert outcome == "ok", (outcome, tail)
    assert sum(seen.values()) == calls
    # the walk reached both sides: calls that succeed and misuse answered with an error
    assert seen.get("0/1", 0) > calls // 10 and seen.get("3", 0) > calls // 10, seen
