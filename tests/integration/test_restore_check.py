"""Roll back only where it is safe.

A foreign FMU that declares canGetAndSetFMUstate has its restore checked once before a
run rolls back through it (save, doStep, restore, doStep again: the same bits); where
the restore is wrong the default adaptive run falls back to fixed steps, warns once in
one line naming the instance, says so in its settings, and is right. A run that cannot
roll back tells each doStep so (noSetFMUStatePriorToCurrentPoint = true), which an FMU
that buffers its steps until then needs to advance at all.

term_decay (tests/handmade/): x' = -x + sin(t), x(0) = 1, each doStep exact on the
FMU's own clock, restoring exactly (restore = 0), not at all (1) or x without the
clock (2). term_lazy: x' = -x, committing a step only once told no rollback follows.
"""
import time
import warnings

import numpy as np
import pytest
from fmpy import simulate_fmu

from assemblies import FMU, Assembly, cosimulate
from assemblies.engine import restore
from assemblies.engine.cosim import DEFAULT_SCHEME
from assemblies.engine.prepare import prepared
from assemblies.experiment import FixedStepFallback
from assemblies.masters.cosim import cosimulate as reference_cosimulate

from handmade_fmus import handmade_fmu

STOP, STEP = 5.0, 0.1
TOL = DEFAULT_SCHEME["tol"]


def decay_exact(t):
    return 1.5 * np.exp(-t) + 0.5 * (np.sin(t) - np.cos(t))


def decay(restore_mode: int) -> Assembly:
    asm = Assembly("decay")
    asm.add("dec", FMU(handmade_fmu("term_decay"), restore=restore_mode))
    return asm


@pytest.mark.parametrize("run", [cosimulate, reference_cosimulate])
@pytest.mark.parametrize("mode, what", [(1, "after a doStep, y reads"),
                                        (2, "stepped again the same, y reads")])
def test_an_inexact_restore_is_found_and_the_run_falls_back(run, mode, what):
    with warnings.catch_warnings(record=True) as caught:
        warnings.simplefilter("always")
        res = run(decay(mode), stop_time=STOP, step=STEP, **DEFAULT_SCHEME)
    fallbacks = [w for w in caught if issubclass(w.category, FixedStepFallback)]
    assert len(fallbacks) == 1  # once, in one line, naming the instance
    text = str(fallbacks[0].message)
    assert "\n" not in text and "'dec'" in text and "does not restore its state exactly" in text
    assert what in text
    assert res.settings["fallback"] == text and what in res.settings["inexact_restore"]["dec"]
    assert res.settings["adaptive"] is False and res.settings["event_sync"] is False
    # right, within the accuracy the run was asked for (each fixed step is exact here)
    assert np.abs(res["dec.y"] - decay_exact(res["time"])).max() < TOL
    fmpy_rows = simulate_fmu(str(handmade_fmu("term_decay")), stop_time=STOP,
                             output_interval=STEP, start_values={"restore": mode})
    np.testing.assert_allclose(res["dec.y"], fmpy_rows["y"], rtol=0, atol=TOL)


@pytest.mark.parametrize("run", [cosimulate, reference_cosimulate])
def test_an_exact_restore_keeps_the_adaptive_run(run):
    with warnings.catch_warnings():
        warnings.simplefilter("error", FixedStepFallback)
        res = run(decay(0), stop_time=STOP, step=STEP, **DEFAULT_SCHEME)
    assert res.settings["adaptive"] is True and res.settings["fallback"] is None
    assert res.settings["inexact_restore"] is None
    assert np.abs(res["dec.y"] - decay_exact(res["time"])).max() < TOL


def test_the_check_runs_once_per_fmu_and_start_values():
    """Memoised: a second run of the same FMU with the same values does not check again
    (the verdict is the same object), one with other values does."""
    asm = decay(1)
    fmu = prepared(asm.components["dec"])
    first = restore.restore_problem("dec", asm.components["dec"], fmu, STEP, 1e-8)
    started = time.perf_counter()
    again = restore.restore_problem("dec", asm.components["dec"], fmu, STEP, 1e-8)
    assert again is first and time.perf_counter() - started < 1e-3
    exact = decay(0).components["dec"]
    assert restore.restore_problem("dec", exact, prepared(exact), STEP, 1e-8) is None


def test_our_own_fmus_are_not_checked():
    from components import MassWithFriction
    m = MassWithFriction()
    assert restore.restore_problem("m", m, prepared(m), STEP, 1e-8) is None


@pytest.mark.parametrize("run", [cosimulate, reference_cosimulate])
def test_a_run_without_rollback_lets_a_buffering_fmu_advance(run):
    """term_lazy keeps each step pending until a doStep says no earlier state will be
    set again; fixed steps say so, and the FMU follows x = e^-t as under fmpy."""
    asm = Assembly("lazy")
    asm.add("lazy", FMU(handmade_fmu("term_lazy")))
    res = run(asm, stop_time=2.0, step=STEP)
    np.testing.assert_allclose(res["lazy.y"], np.exp(-res["time"]), rtol=1e-12)
    fmpy_rows = simulate_fmu(str(handmade_fmu("term_lazy")), stop_time=2.0,
                             output_interval=STEP)
    np.testing.assert_allclose(res["lazy.y"], fmpy_rows["y"], rtol=1e-12)


@pytest.mark.parametrize("run", [cosimulate, reference_cosimulate])
def test_an_exact_fmi3_restore_passes_the_check(run):
    """No false alarm: our own FMI 3 FMU, loaded as a foreign file (so it is checked),
    moves in the check's step (its outputs at 0.1 s differ from the start's) and
    restores exactly: the default adaptive run keeps its scheme."""
    from components import WobblingDisk
    from fmus.build import fetch_fmu
    asm = Assembly("disk")
    asm.add("disk", FMU(fetch_fmu(WobblingDisk()).path))
    comp = asm.components["disk"]
    assert restore.restore_problem("disk", comp, prepared(comp), STEP, 1e-8) is None
    with warnings.catch_warnings():
        warnings.simplefilter("error", FixedStepFallback)
        res = run(asm, stop_time=0.5, step=STEP, **DEFAULT_SCHEME)
    assert res.settings["adaptive"] is True and res.settings["inexact_restore"] is None
    assert res["disk.phi"][1] != res["disk.phi"][0]


@pytest.mark.parametrize("run", [cosimulate, reference_cosimulate])
def test_an_fmi3_restore_that_does_nothing_is_found_too(run):
    """term_stair3 (FMI 3, y = t, ends the run at t = 5) with fmi3SetFMUState doing
    nothing: found, fallen back, warned once; the staircase still ends at 5 with its
    rows, y = t; with an exact restore the adaptive run keeps its scheme."""
    for restore_mode in (1, 0):
        asm = Assembly("stairs")
        asm.add("stair", FMU(handmade_fmu("term_stair3"), restore=restore_mode))
        with warnings.catch_warnings(record=True) as caught:
            warnings.simplefilter("always")
            res = run(asm, stop_time=10.0, step=0.5, **DEFAULT_SCHEME)
        fallbacks = [str(w.message) for w in caught if issubclass(w.category, FixedStepFallback)]
        if restore_mode:
            assert len(fallbacks) == 1 and "'stair'" in fallbacks[0]
            assert "after a doStep, y reads 0.5 instead of 0" in res.settings["inexact_restore"]["stair"]
        else:
            assert not fallbacks and res.settings["adaptive"] is True
        assert res.settings["terminated"]["time"] == pytest.approx(5.0, abs=1e-12)
        np.testing.assert_allclose(res["stair.y"], res["time"], rtol=0, atol=1e-12)
        assert res["time"][-1] == pytest.approx(5.0, abs=1e-12)


def test_an_assembly_fmu_checks_its_foreign_members_restore(tmp_path):
    """export_fmu runs the assembly's master in the FMU: a member whose restore does
    nothing makes it fixed steps, with the warning, and the FMU is right under fmpy."""
    from assemblies import export_fmu
    with pytest.warns(FixedStepFallback, match="'dec' declares canGetAndSetFMUstate but"):
        path = export_fmu(decay(1), tmp_path / "decay.fmu", fmi=2, outputs=["dec.y"],
                          stop_time=STOP, step=STEP)
    rows = simulate_fmu(str(path), stop_time=STOP, output_interval=STEP)
    assert np.abs(rows["dec.y"] - decay_exact(rows["time"])).max() < TOL
