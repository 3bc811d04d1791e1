"""The event-driven fault solver (issue 30) against closed forms, an independent scipy
integration and conservation laws; and its work proportional to motion."""
import math

import numpy as np
import pytest

from assemblies.engine.fault import FaultError, carlson_langer, run_fault, thresholds
from assemblies.scenes.fault_references import scipy_slides
from assemblies.scenes.references import stick_slip_first_cycle

# seed 9.2: m = k = g = 1, mu_k = 0.3, mu_s = 0.4, v = 0.05 is the lone block with
# F_s = mu_s m g, sigma = 1 - mu_k / mu_s and no weakening
SEED = dict(m=1.0, kp=1.0, kc=0.0, V=0.05, sigma=0.25, alpha=0.0, vw=1.0)
CHAIN2 = dict(m=1.0, kp=1.0, kc=4.0, V=0.05, sigma=0.1, alpha=2.5, vw=1.0)


def test_one_block_is_the_seeds_stick_slip_closed_form():
    tol = 1e-10
    run = run_fault([0.4], **SEED, tol=tol, stop_time=40.0)
    t1, t2, x2 = stick_slip_first_cycle(1, 1, 1, 0.3, 0.4, 0.05)
    first = run.catalogue[0]
    assert first["start"] == pytest.approx(t1, abs=100 * tol * t1)
    assert first["end"] == pytest.approx(t2, abs=100 * tol * t2)
    assert first["moment"] == pytest.approx(x2, abs=100 * tol)  # from x = 0
    # every later cycle repeats it: the block re-sticks at the same force each time, so
    # it reloads by the same amount and slides the same distance
    starts = run.catalogue["start"]
    assert run.catalogue.size >= 4
    assert np.allclose(np.diff(starts), np.diff(starts)[0], atol=1e-7)
    assert np.allclose(run.catalogue["moment"], x2, atol=1e-8)


def test_two_blocks_follow_an_independent_scipy_integration():
    """Slides of a 2-block chain ending before t = 75 (before the chain's chaos
    amplifies the solvers' errors) against solve_ivp at 100x tighter tolerance."""
    tol, stop = 1e-10, 75.0
    F = thresholds(2, 1.0, 0.1, 3)
    run = run_fault(F, **CHAIN2, tol=tol, stop_time=stop)
    ref, x_ref = scipy_slides(F, **CHAIN2, stop_time=stop, rtol=tol / 100, atol=tol / 1e4)
    got = sorted(((int(s["block"]), s["t0"], s["t1"], s["slip"]) for s in run.slides),
                 key=lambda s: s[2])
    assert len(got) == len(ref) >= 8
    bound = 100 * tol * stop
    for (b, t0, t1, slip), (rb, rt0, rt1, rslip) in zip(got, ref):
        assert b == rb
        assert abs(t0 - rt0) < bound and abs(t1 - rt1) < bound and abs(slip - rslip) < bound


def test_energy_balance_and_slip_conservation_over_a_long_run():
    tol = 1e-8
    n = 60
    F = thresholds(n, 1.0, 0.01, 2)
    x0 = np.zeros(n)
    run = run_fault(F, **carlson_langer(), tol=tol, max_events=3000, x0=x0)
    t = run.totals
    assert run.settings["status"] == "max_events reached"  # ends with every block stuck
    # plate work = friction dissipation + stored energy change (1e4 tol per unit: DRIFT)
    assert abs(run.energy_residual) < 1e4 * tol * t["plate_work"]
    # every slide belongs to one event: the moments add up to the blocks' displacement
    assert run.totals["slips_dropped"] == 0
    total = float(np.sum(run.x - x0))
    assert run.catalogue["moment"].sum() == pytest.approx(total, rel=1e-9)
    assert run.slides["slip"].sum() == pytest.approx(total, rel=1e-9)
    assert run.catalogue["energy"].sum() == pytest.approx(t["dissipated"], rel=1e-9)
    assert np.all(run.catalogue["energy"] > 0) and np.all(run.catalogue["blocks"] >= 1)


def test_the_first_break_away_is_computed_not_searched():
    """From rest, each block's force is kp V t: the weakest goes at min F / (kp V),
    exactly (to rounding), whatever the chain's size (the others are made far stronger,
    so that its event ends before any of theirs starts)."""
    for n in (1, 7, 5000):
        F = thresholds(n, 1.0, 0.2, 11)
        F = np.where(F == F.min(), F, F + 1.0)
        run = run_fault(F, **carlson_langer(ell=1.0, nu=0.003), tol=1e-8, max_events=1)
        first = run.catalogue[0]
        assert first["start"] == pytest.approx(F.min() / 0.003, rel=1e-14)
        assert first["first"] == int(np.argmin(F))


def test_stuck_blocks_cost_nothing():
    """One weak block among strong ones, weakly coupled: its event is the same whatever
    the length of the chain, and so is the work (block evaluations) it takes; a solver
    that integrated every block would do n times more."""
    work = {}
    for n in (11, 10001):
        F = np.full(n, 2.0)
        F[n // 2] = 1.0
        run = run_fault(F, **carlson_langer(ell=1.0), tol=1e-8, max_events=1)
        assert run.catalogue.size == 1 and run.catalogue[0]["blocks"] == 1
        work[n] = run.totals["block_rhs"]
        others = np.delete(run.slept, n // 2)  # stuck the whole run: no work at all
        assert np.all(others == run.totals["time"])
    assert work[11] == work[10001]


@pytest.mark.parametrize("kwargs, words", [
    (dict(F=[1.0, -1.0], stop_time=1.0), "thresholds F"),
    (dict(F=[1.0], sigma=1.0, stop_time=1.0), "sigma"),
    (dict(F=[1.0], tol=0.0, stop_time=1.0), "tol"),
    (dict(F=[1.0]), "stop_time or max_events"),
    (dict(F=[1.0], max_events=0), "max_events"),
    (dict(F=[1.0, 1.0], x0=[0.0], stop_time=1.0), "x0"),
])
def test_bad_input_is_one_line(kwargs, words):
    F = kwargs.pop("F")
    with pytest.raises(FaultError) as err:
        run_fault(F, **kwargs)
    assert words in str(err.value) and "\n" not in str(err.value)


def test_thresholds_refuse_what_they_cannot_make():
    with pytest.raises(FaultError, match="heterogeneity"):
        thresholds(3, 1.0, 1.5)
    with pytest.raises(FaultError, match="n"):
        thresholds(0)
    assert np.all(thresholds(5, 2.0) == 2.0)


def test_b_estimate_recovers_a_known_power_law():
    from assemblies.scenes.burridge_knopoff import gutenberg_richter_b
    rng = np.random.default_rng(5)
    b, lo, hi = 1.0, 1e-3, 1.0
    r = hi / lo
    u = rng.uniform(size=20000)  # inverse CDF of the truncated Pareto density
    m = lo * (1 - u * (1 - r**-b)) ** (-1 / b)
    est, err, used = gutenberg_richter_b(m, lo, hi)
    assert used == m.size
    assert abs(est - b) < 3 * err and err < 0.02
    assert math.isnan(gutenberg_richter_b(m[:5], lo, hi)[0])
    # a stretch with more large than small events: a negative b, not an exception
    rising = hi * (lo / hi) ** rng.uniform(size=200) ** 3
    assert gutenberg_richter_b(rising, lo, hi)[0] < 0


def test_blocks_past_their_thresholds_at_the_start_slide_as_one_event():
    """A block displaced 0.3 in a stiff chain pushes both neighbours past their
    thresholds at t = 0: one event of three blocks, whose moment is their displacement."""
    x0 = np.array([0.0, 0.3, 0.0])
    run = run_fault([1.0, 1.0, 1.0], **carlson_langer(), tol=1e-8, max_events=1, x0=x0)
    first = run.catalogue[0]
    assert first["start"] == 0.0 and first["blocks"] == 3
    assert first["moment"] == pytest.approx(float(np.sum(run.x - x0)), rel=1e-9)


@pytest.mark.parametrize("seed", range(4))
def test_groups_on_their_own_clocks_follow_scipy(seed):
    """An 8-block chain, weakly coupled, where slides far apart overlap in time (each
    group of sliding blocks steps on its own clock; groups meet and are joined as blocks
    between them break away): every slide against solve_ivp at 100x tighter tolerance."""
    tol, stop = 1e-10, 60.0
    par = dict(CHAIN2, kc=1.0)
    F = thresholds(8, 1.0, 0.05, seed)
    run = run_fault(F, **par, tol=tol, stop_time=stop)
    ref, _ = scipy_slides(F, **par, stop_time=stop, rtol=tol / 100, atol=tol / 1e4)
    got = sorted(((int(s["block"]), s["t0"], s["t1"]) for s in run.slides), key=lambda s: s[2])
    assert len(got) == len(ref) >= 10
    for (b, t0, t1), (rb, rt0, rt1, _) in zip(got, ref):
        assert b == rb
        assert abs(t0 - rt0) < 100 * tol * stop and abs(t1 - rt1) < 100 * tol * stop
    # at least two groups at once: slides three or more blocks apart overlapping in time
    apart = [(a, c) for a in got for c in got
             if abs(a[0] - c[0]) >= 3 and a[1] < c[2] and c[1] < a[2]]
    assert apart


@pytest.mark.parametrize("backward", [True, False])
def test_backward_slides_as_asked_follow_scipy(backward):
    """A block displaced ahead of its neighbours is pushed back past its threshold: with
    friction both ways it slides backward; in Carlson & Langer's model (backward=False)
    it stays stuck. Either way every slide against solve_ivp written the same way."""
    tol, stop = 1e-10, 40.0
    F, x0 = np.array([1.0, 1.1, 0.9]), np.array([0.0, 1.5, 0.0])
    run = run_fault(F, **CHAIN2, tol=tol, stop_time=stop, x0=x0, backward=backward)
    ref, _ = scipy_slides(F, **CHAIN2, stop_time=stop, x0=x0, rtol=tol / 100,
                          atol=tol / 1e4, backward=backward)
    got = sorted(((int(s["block"]), s["t0"], s["t1"], s["slip"]) for s in run.slides),
                 key=lambda s: s[2])
    assert len(got) == len(ref) >= 3
    for (b, t0, t1, slip), (rb, rt0, rt1, rslip) in zip(got, ref):
        assert b == rb and abs(t1 - rt1) < 100 * tol * stop and abs(slip - rslip) < 1e-6
    assert np.any(run.slides["slip"] < 0) == backward
