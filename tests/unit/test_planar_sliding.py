"""SlidingRod and SlidingDisk (seed 9.8): their equations against the seed's friction
integrals taken by adaptive quadrature at random states, the references' closed forms
against the same, and what they refuse."""
import math

import numpy as np
import pytest
from scipy.integrate import quad

from assemblies.scenes.sliding_references import (disk_friction, disk_rule_friction,
                                                   ring_integrals, rod_friction)
from components import ComponentError, SlidingDisk, SlidingRod, flatten


def _rates(component):
    model = flatten(component)
    f = model.functions()
    _, q, _, p = model.start_vectors()
    names = [v.name for v in model.states]

    def rates(**state):
        x = [state.get(n, 0.0) for n in names]
        return dict(zip(names, np.array(f["ode"](0.0, x, q, [], p)).ravel()))
    return rates


def _seed_rod_integrals(vx, vy, w, th, L, mu_N):
    """The seed's integrals of f(r) over the rod, term by term, by scipy's quad."""
    c, s = math.cos(th), math.sin(th)

    def part(r, i):
        ux, uy = vx - w * r * s, vy + w * r * c
        n = math.hypot(ux, uy)
        return (ux / n, uy / n, r * (c * uy - s * ux) / n)[i]
    return [-mu_N / L * quad(part, -L / 2, L / 2, args=(i,), epsabs=0, epsrel=1e-11,
                               limit=400)[0] for i in range(3)]


def _random_rod_states(n, seed=5):
    rng = np.random.default_rng(seed)
    for _ in range(n):
        yield (*rng.normal(size=2), abs(rng.normal()) + 0.1, rng.uniform(-math.pi, math.pi))


@pytest.mark.parametrize("state", list(_random_rod_states(6)))
def test_rod_follows_the_seeds_integrals(state):
    """Eqs. 9.14-9.15 and 9.16 (with A4's v_Gy^2 term + 6) against quadrature of the
    seed's own integrals: the closed forms hold to rounding."""
    vx, vy, w, th = state
    m, L, mu, g = 1.3, 0.8, 0.3, 9.81
    rates = _rates(SlidingRod(m=m, L=L, mu=mu, g=g))(v_x=vx, v_y=vy, omega=w, theta=th)
    Fx, Fy, M = _seed_rod_integrals(vx, vy, w, th, L, mu * m * g)
    assert rates["v_x"] == pytest.approx(Fx / m, rel=1e-9, abs=1e-12)
    assert rates["v_y"] == pytest.approx(Fy / m, rel=1e-9, abs=1e-12)
    assert rates["omega"] == pytest.approx(M / (m * L**2 / 12), rel=1e-9, abs=1e-12)
    # and the references' closed form of the same integrals
    ref = rod_friction(vx, vy, w, th, L, mu * m * g)
    assert ref[:3] == pytest.approx((Fx, Fy, M), rel=1e-10, abs=1e-13)


def test_eq_9_16_as_printed_misses_the_integral():
    """The seed prints (2 cos 2theta - 6) v_Gy^2 in A4: that differs from the integral by
    12 v_Gy^2 log(...) (zero when v_Gy = 0, which is why it only shows once the rod has
    turned), while + 6 matches. Written here from the printed equations."""
    m, L, mu, g = 1.0, 1.0, 0.3, 9.81
    vx, vy, w, th = 0.4, 0.7, 2.0, 0.3
    s, c = math.sin(th), math.cos(th)
    A1 = math.sqrt(w * w * L * L - 4 * vx * w * L * s + 4 * vy * w * L * c + 4 * vx**2 + 4 * vy**2)
    A2 = math.sqrt(w * w * L * L + 4 * vx * w * L * s - 4 * vy * w * L * c + 4 * vx**2 + 4 * vy**2)
    A3 = vy * c - vx * s
    log = math.log((2 * A3 + A2 - w * L) / (2 * A3 + A1 + w * L))

    def alpha(constant):
        A4 = (-((2 * math.cos(2 * th) + constant) * vy**2 - 8 * A3 * c * vy
                + (2 * math.cos(2 * th) + 2) * vx**2) * log
              + 2 * A3 * (A1 - A2) - w * L * (A1 + A2))
        return 3 * mu * g / (2 * w**2 * L**3) * A4
    M = _seed_rod_integrals(vx, vy, w, th, L, mu * m * g)[2]
    exact = M / (m * L**2 / 12)
    assert alpha(6.0) == pytest.approx(exact, rel=1e-10)
    assert abs(alpha(-6.0) - exact) > 0.1 * abs(exact)


def test_rod_at_a_nearly_lengthwise_standstill_has_no_nan():
    """Where the velocity along the rod is tiny, the printed log's argument cancels to 0
    in floating point; the model's identity keeps it finite and right."""
    m, L, mu, g = 1.0, 1.0, 0.3, 9.81
    th, w = 0.7, 0.6
    d, q0 = 1e-9, -0.15  # along-rod and across-rod velocity of G
    vx, vy = d * math.cos(th) - q0 * math.sin(th), d * math.sin(th) + q0 * math.cos(th)
    rates = _rates(SlidingRod(m=m, L=L, mu=mu, g=g))(v_x=vx, v_y=vy, omega=w, theta=th)
    ref = rod_friction(vx, vy, w, th, L, mu * m * g)
    assert all(math.isfinite(x) for x in rates.values())
    assert rates["omega"] == pytest.approx(ref[2] / (m * L**2 / 12), rel=1e-8)
    assert rates["v_x"] == pytest.approx(ref[0] / m, rel=1e-8)


@pytest.mark.parametrize("a, b", [(1.0, 0.3), (0.3, 1.0), (0.5, 2.0), (1.0, 1.0 + 1e-7)])
def test_ring_integrals_in_closed_form(a, b):
    def n(t):
        return math.sqrt(a * a + b * b - 2 * a * b * math.sin(t))
    drag = quad(lambda t: (a - b * math.sin(t)) / n(t), 0, 2 * math.pi, limit=400)[0]
    torque = quad(lambda t: (b - a * math.sin(t)) / n(t), 0, 2 * math.pi, limit=400)[0]
    assert ring_integrals(a, b) == pytest.approx((drag, torque), rel=1e-6)


@pytest.mark.parametrize("pressure", ["uniform", "parabolic"])
@pytest.mark.parametrize("v, w", [(1.0, 5.0), (0.5, 10.0), (0.0653, 1.0), (0.03, 1.0)])
def test_disk_rule_is_within_its_stated_error(pressure, v, w):
    """The model's rule (8 x 2 Gauss points in r, 12 in theta) against the ring integrals
    taken adaptively: geometric convergence with the centre outside the disk (v > w R),
    2e-4 with it inside; and the model evaluates that same rule."""
    R, mu_N = 0.1, 2.0
    exact = disk_friction(v, w, R, pressure, mu_N)
    rule = disk_rule_friction(v, w, R, pressure, mu_N)
    inside = v < w * R
    assert rule == pytest.approx(exact, rel=2e-4 if inside else 1e-7)
    rates = _rates(SlidingDisk(m=1.0, R=R, mu=mu_N / 9.81, g=9.81, pressure=pressure))(
        v_x=v * math.cos(0.4), v_y=v * math.sin(0.4), omega=w)
    assert math.hypot(rates["v_x"], rates["v_y"]) == pytest.approx(rule[0], rel=1e-12)
    assert rates["omega"] == pytest.approx(-rule[1] / (R * R / 2), rel=1e-12)
    # the force opposes v_G: an axisymmetric pressure never turns it
    assert math.atan2(-rates["v_y"], -rates["v_x"]) == pytest.approx(0.4, abs=1e-12)


@pytest.mark.parametrize("component, values, words", [
    (SlidingRod, {"omega": -1.0}, "omega > 0"),
    (SlidingRod, {"L": 0.0}, "L"),
    (SlidingDisk, {"pressure": "conical"}, "pressure"),
    (SlidingDisk, {"v_stop": 0.0}, "v_stop"),
])
def test_bad_values_are_refused_in_one_line(component, values, words):
    with pytest.raises(ComponentError, match=words) as caught:
        flatten(component(**values))
    assert "\n" not in str(caught.value)
