"""Assumed modes of a cantilever (seed 7.5) and their dimensionless mass and stiffness matrices.

Everything here is in the coordinate ξ = x / L of a beam clamped at ξ = 0, with
w(x, t) = Σ a_i(t) φ_i(ξ). With total mass m and flexural rigidity EI the beam's
matrices are ``M = m M̂`` and ``K = EI / L³ K̂`` where

    M̂_ij = ∫₀¹ φ_i φ_j dξ,      K̂_ij = ∫₀¹ φ_i'' φ_j'' dξ      (' = d/dξ).

The integrands are products of polynomials of degree ≤ 2 and sines of frequency ≤ Nπ,
so Gauss–Legendre quadrature with enough points is exact to round-off; the rule used
is checked against one with twice as many points in the tests.

The equations of motion are written premultiplied by M̂⁻¹ (``a'' + M̂⁻¹(...) = 0``), so
the products M̂⁻¹K̂, M̂⁻¹Ĉ and M̂⁻¹φ(1) are kept here as numbers: left to the symbolic
solve, M̂⁻¹ times a parameter-scaled K̂ costs O(n³) operations in the generated Jacobian
(160 000 for 33 coordinates, a minute of gcc) instead of O(n²).
"""
from __future__ import annotations

import functools
from dataclasses import dataclass

from ..lazy import lazy

np = lazy("numpy")  # loaded by the first array: listing the components needs none

BASES = ("poly2", "sine")


@dataclass(frozen=True)
class ShapeBasis:
    """A set of assumed modes and what the beam's equations need from them."""
    kind: str
    names: tuple[str, ...]    # generalised coordinates, named as in the seed (a1, a2 / a0..aN)
    mass: np.ndarray          # M̂
    stiffness: np.ndarray     # K̂
    tip_value: np.ndarray     # φ_i(1): w(L) = tip_value · a
    tip_slope: np.ndarray     # φ_i'(1): w_x(L) = tip_slope · a / L
    modal_damping: np.ndarray  # Ĉ = M̂ Φ̂ Ω̂ Φ̂ᵀ M̂ of the bare cantilever, see _modal_damping
    stiffness_per_mass: np.ndarray      # M̂⁻¹ K̂
    modal_damping_per_mass: np.ndarray  # M̂⁻¹ Ĉ
    tip_per_mass: np.ndarray            # M̂⁻¹ φ(1)

    @property
    def size(self) -> int:
        return len(self.names)


def _poly2(xi):
    """The seed's x²/L², x³/L³: values, first and second ξ-derivatives."""
    return (np.vstack([xi**2, xi**3]), np.vstack([2 * xi, 3 * xi**2]),
            np.vstack([2 + 0 * xi, 6 * xi]))


def _sine(n_modes):
    """Seed Eq. 7.8: ξ² and ξ sin(kπξ), k = 1..N — N + 1 functions."""
    k = np.arange(1, n_modes + 1)[:, None] * np.pi

    def shapes(xi):
        s, c = np.sin(k * xi), np.cos(k * xi)
        return (np.vstack([xi**2, xi * s]), np.vstack([2 * xi, s + k * xi * c]),
                np.vstack([2 + 0 * xi, 2 * k * c - k**2 * xi * s]))
    return shapes


def quadrature_points(kind: str, n_modes: int) -> int:
    """Gauss–Legendre points that integrate products of two modes to round-off.

    poly2's integrands are polynomials of degree ≤ 6: 4 points integrate them exactly.
    An integrand oscillates at most like cos(2Nπξ), i.e. N periods on [0, 1]; an n-point
    rule is exact for polynomials of degree 2n - 1, which resolves such a wave to
    round-off once n is comfortably above 2N. 2N + 64 is past the point where doubling
    the rule changes nothing (below 1e-14 relative, checked in the tests).
    """
    return 4 if kind == "poly2" else 2 * n_modes + 64


def basis_names(kind: str, n_modes: int) -> tuple[str, ...]:
    """The generalised coordinates of a basis, named as in the seed, without computing it
    (a class declaration needs them, and the basis takes scipy)."""
    if kind == "poly2":
        return ("a1", "a2")
    if kind == "sine":
        return tuple(f"a{i}" for i in range(n_modes + 1))
    raise ValueError(f"basis must be one of {', '.join(BASES)}, not {kind!r}")


@functools.lru_cache(maxsize=None)
def shape_basis(kind: str, n_modes: int) -> ShapeBasis:
    """The basis ``poly2`` (n_modes ignored) or ``sine`` with N = n_modes (N + 1 coordinates)."""
    names = basis_names(kind, n_modes)
    if kind == "poly2":
        shapes = _poly2
        tip_value, tip_slope = np.array([1.0, 1.0]), np.array([2.0, 3.0])
    elif kind == "sine":
        shapes = _sine(n_modes)
        k = np.arange(1, n_modes + 1)
        # exact at ξ = 1 (sin kπ = 0, cos kπ = (-1)^k) rather than sin(kπ) ≈ 1e-16
        tip_value = np.concatenate([[1.0], np.zeros(n_modes)])
        tip_slope = np.concatenate([[2.0], k * np.pi * (-1.0) ** k])
    xi, weights = np.polynomial.legendre.leggauss(quadrature_points(kind, n_modes))
    xi, weights = (xi + 1) / 2, weights / 2  # from [-1, 1] to [0, 1]
    phi, _, phi_xx = shapes(xi)
    mass = (phi * weights) @ phi.T
    stiffness = (phi_xx * weights) @ phi_xx.T
    mass, stiffness = (mass + mass.T) / 2, (stiffness + stiffness.T) / 2
    damping = _modal_damping(mass, stiffness)
    arrays = (mass, stiffness, tip_value, tip_slope, damping, np.linalg.solve(mass, stiffness),
              np.linalg.solve(mass, damping), np.linalg.solve(mass, tip_value))
    for array in arrays:
        array.setflags(write=False)  # cached and shared: nobody may change them
    return ShapeBasis(kind, names, *arrays)


def _modal_damping(mass: np.ndarray, stiffness: np.ndarray) -> np.ndarray:
    """Ĉ with Φ̂ᵀ Ĉ Φ̂ = diag(ω̂_i) for the modes of the bare cantilever (no tip spring).

    Φ̂ are the M̂-normalised eigenvectors of K̂ Φ̂ = M̂ Φ̂ Ω̂², so Ĉ = M̂ Φ̂ Ω̂ Φ̂ᵀ M̂.
    Scaled by 2 ζ sqrt(m EI / L³) it damps every mode of the bare beam with ratio ζ.
    """
    from scipy.linalg import eigh  # here: scipy takes 0.1-0.3 s to load, a run of FMUs none
    eigenvalues, modes = eigh(stiffness, mass)
    projected = mass @ modes
    damping = (projected * np.sqrt(eigenvalues)) @ projected.T
    return (damping + damping.T) / 2


@dataclass(frozen=True)
class ModalBasis:
    """The bare cantilever's Ritz modes of a ShapeBasis, each scaled to unit tip deflection.

    With a = Φ η and Φ's columns scaled so that φ(1)·Φ_i = 1, the tip deflection is
    Σ η_i and the beam's equations decouple into one oscillator per mode:

        m η_i'' / gain_i + EI/L³ stiffness_i η_i / gain_i + ... = f_tip,

    i.e. η_i'' + ω_i² η_i = gain_i f_tip / m with ω_i² = stiffness_i EI / (m L³).
    ``gain_i`` = ψ_i² where ψ_i is the tip value of the M̂-normalised mode: the inverse
    modal mass per unit total mass. The static tip flexibility of mode i is
    gain_i / stiffness_i (in L³ / EI); they add up to the discretised model's.
    """
    stiffness: np.ndarray   # λ̂_i, ascending: ω_i = sqrt(λ̂_i EI / (m L³))
    gain: np.ndarray        # ψ_i²
    tip_slope: np.ndarray   # φ'(1)·Φ_i: w_x(L) = tip_slope · η / L
    to_modal: np.ndarray    # Φ⁻¹: η = to_modal @ a
    shapes: np.ndarray      # Φ: a = shapes @ η

    @property
    def size(self) -> int:
        return len(self.stiffness)

    def static_flexibility(self) -> np.ndarray:
        """Each mode's share of the static tip deflection under a tip force, in L³/EI."""
        return self.gain / self.stiffness


@functools.lru_cache(maxsize=None)
def modal_basis(kind: str, n_modes: int) -> ModalBasis:
    """Modes of K̂ u = λ̂ M̂ u for shape_basis(kind, n_modes), in their tip normalisation.

    The bare cantilever's (no tip spring): M̂ and K̂ do not depend on any parameter, so the
    modes are numbers computed once, and EI, L, m only scale the frequencies. Every mode of
    a cantilever moves its tip, so the tip normalisation never divides by zero (checked).
    """
    from scipy.linalg import eigh  # here: scipy takes 0.1-0.3 s to load, a run of FMUs none
    basis = shape_basis(kind, n_modes)
    eigenvalues, modes = eigh(basis.stiffness, basis.mass)  # modes.T @ M̂ @ modes = I
    tip = basis.tip_value @ modes
    if np.any(np.abs(tip) < 1e-9 * np.abs(tip).max()):
        raise ValueError(f"a Ritz mode of the {kind} basis (N = {n_modes}) leaves the tip at rest")
    shapes = modes / tip
    arrays = (eigenvalues, tip**2, basis.tip_slope @ shapes,
              (modes.T @ basis.mass) * tip[:, None], shapes)
    for array in arrays:
        array.setflags(write=False)
    return ModalBasis(*arrays)
