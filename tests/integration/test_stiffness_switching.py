"""The automatic choice between DOPRI5 and RODAS3 cannot thrash (issue 27).

The undamped assumed-modes beam (benchmarks.scenes beam_N*, assumed coordinates) has
imaginary eigenvalues up to about (N pi)^2: Hairer's test calls DOPRI5 stability-bound
there, yet RODAS3 (third order) needs steps no longer than DOPRI5's (fifth order), and
the rule back to DOPRI5 (h rho < 1) fires a few steps later. Before the fix the engine
switched 220 times in 5,195 steps at N = 16, tolerance 1e-5 (660 Jacobians); each
implicit episode that did not pay now doubles the explicit dwell before the next, so
the switches number O(log steps): at most 2 (log2(steps / 15) + 2) (stiffness.c: a dwell
of 15 * 2^penalty steps). Counts, not timings: the bounds hold on any machine.

The answers are checked against the beam's exact modal solution (numpy's eigh of the
same M and K). (The runtime's directional derivatives, now served for every column from
one evaluation of the dense Jacobian per point, are checked column by column at points
that move between calls against CasADi's Jacobian and finite differences by
tests/unit/test_directional_derivatives.py.)
"""
import math
import re

import numpy as np

from assemblies.assembly import Assembly
from assemblies.engine.me import simulate_me
from benchmarks import references
from components.bodies.beam import AssumedModesBeam
from cs_slave import initialize, open_slave

N, TOL, STOP, STEP, W_TIP0 = 16, 1e-5, 2.0, 0.01, 0.1
WORK = re.compile(r"(\d+) steps, (\d+) rejected, (\d+) derivative evaluations, "
                  r"(\d+) Jacobians, (\d+) events, (\d+) method switches")


def _beam():
    return AssumedModesBeam(name="beam", basis="sine", n_modes=N, w_tip0=W_TIP0,
                            coordinates="assumed")


def _log_bound(steps: int) -> int:
    return 2 * (math.ceil(math.log2(max(steps, 15) / 15)) + 2)


def _exact(times):
    _, w_tip = references.beam_free_vibration(N, W_TIP0)
    return w_tip(np.asarray(times))


def test_engine_automatic_method_does_not_thrash_on_the_undamped_beam():
    asm = Assembly("beam_thrash")
    asm.add("beam", _beam())
    auto = simulate_me(asm, STOP, STEP, TOL, record=["beam.w_tip"])
    dopri = simulate_me(asm, STOP, STEP, TOL, record=["beam.w_tip"], method="DOPRI5")
    s = auto.settings
    assert s["method"] == "auto"
    assert 0 < s["method_switches"] <= _log_bound(s["steps"]), s
    # each switch to RODAS3 costs a handful of Jacobians, and the checks thin out: the
    # thrash cost 660 in 5,195 steps
    assert s["jacobians"] <= s["steps"] / 20, s
    assert s["steps"] <= 1.2 * dopri.settings["steps"], (s, dopri.settings)
    exact = _exact(auto["time"])
    error_dopri = np.abs(np.asarray(dopri["beam.w_tip"]) - exact).max()
    error_auto = np.abs(np.asarray(auto["beam.w_tip"]) - exact).max()
    assert error_auto <= max(3 * error_dopri, 3 * TOL), (error_auto, error_dopri)


def test_fmu_automatic_solver_does_not_thrash_on_the_undamped_beam():
    """The same rule in the FMU runtime's Co-Simulation (FMI 3, solver = 2: automatic),
    its counts from the logSolver line every doStep writes."""
    work = np.zeros(6, dtype=int)

    def log(message):
        m = WORK.search(message.decode())
        if m:
            work[:] += [int(g) for g in m.groups()]

    beam = _beam()
    fmu, vr = open_slave(beam, 3, log, instance_name="beam")
    fmu.setDebugLogging(True, ["logSolver"])
    fmu.setInt32([vr["solver"]], [2])
    initialize(fmu, 3, TOL)
    tips = [fmu.getFloat64([vr["w_tip"]])[0]]
    for i in range(round(STOP / STEP)):
        fmu.doStep(i * STEP, STEP)
        tips.append(fmu.getFloat64([vr["w_tip"]])[0])
    fmu.terminate()
    fmu.freeInstance()
    steps, _, _, jacobians, _, switches = work.tolist()
    assert 0 < switches <= _log_bound(steps), work
    assert jacobians <= steps / 20, work
    times = np.arange(len(tips)) * STEP
    assert np.abs(np.array(tips) - _exact(times)).max() <= 3 * TOL



def test_rodas3_on_jacobians_shared_across_columns_matches_differences_and_the_exact_beam():
    """The engine's RODAS3 on the directional derivatives (every column of a Jacobian
    from one evaluation of the model's dense Jacobian) against the same run on forward
    differences (a Jacobian of n + 1 right-hand sides, no directional derivatives at
    all): both within the tolerance of the exact solution, and of each other."""
    asm = Assembly("beam_jacobians")
    asm.add("beam", _beam())
    runs = {how: simulate_me(asm, STOP, STEP, TOL, record=["beam.w_tip"], method="RODAS3",
                             jacobian=how) for how in ("exact", "fd")}
    exact = _exact(runs["exact"]["time"])
    tips = {how: np.asarray(r["beam.w_tip"]) for how, r in runs.items()}
    for how, tip in tips.items():
        assert np.abs(tip - exact).max() <= 5 * TOL, how
    assert np.abs(tips["exact"] - tips["fd"]).max() <= 5 * TOL
