"""Scenes of the assumed-modes cantilever (seed 7.5): a free vibration and a constant tip force.

Their references are the discretised model's own eigen- and static solutions and,
for comparison, the exact Euler–Bernoulli cantilever (with the tip spring, if any).
"""
from __future__ import annotations

import math

import numpy as np
from scipy.linalg import eigh
from scipy.optimize import brentq

from components.bodies.beam import AUTO, MAX_MODES, AssumedModesBeam
from components.sources.force import ConstantForce

from ..assembly import Assembly
from ..result import Result
from .scene import DRIFT, Figure, Scene, solver_accuracy


def cantilever_frequencies(EI: float, L: float, m: float, k_tip: float, count: int) -> list[float]:
    """Exact first `count` natural frequencies [rad/s] of a clamped beam with a tip spring.

    With w = A (cosh βx - cos βx) + B (sinh βx - sin βx) (clamped at 0), the free end's
    EI w'' = 0 and EI w''' = k_tip w give, for λ = βL and κ = k_tip L³ / EI,
    λ³ (1 + cosh λ cos λ) - κ (cos λ sinh λ - cosh λ sin λ) = 0, and ω = λ² sqrt(EI / (m L³))
    with m the total mass. Divided by cosh λ here so that it stays finite.
    """
    kappa = k_tip * L**3 / EI

    def equation(lam):
        return lam**3 * (1 / math.cosh(lam) + math.cos(lam)) - kappa * (
            math.cos(lam) * math.tanh(lam) - math.sin(lam))

    # every root is a sign change: the roots are about π apart, a grid of π/64 separates them
    grid = np.arange(1, 64 * (count + 2)) * (math.pi / 64)
    values = [equation(lam) for lam in grid]
    roots = [brentq(equation, a, b, xtol=1e-15, rtol=1e-15)
             for a, b, fa, fb in zip(grid, grid[1:], values, values[1:]) if fa * fb < 0]
    return [lam**2 * math.sqrt(EI / (m * L**3)) for lam in roots[:count]]


def _crossing_times(t: np.ndarray, y: np.ndarray, dy: np.ndarray) -> np.ndarray:
    """Zero crossings of y, located on the cubic Hermite interpolant of (y, y') per interval."""
    times = []
    for k in np.flatnonzero(y[:-1] * y[1:] < 0):
        h = t[k + 1] - t[k]

        def cubic(s, k=k, h=h):
            return ((2 * s**3 - 3 * s**2 + 1) * y[k] + (s**3 - 2 * s**2 + s) * h * dy[k]
                    + (-2 * s**3 + 3 * s**2) * y[k + 1] + (s**3 - s**2) * h * dy[k + 1])
        times.append(t[k] + h * brentq(cubic, 0.0, 1.0, xtol=1e-15))
    return np.array(times)


def _first_mode_frequency(result: Result, beam: AssumedModesBeam, instance: str) -> float:
    """ω1 measured from the zero crossings of the first modal coordinate u1ᵀ M a(t).

    Projecting on the first mode removes the higher modes that the tip displacement
    also carries, so the crossings are those of one pure cosine: their spacing is π/ω1.
    a(t) comes from the beam's states in whichever coordinates it integrates them
    (AssumedModesBeam.assumed_motion); u1 from scipy's eigensolution of the full M, K.
    """
    mass, stiffness = beam.matrices()
    _, modes = eigh(stiffness, mass)
    projector = modes[:, 0] @ mass
    a, a_dot = beam.assumed_motion(lambda n: result[f"{instance}.{n}"], result["time"])
    crossings = _crossing_times(result["time"], projector @ a, projector @ a_dot)
    if len(crossings) < 3:
        return math.nan
    half_period = np.polyfit(np.arange(len(crossings)), crossings, 1)[0]
    return math.pi / half_period


def discretisation_error(beam: AssumedModesBeam, quantity) -> float:
    """How far `quantity(beam)` of the assumed-modes model may be from the continuous beam's.

    Ritz values converge monotonically, and for the sine basis like 1/N (see
    AssumedModesBeam): with M > N, error(N) = (q_N - q_M) + error(M), and with
    error(M) <= (N/M)^0.6 error(N) (any order >= 0.6) error(N) <= |q_N - q_M| /
    (1 - (N/M)^0.6): 3 |q_N - q_2N| (2.94 rounded up) for M = 2N, which is used up to
    N = 64, and M = 128 (the most the beam takes) above. Another basis is measured
    against the sine model of N = 8 and that model's own error. NaN (no estimate, so the
    figure fails) for N = 128, or 'auto' (modes of N = 128 left out by their static
    share: not a Ritz model of its own).
    """
    def sine(n):
        return AssumedModesBeam(basis="sine", n_modes=n,
                                **{k: beam.values[k] for k in ("EI", "L", "m", "k_tip")})

    if beam.option("basis") != "sine":
        yardstick = sine(8)
        return abs(quantity(beam) - quantity(yardstick)) + discretisation_error(yardstick, quantity)
    n = beam.option("n_modes")
    if n == AUTO or n >= MAX_MODES:
        return math.nan
    finer = min(2 * n, MAX_MODES)
    factor = 3.0 if finer == 2 * n else 1 / (1 - (n / finer) ** 0.6)
    return factor * abs(quantity(beam) - quantity(sine(finer)))


# --- beam_free_vibration: seed 7.5 ---------------------------------------------
def _free_vibration() -> Assembly:
    asm = Assembly("beam_free_vibration")
    asm.add("beam", AssumedModesBeam(basis="sine", n_modes=4, w_tip0=0.1))
    return asm


def _free_vibration_figures(result: Result, asm: Assembly) -> list[Figure]:
    beam = asm.component("beam")
    p = beam.values
    measured = _first_mode_frequency(result, beam, "beam")
    energy = result["beam.E"]
    omega1 = beam.natural_frequencies()[0]
    # the crossings of one pure cosine, on the cubic Hermite interpolant: the solver's error
    # plus ~(omega h)^4 / 384 of the frequency (h the output interval)
    crossing = omega1 * (omega1 * result.settings["step"]) ** 4 / 384
    solver = solver_accuracy(result, omega1) + crossing
    return [Figure("omega1", "first natural frequency from the zero crossings [rad/s]",
                   measured, omega1, solver,
                   source="the discretised model's eigenvalue (ours)"),
            Figure("omega1_EB", "the same against the exact Euler-Bernoulli beam [rad/s] "
                   "(accuracy: the N-mode error, 3 x |omega1(N) - omega1(2N)|)",
                   measured, cantilever_frequencies(p["EI"], p["L"], p["m"], p["k_tip"], 1)[0],
                   discretisation_error(beam, lambda b: b.natural_frequencies()[0]) + solver,
                   source="closed form (Euler-Bernoulli cantilever frequency equation, textbook; not the seed's numbers)"),
            Figure("E_drift", "largest relative energy change (undamped: 0) [1]",
                   float(np.abs(energy - energy[0]).max() / energy[0]), 0.0,
                   solver_accuracy(result, 1.0, DRIFT),
                   source="conservation law (exact: 0)")]


# --- beam_tip_force: seed 7.5 ------------------------------------------------------
def _tip_force() -> Assembly:
    asm = Assembly("beam_tip_force")
    # the assumed coordinates, not the modal default (the same model): with zeta = 0.5 the
    # beam settles, and its states come to rest, while modal amplitudes keep turning at
    # omega_i and the solver follows them (cosim, measured: N = 4 0.010 s against 0.038 s,
    # N = 16 0.10 s against 0.80 s; N = 64 modal over 5 min)
    asm.add("beam", AssumedModesBeam(basis="sine", n_modes=4, zeta=0.5, coordinates="assumed"))
    asm.add("load", ConstantForce(F=0.1))
    asm.connect("load.flange", "beam.tip")
    return asm


def _tip_force_figures(result: Result, asm: Assembly) -> list[Figure]:
    beam, force = asm.component("beam"), asm.component("load").values["F"]
    p, settled = beam.values, result["beam.w_tip"][-1]
    static = beam.static_tip_deflection(force)
    # the solver's error, and what is left of the release transient: the first mode decays
    # slowest, like exp(-zeta omega1 t) of the static deflection (damping by zeta only)
    ringing = abs(static) * math.exp(-p["zeta"] * beam.natural_frequencies()[0]
                                     * float(result["time"][-1]))
    solver = solver_accuracy(result, static) + ringing
    return [Figure("w_static", "settled tip deflection vs the discretised model's [m]",
                   settled, static, solver,
                   source="the discretised model's static solution (ours)"),
            Figure("w_EB", "settled tip deflection vs F / (3 EI / L^3 + k_tip) [m] "
                   "(accuracy: the N-mode error, 3 x |w(N) - w(2N)|)",
                   settled, force / (3 * p["EI"] / p["L"]**3 + p["k_tip"]),
                   discretisation_error(beam, lambda b: b.static_tip_deflection(force)) + solver,
                   source="closed form F/(3EI/L^3 + k_tip) (textbook beam statics, derived here; not the seed's numbers)")]


BEAM_SCENES: dict[str, Scene] = {
    "beam_free_vibration": Scene(
        "beam_free_vibration",
        "seed 7.5: cantilever released from its static shape under a tip load, undamped",
        _free_vibration, stop_time=40.0, step=0.02, tolerance=1e-10,
        record=None,  # every output: the frequency is read off the coordinates, however many
        figures=_free_vibration_figures, plot=["beam.w_tip", "beam.slope_tip", "beam.E"],
        seed="7.5", reference="ω1 of the discretised and the exact beam"),
    "beam_tip_force": Scene(
        "beam_tip_force", "seed 7.5: damped cantilever settling under a constant tip force",
        _tip_force, stop_time=20.0, step=0.05, tolerance=1e-10,
        record=["beam.w_tip", "beam.slope_tip", "beam.E", "load.flange.f"],
        figures=_tip_force_figures, plot=["beam.w_tip", "beam.E"], seed="7.5",
        reference="static deflection F L³/(3EI)"),
}

__all__ = ["BEAM_SCENES", "cantilever_frequencies", "discretisation_error"]
