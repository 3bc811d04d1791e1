"""MSL's ElastoBacklash and ElastoBacklash2 against closed forms, MSL's documented law and
the energy balance; their FMUs in FMI 2 and 3, Model Exchange and Co-Simulation."""
import math

import numpy as np
import pytest
from fmpy import simulate_fmu
from fmpy.validation import validate_fmu

from assemblies import Assembly, simulate_me, simulate_monolithic
from components import ComponentError
from components.rotational.backlash import ElastoBacklash, ElastoBacklash2
from components.rotational.rigid import Fixed, Inertia
from fmus import build_fmu

J, C, B = 5.0, 20e3, math.pi / 4  # MSL Examples.Backlash's inertia, stiffness and gap
TOL = 1e-10


def _flight(kind, d, w0, mode, stop=1.0):
    asm = Assembly("backlash")
    asm.add("fixed", Fixed())
    asm.add("gap", kind(c=C, d=d, b=B))
    asm.add("body", Inertia(J=J, phi=0.0, w=w0))
    asm.connect("fixed.flange", "gap.flange_a")
    asm.connect("gap.flange_b", "body.flange_a")
    run = simulate_me if mode == "me" else simulate_monolithic
    return run(asm, stop, 1e-3, TOL, record=["body.phi", "body.w", "body.E", "gap.tau",
                                            "gap.contact", "gap.E", "gap.W_loss"])


@pytest.mark.parametrize("mode", ("me", "monolithic"))
@pytest.mark.parametrize("kind", (ElastoBacklash, ElastoBacklash2))
def test_undamped_impacts_fly_the_gap_and_rebound_after_half_a_period(kind, mode):
    """d = 0: from the middle of the gap at w0 the inertia flies b/2 in (b/2)/w0, is in
    contact for half a period pi sqrt(J/c) (phi = b/2 + w0/omega sin(omega t')), leaves
    at -w0, flies the whole gap b in b/w0 and meets the other edge: the contact events
    fall at those instants, to the tolerance."""
    w0 = 2.0
    res = _flight(kind, 0.0, w0, mode)
    omega = math.sqrt(C / J)
    t1 = B / 2 / w0
    half = math.pi / omega
    expected = [(t1, 1), (t1 + half, 0), (t1 + half + B / w0, -1), (t1 + 2 * half + B / w0, 0)]
    ev = res.events["gap"]
    got = list(zip(np.asarray(ev["time"]), np.asarray(ev["gap.contact"])))
    assert len(got) == len(expected), got
    for (t, q), (t_ref, q_ref) in zip(got, expected):
        assert q == q_ref and abs(t - t_ref) < 1e-7, (t, t_ref)
    t = np.asarray(res["time"])
    inside = (t > t1) & (t < t1 + half)
    phi_ref = B / 2 + w0 / omega * np.sin(omega * (t[inside] - t1))
    assert np.abs(res["body.phi"][inside] - phi_ref).max() < 1e-7
    after = (t > t1 + half) & (t < t1 + half + B / w0)
    np.testing.assert_allclose(res["body.w"][after], -w0, atol=1e-7)


@pytest.mark.parametrize("kind", (ElastoBacklash, ElastoBacklash2))
def test_damped_impacts_never_pull_and_balance_their_energy(kind):
    """MSL's d = 50: the contact torque only pushes (tau has the sign of the contact side,
    0 in the gap), and the kinetic energy at the start is the kinetic + elastic energy +
    what the element dissipated at every instant (nothing acts from outside)."""
    w0 = 3.0
    res = _flight(kind, 50.0, w0, "monolithic", stop=1.5)
    tau, contact = np.asarray(res["gap.tau"]), np.asarray(res["gap.contact"])
    assert np.all(tau * contact >= 0) and np.all(tau[contact == 0] == 0)
    assert (contact == 1).any() and (contact == -1).any()
    total = res["body.E"] + res["gap.E"] + res["gap.W_loss"]
    e0 = J * w0**2 / 2
    assert np.abs(total - e0).max() < 1e-6 * e0
    assert res["gap.W_loss"][-1] > 0.1 * e0  # the damper did take energy


def _law(phi, w, c, d, b, bounded):
    """MSL's documented characteristic (ElastoBacklash.mo, its Documentation section)."""
    if b <= 1e-10:
        return c * phi + d * w
    if -b / 2 <= phi <= b / 2:
        return 0.0
    tau_c = c * (phi - b / 2) if phi > b / 2 else c * (phi + b / 2)
    tau_d = d * w
    if tau_c > 0:
        return 0.0 if tau_c + tau_d <= 0 else tau_c + (min(tau_c, tau_d) if bounded else tau_d)
    return 0.0 if tau_c + tau_d >= 0 else tau_c + (max(tau_c, tau_d) if bounded else tau_d)


CELLS = [(kind, version, fmi_type) for kind in (ElastoBacklash, ElastoBacklash2)
         for version in (2, 3) for fmi_type in ("ModelExchange", "CoSimulation")]


@pytest.mark.parametrize("kind, version, fmi_type", CELLS,
                         ids=[f"{k.__name__}-fmi{v}-{t}" for k, v, t in CELLS])
def test_the_fmu_follows_msls_law_in_every_cell(kind, version, fmi_type):
    """The FMU validates with no message, and driven through fmpy (flange_a held, flange_b
    swept through the gap and both contacts, its speed set so the damper pulls on the
    way out) its torque is MSL's law at every output point (in Co-Simulation fmpy sets
    the inputs at the start of each step and reads the outputs at its end, where the FMU
    has carried the angle input on by its speed input: phi + w h)."""
    c, d, b = 100.0, 30.0, 0.4
    path = build_fmu(kind(c=c, d=d, b=b), fmi_version=version)
    assert validate_fmu(str(path)) == []
    t = np.linspace(0.0, 2.0, 401)
    phi, w = 0.6 * np.sin(math.pi * t), 0.6 * math.pi * np.cos(math.pi * t)
    signals = np.array(list(zip(t, phi, w)), dtype=[("time", float), ("flange_b.phi", float),
                                                    ("flange_b.w", float)])
    dt = 0.005
    res = simulate_fmu(str(path), fmi_type=fmi_type, stop_time=2.0, output_interval=dt,
                       input=signals, output=["tau", "lossPower"],
                       start_values={"c": c, "d": d, "b": b})
    phi_at, w_at = np.interp(res["time"], t, phi), np.interp(res["time"], t, w)
    if fmi_type == "CoSimulation":
        start = np.maximum(res["time"] - dt, 0.0)
        w_at = np.interp(start, t, w)
        phi_at = np.interp(start, t, phi) + w_at * (res["time"] - start)
    expected = np.array([_law(p, v, c, d, b, kind is ElastoBacklash)
                         for p, v in zip(phi_at, w_at)])
    assert np.abs(res["tau"] - expected).max() < 1e-9 * c
    assert (expected == 0).any() and (expected > 0).any() and (expected < 0).any()
    assert np.all(res["lossPower"] >= -1e-12)


def test_no_backlash_is_a_spring_damper():
    """b below MSL's bEps (1e-10): tau = c phi_rel + d w_rel, no gap."""
    assert _law(0.01, 0.2, 100.0, 3.0, 0.0, True) == pytest.approx(1.6)
    path = build_fmu(ElastoBacklash(c=100.0, d=3.0, b=0.0), fmi_version=3)
    signals = np.array([(0.0, 0.01, 0.2), (1.0, 0.01, 0.2)],
                       dtype=[("time", float), ("flange_b.phi", float), ("flange_b.w", float)])
    res = simulate_fmu(str(path), fmi_type="ModelExchange", stop_time=1.0, output_interval=0.5,
                       input=signals,
                       output=["tau"])
    np.testing.assert_allclose(res["tau"], 100.0 * 0.01 + 3.0 * 0.2, rtol=1e-12)


@pytest.mark.parametrize("values, words", [
    ({"c": 0.0}, r"ElastoBacklash 'gap': parameter c = 0 is not allowed; c \(spring constant "
                 r"\(c > 0 required\), N.m/rad\) must be > 0"),
    ({"b": -0.1}, r"ElastoBacklash 'gap': parameter b = -0.1 is not allowed; b \(total "
                  r"backlash, rad\) must be >= 0"),
    ({"d": -1.0}, r"ElastoBacklash 'gap': parameter d = -1 is not allowed"),
])
def test_bad_parameters_are_one_line(values, words):
    with pytest.raises(ComponentError, match=words):
        ElastoBacklash("gap", **values)
