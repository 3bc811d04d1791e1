"""Independent references for MSL's Rotational.Examples First and Backlash, written from
MSL's documented equations (Inertia, IdealGear, Spring, Damper, SpringDamper,
ElastoBacklash, ElastoBacklash2 and the examples' connections), never from our components.

- **First**: the motor inertia J1 turns the gear's flange_a, ``phi1 = ratio phi2`` and
  ``tau_b = -ratio tau_a`` (no loss), so motor and inertia2 move as one body of inertia
  ``J2 + ratio^2 J1`` seen from inertia2, driven by ``ratio tau(t)``; the damper holds
  inertia2 to the housing, the spring joins it to the load:
  ``(J2 + ratio^2 J1) phi2'' = ratio A sin(2 pi f t) - d phi2' - c (phi2 - phi3)``,
  ``J3 phi3'' = c (phi2 - phi3)``; integrated by scipy (a smooth linear ODE).
- **Backlash**: each inertia J at phi0 = pi/2, at rest, on an element fixed at its other
  flange (``J phi'' = -tau``, phi_rel = phi). The spring-damper's motion is a damped
  oscillation in closed form; the backlash elements' law is piecewise linear, so their
  motion is integrated branch by branch (gap; beyond an edge: released, spring + damper,
  or the damper at its bound ``tau = 2 tau_c``), each branch ending at a located event
  where one of its conditions turns false.
"""
from __future__ import annotations

import math
from dataclasses import dataclass, field

import numpy as np
from scipy.integrate import solve_ivp

#: scipy's relative and absolute tolerance here: events and states to ~1e-10
RTOL = 1e-12

# --- First ------------------------------------------------------------------------------
#: MSL's Examples.First: amplitude and frequency of the motor torque, inertias, gear
#: ratio, bearing damping, spring stiffness, stop time
FIRST = {"amplitude": 10.0, "f": 5.0, "Jmotor": 0.1, "J2": 2.0, "Jload": 2.0, "ratio": 10.0,
         "damping": 10.0, "c": 1e4, "stop": 1.0}


def first(t) -> dict:
    """inertia2 and inertia3 (phi, w) on the grid `t`, and the work of the torque source,
    from rest at phi = 0 with the spring unstretched (MSL's fixed start values)."""
    p = FIRST
    J = p["J2"] + p["ratio"]**2 * p["Jmotor"]
    w_f = 2 * math.pi * p["f"]

    def rhs(tt, y):
        phi2, w2, phi3, w3, work = y
        tau = p["amplitude"] * math.sin(w_f * tt)
        spring = p["c"] * (phi2 - phi3)
        # the motor turns ratio x faster than inertia2: the torque's power is tau w1
        return [w2, (p["ratio"] * tau - p["damping"] * w2 - spring) / J, w3,
                spring / p["Jload"], tau * p["ratio"] * w2]

    t = np.asarray(t, dtype=float)
    sol = solve_ivp(rhs, (0.0, float(t[-1])), np.zeros(5), method="DOP853", rtol=RTOL,
                    atol=RTOL, t_eval=t, max_step=1e-3)
    phi2, w2, phi3, w3, work = sol.y
    return {"phi2": phi2, "w2": w2, "phi3": phi3, "w3": w3, "work": work,
            "phi1": p["ratio"] * phi2, "w1": p["ratio"] * w2}


# --- Backlash ---------------------------------------------------------------------------
#: MSL's Examples.Backlash: the three rows share J, c, d, the start angle and the
#: backlash b of the two backlash elements (45 deg)
BACKLASH = {"J": 5.0, "c": 20e3, "d": 50.0, "b": math.pi / 4, "phi0": math.pi / 2, "stop": 1.0}


def spring_damper(t) -> tuple[np.ndarray, np.ndarray]:
    """(phi, w) of J phi'' + d phi' + c phi = 0 from phi0 at rest (underdamped)."""
    p = BACKLASH
    t = np.asarray(t, dtype=float)
    sigma = p["d"] / (2 * p["J"])
    wd = math.sqrt(p["c"] / p["J"] - sigma**2)
    e = np.exp(-sigma * t)
    phi = p["phi0"] * e * (np.cos(wd * t) + sigma / wd * np.sin(wd * t))
    w = -p["phi0"] * e * (wd + sigma**2 / wd) * np.sin(wd * t)
    return phi, w


# the branches of the backlash law: (edge, kind); edge +1 beyond b/2, -1 beyond -b/2,
# 0 in the gap; kind "free" (no torque), "linear" (tau_c + tau_d), "double" (2 tau_c:
# the damper at its bound |tau_d| <= |tau_c|, ElastoBacklash only)
def _torques(phi, w, edge):
    p = BACKLASH
    return p["c"] * (phi - edge * p["b"] / 2), p["d"] * w  # tau_c, tau_d beyond `edge`


def _branch(phi, w, bounded: bool) -> tuple[int, str]:
    """The branch MSL's law is in at (phi, w) (phi_rel0 = 0)."""
    b = BACKLASH["b"]
    if -b / 2 <= phi <= b / 2:
        return 0, "gap"
    edge = 1 if phi > b / 2 else -1
    tau_c, tau_d = _torques(phi, w, edge)
    if edge * (tau_c + tau_d) <= 0:
        return edge, "free"
    if bounded and edge * (tau_d - tau_c) > 0:
        return edge, "double"
    return edge, "linear"


def _torque(phi, w, branch) -> float:
    edge, kind = branch
    if kind in ("gap", "free"):
        return 0.0
    tau_c, tau_d = _torques(phi, w, edge)
    return 2 * tau_c if kind == "double" else tau_c + tau_d


def _conditions(branch, bounded: bool):
    """The functions that stay positive while `branch` holds (each ends it at 0)."""
    b = BACKLASH["b"]
    edge, kind = branch
    if kind == "gap":
        return [lambda t, y: b / 2 - y[0], lambda t, y: y[0] + b / 2]
    out = [lambda t, y: edge * y[0] - b / 2]  # still beyond the edge

    def pushing(t, y):
        tau_c, tau_d = _torques(y[0], y[1], edge)
        return edge * (tau_c + tau_d)

    def below_bound(t, y):
        tau_c, tau_d = _torques(y[0], y[1], edge)
        return edge * (tau_c - tau_d)

    if kind == "free":
        out.append(lambda t, y: -pushing(t, y))
    elif kind == "linear":
        out.append(pushing)
        if bounded:
            out.append(below_bound)
    else:
        out.append(lambda t, y: -below_bound(t, y))
    return out


@dataclass
class Backlash:
    t: np.ndarray
    phi: np.ndarray
    w: np.ndarray
    #: (time, contact) each time the contact changes: +1 / -1 pushing beyond the upper /
    #: lower edge, 0 not pushing (in the gap or released)
    contacts: list = field(default_factory=list)


def backlash(t, bounded: bool) -> Backlash:
    """The inertia on ElastoBacklash (`bounded`) or ElastoBacklash2 on the grid `t`."""
    p = BACKLASH
    t = np.asarray(t, dtype=float)
    time, y = 0.0, np.array([p["phi0"], 0.0])
    branch = _branch(y[0], y[1], bounded)
    phis, ws, contacts = [], [], []
    pushing = branch[0] if branch[1] in ("linear", "double") else 0
    for _ in range(10000):  # one branch per event: a run has far fewer
        def rhs(tt, yy, br=branch):
            return [yy[1], -_torque(yy[0], yy[1], br) / p["J"]]
        events = _conditions(branch, bounded)
        for g in events:
            g.terminal, g.direction = True, -1
        sol = solve_ivp(rhs, (time, p["stop"]), y, method="DOP853", rtol=RTOL, atol=RTOL,
                        events=events, dense_output=True)
        end = float(sol.t[-1])
        inside = (t >= time) & ((t < end) if sol.status == 1 else (t <= end))
        if inside.any():
            phis.append(sol.sol(t[inside])[0])
            ws.append(sol.sol(t[inside])[1])
        time, y = end, sol.y[:, -1]
        if sol.status != 1:
            break
        # the branch after the event: the law a moment later along the old branch's motion
        ahead = y + 1e-9 * np.array(rhs(time, y))
        branch = _branch(ahead[0], ahead[1], bounded)
        now = branch[0] if branch[1] in ("linear", "double") else 0
        if now != pushing:
            contacts.append((time, now))
            pushing = now
    return Backlash(t, np.concatenate(phis), np.concatenate(ws), contacts)
