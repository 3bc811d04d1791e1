"""Adaptive co-simulation across an impact: a mass on a spring (two FMUs) thrown against
its hard stop, where the event sets its speed to exactly 0, against the closed form of
the piecewise harmonic motion, in both masters.

Before the fix both masters rejected every step that reached the impact: the spring's
input chain (s -> v) could not follow the speed's jump, its defect stayed the jump over
tol however short the step, and the step shrank to 1e-14 s just before the stop."""
import math

import numpy as np
import pytest

from assemblies.assembly import Assembly
from assemblies.engine.cosim import DEFAULT_SCHEME, cosimulate as c_cosimulate
from assemblies.masters.cosim import cosimulate as fmpy_cosimulate
from components import Fixed, MassWithStopAndFriction, Spring

M, C, L = 1.0, 500.0, 1.0
F = 3.0  # Coulomb friction, constant (no Stribeck, no viscous part)
FIXED, S_REL0 = -1.75, 1.0
SMIN, SMAX = -0.9, 0.9
S0, V0 = 0.0, -5.0
W = math.sqrt(C / M)
ANCHOR = FIXED + S_REL0 + L / 2  # stop.s where the spring (to flange_a = s - L/2) is slack
STOP = SMIN + L / 2  # where the mass's left end meets its stop


def closed_form():
    """(t_impact, s(t), v(t)) up to the first reversal after the impact. Sliding with
    v < 0 the friction +F shifts the spring's centre to ANCHOR + F/C; after the impact
    (v := 0 at STOP) the spring pushes off with C (ANCHOR - STOP) > F and the mass
    slides with v > 0 about ANCHOR - F/C."""
    c1, c2 = ANCHOR + F / C, ANCHOR - F / C
    amp, phase = math.hypot(S0 - c1, V0 / W), math.atan2(-V0 / W, S0 - c1)
    # s = c1 + amp cos(W t + phase) reaches STOP first where W t + phase = acos(...)
    t1 = (math.acos((STOP - c1) / amp) - phase) / W

    def s(t):
        t = np.asarray(t)
        return np.where(t < t1, c1 + amp * np.cos(W * t + phase),
                        c2 + (STOP - c2) * np.cos(W * (t - t1)))

    def v(t):
        t = np.asarray(t)
        return np.where(t < t1, -amp * W * np.sin(W * t + phase),
                        -(STOP - c2) * W * np.sin(W * (t - t1)))
    return t1, s, v


def impact_assembly():
    asm = Assembly("trans2_impact")
    asm.add("fixed", Fixed(s0=FIXED))
    asm.add("spring", Spring(c=C, s_rel0=S_REL0))
    asm.add("stop", MassWithStopAndFriction(m=M, L=L, smin=SMIN, smax=SMAX, F_prop=0.0,
                                            F_Coulomb=F, F_Stribeck=0.0, s=S0, v=V0))
    asm.connect("fixed.flange", "spring.flange_a")
    asm.connect("spring.flange_b", "stop.flange_a")
    return asm


@pytest.mark.parametrize("cosimulate", [c_cosimulate, fmpy_cosimulate], ids=["c", "fmpy"])
def test_mass_thrown_against_its_stop_follows_the_closed_form(cosimulate):
    t1, s, v = closed_form()
    assert 0.05 < t1 < 0.07 and C * (ANCHOR - STOP) > 1.001 * F  # it bounces off
    stop_time = t1 + 0.9 * math.pi / W  # before the first reversal after the impact
    tol = DEFAULT_SCHEME["tol"]
    r = cosimulate(impact_assembly(), stop_time=stop_time, step=0.01, tolerance=1e-10,
                   record=["stop.s", "stop.v"], **DEFAULT_SCHEME)
    t = r["time"]
    assert t[-1] == pytest.approx(stop_time)
    # the adaptive master keeps the global error of the states within about tol (its
    # controller's allowance, tol h / horizon per step, summed over the run); the
    # speed's scale is W times the position's
    np.testing.assert_allclose(r["stop.s"], s(t), atol=10 * tol)
    np.testing.assert_allclose(r["stop.v"], v(t), atol=10 * tol * W)
    # it never passes its stop, and it moves away from it after the impact
    assert r["stop.s"].min() >= STOP - 1e-12
    assert np.all(r["stop.v"][t > t1 + 1e-6] > 0)
