"""The references of the seed 9.2, 9.3 and 9.5 scenes (assemblies/scenes/friction_references.py)
against solutions computed here another way: scipy's solve_ivp on the equations of motion
with its own event location (a small hybrid integrator written in this file), and the
seed's printed numbers."""
import math

import numpy as np
import pytest
from scipy.integrate import solve_ivp

from assemblies.scenes.friction_references import (
    DrivenCoulombBlock, chain_first_slip, creep_speed, damped_stick_slip,
    half_period_turning_points, resonance_growth_rate, resonance_threshold, richardson_bound,
    slide_ends, sliding_perturbation, smooth_friction_coefficient, smooth_law_peak,
    smooth_slip_bracket, smooth_turning_allowance, steady_sliding_lag, two_halves_rear_slip)
from assemblies.scenes.references import stick_slip_first_cycle

RTOL = 1e-12


def hybrid(force, m, N, mu_s, mu_k, x0, v0, t_end):
    """m x'' = force(t, x, x') + friction, exact Coulomb, by solve_ivp phase by phase:
    slides until x' crosses zero, sticks until |force| reaches mu_s N. Returns the
    (t, x, mode after) at every phase change."""
    def at_rest_mode(t, x):
        f = force(t, x, 0.0)
        return 0 if abs(f) < mu_s * N else int(math.copysign(1, f))

    t, x, v = 0.0, x0, v0
    mode = int(math.copysign(1, v0)) if v0 else at_rest_mode(0.0, x0)
    changes = []
    while t < t_end:
        if mode == 0:
            def loose(tt, y, s):
                return mu_s * N - s * force(tt, y[0], 0.0)
            events = []
            for s in (1, -1):
                ev = (lambda s: lambda tt, y: loose(tt, y, s))(s)
                ev.terminal, ev.direction = True, -1
                events.append(ev)
            # x'' = 0 would let the solver step over a short stick: events are found
            # only as sign changes between steps, so the steps are kept short
            sol = solve_ivp(lambda tt, y: [0.0, 0.0], (t, t_end), [x, 0.0], events=events,
                            rtol=RTOL, atol=1e-14, method="DOP853", max_step=0.01)
            hits = [(e[0], s) for e, s in zip(sol.t_events, (1, -1)) if len(e)]
            if not hits:
                return changes
            t, mode = min(hits)
            changes.append((t, x, mode))
            continue
        s = mode

        def rhs(tt, y, s=s):
            return [y[1], (force(tt, y[0], y[1]) - s * mu_k * N) / m]

        def stops(tt, y):
            return y[1]
        stops.terminal, stops.direction = True, -s
        sol = solve_ivp(rhs, (t, t_end), [x, v], events=stops, rtol=RTOL, atol=1e-14,
                        method="DOP853", max_step=0.01)
        if not len(sol.t_events[0]):
            return changes
        t, x, v = sol.t_events[0][0], sol.y_events[0][0][0], 0.0
        mode = at_rest_mode(t, x)
        changes.append((t, x, mode))
    return changes


def driven(U, w, k=1.0):
    return lambda t, x, v: k * (U * math.sin(w * t) - x)


@pytest.mark.parametrize("case", [
    dict(U=1.0, w=1.0, mu_s=0.6, mu_k=0.6, x0=10.0, T=40.0),    # seed 9.5, Fig. 9.7
    dict(U=0.4, w=1.0, mu_s=0.6, mu_k=0.6, x0=10.0, T=40.0),    # seed 9.5, Fig. 9.6
    dict(U=1.5, w=0.7, mu_s=0.5, mu_k=0.3, x0=2.0, T=30.0),     # off resonance, mu_s > mu_k
], ids=["growth", "below", "off_resonance"])
def test_driven_block_events_match_a_hybrid_solve_ivp(case):
    block = DrivenCoulombBlock(1.0, 1.0, 1.0, case["mu_s"], case["mu_k"], case["U"], case["w"])
    phases = block.solve(case["x0"], 0.0, case["T"])
    ours = [(ph.t, ph.x, ph.mode) for ph in phases[1:]]
    theirs = hybrid(driven(case["U"], case["w"]), 1.0, 1.0, case["mu_s"], case["mu_k"],
                    case["x0"], 0.0, case["T"])
    assert len(ours) == len(theirs) >= 8
    for (t, x, mode), (t_ref, x_ref, mode_ref) in zip(ours, theirs):
        assert mode == mode_ref
        assert abs(t - t_ref) < 1e-8 and abs(x - x_ref) < 1e-8
    # the closed forms end each phase where the next begins
    ends = block.position(phases, [ph.t - 1e-12 for ph in phases[1:]])
    assert np.abs(ends - [ph.x for ph in phases[1:]]).max() < 1e-9


def test_driven_block_position_solves_its_ode_between_events():
    """x(t) from the closed forms satisfies m x'' = k (U sin t - x) -+ mu m g inside slides
    (second differences) and is continuous at every event."""
    block = DrivenCoulombBlock(1.0, 1.0, 1.0, 0.6, 0.6, 1.0, 1.0)
    phases = block.solve(10.0, 0.0, 30.0)
    for ph, nxt in zip(phases, phases[1:]):
        if ph.mode == 0 or nxt.t - ph.t < 0.1:
            continue
        t = np.linspace(ph.t + 0.02, nxt.t - 0.02, 7)
        h = 1e-4
        x = block.position(phases, np.concatenate([t - h, t, t + h])).reshape(3, -1)
        accel = (x[0] - 2 * x[1] + x[2]) / h**2
        expected = np.sin(t) - x[1] - ph.mode * 0.6
        assert np.abs(accel - expected).max() < 1e-5


def test_half_period_law_is_the_exact_solution_while_it_holds():
    for U, x0 in ((1.0, 10.0), (0.4, 10.0), (0.4, -10.0), (1.0, -10.0)):
        law = half_period_turning_points(1, 1, 1, 0.6, U, x0, 60.0)[1:]
        block = DrivenCoulombBlock(1, 1, 1, 0.6, 0.6, U, 1.0)
        turns = slide_ends(block.solve(x0, 0.0, 60.0))
        assert len(law) >= 3
        for (t, x), ph in zip(law, turns):
            assert abs(t - ph.t) < 1e-9 and abs(x - ph.x) < 1e-9
    # the seed's numbers: from x(0) = 10 the first half period takes U pi / 2 + 2 mu off
    assert half_period_turning_points(1, 1, 1, 0.6, 1.0, 10.0, 5.0)[1][1] == pytest.approx(
        -(10 - math.pi / 2 - 1.2), abs=1e-14)


def test_seed_resonance_numbers():
    # seed 9.5: (pi - 2.4) / 2 pi = 0.118 per unit time at U = 1; negative at U = 0.4
    assert resonance_growth_rate(1, 1, 1, 0.6, 1.0) == pytest.approx(0.118, abs=5e-4)
    assert resonance_growth_rate(1, 1, 1, 0.6, 0.4) < 0
    U_star = resonance_threshold(1, 1, 1, 0.6)
    assert resonance_growth_rate(1, 1, 1, 0.6, U_star) == pytest.approx(0.0, abs=1e-15)
    # in phase, the exact motion's |x| at turning points falls on that line exactly
    turns = slide_ends(DrivenCoulombBlock(1, 1, 1, 0.6, 0.6, 1.0, 1.0).solve(-3.0, 0.0, 40.0))
    slope = np.polyfit([ph.t for ph in turns], [abs(ph.x) for ph in turns], 1)[0]
    assert slope == pytest.approx(resonance_growth_rate(1, 1, 1, 0.6, 1.0), abs=1e-10)


def test_damped_stick_slip_against_hybrid_solve_ivp():
    m, k, g, mu_k, mu_s, v = 1.0, 1.0, 1.0, 0.3, 0.4, 0.05
    # d = 0: the seed's closed form and printed numbers
    cycle = damped_stick_slip(m, k, 0.0, g, mu_k, mu_s, v)
    t1, t2, x2 = stick_slip_first_cycle(m, k, g, mu_k, mu_s, v)
    assert (cycle.t1, cycle.t2, cycle.x2) == pytest.approx((t1, t2, x2), abs=1e-12)
    assert cycle.t2 == pytest.approx(12.0689, abs=5e-5)
    assert cycle.x2 == pytest.approx(0.40344, abs=5e-6)
    for d in (0.05, 0.2):
        cycle = damped_stick_slip(m, k, d, g, mu_k, mu_s, v)
        changes = hybrid(lambda t, x, xd: k * (v * t - x) + d * (v - xd), m, m * g, mu_s, mu_k,
                         0.0, 0.0, cycle.t1 + 2.5 * cycle.period)
        slips = [t for t, _, mode in changes if mode == 1]
        sticks = [(t, x) for t, x, mode in changes if mode == 0]
        assert slips[0] == pytest.approx(cycle.t1, abs=1e-8)
        assert sticks[0][0] == pytest.approx(cycle.t2, abs=1e-8)
        assert sticks[0][1] == pytest.approx(cycle.x2, abs=1e-9)
        assert slips[1] - slips[0] == pytest.approx(cycle.period, abs=1e-8)
        assert slips[2] - slips[1] == pytest.approx(cycle.period, abs=1e-8)
    # a lot of damping: the first slide never stops, the hybrid run agrees
    with pytest.raises(ValueError, match="does not persist"):
        damped_stick_slip(m, k, 0.5, g, mu_k, mu_s, v)
    changes = hybrid(lambda t, x, xd: k * (v * t - x) + 0.5 * (v - xd), m, m * g, mu_s, mu_k,
                     0.0, 0.0, 60.0)
    assert [mode for _, _, mode in changes] == [1]


def test_sliding_perturbation_solves_the_damped_oscillator():
    m, k, d, eta0, deta0 = 2.0, 3.0, 0.7, 0.03, -0.01
    t = np.linspace(0, 20, 41)
    sol = solve_ivp(lambda tt, y: [y[1], -(k * y[0] + d * y[1]) / m], (0, 20), [eta0, deta0],
                    t_eval=t, rtol=1e-12, atol=1e-15, method="DOP853")
    eta, deta = sliding_perturbation(t, m, k, d, eta0, deta0)
    assert np.abs(eta - sol.y[0]).max() < 1e-11 and np.abs(deta - sol.y[1]).max() < 1e-11
    assert steady_sliding_lag(2.0, 4.0, 9.81, 0.3) == pytest.approx(0.3 * 2 * 9.81 / 4)


def test_smooth_law_peak_and_slip_bounds():
    u_star, mu_max = smooth_law_peak(0.3, 0.4)
    # a maximum: the law's slope vanishes there and it is lower on both sides
    du = 1e-6
    slope = (smooth_friction_coefficient(u_star + du, 0.3, 0.4)
             - smooth_friction_coefficient(u_star - du, 0.3, 0.4)) / (2 * du)
    assert abs(slope) < 1e-7
    grid = np.linspace(0, 50, 500_001)
    assert smooth_friction_coefficient(grid, 0.3, 0.4).max() <= mu_max + 1e-15
    # "very close to 0.4" (seed 9.2), below it
    assert 0.398 < mu_max < 0.4
    # the onset of gross slip of Eq. 9.6 (solve_ivp, stiff) lies within the bounds
    for eps in (1e-3, 1e-4):
        def rhs(t, y):
            friction = float(smooth_friction_coefficient(y[1] / eps, 0.3, 0.4))
            return [y[1], (0.05 * t - y[0]) - friction]

        def onset(t, y):
            return y[1] - u_star * eps
        onset.terminal, onset.direction = True, 1
        sol = solve_ivp(rhs, (0, 12), [0.0, 0.0], method="Radau", events=onset, rtol=1e-10,
                        atol=1e-13)
        lo, hi = smooth_slip_bracket(1, 1, 1, 0.3, 0.4, 0.05, eps)
        assert lo <= sol.t_events[0][0] <= hi
        assert lo == pytest.approx(mu_max / 0.05)


def test_richardson_bound_is_an_upper_bound_for_one_signed_errors():
    # e(h) = 2 h^(2/3) + 5 h: terms of one sign, orders >= 2/3
    def e(h):
        return 2 * h ** (2 / 3) + 5 * h
    for h in (1e-2, 1e-3):
        bound = richardson_bound(1.0 + e(h), 1.0 + e(h / 10), 10, 2 / 3)
        assert e(h) <= bound <= 1.5 * e(h)


def test_chain_first_slip():
    # n = 1 is the rigid block of seed 9.2: t1 = mu_s m g / (k v) = 8
    assert chain_first_slip(1, 1, 1, 1, 0.4, 0.05) == pytest.approx(8.0)
    assert [chain_first_slip(n, 1, 1, 1, 0.4, 0.05) for n in (2, 4)] == pytest.approx([4.0, 2.0])


def test_two_halves_rear_slip_staircase():
    # the seed's mu: the second step of 2 (mu_s - mu_k) m g / 2 reaches mu_s m g / 2: t = 6
    assert two_halves_rear_slip(1, 1, 1, 0.3, 0.4, 0.05) == pytest.approx(6.0)
    # mu_k = 0.25: steps of 0.15, the second passes 0.2 at the pull 0.35: t = 7
    assert two_halves_rear_slip(1, 1, 1, 0.25, 0.4, 0.05) == pytest.approx(7.0)
    # mu_k = 0.1: the first step already reaches it: the rear slips with the front
    assert two_halves_rear_slip(1, 1, 1, 0.1, 0.4, 0.05) == pytest.approx(4.0)
    with pytest.raises(ValueError, match="mu_s > mu_k"):
        two_halves_rear_slip(1, 1, 1, 0.4, 0.4, 0.05)


def _tanh_turning_points(eps, x0=6.55, mu=0.6, t_end=16.0):
    def rhs(t, y):
        return [y[1], -y[0] - mu * math.tanh(3 * y[1] / eps)]

    def rest(t, y):
        return y[1]
    sol = solve_ivp(rhs, (0.0, t_end), [x0, 0.0], method="DOP853", events=rest,
                    rtol=RTOL, atol=1e-14)
    return [(0.0, x0)] + [(t, y[0]) for t, y in zip(sol.t_events[0], sol.y_events[0])
                          if t > 1e-9]


@pytest.mark.parametrize("eps", [1e-3, 1e-2])
def test_smooth_turning_allowance_covers_the_laws_difference_from_coulomb(eps):
    """Seed 9.4 under Eq. 9.7 (solve_ivp here) against exact Coulomb: every turning
    point lies within the allowance, which is of first order in eps for times and second
    for positions (the law differs from Coulomb only within a few eps of rest)."""
    coulomb = [(n * math.pi, (-1) ** n * (6.55 - 1.2 * n)) for n in range(6)]
    smooth = _tanh_turning_points(eps)
    allowance = smooth_turning_allowance("tanh", 1, 1, 1, 0.6, 0.6, eps,
                                         [x for _, x in coulomb])
    assert len(smooth) >= 6
    for (t, x), (t_c, x_c), (dt, dx) in zip(smooth, coulomb, allowance):
        assert abs(t - t_c) <= dt + 1e-9 and abs(x - x_c) <= dx + 1e-10, (t, t_c, dt)
    # the law's difference is real: at the last turn it is over a tenth of the allowance
    assert abs(smooth[5][0] - coulomb[5][0]) > 0.1 * allowance[5][0]
    finer = smooth_turning_allowance("tanh", 1, 1, 1, 0.6, 0.6, eps / 10,
                                     [x for _, x in coulomb])
    assert finer[3][0] == pytest.approx(allowance[3][0] / 10, rel=0.02)
    assert finer[3][1] == pytest.approx(allowance[3][1] / 100, rel=0.02)


def test_smooth_turning_allowance_is_inf_where_the_law_holds_the_block():
    """Eq. 9.5 with mu_s = 0.9 peaks near 0.9 > k |A| / m g = 0.8 for A = 0.8: the block
    would not leave rest there as Coulomb's (mu_k = 0.6) does."""
    allowance = smooth_turning_allowance("smooth", 1, 1, 1, 0.6, 0.9, 1e-3, [2.0, -0.8, 0.5])
    assert math.isfinite(allowance[1][0]) and allowance[2] == (math.inf, math.inf)


def test_creep_speed_balances_the_spring():
    # Eq. 9.7: mu_k tanh(3 v / eps) m g = F in closed form
    assert creep_speed("tanh", 1, 1, 0.6, 0.6, 1e-3, 0.55) == pytest.approx(
        1e-3 / 3 * math.atanh(0.55 / 0.6), rel=1e-12)
    assert creep_speed("tanh", 1, 1, 0.6, 0.6, 1e-3, 0.7) == math.inf
    # Eq. 9.5: the least speed where the law reaches the force, below its peak
    v = creep_speed("smooth", 1, 1, 0.3, 0.4, 1e-3, 0.35)
    u = np.linspace(0, v / 1e-3, 1000)
    assert smooth_friction_coefficient(v / 1e-3, 0.3, 0.4) == pytest.approx(0.35, rel=1e-12)
    assert (smooth_friction_coefficient(u[:-1], 0.3, 0.4) < 0.35).all()
