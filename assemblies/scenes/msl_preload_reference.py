"""References for MSL's Translational.Examples.PreLoad, written from MSL's equations
(Mass, Spring, Damper, ElastoGap, Rod, Fixed, Force and the example's connections),
never from our components.

The example has three bodies, q = (spool.s, springPlateA.s, springPlateB.s); every
compliant element's ``s_rel = flange_b.s - flange_a.s`` is ``g . q + g0`` (rods and
mass lengths give g0), and its force f acts -f g on q (MSL PartialCompliant:
``flange_b.f = f``, ``flange_a.f = -f``). With ElastoGap's n = 1 the law is linear
in each contact mode (apart; in contact with the damper within its bound |d v_rel| <=
c depth; or clipped at that bound), so:

- **statics** (:func:`static_state`): the equilibrium under a constant force F solves
  K q = b + F e_spool in the set of closed contacts; the set is found by trying all
  2^4 and keeping the one consistent with its own gaps (the potential energy is convex,
  so the equilibrium is unique where the spool touches a plate);
- **quasi-static response** (:func:`quasi_static`): the force 150 sin(2 pi 0.01 t) is
  slow against every time constant of the closed-contact system (the slowest, the
  spring against the friction damper, d/c = 0.125 s, against a 100 s period), so in
  one contact set M q'' + D q' + K q = b + F(t) e has the expansion
  ``q = A F - A D A F' + A (D A D - M) A F'' + ...`` with A = K^-1, e = e_spool (each
  term from substituting the one before; the transient of the last contact change
  decays as exp(-t / 0.125 s)). :func:`quasi_static` returns the three terms shown and a
  bound on the next (with the transient's), which is the stated accuracy;
- **dynamics** (:func:`dynamics`): the motion itself from MSL's start values, with every
  ElastoGap's mode (apart; in contact; its damper clipped either way) switched at located
  events. Within one set of modes the system is linear with a sine force, so the state
  and the force's sin, cos and 1 form one autonomous linear system z' = A z, solved
  exactly by the matrix exponential (no step error); each condition of the modes is
  watched on a look-ahead grid fine enough for the fastest contact motion and located
  by brentq.
"""
from __future__ import annotations

import itertools
import math
from dataclasses import dataclass

import numpy as np

# --- MSL's parameters (Translational.Examples.PreLoad) -------------------------------
SPOOL = {"m": 0.150, "L": 0.19, "s": 0.01475}
PLATE_A = {"m": 10e-3, "L": 0.002, "s": -0.093}
PLATE_B = {"m": 10e-3, "L": 0.002, "s": -0.06925}
SPRING = {"c": 20e3, "s_rel0": 0.025}
CONTACT = {"c": 1000e3, "d": 250.0}
INNER_REL0, OUTER_REL0 = 0.001, 0.0015
FIXED_S0 = -0.0955
HOUSING_L, ROD12_L, ROD34_L = 0.0305, 0.007, 0.00575
FRICTION_D = 2500.0
SINE = {"amplitude": 150.0, "f": 0.01}
STOP_TIME = 100.0



@dataclass(frozen=True)
class Element:
    """A compliant element: s_rel = g . q + g0, its law, and MSL's s_rel0."""
    name: str
    g: tuple[float, float, float]
    g0: float
    kind: str  # "gap", "spring" or "damper"
    s_rel0: float = 0.0


def elements() -> list[Element]:
    """The example's compliant elements, their s_rel from the masses' centres (a mass's
    flanges sit at s -+ L/2, a rod's flange_b at its flange_a + L)."""
    la, lb, ls = PLATE_A["L"] / 2, PLATE_B["L"] / 2, SPOOL["L"] / 2
    housing_b = FIXED_S0 + HOUSING_L
    return [
        # fixedLe -> springPlateA.flange_a
        Element("outerContactA", (0, 1, 0), -la - FIXED_S0, "gap", OUTER_REL0),
        # springPlateA.flange_b -> springPlateB.flange_a
        Element("spring", (0, -1, 1), -la - lb, "spring", SPRING["s_rel0"]),
        # springPlateB.flange_b -> housing.flange_b
        Element("outerContactB", (0, 0, -1), housing_b - lb, "gap", OUTER_REL0),
        # rod3.flange_a (spool.flange_a - L3) -> rod1.flange_b (springPlateA.flange_b + L1)
        Element("innerContactA", (-1, 1, 0), la + ROD12_L + ls + ROD34_L, "gap", INNER_REL0),
        # rod2.flange_a (springPlateB.flange_a - L2) -> rod4.flange_b (spool.flange_a + L4)
        Element("innerContactB", (1, 0, -1), -ls + ROD34_L + lb + ROD12_L, "gap", INNER_REL0),
        # fixedLe -> rod3.flange_a (spool.flange_a - L3): the "friction" damper
        Element("friction", (1, 0, 0), -ls - ROD34_L - FIXED_S0, "damper"),
    ]


ELEMENTS = elements()
GAPS = [k for k, e in enumerate(ELEMENTS) if e.kind == "gap"]
MASSES = np.array([SPOOL["m"], PLATE_A["m"], PLATE_B["m"]])
Q0 = np.array([SPOOL["s"], PLATE_A["s"], PLATE_B["s"]])
E_SPOOL = np.array([1.0, 0.0, 0.0])  # the force acts on spool.flange_a


def force(t):
    return SINE["amplitude"] * np.sin(2 * math.pi * SINE["f"] * t)


def s_rel(q) -> np.ndarray:
    return np.array([np.dot(e.g, q) + e.g0 for e in ELEMENTS])


# --- linear systems of one contact mode -----------------------------------------------
# a gap's mode: 0 apart; 1 in contact, damper within its bound; 2 in contact, damper
# clipped at f_c (closing fast: f = 2 f_c); 3 in contact, clipped at -f_c (opening
# fast: f = 0). Spring and damper have one mode.
def _matrices(modes):
    """(K, D, b) of the contact modes `modes` (one per gap): the elements' forces on q
    are -K q - D q' + b."""
    K, D, b = np.zeros((3, 3)), np.zeros((3, 3)), np.zeros(3)
    mode = dict(zip(GAPS, modes))
    for k, e in enumerate(ELEMENTS):
        g = np.array(e.g, dtype=float)
        G = np.outer(g, g)
        if e.kind == "spring":  # f = c (s_rel - s_rel0): force -f g
            K += SPRING["c"] * G
            b -= SPRING["c"] * (e.g0 - e.s_rel0) * g
        elif e.kind == "damper":  # f = d v_rel
            D += FRICTION_D * G
        else:  # f_c = -c (s_rel0 - s_rel) = c (s_rel - s_rel0) in contact, f_d = d v_rel
            m = mode[k]
            scale = {0: 0.0, 1: 1.0, 2: 2.0, 3: 0.0}[m]
            K += scale * CONTACT["c"] * G
            b -= scale * CONTACT["c"] * (e.g0 - e.s_rel0) * g
            if m == 1:
                D += CONTACT["d"] * G
    return K, D, b


def gap_modes(q, v) -> tuple[int, ...]:
    """The modes of the gaps at (q, v), from MSL's ElastoGap law."""
    modes = []
    for k in GAPS:
        e = ELEMENTS[k]
        depth = e.s_rel0 - (np.dot(e.g, q) + e.g0)
        if depth <= 0:
            modes.append(0)
            continue
        f_c, f_d2 = -CONTACT["c"] * depth, CONTACT["d"] * np.dot(e.g, v)
        modes.append(2 if f_d2 < f_c else 3 if f_d2 > -f_c else 1)
    return tuple(modes)


# --- statics and the quasi-static response --------------------------------------------
def static_state(F: float) -> tuple[np.ndarray, tuple[int, ...]]:
    """(q, contact set) of the equilibrium under a constant force F on the spool."""
    found = []
    for closed in itertools.product((0, 1), repeat=len(GAPS)):
        K, _, b = _matrices(closed)
        if abs(np.linalg.det(K)) < 1e-6 * np.linalg.norm(K)**3:
            continue  # the spool or a plate floats: no equilibrium in this set
        q = np.linalg.solve(K, b + F * E_SPOOL)
        depth = np.array([ELEMENTS[k].s_rel0 - s_rel(q)[k] for k in GAPS])
        if all((d > 0) == bool(c) for d, c in zip(depth, closed)):
            found.append((q, closed))
    if len(found) != 1:
        raise RuntimeError(f"PreLoad statics at F = {F}: {len(found)} consistent contact sets")
    return found[0]


def quasi_static(t: float) -> tuple[np.ndarray, np.ndarray]:
    """(q, bound) at time t: the first two terms of the quasi-static expansion (module
    doc) in the contact set of the static equilibrium under F(t), and the size of the
    third term per body, the first one left out."""
    w = 2 * math.pi * SINE["f"]
    F, dF, ddF = (SINE["amplitude"] * x for x in (math.sin(w * t), w * math.cos(w * t),
                                                  -w * w * math.sin(w * t)))
    q_static, closed = static_state(F)
    K, D, _ = _matrices(closed)
    A = np.linalg.inv(K)
    first = A @ D @ A @ E_SPOOL * dF
    second = A @ (D @ A @ D - np.diag(MASSES)) @ A @ E_SPOOL * ddF
    # the third term ~ tau^2 |A D A e| F''' with |F'''| <= amplitude w^3 (tau: the slowest
    # time constant, of the damping or of the masses on the contacts), doubled; and the
    # transient of the last contact change, which decays as exp(-dt / tau) from at most
    # the first term's size at the change
    AM = A @ np.diag(MASSES)
    tau = max(np.max(np.abs(np.linalg.eigvals(A @ D))),
              math.sqrt(np.max(np.abs(np.linalg.eigvals(AM)))))
    lag = np.abs(A @ D @ A @ E_SPOOL)
    amp = SINE["amplitude"]
    bound = 2 * lag * tau**2 * amp * w**3
    bound += lag * amp * w * math.exp(-_since_contact_change(t) / tau)
    return q_static - first + second, bound


def _since_contact_change(t: float) -> float:
    """Time since the quasi-static contact set last changed: where |F| crossed the
    opening force (the example is symmetric: the same force opens either side)."""
    w, f_open = 2 * math.pi * SINE["f"], opening_force()
    x = math.asin(min(1.0, f_open / SINE["amplitude"]))
    period = 1 / SINE["f"]
    base = math.floor(t / period) * period
    # in each period |F| = f_open at the phases x, pi - x, pi + x, 2 pi - x
    crossings = [base + k * period + ph / w for k in (-1, 0)
                 for ph in (x, math.pi - x, math.pi + x, 2 * math.pi - x)]
    before = [t - c for c in crossings if c <= t]
    return min(before) if before else t


def opening_force() -> float:
    """The force at which outerContactA opens under a slowly rising F: the preload the
    spool must overcome before it moves more than the contacts' compliance."""
    q0, closed = static_state(0.0)
    K, _, b = _matrices(closed)
    k = ELEMENTS.index(next(e for e in ELEMENTS if e.name == "outerContactA"))
    g = np.array(ELEMENTS[k].g, dtype=float)
    # s_rel(F) = g . K^-1 (b + F e) + g0 reaches s_rel0: linear in F within this set
    base = g @ np.linalg.solve(K, b) + ELEMENTS[k].g0
    slope = g @ np.linalg.solve(K, E_SPOOL)
    return float((ELEMENTS[k].s_rel0 - base) / slope)


# --- dynamics ---------------------------------------------------------------------------
def element_forces(q, v, modes) -> np.ndarray:
    """Each element's force f (MSL: flange_b.f = f, tension positive) at (q, v), the gaps
    in `modes` (0 apart; 1 spring + damper; 2 damper clipped at f_c: f = 2 f_c; 3 damper
    clipped at -f_c: f = 0), written element by element from MSL's laws."""
    out = np.zeros(len(ELEMENTS))
    mode = dict(zip(GAPS, modes))
    for k, e in enumerate(ELEMENTS):
        s_rel, v_rel = float(np.dot(e.g, q) + e.g0), float(np.dot(e.g, v))
        if e.kind == "spring":
            out[k] = SPRING["c"] * (s_rel - e.s_rel0)
        elif e.kind == "damper":
            out[k] = FRICTION_D * v_rel
        else:
            f_c = -CONTACT["c"] * (e.s_rel0 - s_rel)  # MSL: -c |s_rel - s_rel0| in contact
            f_d2 = CONTACT["d"] * v_rel
            out[k] = {0: 0.0, 1: f_c + f_d2, 2: 2 * f_c, 3: 0.0}[mode[k]]
    return out


def _gap_conditions(modes) -> np.ndarray:
    """Rows a with a . (q, v, 1) positive while each gap stays in its mode (MSL's law is
    affine in q and v, so are its conditions): depth = s_rel0 - s_rel > 0 in contact,
    and the damper's f_d2 = d v_rel against its bounds f_c = -c depth and -f_c."""
    rows = []
    for k, m in zip(GAPS, modes):
        e = ELEMENTS[k]
        g = np.array(e.g, dtype=float)
        depth = np.concatenate([-g, np.zeros(3), [e.s_rel0 - e.g0]])
        f_c = -CONTACT["c"] * depth
        f_d2 = np.concatenate([np.zeros(3), CONTACT["d"] * g, [0.0]])
        rows += {0: [-depth], 1: [depth, f_d2 - f_c, -f_c - f_d2], 2: [depth, f_c - f_d2],
                 3: [depth, f_d2 + f_c]}[m]
    return np.array(rows)


def _system(modes) -> np.ndarray:
    """A of z' = A z in one set of gap modes, z = (q, v, sin w t, cos w t, 1): the motion,
    the sine force and the constant terms as one autonomous linear system (exact by expm)."""
    w = 2 * math.pi * SINE["f"]
    G = np.array([e.g for e in ELEMENTS], dtype=float)  # (elements, bodies)

    def accel(q, v, S, one):
        f = element_forces(q, v, modes) if one else (
            element_forces(q, v, modes) - element_forces(np.zeros(3), np.zeros(3), modes))
        return (SINE["amplitude"] * S * E_SPOOL - G.T @ f) / MASSES

    A = np.zeros((9, 9))
    A[0:3, 3:6] = np.eye(3)
    A[6, 7], A[7, 6] = w, -w
    for j in range(9):  # the forces are affine in (q, v): columns by unit vectors, exactly
        z = np.zeros(9)
        z[j] = 1.0
        A[3:6, j] = accel(z[0:3], z[3:6], z[6], z[8])
    return A


@dataclass
class Motion:
    t: np.ndarray
    q: np.ndarray  # (len(t), 3): spool, springPlateA, springPlateB
    v: np.ndarray
    #: (time, gap name, new mode) at each change of a gap's mode
    events: list


#: the look-ahead after each change of modes: doubling from FIRST_LOOK to SHORT, steps of
#: SHORT until SETTLE, then steps of LONGEST. SHORT samples the fastest motion in contact
#: (a plate on two clipped gaps, 2e6 N/m on 10 g: 1.4e4 rad/s) 20 times a period; by
#: SETTLE the slowest contact transient (c/d = 4000 1/s) has decayed by exp(-20), and the
#: motion left follows the force (period 100 s), which LONGEST samples 5000 times a period
FIRST_LOOK, SHORT, SETTLE, LONGEST = 1e-9, 2e-5, 5e-3, 0.02


def _looks(stop: float):
    """The look-ahead offsets after a change of modes, up to `stop` (module constants)."""
    h = FIRST_LOOK
    while h < SHORT and h < stop:
        yield h
        h *= 2
    h = SHORT
    while h < SETTLE and h < stop:
        yield h
        h += SHORT
    while h < stop:
        yield h
        h += LONGEST
    yield stop


def dynamics(t, stop: float = STOP_TIME) -> Motion:
    """The motion of MSL's PreLoad from its start values (at rest) under the sine force,
    M q'' = F(t) e_spool - sum_k f_k g_k (module doc). In one set of gap modes the system
    is linear, so z(t0 + h) = expm(A h) z(t0) exactly; the conditions of the modes are
    watched on a look-ahead grid growing from FIRST_LOOK by GROWTH to LONGEST, the first
    to turn false located by brentq, and the modes read again a moment after it."""
    from scipy.linalg import expm
    from scipy.optimize import brentq
    t = np.asarray(t, dtype=float)
    w = 2 * math.pi * SINE["f"]
    time = 0.0
    z = np.concatenate([Q0, np.zeros(3), [0.0, 1.0, 1.0]])
    modes = gap_modes(Q0, np.zeros(3))
    out = np.full((len(t), 6), np.nan)
    events = []
    for _ in range(1000):  # a mode change per event: the run has a few dozen
        A, rows = _system(modes), _gap_conditions(modes)

        def at(h, A=A, z=z):
            return expm(A * h) @ z

        def margins(zz, rows=rows):
            return rows @ np.concatenate([zz[:6], [zz[8]]])

        steps = {SHORT: expm(A * SHORT), LONGEST: expm(A * LONGEST)}
        h_prev, z_prev, found = 0.0, z, None
        for h in _looks(stop - time):
            step = h - h_prev
            # on the fixed steps, one matrix product (the exponential of each step is
            # computed once per set of modes); elsewhere the exponential itself
            known = next((E for size, E in steps.items() if abs(step - size) < 1e-15), None)
            z_h = known @ z_prev if known is not None and h_prev > 0 else at(h)
            m = margins(z_h)
            if np.any(m <= 0):  # the earliest of the conditions that turned false
                before = margins(z_prev)
                # one already at or below 0 (two conditions crossing within the moment
                # below): it ends the modes at once
                found = min(h_prev if before[i] <= 0 else
                            brentq(lambda x, i=i: margins(at(x))[i], h_prev, h, xtol=1e-15)
                            for i in np.flatnonzero(m <= 0))
                break
            h_prev, z_prev = h, z_h
        if found is None:
            end, new = stop, modes
        else:
            # the new modes start a moment later along the old ones' motion, once the law
            # sees the change (a longer moment where the motion is slow); the law is
            # continuous across every condition, so that moment changes the motion by
            # O(moment^2) of a jump in the jerk
            for moment in (1e-9, 1e-8, 1e-7, 1e-6, 1e-5):
                ahead = at(found + moment)
                new = gap_modes(ahead[:3], ahead[3:6])
                if new != modes:
                    break
            else:
                raise RuntimeError(f"PreLoad dynamics: no mode change after t = {time + found}")
            end = time + found + moment
        inside = (t >= time) & ((t < end) if found is not None else (t <= end))
        for k in np.flatnonzero(inside):
            out[k] = at(t[k] - time)[:6]
        if found is None:
            break
        for k, (old, now) in zip(GAPS, zip(modes, new)):
            if old != now:
                events.append((time + found, ELEMENTS[k].name, now))
        z = at(end - time)
        z[6], z[7] = math.sin(w * end), math.cos(w * end)  # the forcing kept exact
        time, modes = end, new
    return Motion(t, out[:, :3], out[:, 3:], events)
