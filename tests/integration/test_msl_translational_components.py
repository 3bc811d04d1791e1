"""MSL's translational elements, each against a closed form of its documented equations
(run as small assemblies in the compiled engine), and their one-line refusals."""
import math

import numpy as np
import pytest

from assemblies.assembly import Assembly
from assemblies.engine.me import simulate_monolithic
from components import (Brake, ConstantForce, Damper, ElastoGap, Fixed, Mass,
                        MassWithStopAndFriction, SupportFriction)
from components.errors import ComponentError
from components.sources.signals import Constant

TOL = 1e-10


def _chain(name, *pairs, **parts):
    asm = Assembly(name)
    for instance, component in parts.items():
        asm.add(instance, component)
    for a, b in pairs:
        asm.connect(a, b)
    return asm


def _run(asm, stop, step):
    return simulate_monolithic(asm, stop, step, TOL)


def test_mass_under_a_constant_force_and_its_flanges():
    m, F, L, s0, v0 = 4.0, 2.0, 0.5, 1.0, 0.5
    asm = _chain("mass_force", ("push.flange", "mass.flange_a"),
                 push=ConstantForce(F=F), mass=Mass(m=m, L=L, s=s0, v=v0))
    r = _run(asm, 2.0, 0.01)
    t = r["time"]
    np.testing.assert_allclose(r["mass.s"], s0 + v0 * t + F * t**2 / (2 * m), atol=1e-9)
    np.testing.assert_allclose(r["mass.flange_b.s"] - r["mass.flange_a.s"], L, atol=1e-12)
    np.testing.assert_allclose(r["mass.a"], F / m, atol=1e-12)


def test_damper_slows_a_mass_exponentially_and_dissipates_its_energy():
    m, d, v0 = 2.0, 3.0, 1.5
    asm = _chain("damped", ("mass.flange_b", "damper.flange_a"), ("damper.flange_b", "wall.flange"),
                 mass=Mass(m=m, v=v0), damper=Damper(d=d), wall=Fixed(s0=5.0))
    r = _run(asm, 2.0, 0.001)
    t, v = r["time"], r["mass.v"]
    np.testing.assert_allclose(v, v0 * np.exp(-d * t / m), atol=1e-9)
    lost = np.trapezoid(r["damper.lossPower"], t)
    # the trapezoid rule errs by at most T h^2 / 12 max|P''|, P = d v^2, P'' = (2 d / m)^2 P
    bound = t[-1] * (t[1] - t[0])**2 / 12 * (2 * d / m)**2 * d * v0**2
    assert abs(lost - m * (v0**2 - v[-1]**2) / 2) < bound


def test_elastogap_settles_at_its_contact_force_and_only_pushes():
    """A mass pushed into an ElastoGap (n = 1.5) comes to rest where c depth^n = F."""
    c, d, n, gap, F = 100.0, 5.0, 1.5, 1.0, 10.0
    asm = _chain("gap", ("wall.flange", "contact.flange_a"), ("contact.flange_b", "mass.flange_a"),
                 ("mass.flange_b", "push.flange"),
                 wall=Fixed(s0=0.0), contact=ElastoGap(c=c, d=d, s_rel0=gap, n=n),
                 mass=Mass(m=1.0, s=1.5, v=0.0), push=ConstantForce(F=-F))
    r = _run(asm, 30.0, 0.01)
    depth = (F / c)**(1 / n)
    assert abs(r["mass.s"][-1] - (gap - depth)) < 1e-8
    assert abs(r["contact.f"][-1] + F) < 1e-6
    assert np.max(r["contact.f"]) <= 0.0  # never pulls
    assert np.all(r["contact.f"][r["mass.s"] > gap] == 0.0)  # apart: no force


def test_mass_slides_into_its_stop_and_stays_there():
    """Constant Coulomb friction (F_prop = F_Stribeck = 0): s - s0 = (F - F_C) t^2 / 2m
    until the stop at smax - L/2, reached at t = sqrt(2 m gap / (F - F_C)); then at
    rest on the stop, v exactly 0, though the force still pushes into it."""
    m, F, FC, L, smax = 1.0, 5.0, 2.0, 0.2, 1.0
    mass = MassWithStopAndFriction(m=m, L=L, smax=smax, smin=-1.0, F_prop=0.0, F_Coulomb=FC,
                                   F_Stribeck=0.0, s=0.0, v=0.0)
    asm = _chain("stop", ("push.flange", "mass.flange_a"), push=ConstantForce(F=F), mass=mass)
    r = _run(asm, 2.0, 0.001)
    t_hit = math.sqrt(2 * m * (smax - L / 2) / (F - FC))
    ev = r.events["mass"]
    assert [int(q) for q in ev["mass.mode"]] == [0]
    assert abs(float(ev["time"][0]) - t_hit) < 100 * TOL
    after = r["time"] > t_hit
    assert np.all(r["mass.s"][after] == smax - L / 2) and np.all(r["mass.v"][after] == 0.0)
    before = r["time"] < t_hit
    np.testing.assert_allclose(r["mass.s"][before], (F - FC) * r["time"][before]**2 / (2 * m),
                               atol=1e-9)


@pytest.mark.parametrize("ratio, slides", [(1.0005, False), (1.0015, True)])
def test_breakaway_needs_msls_peak_of_0_1_percent(ratio, slides):
    """MSL's MassWithStopAndFriction holds up to f0_max = 1.001 (F_Coulomb + F_Stribeck)."""
    f0 = 15.0
    mass = MassWithStopAndFriction(F_Coulomb=5.0, F_Stribeck=10.0)
    asm = _chain("peak", ("push.flange", "mass.flange_a"),
                 push=ConstantForce(F=ratio * f0), mass=mass)
    r = _run(asm, 0.5, 0.01)
    assert (r["mass.v"][-1] > 0) == slides
    if not slides:
        assert np.all(r["mass.v"] == 0.0) and np.all(r["mass.f"] == ratio * f0)


def test_brake_with_a_speed_dependent_table_extrapolated_past_its_end():
    """mu_pos = [[0, 0.5], [1, 0.3]]: mu = 0.5 - 0.2 v, also beyond v = 1 (MSL's
    LastTwoPoints). With fn = 10 N, m = 2 kg from v0 = 2 m/s: v' = v - 2.5, so
    v = 2.5 - 0.5 e^t, at rest at t = ln 5 and held there."""
    brake = Brake(m=2.0, fn_max=10.0, mu_pos=[[0.0, 0.5], [1.0, 0.3]], v=2.0)
    asm = _chain("brake", ("press.y", "brake.f_normalized"), press=Constant(k=1.0), brake=brake)
    r = _run(asm, 2.0, 0.001)
    t, v = r["time"], r["brake.v"]
    sliding = t < math.log(5)
    np.testing.assert_allclose(v[sliding], 2.5 - 0.5 * np.exp(t[sliding]), atol=1e-8)
    # an event time: located to 100 x the tolerance (scenes' solver_accuracy)
    assert abs(float(r.events["brake"]["time"][0]) - math.log(5)) < 100 * TOL
    assert np.all(v[~sliding] == 0.0)


def test_support_friction_carried_by_its_support_until_pushed_off():
    """A SupportFriction table of one row is Coulomb friction f_pos(0) = 3 N: on a fixed
    support under 2 N it stays put; under 4 N it slides at (4 - 3) / m."""
    for F, a in ((2.0, 0.0), (4.0, 0.5)):
        asm = _chain("support", ("push.flange", "mass.flange_a"), push=ConstantForce(F=F),
                     mass=SupportFriction(m=2.0, f_pos=[[0.0, 3.0]]))
        r = _run(asm, 1.0, 0.01)
        np.testing.assert_allclose(r["mass.v"], a * r["time"], atol=1e-10)


@pytest.mark.parametrize("make, words", [
    (lambda: Brake(mu_pos=[[1.0, 0.5], [0.5, 0.3]]), ["mu_pos", "increase"]),
    (lambda: Brake(mu_pos="steel"), ["mu_pos", "rows [v, value]"]),
    (lambda: Brake(mu_pos=[[-1.0, 0.5]]), ["mu_pos[1,1]", ">= 0"]),
    (lambda: MassWithStopAndFriction(s=30.0), ["s + L/2 <= smax"]),
    (lambda: MassWithStopAndFriction(F_Coulomb=0.0, F_Stribeck=0.0), ["F_Coulomb + F_Stribeck"]),
    (lambda: ElastoGap(n=0.5), ["n", ">= 1"]),
    (lambda: Mass(m=0.0), ["m", "> 0"]),
])
def test_bad_values_are_refused_in_one_line(make, words):
    with pytest.raises(ComponentError) as err:
        make()
    message = str(err.value)
    assert "\n" not in message and all(w in message for w in words), message


def test_rod_and_junction_join_a_mass_to_two_springs():
    """A mass whose flange_b carries, through a Junction, two springs to walls, one of
    them through a rod: they act in parallel, so it oscillates about their common rest
    point at sqrt(2 c / m)."""
    from components import Junction, Rod, Spring
    m, c, L = 2.0, 50.0, 0.3
    asm = _chain("joint", ("mass.flange_b", "joint.flange_a"),
                 ("joint.flange_b", "left.flange_a"), ("left.flange_b", "wallL.flange"),
                 ("joint.flange_c", "rod.flange_a"), ("rod.flange_b", "right.flange_a"),
                 ("right.flange_b", "wallR.flange"),
                 mass=Mass(m=m, s=0.1), joint=Junction(), rod=Rod(L=L),
                 left=Spring(c=c, s_rel0=1.0), right=Spring(c=c, s_rel0=1.0),
                 wallL=Fixed(s0=1.0), wallR=Fixed(s0=1.0 + L))
    r = _run(asm, 2.0, 0.01)
    w = math.sqrt(2 * c / m)
    np.testing.assert_allclose(r["mass.s"], 0.1 * np.cos(w * r["time"]), atol=1e-8)
    np.testing.assert_allclose(r["rod.flange_b.s"] - r["mass.s"], L, atol=1e-12)
    # flows sum to zero at the joint: the cut force at flange_a is minus the springs'
    # tensions (each pulls the joint towards its wall: +f at flange_a of a spring)
    np.testing.assert_allclose(r["joint.flange_a.f"], -(r["left.f"] + r["right.f"]), atol=1e-9)


def test_rows_set_after_construction_sizes_the_brake_table():
    """`--param brake.rows=3` on a built Brake: rows 2 and 3 appear at the default speeds
    1 and 2 m/s with the default mu, row 1 keeps what was set."""
    b = Brake("b", **{"mu_pos[1,2]": 0.3})
    b.set("rows", 3)
    b.validate()
    assert [b.values[f"mu_pos[{k},{j}]"] for k in (1, 2, 3) for j in (1, 2)] == [
        0.0, 0.3, 1.0, 0.5, 2.0, 0.5]
