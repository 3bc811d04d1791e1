"""Shared test helpers: the seed's parameter sets and an independent Coulomb reference."""
from __future__ import annotations

import math

import numpy as np
import pytest
from scipy.optimize import brentq

# seed Eq. 9.4
SEED_94 = dict(m=1.0, k=1.0, g=1.0, mu_k=0.3, mu_s=0.4)
SEED_94_SPEED = 0.05


def coulomb_drag_reference(m, k, g, mu_k, mu_s, v, t_end):
    """Piecewise exact solution of m x'' = k (v t - x) + f under Coulomb friction (seed 9.2).

    Derived here from the linear ODE of each phase, independently of the library:
    stuck phases hold x until the spring force k (v t - x) reaches mu_s m g; sliding
    phases solve m xi'' = -k xi for xi = x - v t + mu_k m g / k, until x' = 0.
    Returns (phases, x_of_t) where phases are (kind, t_start, t_end) tuples.
    """
    w, N = math.sqrt(k / m), m * g
    t, x, phases, pieces = 0.0, 0.0, [], []
    while t < t_end:
        t_slip = (mu_s * N / k + x) / v
        phases.append(("stick", t, t_slip))
        pieces.append((t, t_slip, lambda tt, x=x: np.full_like(tt, x)))
        xi0, dxi0 = x - v * t_slip + mu_k * N / k, -v

        def x_slide(tt, t0=t_slip, xi0=xi0, dxi0=dxi0):
            tau = tt - t0
            return v * tt - mu_k * N / k + xi0 * np.cos(w * tau) + dxi0 / w * np.sin(w * tau)

        def v_slide(tau, xi0=xi0, dxi0=dxi0):
            return v - xi0 * w * math.sin(w * tau) + dxi0 * math.cos(w * tau)

        # x' > 0 right after slip starts; its first zero lies within one period
        grid = np.linspace(1e-9, 2 * math.pi / w, 2001)
        vals = [v_slide(s) for s in grid]
        i = next(j for j in range(1, len(grid)) if vals[j] <= 0 < vals[j - 1])
        tau_stop = brentq(v_slide, grid[i - 1], grid[i], xtol=1e-15, rtol=1e-15)
        t_stick = t_slip + tau_stop
        phases.append(("slide", t_slip, t_stick))
        pieces.append((t_slip, t_stick, x_slide))
        t, x = t_stick, float(x_slide(np.array(t_stick)))
        assert abs(k * (v * t - x)) < mu_s * N, "the block re-sticks in this regime"

    def x_of_t(tt):
        tt = np.asarray(tt, dtype=float)
        out = np.empty_like(tt)
        for a, b, fn in pieces:
            sel = (tt >= a) & (tt <= b)
            out[sel] = fn(tt[sel])
        return out

    return phases, x_of_t


@pytest.fixture(scope="session")
def fresh_cache(tmp_path_factory):
    return tmp_path_factory.mktemp("fmu-cache")


def simulate_in_fmpy(component, fmi_type, stop_time, output_interval, tolerance=1e-10,
                     output=None, tmp_path=None):
    """Run a component's FMU through fmpy.simulate_fmu alone (no master of ours).

    The component's parameter values and state starts are passed as start values,
    as any importer would set them.
    """
    from fmpy import simulate_fmu

    from fmus import build_fmu

    path = build_fmu(component)
    starts = {**component.values, **component.starts}
    return simulate_fmu(str(path), fmi_type=fmi_type, stop_time=stop_time,
                        output_interval=output_interval, relative_tolerance=tolerance,
                        start_values=starts, output=output, record_events=True)


# seed 9.4 with m = k = g = 1, mu_s = mu_k = 0.6, x(0) = 6.55
FRICTION_DAMPING_TURNING = [6.55, -5.35, 4.15, -2.95, 1.75, -0.55]


def exact_friction_damping(t, mu=0.6):
    """Seed 9.4 by hand: half-cycle n is x = c + (A - c) cos(t - n pi) about c = sign(A) mu,
    then stuck at the last turning point."""
    turning = FRICTION_DAMPING_TURNING
    x = np.full_like(t, turning[-1])
    for n, amplitude in enumerate(turning[:-1]):
        centre = math.copysign(mu, amplitude)
        inside = (t >= n * math.pi) & (t <= (n + 1) * math.pi)
        x[inside] = centre + (amplitude - centre) * np.cos(t[inside] - n * math.pi)
    return x


def drop_component():
    """A point mass falling from 2 m; the model ends its run when it reaches the ground."""
    from components import Component
    from components.interfaces import Parameter, Profile, State

    class Drop(Component):
        """Point mass falling from a height; the model ends when it reaches the ground."""

        parameters = (Parameter("g", 9.81, "m/s2", "gravity", min=0.0, min_strict=True),)
        states = (State("h", 2.0, "m", "height above the ground"),
                  State("w", 0.0, "m/s", "upward velocity"))
        profiles = (Profile("free", "no ports"),)

        def equations(self, e):
            e.residual(e.der.h - e.x.w)
            e.residual(e.der.w + e.p.g)
            e.terminate_when(e.x.h, "the mass hit the ground")

    return Drop
