"""The Euler–Bernoulli cantilever by assumed modes, Chatterjee, Intermediate Dynamics, 7.5."""
from __future__ import annotations

import math
from types import SimpleNamespace

from .beam_shapes import BASES, basis_names, modal_basis, shape_basis
from ..component import Component
from ..interfaces import (FORCE_IN, TRANSLATIONAL, ComponentError, Mode, Option, Parameter,
                         Port, Profile, State)
from ..lazy import lazy

ca = lazy("casadi")  # loaded by the first equation written, not by an import
np = lazy("numpy")  # loaded by the first array: listing the components needs none

COORDINATES = ("assumed", "modal")
MAX_MODES = 128
AUTO = "auto"
FRAME = Mode("frame", 0, "1 once the modal amplitudes refer to the frame anchored at t = 0",
             values=(0, 1))


class _ModesOption(Option):
    """n_modes: an integer N, or 'auto' (N = MAX_MODES, modes kept by `accuracy`)."""
    words = (AUTO,)  # the values besides the integers, for whoever lists them all

    def parse(self, value):
        return AUTO if value == AUTO else super().parse(value)

    def allowed(self) -> str:
        return f"{super().allowed()} or '{AUTO}'"


class _AccuracyOption(Option):
    """accuracy: a number in (0, 1), the relative tip error that n_modes='auto' aims at."""

    def parse(self, value):
        try:
            number = float(value)
        except (TypeError, ValueError):
            return None
        return number if 0.0 < number < 1.0 else None

    def allowed(self) -> str:
        return "a number between 0 and 1 (exclusive)"


def _assumed_states(names) -> tuple[State, ...]:
    return (tuple(State(n, 0.0, "m", f"generalised coordinate {n} of the assumed modes")
                  for n in names)
            + tuple(State(f"{n}_dot", 0.0, "m/s", f"rate of the generalised coordinate {n}")
                    for n in names))


def _modal_states(count: int) -> tuple[State, ...]:
    return tuple(State(f"mode{i}_{part}", 0.0, "m",
                       f"{what} amplitude of mode {i}'s tip deflection (frame of t = 0)")
                 for part, what in (("c", "cosine"), ("s", "sine")) for i in range(1, count + 1))


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
    = N of Eq. 7.8 (N + 1 coordinates; ignored by poly2), or ``auto`` (modal only: the
    modes of N = 128 that ``accuracy`` needs); ``coordinates`` — ``modal`` (default) or
    ``assumed``, which the solver integrates.
    States, ``coordinates='assumed'``: the coordinates ``a_i`` [m] and their rates
    ``a_i_dot`` [m/s]. ``coordinates='modal'``: a = Φ η, with Φ the Ritz modes of the bare
    cantilever (the eigenvectors of the same M̂, K̂), and each η_i = c_i cos ω_i t +
    s_i sin ω_i t; the states are ``mode{i}_c``, ``mode{i}_s`` [m] and the mode ``frame``.
    With an integer n_modes every mode is kept, so a = Φ η is a change of basis and both
    coordinates are the same model: tip spring, Rayleigh and modal damping and the tip
    force included (the tip spring and beta's share of it act on Σ η, the tip). The modal
    form is the default because a free, undamped beam's states are then constant and its
    cost does not grow with the highest frequency ω_N (N = 64: ω_N ≈ 4e4 rad/s; the
    assumed coordinates have the solver step through it). The other way round where the
    beam settles (heavy damping, a constant load): its assumed coordinates come to rest
    while the modal amplitudes keep turning at ω_i, and the solver follows them
    (beam_tip_force, zeta = 0.5, N = 16: 0.8 s modal, 0.1 s assumed), so a scene of a
    settling beam names coordinates='assumed'. A modal beam still takes the
    ``a_i``, ``a_i_dot`` as start values (converted), and :meth:`assumed_motion` gives
    a(t) from a result in either coordinates.
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

    Reproduce: ``python -m components.bodies.beam``. The error falls like 1/N: with w = ξ h(ξ),
    the sine series of h - a0 ξ has coefficients ~ 1/k³ (its odd extension's h'' jumps),
    so the strain energy of the truncated tail, and with it the error, is ~ Σ_{k>N} 1/k².
    """

    options = (Option("basis", "sine", BASES, "assumed modes: the seed's two powers or Eq. 7.8"),
               _ModesOption("n_modes", 4, range(1, MAX_MODES + 1),
                            "N of Eq. 7.8, the number of sine terms (N + 1 coordinates)"),
               Option("coordinates", "modal", COORDINATES,
                      "integrate the bare cantilever's modes, each propagated exactly while "
                      "unforced (the default: the same physics, a change of basis), or the "
                      "assumed-modes coordinates a_i"),
               _AccuracyOption("accuracy", 1e-6, (),
                               "with n_modes='auto': largest share of the static tip deflection "
                               "left to the modes not kept"))
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
    # those of the default options (what `mechfmu show` lists); instances redeclare them
    states, modes = _modal_states(len(basis_names("sine", 4))), (FRAME,)
    start_aliases = (
        ("w_tip0", "[m] start at rest in the static shape under a tip load, tip deflected "
                   "by w_tip0"),
        ("a0 .. aN, a0_dot .. aN_dot (poly2: a1, a2, ...)",
         "[m, m/s] the assumed-modes coordinates and rates; the states with "
         "coordinates=assumed, converted into the modal amplitudes with modal"))
    ports = (Port("tip", TRANSLATIONAL, "free end of the beam, moving transversally"),)
    profiles = (Profile("free_tip", "tip force in; tip displacement, velocity and acceleration out",
                        {"tip": FORCE_IN}),)
    default_stop_time = 20.0

    def __init__(self, name: str | None = None, profile: str | None = None, **values):
        self._release_w_tip = None
        self._assumed_starts: dict[str, float] = {}  # a_i, a_i_dot given to a modal beam
        self._derive_modal = False  # modal amplitudes still to be computed from them
        # options first: they decide which coordinates, and so which start values, exist
        options = {o.name for o in self.options}
        ordered = {**{k: v for k, v in values.items() if k in options},
                   **{k: v for k, v in values.items() if k not in options}}
        super().__init__(name, profile, **ordered)

    # --- coordinates that depend on the options --------------------------------
    def _modal(self) -> bool:
        return self.option("coordinates") == "modal"

    def basis(self):
        n = self.option("n_modes")
        return shape_basis(self.option("basis"), MAX_MODES if n == AUTO else n)

    def modal(self):
        """The bare cantilever's modes of basis() (components.bodies.beam_shapes.ModalBasis)."""
        n = self.option("n_modes")
        return modal_basis(self.option("basis"), MAX_MODES if n == AUTO else n)

    def kept_modes(self) -> int:
        """How many modes a modal beam integrates: all, or with n_modes='auto' the fewest
        whose neglected static tip flexibility is at most `accuracy` of the total (a tip
        force slower than the first neglected mode, or a release from a static shape,
        then moves the tip by at most that share more than the full model does)."""
        flexibility = self.modal().static_flexibility()
        if self.option("n_modes") != AUTO:
            return len(flexibility)
        tail = np.cumsum(flexibility[::-1])[::-1] / flexibility.sum()  # tail[k]: modes k, k+1, ...
        return int(np.argmax(np.append(tail, 0.0) <= self.option("accuracy")))

    def assumed_motion(self, column, time) -> tuple[np.ndarray, np.ndarray]:
        """(a, a') over time, one row per coordinate of basis(), whichever coordinates the
        beam integrates. `column(name)` returns the recorded values of this instance's
        state or mode `name`; `time` the result's time column.

        Modal: a = Φ η, η_i = c_i cos ω_i t + s_i sin ω_i t and η_i' = ω_i (s_i cos ω_i t
        - c_i sin ω_i t) once the amplitudes refer to t = 0 (frame = 1); before that (a
        row at the start time, frame = 0) η = c, η' = ω s. The rate holds under any tip
        force: variation of constants keeps c' cos + s' sin = 0.
        """
        names = self.basis().names
        if not self._modal():
            return (np.array([column(n) for n in names], dtype=float),
                    np.array([column(f"{n}_dot") for n in names], dtype=float))
        kept, omega = self.kept_modes(), self.modal_frequencies()[:, None]
        c = np.array([column(f"mode{i}_c") for i in range(1, kept + 1)], dtype=float)
        s = np.array([column(f"mode{i}_s") for i in range(1, kept + 1)], dtype=float)
        anchored = np.asarray(column("frame")) != 0
        phase = omega * np.asarray(time, dtype=float)[None, :]
        cos, sin = np.where(anchored, np.cos(phase), 1.0), np.where(anchored, np.sin(phase), 0.0)
        shapes = self.modal().shapes[:, :kept]
        return shapes @ (c * cos + s * sin), shapes @ (omega * (s * cos - c * sin))

    def _assumed_names(self) -> list[str]:
        names = self.basis().names
        return list(names) + [f"{n}_dot" for n in names]

    def _redeclare(self) -> None:
        previous = self.starts
        if self._modal():
            if not self._assumed_starts and any(previous.get(n) for n in self._assumed_names()):
                self._assumed_starts, self._derive_modal = dict(previous), True
            self.states, self.modes = _modal_states(self.kept_modes()), (FRAME,)
        else:
            previous = {**previous, **self._assumed_starts}
            self.states, self.modes = _assumed_states(self.basis().names), ()
        self.starts = {s.name: previous.get(s.name, s.start) for s in self.states}

    def settable_names(self) -> list[str]:
        aliases = self._assumed_names() if self._modal() else []
        return super().settable_names() + aliases + ["w_tip0"]

    def _number(self, key: str, value) -> float:
        try:
            number = float(value)
        except (TypeError, ValueError):
            raise ComponentError(f"{self._where()}: {key} = {value!r} is not a number") from None
        if not math.isfinite(number):
            raise ComponentError(f"{self._where()}: start value {key} = {value} must be finite")
        return number

    def set(self, key: str, value) -> None:
        if key == "w_tip0":
            self._release_w_tip = self._number(key, value)
            return
        if self._modal() and key in self._assumed_names():
            # a start in the seed's coordinates: the modal amplitudes follow from all of them
            self._assumed_starts[key] = self._number(key, value)
            self._release_w_tip, self._derive_modal = None, True
            return
        super().set(key, value)
        if key in self.option_values:
            self._redeclare()
        elif key in self.starts:
            self._release_w_tip = None  # an explicit start value replaces the static shape
            self._derive_modal = False

    def validate(self) -> None:
        super().validate()
        if self.option("n_modes") == AUTO and not self._modal():
            raise ComponentError(f"{self._where()}: n_modes = 'auto' needs coordinates = 'modal' "
                                 f"(the assumed coordinates keep every one of the N + 1)")
        if self._release_w_tip is not None:
            shape = self.static_shape(1.0)
            a = shape * (self._release_w_tip / (self.basis().tip_value @ shape))
            values = dict(zip(self.basis().names, a))
            values.update({f"{n}_dot": 0.0 for n in self.basis().names})
            if self._modal():
                self._assumed_starts, self._derive_modal = values, True
            else:
                self.starts.update({k: float(v) for k, v in values.items()})
        if self._modal() and self._derive_modal:
            self._modal_starts_from_assumed()

    def _modal_starts_from_assumed(self) -> None:
        """η = Φ⁻¹ a, and the sine amplitude η'/ω: the amplitudes at the start time."""
        names = self.basis().names
        a = np.array([self._assumed_starts.get(n, 0.0) for n in names])
        a_dot = np.array([self._assumed_starts.get(f"{n}_dot", 0.0) for n in names])
        kept, to_modal = self.kept_modes(), self.modal().to_modal
        omega = self.modal_frequencies()
        for i, (eta, eta_dot) in enumerate(zip(to_modal[:kept] @ a, to_modal[:kept] @ a_dot)):
            self.starts[f"mode{i + 1}_c"] = float(eta)
            self.starts[f"mode{i + 1}_s"] = float(eta_dot / omega[i])

    # --- the discretised model, numerically, at the current parameter values --
    def matrices(self) -> tuple[np.ndarray, np.ndarray]:
        """(M, K) in SI units at the current parameter values."""
        p, b = self.values, self.basis()
        stiffness = p["EI"] / p["L"]**3 * b.stiffness + p["k_tip"] * np.outer(b.tip_value, b.tip_value)
        return p["m"] * b.mass, stiffness

    def natural_frequencies(self) -> np.ndarray:
        """Undamped natural frequencies [rad/s], ascending: K u = ω² M u (seed Eq. 7.4)."""
        from scipy.linalg import eigh  # here: scipy loads in 0.1-0.3 s, a beam's run may not ask
        mass, stiffness = self.matrices()
        return np.sqrt(eigh(stiffness, mass, eigvals_only=True))

    def modal_frequencies(self) -> np.ndarray:
        """ω_i [rad/s] of the modes a modal beam integrates: the bare cantilever's, ascending."""
        p = self.values
        return np.sqrt(self.modal().stiffness[:self.kept_modes()] * p["EI"] / (p["m"] * p["L"]**3))

    def static_shape(self, force: float) -> np.ndarray:
        """Coordinates of the static equilibrium under a tip force `force` [N]: K a = φ(L) F."""
        return np.linalg.solve(self.matrices()[1], self.basis().tip_value * force)

    def static_tip_deflection(self, force: float) -> float:
        """w(L) [m] of the discretised model at rest under a tip force `force` [N]."""
        return float(self.basis().tip_value @ self.static_shape(force))

    # --- equations --------------------------------------------------------------
    def equations(self, e):
        if self._modal():
            self._modal_equations(e)
        else:
            self._assumed_equations(e)

    def _modal_terms(self, t, c, s, tip_f, p, tip_motion=None):
        """The modal beam's right-hand side and outputs, in SX (flatten) or MX (the C code).

        η_i'' + ω_i² η_i = F_i, F_i = gain_i (f - k_tip (w + beta w')) / m - d_i η_i',
        d_i = alpha + beta ω_i² + 2 zeta ω_i (Rayleigh and modal damping are diagonal in the
        bare modes; the tip spring and its share of beta K are the rank-one tip force).
        With η = c cos ω t + s sin ω t and η' = ω (s cos ω t - c sin ω t) (variation of
        constants): c' = -sin(ω t) F / ω, s' = cos(ω t) F / ω. An undamped beam with a free
        tip has F = 0: its states are constant and the solver's step is set by the outputs
        asked for, not by the highest mode. Every expression is elementwise over the modes.
        `tip_motion` = (w, w') held as symbols instead of Σ η, Σ η': the Jacobians then
        split into a diagonal part and a rank-one part (see vectorised_functions).
        """
        kept, modal = self.kept_modes(), self.modal()
        omega = ca.sqrt(p.EI / (p.m * p.L**3)) * ca.DM(np.sqrt(modal.stiffness[:kept]))
        gain = ca.DM(modal.gain[:kept])
        cos, sin = ca.cos(omega * t), ca.sin(omega * t)
        eta, eta_dot = c * cos + s * sin, omega * (s * cos - c * sin)
        w, w_dot = tip_motion if tip_motion is not None else (ca.sum1(eta), ca.sum1(eta_dot))
        decay = p.alpha + p.beta * omega**2 + 2 * p.zeta * omega
        force = gain * (tip_f - p.k_tip * (w + p.beta * w_dot)) / p.m - decay * eta_dot
        return SimpleNamespace(
            omega=omega, cos=cos, sin=sin, c_dot=-sin * force / omega, s_dot=cos * force / omega,
            outputs={"tip.s": w, "tip.v": w_dot, "tip.a": ca.sum1(force - omega**2 * eta),
                     "w_tip": w, "slope_tip": ca.dot(ca.DM(modal.tip_slope[:kept]), eta) / p.L,
                     "E": p.m * ca.sum1((eta_dot**2 + omega**2 * eta**2) / gain) / 2
                     + p.k_tip * w**2 / 2})

    def _modal_equations(self, e):
        p, tip, kept = e.p, e.port("tip"), self.kept_modes()
        c = ca.vertcat(*[getattr(e.x, f"mode{i}_c") for i in range(1, kept + 1)])
        s = ca.vertcat(*[getattr(e.x, f"mode{i}_s") for i in range(1, kept + 1)])
        terms = self._modal_terms(e.t, c, s, tip.f, p)
        for i in range(kept):
            e.residual(getattr(e.der, f"mode{i + 1}_c") - terms.c_dot[i])
            e.residual(getattr(e.der, f"mode{i + 1}_s") - terms.s_dot[i])
        e.jump("frame", 1)
        c_new, s_new = self._to_frame_of_zero(e.q.frame, c, s, terms)
        for i in range(kept):
            e.jump(f"mode{i + 1}_c", c_new[i])
            e.jump(f"mode{i + 1}_s", s_new[i])
        out = terms.outputs
        e.residual(tip.s - out["tip.s"])
        e.residual(tip.v - out["tip.v"])
        e.residual(tip.a - out["tip.a"])
        e.output("w_tip", out["w_tip"], "m", "tip deflection w(L)")
        e.output("slope_tip", out["slope_tip"], "1", "tip slope w_x(L)")
        e.output("E", out["E"], "J", "kinetic energy + strain energy of beam and tip spring")

    @staticmethod
    def _to_frame_of_zero(frame, c, s, terms):
        """The start values are the amplitudes at the start time t0 (η(t0) = c,
        η'(t0) = ω s); the first event iteration turns them, once, into those of the frame
        anchored at t = 0, so that the run is right whatever t0 is."""
        start = frame == 0
        return (ca.if_else(start, c * terms.cos - s * terms.sin, c),
                ca.if_else(start, c * terms.sin + s * terms.cos, s))

    def vectorised_functions(self, model) -> dict:
        """ode, out, jac and dd of the modal beam as MX: loops over the modes in C, so that
        the code, and gcc's time, grow like N (N = 128 builds in seconds).

        The Jacobians by the chain rule through the tip motion W = (w, w'): with W held,
        every result is elementwise in the modes (a diagonal Jacobian, one sweep of AD);
        W's own dependence adds d/dW ⊗ dW/dx, a product of a few vectors.
        """
        if not self._modal():
            return {}
        if model.z.numel():
            raise AssertionError("the modal beam has no event indicators")
        t, q = ca.MX.sym("t"), ca.MX.sym("q", model.q.numel())
        x, u, p = (ca.MX.sym(n, v.numel()) for n, v in (("x", model.x), ("u", model.u),
                                                        ("p", model.p)))
        params = SimpleNamespace(**{par.name: p[i] for i, par in enumerate(self.parameters)})
        kept, held = self.kept_modes(), ca.MX.sym("W", 2)
        c, s = x[:kept], x[kept:]
        terms = self._modal_terms(t, c, s, u[0], params, tip_motion=(held[0], held[1]))
        xdot = ca.vertcat(terms.c_dot, terms.s_dot)
        y = ca.vertcat(*[terms.outputs[v.name] for v in model.outputs])
        motion = ca.vertcat(ca.sum1(c * terms.cos + s * terms.sin),
                            ca.sum1(terms.omega * (s * terms.cos - c * terms.sin)))

        def d_dx(expr):
            return ca.jacobian(expr, x) + ca.mtimes(ca.jacobian(expr, held), ca.jacobian(motion, x))

        unknowns = ca.vertcat(xdot, y)
        results = [xdot, y, ca.densify(d_dx(xdot)),
                   ca.densify(ca.horzcat(d_dx(unknowns), ca.jacobian(unknowns, u)))]
        results = ca.substitute(results, [held], [motion])
        args, names = [t, x, q, u, p], ["t", "x", "q", "u", "p"]
        functions = {key: ca.Function(f"mf_{key}", args, [result], names, [label])
                     for key, result, label in zip(("ode", "out", "jac", "dd"), results,
                                                   ("xdot", "y", "jac", "dd"))}
        c_new, s_new = self._to_frame_of_zero(q[0], c, s, terms)
        functions["jump"] = ca.Function("mf_jump", args, [ca.vertcat(c_new, s_new), ca.MX(1.0)],
                                        names, ["x_new", "q_new"])
        return functions

    def _assumed_equations(self, e):
        p, b, tip = e.p, self.basis(), e.port("tip")
        a = ca.vertcat(*[getattr(e.x, n) for n in b.names])
        a_dot = ca.vertcat(*[getattr(e.x, f"{n}_dot") for n in b.names])
        a_ddot = ca.vertcat(*[getattr(e.der, f"{n}_dot") for n in b.names])
        phi, g = ca.DM(b.tip_value), ca.DM(b.tip_per_mass)
        omega0_sq = p.EI / (p.m * p.L**3)  # the frequency scale: ω = λ² sqrt(EI / (m L³))
        for n in b.names:
            e.residual(getattr(e.der, n) - getattr(e.x, f"{n}_dot"))
        # M a'' + (alpha M + beta K + zeta C_modal) a' + K a = φ f, premultiplied by M⁻¹ so
        # that the matrices are numbers (see components.bodies.beam_shapes); K acts on a + beta a'
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
