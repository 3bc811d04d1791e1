"""The Euler–Bernoulli cantilever by assumed modes, Chatterjee, Intermediate Dynamics, 7.5."""
from __future__ import annotations

import math

import casadi as ca
import numpy as np
from scipy.linalg import eigh

from .beam_shapes import BASES, shape_basis
from .component import Component
from .interfaces import (FORCE_IN, TRANSLATIONAL, ComponentError, Option, Parameter, Port,
                         Profile, State)


def _coordinate_states(kind: str, n_modes: int) -> tuple[State, ...]:
    names = shape_basis(kind, n_modes).names
    return (tuple(State(n, 0.0, "m", f"generalised coordinate {n} of the assumed modes")
                  for n in names)
            + tuple(State(f"{n}_dot", 0.0, "m/s", f"rate of the generalised coordinate {n}")
                    for n in names))


class AssumedModesBeam(Component):
    """Euler–Bernoulli cantilever with a tip spring, discretised by assumed modes (seed 7.5).

    Clamped at x = 0, w(x, t) = Σ a_i(t) φ_i(x/L); Lagrange's equations give
    ``M a'' + C a' + K a = φ(L) f_tip`` (seed Eqs. 7.4, 7.6) with
    ``M = m M̂``, ``K = EI/L³ K̂ + k_tip φ(L) φ(L)ᵀ``, ``M̂ = ∫φφᵀ dξ``, ``K̂ = ∫φ''φ''ᵀ dξ``
    (the seed prints the strain energy with w_x² where w_xx² is meant). ``m`` is the
    beam's TOTAL mass: the seed's kinetic energy is ∫ m/(2L) w_t² dx, so frequencies come
    in units of sqrt(EI / (m L³)) although the text calls m a mass per unit length.

    Parameters: ``EI`` [N.m2], ``L`` [m], ``m`` [kg] total mass, ``k_tip`` [N/m] tip spring
    to ground (may be 0), ``alpha`` [1/s], ``beta`` [s] Rayleigh damping ``alpha M + beta K``
    (K with the tip spring), ``zeta`` [1] modal damping ratio of every mode of the bare
    cantilever (exact modal ratio when k_tip = 0; the tip spring itself is undamped).
    The three damping terms add; each defaults to 0. All are FMU parameters.
    Options: ``basis`` — ``poly2`` (seed: x²/L², x³/L³; coordinates a1, a2) or ``sine``
    (seed Eq. 7.8: x²/L² and (x/L) sin(kπx/L), k = 1..N; coordinates a0..aN); ``n_modes``
    = N of Eq. 7.8 (N + 1 coordinates; ignored by poly2).
    States: the coordinates ``a_i`` [m] and their rates ``a_i_dot`` [m/s]; all outputs.
    Start value alias: ``w_tip0`` [m] starts the beam at rest in its static shape under a
    tip load that deflects the tip by w_tip0 (recomputed whenever the component is
    validated, so it follows later changes of basis, n_modes or parameters).
    Connector: ``tip`` — the free end; the force on the beam there (``tip.f``) is the
    input, w(L), its rate and acceleration are ``tip.s``, ``tip.v``, ``tip.a``.
    Outputs: ``w_tip`` [m], ``slope_tip`` [1] = w_x(L), ``E`` [J] kinetic + strain + tip
    spring energy.

    Convergence of the sine basis, k_tip = 0, relative error of ω_i against the exact
    cantilever (βL)² = 3.51602, 22.0345, 61.6972, 120.902 (Ritz: every error is positive):

        N    coords  err ω1      err ω2      err ω3      err ω4
        1    2       8.991e-03   3.146e-01   -           -
        2    3       8.884e-03   2.430e-02   2.272e-01   -
        4    5       4.097e-03   1.116e-02   1.889e-02   1.793e-02
        8    9       2.062e-03   5.444e-03   4.250e-03   3.833e-03
        16   17      1.069e-03   2.775e-03   1.438e-03   1.030e-03
        32   33      5.525e-04   1.424e-03   6.338e-04   3.840e-04

    Reproduce: ``python -m components.beam``. The error falls like 1/N: with w = ξ h(ξ),
    the sine series of h - a0 ξ has coefficients ~ 1/k³ (its odd extension's h'' jumps),
    so the strain energy of the truncated tail, and with it the error, is ~ Σ_{k>N} 1/k².
    """

    options = (Option("basis", "sine", BASES, "assumed modes: the seed's two powers or Eq. 7.8"),
               Option("n_modes", 4, range(1, 65),
                      "N of Eq. 7.8, the number of sine terms (N + 1 coordinates)"))
    parameters = (
        Parameter("EI", 1.0, "N.m2", "flexural rigidity", min=0.0, min_strict=True),
        Parameter("L", 1.0, "m", "length", min=0.0, min_strict=True),
        Parameter("m", 1.0, "kg", "total mass of the beam", min=0.0, min_strict=True),
        Parameter("k_tip", 0.0, "N/m", "stiffness of the spring from the tip to ground", min=0.0),
        Parameter("alpha", 0.0, "1/s", "mass-proportional Rayleigh damping", min=0.0),
        Parameter("beta", 0.0, "s", "stiffness-proportional Rayleigh damping", min=0.0),
        Parameter("zeta", 0.0, "1", "modal damping ratio of the bare cantilever's modes",
                  min=0.0),
    )
    states = _coordinate_states("sine", 4)  # the default options; instances redeclare theirs
    ports = (Port("tip", TRANSLATIONAL, "free end of the beam, moving transversally"),)
    profiles = (Profile("free_tip", "tip force in; tip displacement, velocity and acceleration out",
                        {"tip": FORCE_IN}),)
    default_stop_time = 20.0

    def __init__(self, name: str | None = None, profile: str | None = None, **values):
        self._release_w_tip = None
        # options first: they decide which coordinates, and so which start values, exist
        options = {o.name for o in self.options}
        ordered = {**{k: v for k, v in values.items() if k in options},
                   **{k: v for k, v in values.items() if k not in options}}
        super().__init__(name, profile, **ordered)

    # --- coordinates that depend on the options --------------------------------
    def basis(self):
        return shape_basis(self.option("basis"), self.option("n_modes"))

    def settable_names(self) -> list[str]:
        return super().settable_names() + ["w_tip0"]

    def set(self, key: str, value) -> None:
        if key == "w_tip0":
            try:
                number = float(value)
            except (TypeError, ValueError):
                raise ComponentError(f"{self._where()}: w_tip0 = {value!r} is not a number") from None
            if not math.isfinite(number):
                raise ComponentError(f"{self._where()}: start value w_tip0 = {value} must be finite")
            self._release_w_tip = number
            return
        super().set(key, value)
        if key in self.option_values:
            previous = self.starts
            self.states = _coordinate_states(self.option("basis"), self.option("n_modes"))
            self.starts = {s.name: previous.get(s.name, s.start) for s in self.states}
        elif key in self.starts:
            self._release_w_tip = None  # an explicit start value replaces the static shape

    def validate(self) -> None:
        super().validate()
        if self._release_w_tip is not None:
            shape = self.static_shape(1.0)
            a = shape * (self._release_w_tip / (self.basis().tip_value @ shape))
            for name, value in zip(self.basis().names, a):
                self.starts[name], self.starts[f"{name}_dot"] = float(value), 0.0

    # --- the discretised model, numerically, at the current parameter values --
    def matrices(self) -> tuple[np.ndarray, np.ndarray]:
        """(M, K) in SI units at the current parameter values."""
        p, b = self.values, self.basis()
        stiffness = p["EI"] / p["L"]**3 * b.stiffness + p["k_tip"] * np.outer(b.tip_value, b.tip_value)
        return p["m"] * b.mass, stiffness

    def natural_frequencies(self) -> np.ndarray:
        """Undamped natural frequencies [rad/s], ascending: K u = ω² M u (seed Eq. 7.4)."""
        mass, stiffness = self.matrices()
        return np.sqrt(eigh(stiffness, mass, eigvals_only=True))

    def static_shape(self, force: float) -> np.ndarray:
        """Coordinates of the static equilibrium under a tip force `force` [N]: K a = φ(L) F."""
        return np.linalg.solve(self.matrices()[1], self.basis().tip_value * force)

    def static_tip_deflection(self, force: float) -> float:
        """w(L) [m] of the discretised model at rest under a tip force `force` [N]."""
        return float(self.basis().tip_value @ self.static_shape(force))

    # --- equations --------------------------------------------------------------
    def equations(self, e):
        p, b, tip = e.p, self.basis(), e.port("tip")
        a = ca.vertcat(*[getattr(e.x, n) for n in b.names])
        a_dot = ca.vertcat(*[getattr(e.x, f"{n}_dot") for n in b.names])
        a_ddot = ca.vertcat(*[getattr(e.der, f"{n}_dot") for n in b.names])
        phi, g = ca.DM(b.tip_value), ca.DM(b.tip_per_mass)
        omega0_sq = p.EI / (p.m * p.L**3)  # the frequency scale: ω = λ² sqrt(EI / (m L³))
        for n in b.names:
            e.residual(getattr(e.der, n) - getattr(e.x, f"{n}_dot"))
        # M a'' + (alpha M + beta K + zeta C_modal) a' + K a = φ f, premultiplied by M⁻¹ so
        # that the matrices are numbers (see components.beam_shapes); K acts on a + beta a'
        strained = a + p.beta * a_dot
        e.residual(a_ddot + omega0_sq * ca.mtimes(ca.DM(b.stiffness_per_mass), strained)
                   + p.k_tip / p.m * g * ca.dot(phi, strained) + p.alpha * a_dot
                   + 2 * p.zeta * ca.sqrt(omega0_sq) * ca.mtimes(ca.DM(b.modal_damping_per_mass), a_dot)
                   - g * tip.f / p.m)
        e.residual(tip.s - ca.dot(phi, a))
        e.residual(tip.v - ca.dot(phi, a_dot))
        e.residual(tip.a - ca.dot(phi, a_ddot))
        w_tip = ca.dot(phi, a)
        kinetic = p.m * ca.dot(a_dot, ca.mtimes(ca.DM(b.mass), a_dot)) / 2
        strain = p.EI / p.L**3 * ca.dot(a, ca.mtimes(ca.DM(b.stiffness), a)) / 2
        e.output("w_tip", w_tip, "m", "tip deflection w(L)")
        e.output("slope_tip", ca.dot(ca.DM(b.tip_slope), a) / p.L, "1", "tip slope w_x(L)")
        e.output("E", kinetic + strain + p.k_tip * w_tip**2 / 2, "J",
                 "kinetic energy + strain energy of beam and tip spring")


def _convergence_table(n_values=(1, 2, 4, 8, 16, 32)) -> str:
    """The docstring's table: sine basis against the roots of 1 + cosh λ cos λ = 0."""
    from scipy.optimize import brentq

    # the k-th root lies within 0.5 of (k - 1/2) π, where cos λ crosses zero
    exact = [brentq(lambda lam: 1 / math.cosh(lam) + math.cos(lam), (k - 0.5) * math.pi - 0.5,
                    (k - 0.5) * math.pi + 0.5, xtol=1e-15) ** 2 for k in range(1, 5)]
    lines = ["N    coords  " + "  ".join(f"err ω{i + 1:<6}" for i in range(4)).rstrip()]
    for n in n_values:
        omega = AssumedModesBeam(basis="sine", n_modes=n).natural_frequencies()
        errors = [f"{w / x - 1:<10.3e}" if i < len(omega) else f"{'-':<10}"
                  for i, (w, x) in enumerate(zip(list(omega) + [math.nan] * 4, exact))]
        lines.append((f"{n:<4} {n + 1:<7} " + "  ".join(errors)).rstrip())
    return "\n".join(lines)


if __name__ == "__main__":
    print(_convergence_table())
