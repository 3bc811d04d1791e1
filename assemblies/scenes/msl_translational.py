"""``Modelica.Mechanics.Translational.Examples`` rebuilt from our components (issue 28).

MSL's parameters, start values and stop times; each figure is held to a reference of
:mod:`.msl_translational_references` (closed forms, or an event-driven scipy solution
written from MSL's documented equations). Where MSL joins three flanges at one point
(a damper beside a spring) we use the one component that is that parallel connection
(SpringDamper), since a connection here joins exactly two ports.

- ``translational_oscillator``: two masses on springs (c = 1e4 N/m) driven by a 1 N
  sine at the resonance f = 15.9155 Hz (w = 100 rad/s), one undamped (the amplitude
  grows like t/(2 m w)), one with a 10 N.s/m damper (it settles at F/(d w) = 1 mm).
- ``translational_friction``: stop1, MassWithStopAndFriction (Stribeck friction)
  pushed by a 25 N sine at 0.25 Hz: stuck, breaks away at 1.001 (F_Coulomb +
  F_Stribeck), slides, sticks again; the same with a SupportFriction whose table f_pos
  samples that friction law at 50 speeds (MSL's GenerateStribeckFrictionTable); stop2,
  thrown at -5 m/s against a spring, hits its stop, is pushed off it by the spring and
  comes to rest by friction.
- ``translational_brake``: a 1 kg mass at 1 m/s braked from t = 0.1 s by fn = 2 N with
  mu = 0.5: it stops at t = 1.1 s, 0.6 m on, and stays (the brake holds it), once with
  the brake grounded implicitly and once through a Fixed support.
- ``translational_elastogap``: two masses between walls at +-2 m, one on spring-dampers,
  one on ElastoGaps that lift off for |s| < 0.5 m.
- ``translational_preload``: a spool between two spring plates, a 20 kN/m spring
  preloaded between them and four 1e6 N/m ElastoGap contacts: the spool stays put until
  the 150 N, 0.01 Hz sine force passes the preload (29.4 N), then follows it along the
  spring; held to the statics and quasi-static response, to the exact mode-by-mode
  motion (msl_preload_reference) over the whole run, and to the energy balance.
"""
from __future__ import annotations

import math

import numpy as np

from components.sources.force import Force
from components.sources.signals import Sine, Step
from components.translational.brakes import Brake, SupportFriction
from components.translational.elements import Damper, ElastoGap, Fixed, Spring, SpringDamper
from components.translational.masses import PEAK, Mass, MassWithStopAndFriction
from components.translational.rigid import Junction, Rod

from ..assembly import Assembly
from ..result import Result
from . import msl_preload_reference as pre
from . import msl_translational_references as ref
from .joined import _trapezoid_accuracy
from .scene import Figure, Scene


def solver_accuracy(result: Result, scale: float = 1.0, factor: float = 100.0) -> float:
    """As :func:`.scene.solver_accuracy` (100 x the tolerance: an event time, a state at
    an event), with the tolerance the run controls: co-simulating with adaptive steps,
    the coupling's too (extrapolated inputs are held to it, not to the FMUs' own)."""
    s = result.settings
    tol = s["tolerance"]
    if s.get("scheme") in ("jacobi", "gauss-seidel"):
        tol = max(tol, s["tol"]) if s.get("adaptive") else math.nan  # fixed steps: no bound
    return factor * tol * max(1.0, abs(scale))


def _work(result: Result, power: np.ndarray) -> tuple[float, float]:
    """(integral of `power` over the samples by the trapezoid rule, 3 x its Richardson
    error estimate |I_h - I_2h|), the rule's error bound from the samples themselves."""
    return _integral(result["time"], power)


def _integral(t: np.ndarray, f: np.ndarray) -> tuple[float, float]:
    """:func:`_work` on the samples (t, f)."""
    return float(np.trapezoid(f, t)), 3 * _trapezoid_accuracy(t, f)


def _events(result: Result, instance: str) -> list[tuple[float, int]]:
    """(time, mode) after each event of `instance` that changed its mode."""
    if instance not in result.events:
        return []
    ev = result.events[instance]
    return [(float(t), int(q)) for t, q in zip(ev["time"], ev[f"{instance}.mode"])]


def _first(events, mode: int, after: float = 0.0) -> float:
    return next((t for t, q in events if t > after and q == mode), math.nan)


# --- Oscillator -----------------------------------------------------------------------
OSC = {"m": 1.0, "c": 1e4, "d": 10.0, "F": 1.0, "f": 15.9155, "s0": -0.5}


def _oscillator() -> Assembly:
    asm = Assembly("translational_oscillator")
    for k, d in (("1", 0.0), ("2", OSC["d"])):
        asm.add(f"sine{k}", Sine(f=OSC["f"], amplitude=OSC["F"]))
        asm.add(f"force{k}", Force())
        asm.add(f"mass{k}", Mass(m=OSC["m"], L=1.0, s=OSC["s0"], v=0.0))
        asm.add(f"spring{k}", SpringDamper(c=OSC["c"], d=d, s_rel0=1.0) if d else
                Spring(c=OSC["c"], s_rel0=1.0))
        asm.add(f"fixed{k}", Fixed(s0=1.0))
        asm.connect(f"sine{k}.y", f"force{k}.f")
        asm.connect(f"force{k}.flange", f"mass{k}.flange_a")
        asm.connect(f"mass{k}.flange_b", f"spring{k}.flange_a")
        asm.connect(f"spring{k}.flange_b", f"fixed{k}.flange")
    return asm


def _oscillator_figures(result: Result, asm: Assembly) -> list[Figure]:
    t, w = result["time"], 2 * math.pi * OSC["f"]
    figures = []
    for k, d in (("1", 0.0), ("2", OSC["d"])):
        s, v = result[f"mass{k}.s"], result[f"mass{k}.v"]
        s_ref, _ = ref.forced_oscillator(t, OSC["m"], OSC["c"], d, OSC["F"], w, OSC["s0"])
        amplitude = float(np.max(np.abs(s_ref - OSC["s0"])))
        # the error of a tolerance-controlled run, on a scale of the motion's amplitude
        acc = solver_accuracy(result, 1.0) * amplitude
        figures.append(Figure(f"s{k}_end", f"mass{k} position at the stop time [m] vs the "
                              "closed form of m x'' + d x' + c x = F sin(w t) from rest",
                              float(s[-1]), float(s_ref[-1]), acc,
               source='closed form (forced oscillator from rest, derived here)'))
        figures.append(Figure(f"amp{k}", f"mass{k} largest |s - s0| [m] vs closed form",
                              float(np.max(np.abs(s - OSC["s0"]))), amplitude, acc,
               source='closed form (forced oscillator from rest, derived here)'))
        # energy: the force's work = kinetic + elastic + dissipated, by quadrature
        F = result[f"sine{k}.y"]
        W, err_w = _work(result, F * v)
        D, err_d = _work(result, d * v**2)
        E = OSC["m"] * v[-1]**2 / 2 + OSC["c"] * (s[-1] - OSC["s0"])**2 / 2
        figures.append(Figure(f"W{k}", f"work of force{k} [J] vs kinetic + elastic energy + "
                              "damper loss", W, E + D, err_w + err_d + solver_accuracy(
                                  result, 1.0) * max(E, 1e-3),
               source='conservation law (work = kinetic + elastic energy + damper loss)'))
    # the damped mass settles at the closed-form amplitude F / sqrt((c - m w^2)^2 + (d w)^2)
    late = t >= t[-1] - 2 * (2 * math.pi / w)
    transient = math.exp(-OSC["d"] / (2 * OSC["m"]) * t[late][0])  # of the start's 1e-3 m
    steady = ref.steady_amplitude(OSC["m"], OSC["c"], OSC["d"], OSC["F"], w)
    figures.append(Figure("amp2_steady", "mass2 amplitude over its last two periods [m] vs "
                          "F / sqrt((c - m w^2)^2 + (d w)^2)",
                          float(np.max(np.abs(result["mass2.s"][late] - OSC["s0"]))), steady,
                          # what is left of the transient, plus sampling a peak at 1e-4 s
                          2 * transient * steady + steady * (w * (t[1] - t[0]))**2 / 2,
           source='closed form (steady forced oscillation)'))
    return figures


# --- Friction ---------------------------------------------------------------------------
STOP1 = {"m": 1.0, "L": 1.0, "smax": 25.0, "smin": -25.0, "F_prop": 1.0, "F_Coulomb": 5.0,
         "F_Stribeck": 10.0, "fexp": 2.0}
STOP2 = {"m": 1.0, "L": 1.0, "smax": 0.9, "smin": -0.9, "F_prop": 1.0, "F_Coulomb": 3.0,
         "F_Stribeck": 5.0, "fexp": 2.0}
SINE1 = {"amplitude": 25.0, "f": 0.25}
SPRING2 = {"c": 500.0, "s_rel0": 1.0, "fixed": -1.75}
STOP2_V0 = -5.0
#: MSL's Examples.Utilities.GenerateStribeckFrictionTable(v_max = 12, nTable = 50)
V_MAX, N_TABLE = 12.0, 50


def stribeck_table() -> np.ndarray:
    """stop1's sliding friction tabulated at N_TABLE speeds from 0 to V_MAX (MSL's table
    for the SupportFriction beside it)."""
    v = V_MAX * np.arange(N_TABLE) / (N_TABLE - 1)
    f = ref.stribeck(STOP1["F_prop"], STOP1["F_Coulomb"], STOP1["F_Stribeck"], STOP1["fexp"])
    return np.column_stack([v, [f(x) for x in v]])


def _friction() -> Assembly:
    asm = Assembly("translational_friction")
    asm.add("sineForce", Sine(**SINE1))
    asm.add("force", Force())
    asm.add("stop1", MassWithStopAndFriction(**STOP1, s=0.0, v=0.0))
    asm.connect("sineForce.y", "force.f")
    asm.connect("force.flange", "stop1.flange_a")
    # MSL's Mass + SupportFriction(f_pos = the table): one element here (see Brake); an
    # input takes one source, so the same sine comes from a second block
    asm.add("sineForce2", Sine(**SINE1))
    asm.add("force2", Force())
    asm.add("supportFriction", SupportFriction(m=STOP1["m"], f_pos=stribeck_table()))
    asm.connect("sineForce2.y", "force2.f")
    asm.connect("force2.flange", "supportFriction.flange_a")
    asm.add("fixed2", Fixed(s0=SPRING2["fixed"]))
    asm.add("spring", Spring(c=SPRING2["c"], s_rel0=SPRING2["s_rel0"]))
    asm.add("stop2", MassWithStopAndFriction(**STOP2, s=0.0, v=STOP2_V0))
    asm.connect("fixed2.flange", "spring.flange_a")
    asm.connect("spring.flange_b", "stop2.flange_a")
    return asm


def _body(p: dict, force) -> ref.StickSlipBody:
    f0 = p["F_Coulomb"] + p["F_Stribeck"]
    return ref.StickSlipBody(m=p["m"], force=force, f0_max=PEAK * f0,
                             kinetic=ref.stribeck(p["F_prop"], p["F_Coulomb"], p["F_Stribeck"],
                                                  p["fexp"]),
                             low=p["smin"] + p["L"] / 2, high=p["smax"] - p["L"] / 2)


def friction_references(stop_time: float) -> tuple[ref.Trajectory, ...]:
    """The event-driven solutions for stop1, stop2 and the SupportFriction's mass of MSL's
    Friction example."""
    w = 2 * math.pi * SINE1["f"]
    stop1 = _body(STOP1, lambda t, s, v: SINE1["amplitude"] * math.sin(w * t))
    # the spring from fixed2 to stop2.flange_a = s - L/2, unstretched at s_rel0
    anchor = SPRING2["fixed"] + SPRING2["s_rel0"] + STOP2["L"] / 2
    stop2 = _body(STOP2, lambda t, s, v: -SPRING2["c"] * (s - anchor))
    table = stribeck_table()
    # SupportFriction: peak 1 (MSL's default) on the table, interpolated linearly
    support = ref.StickSlipBody(m=STOP1["m"], force=stop1.force, f0_max=float(table[0, 1]),
                                kinetic=lambda u: float(np.interp(u, table[:, 0], table[:, 1])))
    return (ref.stick_slip(stop1, 0.0, 0.0, stop_time),
            ref.stick_slip(stop2, 0.0, STOP2_V0, stop_time),
            ref.stick_slip(support, 0.0, 0.0, stop_time))


def _friction_figures(result: Result, asm: Assembly) -> list[Figure]:
    r1, r2, r3 = friction_references(float(result["time"][-1]))
    acc = solver_accuracy(result, 1.0)
    figures = []
    for name, traj in (("stop1", r1), ("stop2", r2), ("supportFriction", r3)):
        ours = _events(result, name)
        for k, (t_ref, q_ref, _, _) in enumerate(traj.events[:6]):
            # the k-th mode change of the reference against ours into the same mode
            t_prev = traj.events[k - 1][0] if k else 0.0
            after = t_prev + (t_ref - t_prev) / 2
            figures.append(Figure(f"{name}_t{k + 1}", f"{name}: time of its event {k + 1} "
                                  f"(into mode {q_ref:+d}) [s] vs event-driven reference",
                                  _first(ours, q_ref, after), t_ref, acc,
                   source="independent integration (event-driven scipy of MSL's friction law)"))
        s_ref, v_ref = traj.s[-1], traj.v[-1]
        figures.append(Figure(f"{name}_s_end", f"{name} position at the stop time [m] vs "
                              "event-driven reference", float(result[f"{name}.s"][-1]), s_ref,
                              acc * max(1.0, abs(s_ref)) * 10,
               source="independent integration (event-driven scipy of MSL's friction law)"))
        figures.append(Figure(f"{name}_v_end", f"{name} speed at the stop time [m/s] vs "
                              "event-driven reference", float(result[f"{name}.v"][-1]), v_ref,
                              acc * 10,
               source="independent integration (event-driven scipy of MSL's friction law)"))
    # stop1's energy: the force's work = kinetic energy + friction loss
    v = result["stop1.v"]
    W, err_w = _work(result, result["sineForce.y"] * v)
    D, err_d = _work(result, result["stop1.lossPower"])
    E = STOP1["m"] * v[-1]**2 / 2
    figures.append(Figure("stop1_W", "work of the sine force on stop1 [J] vs kinetic energy + "
                          "friction loss", W, E + D, err_w + err_d + acc * max(1.0, W) * 10,
           source='conservation law (work = kinetic energy + friction loss)'))
    return figures


# --- Brake ------------------------------------------------------------------------------
BRAKE = {"m": 1.0, "v0": 1.0, "fn_max": 1.0, "mu": 0.5, "height": 2.0, "startTime": 0.1}


def _brake() -> Assembly:
    asm = Assembly("translational_brake")
    asm.add("step", Step(startTime=BRAKE["startTime"], height=BRAKE["height"]))
    asm.add("step1", Step(startTime=BRAKE["startTime"], height=BRAKE["height"]))
    # MSL: Mass(m=1, v = 1) -> Brake; here the brake carries the mass it holds (see Brake)
    asm.add("brake", Brake(m=BRAKE["m"], fn_max=BRAKE["fn_max"], mu_pos=[[0.0, BRAKE["mu"]]],
                           v=BRAKE["v0"]))
    asm.add("brake1", Brake(m=BRAKE["m"], fn_max=BRAKE["fn_max"], mu_pos=[[0.0, BRAKE["mu"]]],
                            v=BRAKE["v0"], profile="on_support"))
    asm.add("fixed", Fixed())
    asm.connect("step.y", "brake.f_normalized")
    asm.connect("step1.y", "brake1.f_normalized")
    asm.connect("fixed.flange", "brake1.support")
    return asm


def _brake_figures(result: Result, asm: Assembly) -> list[Figure]:
    force = BRAKE["mu"] * BRAKE["fn_max"] * BRAKE["height"]
    t_stop, s_stop = ref.brake_stop(BRAKE["v0"], BRAKE["m"], BRAKE["startTime"], force)
    acc = solver_accuracy(result, 1.0)
    figures = []
    for name in ("brake", "brake1"):
        figures.append(Figure(f"{name}_t_stop", f"{name}: time the mass sticks [s] vs "
                              "t_on + m v0 / (mu fn)", _first(_events(result, name), 0), t_stop,
                              acc,
               source='closed form (constant brake force, derived here)'))
        figures.append(Figure(f"{name}_s_end", f"{name}: position at the stop time [m] vs "
                              "v0 t_on + m v0^2 / (2 mu fn)", float(result[f"{name}.s"][-1]),
                              s_stop, acc,
               source='closed form (constant brake force, derived here)'))
        v = result[f"{name}.v"]
        D, err = _work(result, result[f"{name}.lossPower"])
        figures.append(Figure(f"{name}_loss", f"{name}: energy dissipated [J] vs m v0^2 / 2",
                              D + BRAKE["m"] * v[-1]**2 / 2, BRAKE["m"] * BRAKE["v0"]**2 / 2,
                              err + acc,
               source='conservation law (kinetic energy = brake loss)'))
    return figures


# --- ElastoGap --------------------------------------------------------------------------
GAP = {"m": 1.0, "c": 10.0, "d": 1.5, "spring_rel0": 1.0, "gap_rel0": 1.5, "wall": 2.0,
       "s0": 2.0}


def _elastogap() -> Assembly:
    asm = Assembly("translational_elastogap")
    for k, kind in (("1", SpringDamper), ("2", ElastoGap)):
        rel0 = GAP["spring_rel0"] if k == "1" else GAP["gap_rel0"]
        asm.add(f"wall{k}a", Fixed(s0=-GAP["wall"]))
        asm.add(f"wall{k}b", Fixed(s0=GAP["wall"]))
        left, right = ("springDamper1", "springDamper2") if k == "1" else ("elastoGap1",
                                                                          "elastoGap2")
        asm.add(left, kind(c=GAP["c"], d=GAP["d"], s_rel0=rel0))
        asm.add(right, kind(c=GAP["c"], d=GAP["d"], s_rel0=rel0))
        asm.add(f"mass{k}", Mass(m=GAP["m"], L=0.0, s=GAP["s0"], v=0.0))
        asm.connect(f"wall{k}a.flange", f"{left}.flange_a")
        asm.connect(f"{left}.flange_b", f"mass{k}.flange_a")
        asm.connect(f"mass{k}.flange_b", f"{right}.flange_a")
        asm.connect(f"{right}.flange_b", f"wall{k}b.flange")
    return asm


def elastogap_reference(stop_time: float):
    """mass2 between the ElastoGaps, from MSL's ElastoGap equations, by scipy.

    Contact with the right gap for s > wall - gap_rel0, with the left for s < gap_rel0 -
    wall; each pushes with c depth plus the damper d v bounded by c depth.
    """
    from scipy.integrate import solve_ivp
    lift = GAP["wall"] - GAP["gap_rel0"]

    c, d = GAP["c"], GAP["d"]

    def rhs(t, y):
        s, v = y
        f = 0.0
        right, left = s - lift, -lift - s  # penetration of each gap
        if right > 0:  # elastoGap2: flange_a on the mass, v_rel = -v
            f += -c * right + min(max(-d * v, -c * right), c * right)
        if left > 0:  # elastoGap1: flange_b on the mass, v_rel = v; it feels -f
            f += c * left - min(max(d * v, -c * left), c * left)
        return [v, f / GAP["m"]]

    def boundary(sign):
        def g(t, y):
            return sign * y[0] - lift
        return g
    events = [boundary(1), boundary(-1)]
    sol = solve_ivp(rhs, (0.0, stop_time), [GAP["s0"], 0.0], events=events, rtol=ref.REF_TOL,
                    atol=ref.REF_TOL, dense_output=True)
    return sol


def _elastogap_figures(result: Result, asm: Assembly) -> list[Figure]:
    t = result["time"]
    acc = solver_accuracy(result, 1.0) * GAP["s0"]
    # the largest deviation over the whole run: the global error of a tolerance-controlled
    # solver over its 4 periods and 8 contact changes (each a located event) adds up
    # to ten times that of one figure at one point
    acc_run = 10 * acc
    # mass1: two spring-dampers in parallel, 2c and 2d about s = 0
    x1, _ = ref.damped_free(t, GAP["m"], 2 * GAP["c"], 2 * GAP["d"], GAP["s0"])
    figures = [Figure("mass1_s_end", "mass1 position at the stop time [m] vs the closed form "
                      "of m x'' + 2 d x' + 2 c x = 0", float(result["mass1.s"][-1]),
                      float(x1[-1]), acc,
           source='closed form (damped oscillator, derived here)'),
               Figure("mass1_err", "mass1 largest deviation from the closed form [m]",
                      float(np.max(np.abs(result["mass1.s"] - x1))), 0.0, acc_run,
                      source='closed form (damped oscillator, derived here)')]
    sol = elastogap_reference(float(t[-1]))
    s2 = sol.sol(t)[0]
    lifts = sorted(float(x) for te in sol.t_events for x in te)
    figures.append(Figure("mass2_s_end", "mass2 position at the stop time [m] vs scipy from "
                          "MSL's ElastoGap law", float(result["mass2.s"][-1]), float(s2[-1]),
                          acc,
           source="independent integration (scipy of MSL's documented ElastoGap law)"))
    figures.append(Figure("mass2_err", "mass2 largest deviation from the scipy reference [m]",
                          float(np.max(np.abs(result["mass2.s"] - s2))), 0.0, acc_run,
           source="independent integration (scipy of MSL's documented ElastoGap law)"))
    # the first lift-off from the right gap: mass2 passes s = wall - gap_rel0
    lift = GAP["wall"] - GAP["gap_rel0"]
    s = result["mass2.s"]
    k = int(np.argmax(s < lift))
    measured = float(np.interp(lift, [s[k], s[k - 1]], [t[k], t[k - 1]])) if k else math.nan
    figures.append(Figure("mass2_lift_off", "time mass2 leaves the right gap [s] vs scipy "
                          "(sampled, linear interpolation)", measured,
                          lifts[0] if lifts else math.nan,
                          acc + (t[1] - t[0])**2 * GAP["c"] * GAP["s0"],
           source="independent integration (scipy of MSL's documented ElastoGap law)"))
    # energy of mass2: elastic at the start = kinetic + elastic + damper loss
    D, err = _work(result, result["elastoGap1.lossPower"] + result["elastoGap2.lossPower"])
    E0 = GAP["c"] * (GAP["s0"] - lift)**2 / 2
    E = (GAP["m"] * result["mass2.v"][-1]**2 / 2 + result["elastoGap1.E"][-1]
         + result["elastoGap2.E"][-1])
    figures.append(Figure("mass2_energy", "mass2: initial elastic energy [J] vs kinetic + "
                          "elastic + damper loss", float(E + D), E0, err + acc * E0,
           source='conservation law (elastic energy = kinetic + elastic + damper loss)'))
    return figures


# --- PreLoad --------------------------------------------------------------------------
def _preload() -> Assembly:
    """MSL's PreLoad: where MSL connects three or four flanges at one point, Junctions
    (a four-flange point is two); MSL's one fixedLe on three flanges is three Fixed."""
    P = pre
    asm = Assembly("translational_preload")
    gap = dict(c=P.CONTACT["c"], d=P.CONTACT["d"])
    asm.add("innerContactA", ElastoGap(**gap, s_rel0=P.INNER_REL0))
    asm.add("innerContactB", ElastoGap(**gap, s_rel0=P.INNER_REL0))
    asm.add("outerContactA", ElastoGap(**gap, s_rel0=P.OUTER_REL0))
    asm.add("outerContactB", ElastoGap(**gap, s_rel0=P.OUTER_REL0))
    asm.add("spool", Mass(m=P.SPOOL["m"], L=P.SPOOL["L"], s=P.SPOOL["s"], v=0.0))
    asm.add("springPlateA", Mass(m=P.PLATE_A["m"], L=P.PLATE_A["L"], s=P.PLATE_A["s"], v=0.0))
    asm.add("springPlateB", Mass(m=P.PLATE_B["m"], L=P.PLATE_B["L"], s=P.PLATE_B["s"], v=0.0))
    asm.add("spring", Spring(c=P.SPRING["c"], s_rel0=P.SPRING["s_rel0"]))
    asm.add("friction", Damper(d=P.FRICTION_D))
    asm.add("housing", Rod(L=P.HOUSING_L))
    for rod, length in (("rod1", P.ROD12_L), ("rod2", P.ROD12_L), ("rod3", P.ROD34_L),
                        ("rod4", P.ROD34_L)):
        asm.add(rod, Rod(L=length))
    for fixed in ("fixedLe", "fixedLe2", "fixedLe3"):
        asm.add(fixed, Fixed(s0=P.FIXED_S0))
    asm.add("sineForce", Sine(amplitude=P.SINE["amplitude"], f=P.SINE["f"]))
    asm.add("force", Force())
    for j in ("jointA", "jointB", "jointFriction", "jointSpool", "jointSpool2"):
        asm.add(j, Junction())
    for a, b in (
            # fixedLe: outerContactA, housing, friction
            ("fixedLe.flange", "outerContactA.flange_a"),
            ("fixedLe2.flange", "housing.flange_a"),
            ("fixedLe3.flange", "friction.flange_a"),
            ("outerContactA.flange_b", "springPlateA.flange_a"),
            # springPlateA.flange_b = spring.flange_a = rod1.flange_a
            ("springPlateA.flange_b", "jointA.flange_a"),
            ("jointA.flange_b", "spring.flange_a"),
            ("jointA.flange_c", "rod1.flange_a"),
            ("rod1.flange_b", "innerContactA.flange_b"),
            # spring.flange_b = springPlateB.flange_a = rod2.flange_b
            ("springPlateB.flange_a", "jointB.flange_a"),
            ("jointB.flange_b", "spring.flange_b"),
            ("jointB.flange_c", "rod2.flange_b"),
            ("rod2.flange_a", "innerContactB.flange_a"),
            ("springPlateB.flange_b", "outerContactB.flange_a"),
            ("outerContactB.flange_b", "housing.flange_b"),
            # spool.flange_a = rod3.flange_b = rod4.flange_a = force.flange
            ("spool.flange_a", "jointSpool.flange_a"),
            ("jointSpool.flange_b", "rod3.flange_b"),
            ("jointSpool.flange_c", "jointSpool2.flange_a"),
            ("jointSpool2.flange_b", "rod4.flange_a"),
            ("jointSpool2.flange_c", "force.flange"),
            ("rod4.flange_b", "innerContactB.flange_b"),
            # rod3.flange_a = innerContactA.flange_a = friction.flange_b
            ("rod3.flange_a", "jointFriction.flange_a"),
            ("jointFriction.flange_b", "innerContactA.flange_a"),
            ("jointFriction.flange_c", "friction.flange_b"),
            ("sineForce.y", "force.f")):
        asm.connect(a, b)
    return asm


PRELOAD_TIMES = (1.0, 2.0, 25.0, 50.0, 75.0, 100.0)  # below the preload; the peaks and zeros


def _preload_figures(result: Result, asm: Assembly) -> list[Figure]:
    t = result["time"]
    acc = solver_accuracy(result, 0.1)  # positions ~0.1 m
    figures = []
    q0, _ = pre.static_state(0.0)
    for time in PRELOAD_TIMES:
        if time > t[-1] + 1e-9:
            continue
        q, bound = pre.quasi_static(time)
        k = int(np.argmin(np.abs(t - time)))
        for j, body in enumerate(("spool", "springPlateA", "springPlateB")):
            figures.append(Figure(
                f"{body}_s_{time:g}", f"{body}.s at t = {time:g} s (F = "
                f"{float(pre.force(time)):.3g} N) [m] vs the quasi-static response",
                float(result[f"{body}.s"][k]), float(q[j]), acc + float(bound[j]),
                source="closed form derived here: statics of MSL's PreLoad in its contact "
                       "set, with the damping and inertia terms of the slow force"))
    # the preload: at F = 0 the spool sits at its start value, the springs preloaded
    figures.append(Figure("preload_spool_s", "spool.s of the preloaded state (F = 0) [m] vs "
                          "MSL's start value spool.s.start", float(q0[0]), pre.SPOOL["s"],
                          1e-12, source="statics (closed form) against MSL's design value"))
    # the force at which the spool starts to move: outerContactA opens
    f_open = pre.opening_force()
    spring_preload = pre.SPRING["c"] * (pre.SPRING["s_rel0"] - (q0[2] - q0[1]
                                                               - pre.PLATE_A["L"] / 2
                                                               - pre.PLATE_B["L"] / 2))
    figures.append(Figure("opening_force", "force that opens outerContactA [N] vs the spring's "
                          "preload", f_open, spring_preload, 0.02 * spring_preload,
                          source="closed form: the spring's preload; the contacts' "
                                 "compliance (c_spring / c_contact) moves it by 2 %"))
    figures += _preload_dynamics_figures(result, acc)
    contact = result["outerContactA.contact"]
    opened = np.flatnonzero((contact[1:] < 0.5) & (contact[:-1] > 0.5))
    w = 2 * math.pi * pre.SINE["f"]
    t_open = math.asin(f_open / pre.SINE["amplitude"]) / w
    measured = float(t[opened[0] + 1]) if len(opened) else math.nan
    figures.append(Figure("outerContactA_opens", "first time outerContactA is open [s] "
                          "(sampled) vs F(t) = the opening force", measured, t_open,
                          (t[1] - t[0]) + 0.01,
                          source="closed form: asin(F_open / amplitude) / w; accuracy: "
                                 "the sampling interval, and 10 ms for the lag of the "
                                 "closed contacts (d/c ~ 1.5 ms)"))
    return figures


_BODIES = ("spool", "springPlateA", "springPlateB")
_GAPS = ("outerContactA", "outerContactB", "innerContactA", "innerContactB")
SOURCE_PRELOAD = ("independent integration (exact, mode by mode, of MSL's PreLoad "
                  "equations: msl_preload_reference.dynamics)")


def _preload_dynamics_figures(result: Result, acc: float) -> list[Figure]:
    """The run against the dynamics of MSL's PreLoad (every body over the whole run, the
    contacts' changes), and its energy balance."""
    t = np.asarray(result["time"])
    motion = pre.dynamics(t, stop=float(t[-1]))
    figures = []
    for j, body in enumerate(_BODIES):
        figures.append(Figure(f"{body}_s_err", f"{body}.s: largest deviation from the "
                              "dynamics over the run [m]",
                              float(np.max(np.abs(result[f"{body}.s"] - motion.q[:, j]))), 0.0,
                              acc, source=SOURCE_PRELOAD))
        figures.append(Figure(f"{body}_v_err", f"{body}.v: largest deviation from the "
                              "dynamics over the run [m/s]",
                              float(np.max(np.abs(result[f"{body}.v"] - motion.v[:, j]))), 0.0,
                              solver_accuracy(result, 1.0), source=SOURCE_PRELOAD))
    # each contact's first opening after the start (mode 0 of the reference): a slow
    # crossing, so its time is known to the position's accuracy over the gap's speed
    for gap in ("outerContactA", "innerContactB"):
        t_ref = next((te for te, name, q in motion.events if name == gap and q == 0), math.nan)
        ev = result.events.get(gap)
        ours = (next((float(te) for te, c in zip(ev["time"], ev[f"{gap}.contact"]) if c == 0),
                     math.nan) if ev is not None else math.nan)
        k = pre.ELEMENTS.index(next(e for e in pre.ELEMENTS if e.name == gap))
        v_rel = abs(float(np.dot(pre.ELEMENTS[k].g, _state_at(motion, t_ref)[1])))
        figures.append(Figure(f"{gap}_opens_at", f"{gap} opens at [s] (event) vs the dynamics",
                              ours, t_ref, acc / max(v_rel, 1e-300), source=SOURCE_PRELOAD))
    # the force's work = kinetic + elastic energy + the dampers' and contacts' loss, from
    # the first sample on (the start's snap of the plates onto their contacts, over in a
    # millisecond, is not sampled). The work by parts, F s - int F' s dt: s is smooth where
    # the speed jumps with the contacts' stiffness, F' is exact
    k0 = 1
    tt, s = t[k0:], np.asarray(result["spool.s"])[k0:]
    F = np.asarray(result["sineForce.y"])[k0:]
    w = 2 * math.pi * pre.SINE["f"]
    dF = pre.SINE["amplitude"] * w * np.cos(w * tt)
    I, err_i = _integral(tt, dF * s)
    W = F[-1] * s[-1] - F[0] * s[0] - I
    loss = np.asarray(result["friction.lossPower"]) + sum(
        np.asarray(result[f"{g}.lossPower"]) for g in _GAPS)
    D, err_d = _integral(tt, loss[k0:])
    E = sum(np.asarray(result[f"{name}.E"]) for name in (*_BODIES, "spring", *_GAPS))
    figures.append(Figure("energy", f"work of the force from {t[k0]:g} s [J] vs the change of "
                          "kinetic + elastic energy + the loss", W, float(E[-1] - E[k0]) + D,
                          err_i + err_d + solver_accuracy(result, max(W, 1e-3)),
                          source="conservation law (work = kinetic + elastic energy + loss)"))
    return figures


def _state_at(motion, time: float):
    """(q, v) of the reference's motion at `time`, interpolated between its samples."""
    q = np.array([np.interp(time, motion.t, motion.q[:, j]) for j in range(3)])
    v = np.array([np.interp(time, motion.t, motion.v[:, j]) for j in range(3)])
    return q, v


MSL_TRANSLATIONAL_SCENES: dict[str, Scene] = {
    "translational_oscillator": Scene(
        "translational_oscillator", "MSL Translational.Examples.Oscillator: masses on springs "
        "driven at resonance, undamped and damped",
        _oscillator, stop_time=1.0, step=1e-4, tolerance=1e-10, record=None,
        figures=_oscillator_figures, plot=["mass1.s", "mass2.s"], mode="monolithic",
        seed="MSL", reference="closed forms of the forced oscillator; work = energy + loss"),
    "translational_friction": Scene(
        "translational_friction", "MSL Translational.Examples.Friction: Stribeck friction with "
        "stick/slip under a sine force, and a mass thrown against its hard stop",
        _friction, stop_time=5.0, step=1e-3, tolerance=1e-10, record=None,
        figures=_friction_figures, plot=["stop1.s", "stop1.v", "stop2.s", "stop2.v"],
        mode="monolithic", seed="MSL",
        reference="event-driven scipy solution of MSL's MassWithStopAndFriction"),
    "translational_brake": Scene(
        "translational_brake", "MSL Translational.Examples.Brake: a sliding mass braked to "
        "rest by a normal force stepped on at 0.1 s",
        _brake, stop_time=2.0, step=1e-3, tolerance=1e-10, record=None,
        figures=_brake_figures, plot=["brake.s", "brake.v", "brake1.v"], mode="monolithic",
        seed="MSL", reference="stopping time and distance at constant friction"),
    "translational_elastogap": Scene(
        "translational_elastogap", "MSL Translational.Examples.ElastoGap: a mass on "
        "spring-dampers beside one between ElastoGaps that lift off",
        _elastogap, stop_time=5.0, step=1e-3, tolerance=1e-10, record=None,
        figures=_elastogap_figures, plot=["mass1.s", "mass2.s"], mode="monolithic",
        seed="MSL", reference="closed form (mass1); scipy from MSL's ElastoGap law (mass2)"),
    "translational_preload": Scene(
        "translational_preload", "MSL Translational.Examples.PreLoad: a spool held by two "
        "preloaded ElastoGap stops until a slow sine force overcomes the preload",
        _preload, stop_time=pre.STOP_TIME, step=0.1, tolerance=1e-8, record=None,
        figures=_preload_figures, plot=["spool.s", "force.f"], mode="monolithic",
        seed="MSL", reference="statics, quasi-static response and exact mode-by-mode "
                              "motion of MSL's PreLoad; work = energy + loss"),
}
