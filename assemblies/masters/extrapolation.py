"""Input extrapolation for the co-simulation master, within what FMI 3 allows.

FMI 3 Co-Simulation has no input-derivative call (FMI 2's
``fmi2SetRealInputDerivatives``): an FMU holds an input constant over a step
unless it extrapolates it itself. Ours do so along a *derivative chain* of
inputs: a flange's ``s`` is extrapolated with ``v`` and ``a``, ``v`` with ``a``
(Taylor, quadratic and linear), and the end of each chain (a force ``f``, or a
motion's ``a``) with its *rate inputs* ``f_rate``, ``f_rate2``, ``f_rate3``
(``a_rate`` ...), which nothing couples and which stay 0 for an importer that
never sets them. Signals have no chain and stay constant over the step.

With extrapolation order p (at most 3) the master fits the polynomial of degree
p through a held input's last p + 1 values at communication points
(interpolating where Gauss–Seidel has already stepped the source). Where the
target takes the input's rates, the master sets the polynomial's value and
derivatives at the step's start (:func:`taylor`) and the FMU runs along the
polynomial itself: the input is O(h^(p+1)) off within the step, and the
coupling is of global order p + 1 (two_block_belt, fixed steps: 2.00, 2.99 and
4.00 with p = 1, 2, 3; tests/integration/test_rate_inputs.py). Elsewhere the
master holds the polynomial's *mean over the step*: the input's integral over
the step is then exact to O(h^(p+2)), but its double integral (the displacement
it causes) stays O(h^3), because a constant cannot carry a slope, and the
coupling is of order 2 for every p >= 1.
"""
from __future__ import annotations

from components.dae import flatten

ORDERS = (0, 1, 2, 3)
RATES = 3  # a chain end's rate inputs (components.dae): enough for the cubic of order 3


def step_mean(points: list[tuple[float, float]], t: float, h: float, order: int) -> float:
    """Mean over [t, t + h] of the polynomial through the last ``order + 1`` points.

    `points` are (time, value), oldest first, with distinct times; fewer points than
    ``order + 1`` lower the degree (the first steps of a run).
    """
    return float(sum(ck / (k + 1) for k, ck in enumerate(_fit(points, t, h, order))))


def taylor(points: list[tuple[float, float]], t: float, h: float, order: int) -> list[float]:
    """Value and first three derivatives at `t` of the polynomial through the last
    ``order + 1`` points (0 beyond its degree): what a target's rate inputs take, so
    that its Taylor chain runs along the polynomial over the step (cosim.c set_held)."""
    coef = _fit(points, t, h, order)
    out, scale = [float(coef[0])], 1.0
    for j in range(RATES):
        scale *= (j + 1) / h
        out.append(float(coef[j + 1] * scale) if j + 1 < len(coef) else 0.0)
    return out


def end_value(points: list[tuple[float, float]], h: float, order: int) -> float:
    """Where the polynomial through the last ``order + 1`` points puts the value a step
    of `h` after the last of them: what the extrapolation expected at the step's end,
    to compare with what the source returns there (the coupling defect)."""
    return float(sum(_fit(points, points[-1][0], h, order)))


def _fit(points, t, h, order) -> list[float]:
    """Coefficients, in units of the step from t, of the polynomial through the last
    ``order + 1`` points (at most 4): Newton's divided differences in absolute time,
    expanded about t by Horner's scheme and scaled by h^k, the same operations in the
    same order as the engine's fit_held (cosim.c), so that the two masters round alike
    (a solve of the Vandermonde system costs the engine a quarter of its time on
    two_block_belt; issue 27)."""
    pts = points[-(order + 1):]
    ts = [float(p[0]) for p in pts]
    coef = [float(p[1]) for p in pts]
    m = len(pts)
    for a in range(1, m):  # coef[b]: the divided difference over points b - a ... b
        for b in range(m - 1, a - 1, -1):
            coef[b] = (coef[b] - coef[b - 1]) / (ts[b] - ts[b - a])
    for a in range(m - 2, -1, -1):  # p = d[a] + (x - ts[a]) p, from the highest down
        for b in range(a, m - 1):
            coef[b] -= (ts[a] - t) * coef[b + 1]
    scale = 1.0
    for k in range(1, m):
        scale *= h
        coef[k] *= scale
    return coef


def derivative_inputs(component) -> dict[str, str]:
    """{input: its derivative input} of our component's FMU: the chains (s -> v -> a)
    along which the FMU extrapolates those inputs over a step itself."""
    inputs = flatten(component).inputs
    return {v.name: inputs[v.derivative_input].name for v in inputs
            if v.derivative_input is not None}


def rate_inputs(name: str, chained: dict, set_by_coupling) -> list[str]:
    """The chain below input `name` that no coupling sets (a force flange's f_rate and
    f_rate2): the master sets them from the polynomial it extrapolates `name` with.
    Empty where the chain is coupled (s -> v -> a) or there is none."""
    out, d = [], chained.get(name)
    while d is not None and d not in set_by_coupling and len(out) < RATES:
        out.append(d)
        d = chained.get(d)
    return out


def is_held(name: str, chained: dict, is_int: bool, set_by_coupling) -> bool:
    """Does the master choose how input `name` moves over a step? Not an integer, nor an
    input whose chain (`chained`: derivative_inputs) another coupling sets (s by v and
    a); the end of a chain is, through its rate inputs (:func:`rate_inputs`, the
    couplings' targets in `set_by_coupling`) where it has them, and an input with no
    chain through the constant it holds. (Setting a chain's end to the source's value at
    the step's start, the plain Taylor chain, was measured 15x as many steps on the
    short-slip fixture as holding its step mean.)"""
    if is_int:
        return False
    return name not in chained or bool(rate_inputs(name, chained, set_by_coupling))


def derivative_couplings(couplings, chained: dict) -> list[int]:
    """Per coupling, the index of the coupling that sets its target's derivative input
    (`chained`: instance -> :func:`derivative_inputs`), or -1: the master's view of the
    chains, to measure how far an FMU's extrapolated motion strays from its source's."""
    setting = {c.target: k for k, c in enumerate(couplings)}
    out = []
    for c in couplings:
        d = chained.get(c.target[0], {}).get(c.target[1])
        out.append(setting.get((c.target[0], d), -1) if d is not None else -1)
    return out


def chain_order(derivative: list[int], k: int) -> int:
    """1 + the length of coupling `k`'s chain below it (3 for s -> v -> a): the order in
    the step of how far the FMU's Taylor extrapolation of it strays."""
    order, d = 1, derivative[k]
    while d >= 0 and order <= len(derivative):
        order, d = order + 1, derivative[d]
    return order


__all__ = ["ORDERS", "chain_order", "is_held", "rate_inputs", "taylor", "derivative_couplings", "derivative_inputs",
           "end_value", "step_mean"]
