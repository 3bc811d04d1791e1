"""The seed's rigid body on an axle (8.5) as a scene: a disk swinging as a pendulum."""
from __future__ import annotations

import math

import numpy as np

from components.bodies.axle import RigidBodyOnAxle

from ..assembly import Assembly
from ..result import Result
from .scene import DRIFT, Figure, Scene, solver_accuracy


def seed_disk(m: float = 1.0, R: float = 1.0, g: float = 9.81, **values) -> RigidBodyOnAxle:
    """Seed 8.5's example: uniform disk flat in X-Y, axle through its rim along (j + k)/sqrt(2)."""
    return RigidBodyOnAxle(m=m, I_xx=m * R**2 / 4, I_yy=m * R**2 / 4, I_zz=m * R**2 / 2,
                           r_x=0.0, r_y=R, r_z=0.0, n_x=0.0, n_y=math.sqrt(0.5),
                           n_z=math.sqrt(0.5), g=g, **values)


def zero_crossings(t: np.ndarray, x: np.ndarray, dx: np.ndarray) -> np.ndarray:
    """Times where x crosses zero, from the cubic Hermite interpolant of (x, dx).

    With the exact derivative at every sample the interpolant errs by O(h^4), far below
    what a linear interpolation of the samples would give.
    """
    # here: a figure's reference; scipy loads in 0.1-0.5 s
    from scipy.interpolate import CubicHermiteSpline
    return CubicHermiteSpline(t, x, dx).roots(extrapolate=False)


def period_from_crossings(t: np.ndarray, x: np.ndarray, dx: np.ndarray) -> float:
    """Twice the least-squares spacing of successive zero crossings (nan if fewer than 3)."""
    crossings = zero_crossings(t, x, dx)
    if len(crossings) < 3:
        return math.nan
    slope = np.polyfit(np.arange(len(crossings)), crossings, 1)[0]
    return 2 * slope


def pendulum_period(omega0: float, amplitude: float) -> float:
    """Exact period of theta'' = -omega0^2 sin(theta): 4 K(k) / omega0, k = sin(amplitude/2)
    (scipy's ellipk takes the parameter k^2)."""
    # here: a figure's reference; scipy loads in 0.1-0.5 s
    from scipy.special import ellipk
    return 4 * ellipk(math.sin(amplitude / 2) ** 2) / omega0


def _axle_pendulum() -> Assembly:
    asm = Assembly("axle_pendulum")
    asm.add("body", seed_disk(theta0=1.0))
    return asm


def _axle_pendulum_figures(result: Result, asm: Assembly) -> list[Figure]:
    body = asm.component("body")
    p = body.values
    radius = math.hypot(p["r_x"], p["r_y"], p["r_z"])
    omega0_seed = math.sqrt(4 * p["g"] / (7 * radius))  # seed 8.5, Eq. 8.19 for the disk
    theta0 = body.starts["theta"]
    theta_eq = body.equilibrium_angle()
    t, theta, omega, E = (result["time"], result["body.theta"], result["body.omega"],
                          result["body.E"])
    period = float(pendulum_period(omega0_seed, abs(theta0 - theta_eq)))
    # a crossing read off the cubic Hermite interpolant errs by ~(omega h)^4 / 384 of a
    # period (h the output interval), on top of the solver's error
    crossing = period * (omega0_seed * result.settings["step"]) ** 4 / 384
    return [
        # two closed forms of the same linearisation: equal to round-off
        Figure("omega0", "small-oscillation frequency [rad/s] vs sqrt(4g/7R)",
               body.small_oscillation_frequency(), omega0_seed, 1e-12, relative=True,
               source="seed 8.5, Eq. 8.19 (sqrt(4g/7R)) vs the model's linearisation"),
        Figure("T", "period from zero crossings [s] vs 4K(sin(theta0/2))/omega0",
               float(period_from_crossings(t, theta - theta_eq, omega)), period,
               solver_accuracy(result, period) + crossing,
               source="closed form (exact pendulum period 4K(k)/omega0, derived here from seed 8.5)"),
        Figure("E_drift", "largest |E - E(0)| [J] (frictionless: 0)",
               float(np.abs(E - E[0]).max()), 0.0, solver_accuracy(result, E[0], DRIFT),
               source="conservation law (exact: 0)"),
    ]


AXLE_SCENES: dict[str, Scene] = {
    "axle_pendulum": Scene(
        "axle_pendulum", "seed 8.5: disk on an inclined axle through its rim, released from rest",
        _axle_pendulum, stop_time=15.0, step=0.01, tolerance=1e-10,
        record=["body.theta", "body.omega", "body.E", "body.G_z"],
        figures=_axle_pendulum_figures, plot=["body.theta", "body.omega"], seed="8.5",
        reference="ω0 = sqrt(4g/7R); period 4K(sin(θ0/2))/ω0; energy"),
}

__all__ = ["AXLE_SCENES", "pendulum_period", "period_from_crossings", "seed_disk",
           "zero_crossings"]
