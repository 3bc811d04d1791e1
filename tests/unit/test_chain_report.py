"""benchmarks/chain.py's report: where a mode counts its events, the steps' growth is
split into the events that cause it (issue 27: one integrator ends a step at every
event, so steps = events + a few)."""
import math

from benchmarks.chain import report, step_exponents


def _rows(events):
    # 2 and 8 blocks: steps = events + 20, CPU per step 1 us per block
    return {n: {"cpu_s": (e + 20) * n * 1e-6, "cpu_all_s": [(e + 20) * n * 1e-6],
                "steps": e + 20, "events": e, "cpu_per_step_s": n * 1e-6,
                "max_ds_vs_ref": 1e-7} for n, e in zip((2, 8), events)}


def test_the_events_and_their_exponent_stand_beside_the_steps():
    rows = _rows((4, 16))
    fits = step_exponents(rows)
    assert math.isclose(fits["events"], math.log(4) / math.log(4))  # 4 -> 16 over 2 -> 8
    assert math.isclose(fits["steps"], math.log(36 / 24) / math.log(4))
    assert math.isclose(fits["cpu_per_step"], 1.0)
    data = {"sizes": [2, 8], "stretch": 0.5, "stop_time": 10.0, "step": 0.1,
            "tolerance": 1e-6, "repeats": 1, "reference": "composite FMU", "notes": [],
            "modes": {"engine me": {str(n): r for n, r in rows.items()}},
            "exponents": {"engine me": {"all": 1.3, "lo": 1.3, "hi": 1.3, "tail": 1.3}},
            "per_step": {"engine me": fits}}
    line = next(x for x in report(data).splitlines() if x.startswith("engine me events"))
    assert line.split()[3:] == ["4", "16", "1.00"]


def test_a_mode_without_events_has_no_events_row():
    rows = _rows((4, 16))
    for r in rows.values():
        r["events"] = None  # cosim: communication steps, no events of its own
    assert "events" not in step_exponents(rows)


def test_a_timed_call_leaves_the_collector_as_it_found_it():
    """cpu_seconds freezes what the process held before the call (gc.freeze), so that
    a collection the call triggers does not scan the benchmark's own heap, and thaws
    it afterwards, also when the call fails."""
    import gc

    import pytest

    from benchmarks.chain import cpu_seconds
    seen = []
    cpu, result = cpu_seconds(lambda: seen.append(gc.get_freeze_count()) or "done")
    assert result == "done" and cpu >= 0.0 and seen[0] > 0
    assert gc.get_freeze_count() == 0 and gc.isenabled()

    def fails():
        raise RuntimeError("a mode that fails")
    with pytest.raises(RuntimeError):
        cpu_seconds(fails)
    assert gc.get_freeze_count() == 0
