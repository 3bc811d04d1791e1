"""Kinematic sources that are explicit functions of time (no states, no event indicators)
are evaluated at the step's end, not integrated (issue 27): their doStep takes no solver
step and no derivative evaluation, and their outputs are the closed form to rounding."""
from __future__ import annotations

import math
import re

import pytest

from components import HarmonicMotion, SineMotion
from cs_slave import initialize, open_slave

WORK = re.compile(r"(\d+) steps, (\d+) rejected, (\d+) derivative evaluations")


def _path(component, t):
    p = component.values
    if isinstance(component, SineMotion):
        return p["s0"] + p["U"] * math.sin(p["omega"] * t)
    return p["s0"] + p["U"] * sum(c * math.sin(k * p["omega"] * t)
                                  for k, c in ((1, p["c1"]), (2, p["c2"]), (3, p["c3"])))


@pytest.mark.parametrize("component", [SineMotion(U=0.1, omega=20.0, s0=0.3),
                                       HarmonicMotion(U=0.1, omega=20.0)],
                         ids=["sine", "harmonic"])
def test_a_source_explicit_in_time_takes_no_solver_step(component):
    work = [0, 0, 0]

    def log(message):
        m = WORK.search(message.decode())
        if m:
            work[:] = [w + int(g) for w, g in zip(work, m.groups())]

    fmu, vr = open_slave(component, 3, log, instance_name="table")
    fmu.setDebugLogging(True, ["logSolver"])  # every doStep reports its work there
    initialize(fmu, 3, 1e-8)
    t, h, worst = 0.0, 0.0123, 0.0
    for _ in range(50):
        fmu.doStep(t, h)
        t += h
        (s,) = fmu.getFloat64([vr["flange.s"]])
        worst = max(worst, abs(s - _path(component, t)))
    fmu.terminate()
    fmu.freeInstance()
    assert work == [0, 0, 0], f"steps, rejected, derivative evaluations: {work}"
    assert worst < 1e-14
