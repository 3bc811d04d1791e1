"""`python -m benchmarks.peers`: the error it measures, its step search, its table and JSON.

Nothing here depends on how fast a tool was. The peers (libcosimpy, ecospy: the
``compare`` extra) are skipped, with the reason, where they are not installed.
"""
import importlib.util
import json
import math

import numpy as np
import pytest

from benchmarks import peers
from benchmarks.run_all import kept_sections


def _peer_or_skip(module):
    if importlib.util.find_spec(module) is None:
        pytest.skip(f"{module} is not installed (pip install -e .[compare])")
    if module == "ecospy":
        try:
            from benchmarks.cosim_compare import load_ecospy
            load_ecospy()
        except (ImportError, OSError) as exc:  # libtbb.so.12 missing: the tbb wheel
            pytest.skip(f"ecospy does not load: {exc}")


def test_error_is_the_weighed_largest_deviation_on_the_grid():
    times = np.round(np.arange(0, 1.01, 0.1), 10)
    ref = peers.sample_rows(times, {"a.s": 4 * times, "a.v": 0.5 * np.ones_like(times)},
                            np.array([0.5, 1.0]))
    assert list(ref["a.s"]) == [2.0, 4.0]
    run = peers.Columns({"a.s": np.array([2.0, 4.0 + 2e-3]), "a.v": np.array([0.5, 0.5 - 3e-4])})
    # a.s weighed by its largest |value| (4), a.v by 1 (its values are below 1)
    assert peers.error(run, ref) == pytest.approx(max(2e-3 / 4, 3e-4), rel=1e-12)
    # a run that stopped before a grid time has no value there: an infinite error
    short = peers.sample_rows(times[:6], {"a.s": 4 * times[:6], "a.v": 0.5 * np.ones(6)},
                              np.array([0.5, 1.0]))
    assert math.isnan(short["a.s"][1]) and peers.error(short, ref) == math.inf


def test_the_step_search_finds_the_largest_step_within_the_target():
    # a first-order method: error = 3 h, h = 0.5 / k; the largest h within 1e-3 is the
    # smallest divisor k of 5e8 with 1.5 / k <= 1e-3, i.e. k >= 1500: 1600
    ladder, every_k = peers.step_ladder(0.5), peers.divisors(500_000_000)
    tries = []

    def try_run(k):
        tries.append(k)
        return {"error": 1.5 / k, "run_s": 1e-3 * k}

    found = peers.search(try_run, ladder, 1e-3, budget_s=100.0,
                         between=lambda a, b: [k for k in every_k if a < k < b],
                         cost=lambda k, last: None if last is None else last[2] * k / last[0])
    best_k = min(k for k in every_k if 1.5 / k <= 1e-3)
    assert best_k == 1600
    assert found["reached"] and found["chosen"][0] == best_k
    assert len(tries) == len(set(tries)) < 25  # the ladder, then a bisection

    # a budget the next rung (k = 2048, 2.05 s) exceeds: the finest k short of it that
    # the budget affords is tried (1600 at 1.6 s), and met
    found = peers.search(try_run, ladder, 1e-3, budget_s=1.7,
                         between=lambda a, b: [k for k in every_k if a < k < b],
                         cost=lambda k, last: None if last is None else last[2] * k / last[0])
    assert found["reached"] and found["chosen"][0] == 1600
    # a budget the ladder exhausts first: not reached, the best error said
    found = peers.search(try_run, ladder, 1e-3, budget_s=0.5,
                         between=lambda a, b: [k for k in every_k if a < k < b],
                         cost=lambda k, last: None if last is None else last[2] * k / last[0])
    assert not found["reached"] and "budget" in found["why"]
    assert found["best"][1] == min(1.5 / k for k, *_ in found["tried"]) > 1e-3

    # an error that stops falling (a floor) ends the search, not the budget
    found = peers.search(lambda k: {"error": 1e-2 + 1.5 / k, "run_s": 0.0}, ladder, 1e-3,
                         budget_s=100.0)
    assert not found["reached"] and found["why"] == "the error stopped falling"


def test_peers_and_our_fixed_steps_agree_and_converge_at_first_order(tmp_path):
    """Jacobi with a zero-order hold on the same FMUs is one algorithm: libcosim, Ecos, a
    plain fmpy loop and our engine at the same step give the same trajectory (to the
    FMUs' solver tolerance), and its error against the composite FMU halves with h."""
    _peer_or_skip("libcosimpy")
    _peer_or_skip("ecospy")
    from assemblies.scenes import scene
    from assemblies.ssp import export_ssp

    stop, compared = 4.0, peers.SCENES["two_block_belt"]
    sc = scene("two_block_belt")
    grid = peers.sample_grid(stop)
    ref = peers.reference("two_block_belt", compared, grid)
    ssp = export_ssp(sc.build(), tmp_path / "belt.ssp", stop)
    runs = peers.tools("two_block_belt", sc.build, ssp, stop, peers.SAMPLE, compared, tmp_path)
    errors = {}
    for k in (100, 200):
        results = {tool: runs[tool](k) for tool in peers.PEERS}
        errors[k] = peers.error(results["ecos"]["values"], ref)
        for tool, r in results.items():
            assert r["steps"] == k * round(stop / peers.SAMPLE)
            # the FMI 2 FMUs of the SSP and our engine's own (FMI 3) differ by their
            # solvers' tolerance (1e-8), not by the coupling error (1e-3 x smaller)
            assert peers.error(r["values"], results["ours fixed"]["values"]) < 1e-3 * errors[k], tool
    assert 1.7 < errors[100] / errors[200] < 2.3, errors
    # ours adaptive at a loose tolerance is within a looser error, at a tight one closer
    loose, tight = runs[peers.OURS]((1e-2, 1e-8)), runs[peers.OURS]((1e-5, 1e-10))
    assert peers.error(tight["values"], ref) < peers.error(loose["values"], ref) < 5e-2


def test_table_json_and_results_section(tmp_path, monkeypatch):
    """A scene measured end to end on a short run with a budget too small for the finest
    target: every row is written, a target no tool reaches says so with the smallest
    error, and the section is one run_all keeps."""
    data = {"when": "now", "machine": "here", "repeats": 1, "budget_s": 0.3,
            "sample": peers.SAMPLE, "fmu_tolerance": 1e-8, "load_average": [1.0, 1.0],
            "scenes": [peers.measure_scene("two_block_belt", peers.SCENES["two_block_belt"],
                                           (1e-1, 1e-9), 1, 0.3, tmp_path, log=lambda s: None,
                                           stop=1.0, only=("ours fixed", peers.OURS))]}
    rows = data["scenes"][0]["targets"]
    assert rows["0.1"]["ours fixed"]["reached"] and rows["0.1"][peers.OURS]["reached"]
    assert rows["0.1"]["ours fixed"]["error_reached"] <= 0.1
    unreached = rows["1e-09"]["ours fixed"]
    assert not unreached["reached"] and unreached["smallest_error"] > 1e-9
    text = peers.table(data)
    assert "cannot reach" in text and "smallest error" in text
    json.loads(json.dumps(data, default=float))  # what --json writes
    section = peers.results_section(data)
    assert section[0] == "## Peer co-simulation masters (issue 27)"
    assert any("| cannot reach |" in line for line in section)
    results = tmp_path / "RESULTS.md"
    results.write_text("## Other\n\nx\n\n## Known weaknesses of this suite\n\n- y\n")
    from benchmarks.run_all import replace_section
    replace_section(results, section)
    assert kept_sections(results)[0] == section[0]
