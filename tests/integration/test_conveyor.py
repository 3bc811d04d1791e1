"""Seed 9.6 ex. 2 (the conveyor): the exact periodic Coulomb motion, checked on its own
against a brute-force integration and the seed's median rule, then reproduced by every
fmpy-driven mode, friction event by friction event."""
import math

import numpy as np
import pytest

from assemblies.masters import cosimulate, simulate_me, simulate_monolithic
from assemblies.scenes import scene
from assemblies.scenes.table import (CONVEYOR, CONVEYOR_ACCURACY, MU, OMEGA, PERIOD, U, G,
                                     CoulombOnTable, HarmonicTable, conveyor_median_velocity,
                                     table_periodic_speed)

EXACT = table_periodic_speed(U, OMEGA, CONVEYOR, MU, MU, G)


def _table_velocity(t):
    return U * OMEGA * sum(k * c * math.cos(k * OMEGA * t) for k, c in enumerate(CONVEYOR, 1))


def _table_acceleration(t):
    return -U * OMEGA**2 * sum(k * k * c * math.sin(k * OMEGA * t)
                               for k, c in enumerate(CONVEYOR, 1))


def _brute_force_speed(v0, periods, steps_per_period):
    """Mean speed over the last period of a fixed-step integration of the same Coulomb
    law, sharing nothing with the exact solution's root finding: the block's velocity
    moves by -mu g sign(v_rel) dt while it slides; where v_rel changes sign within a step
    the crossing is placed by linear interpolation, and the block then sticks if the
    table's acceleration there is within mu g, else slides the other way for the rest
    of the step; a stick ends at the first step end where |a_table| > mu g."""
    dt = PERIOD / steps_per_period
    v, x = v0, 0.0
    v_rel = v - _table_velocity(0.0)
    mode = int(math.copysign(1, v_rel)) if v_rel else 0
    x_at = []
    for n in range(periods * steps_per_period):
        if n % steps_per_period == 0:
            x_at.append(x)
        t, t_new = n * dt, (n + 1) * dt
        vt_new = _table_velocity(t_new)
        if mode == 0:
            v_new = vt_new
            a = _table_acceleration(t_new)
            if abs(a) > MU * G:
                mode = -int(math.copysign(1, a))
            x += 0.5 * (v + v_new) * dt
        else:
            v_new = v - MU * G * mode * dt
            r0, r1 = v - _table_velocity(t), v_new - vt_new
            if mode * r1 > 0:
                x += 0.5 * (v + v_new) * dt
            else:  # met the table's velocity at t + theta dt
                theta = r0 / (r0 - r1)
                v_meet = v - MU * G * mode * theta * dt
                a = _table_acceleration(t + theta * dt)
                mode = 0 if abs(a) <= MU * G else -int(math.copysign(1, a))
                v_new = vt_new if mode == 0 else v_meet - MU * G * mode * (1 - theta) * dt
                x += 0.5 * (v + v_meet) * theta * dt + 0.5 * (v_meet + v_new) * (1 - theta) * dt
        v = v_new
    x_at.append(x)
    return (x_at[-1] - x_at[-2]) / PERIOD


def test_the_exact_motion_becomes_periodic():
    assert EXACT.periods < 80  # measured 49 at tol 1e-13
    block = CoulombOnTable(HarmonicTable(U, OMEGA, CONVEYOR), MU, MU, G)
    phase = block.start(0.0, EXACT.v_start)
    speeds = []
    for n in range(1, 6):  # from the periodic state: same state and speed every period
        phase, moved, begun = block.advance(phase, n * PERIOD)
        speeds.append(moved / PERIOD)
        assert abs(phase.v - EXACT.v_start) < 1e-12 and phase.mode == EXACT.mode_start
        assert [b.mode for b in begun] == [1, -1, 1, -1, 1, -1]
    np.testing.assert_allclose(speeds, EXACT.speed, rtol=0, atol=1e-12)


def test_the_exact_speed_against_independent_estimates():
    # the seed's median rule neglects the speed change within a cycle: close, not exact
    median = conveyor_median_velocity(U, OMEGA, CONVEYOR)
    assert abs(median - 1.069) < 1e-3 and abs(EXACT.speed - median) < 0.01 * median
    # a brute-force fixed-step integration converges to it (at least at second order:
    # measured 4e-6, 9e-8, 7e-10 for 1000, 4000, 16000 steps a period)
    errors = [abs(_brute_force_speed(EXACT.v_start, 3, n) - EXACT.speed)
              for n in (1000, 4000, 16000)]
    assert errors[2] < 1e-8 and errors[1] < errors[0] / 10 and errors[2] < errors[1] / 10, errors


def _conveyor_from(v_absolute, periods):
    """The conveyor scene started at the start of a table period with the block's
    absolute velocity `v_absolute` (the table is T-periodic, so this is any period)."""
    asm = scene("conveyor").build()
    asm.set("block.v", v_absolute - _table_velocity(0.0))
    return asm, periods * PERIOD


def _run(mode, asm, stop):
    sc = scene("conveyor")
    if mode == "cosim":  # first order in the communication step (see test_masters)
        return cosimulate(asm, stop, PERIOD / 256, 1e-10, record=sc.record)
    master = simulate_me if mode == "me" else simulate_monolithic
    return master(asm, stop, PERIOD / 16, 1e-9, record=sc.record)


def _mode_changes(res):
    ev = res.events["block"]
    changes, last = [], None
    for t, q in zip(ev["time"], ev["block.mode"]):
        if q != last:
            changes.append((float(t), int(q)))
            last = q
    return changes


@pytest.mark.parametrize("mode", ["me", "monolithic", "cosim"])
def test_every_mode_reproduces_the_exact_periodic_speed(mode):
    periods = 4
    asm, stop = _conveyor_from(EXACT.v_start, periods)
    res = _run(mode, asm, stop)
    t, s = res["time"], res["block.s"]
    speed = (s[-1] - s[0]) / t[-1]
    assert abs(speed - EXACT.speed) < CONVEYOR_ACCURACY, (speed, EXACT.speed)
    if mode != "cosim":  # solver-accurate: the tolerance, not the stated 1e-4
        assert abs(speed - EXACT.speed) < 1e-6, (speed, EXACT.speed)
    # every friction event of the periodic motion, the 4 ms slide included
    block = CoulombOnTable(HarmonicTable(U, OMEGA, CONVEYOR), MU, MU, G)
    _, _, phases = block.advance(block.start(0.0, EXACT.v_start), stop)
    found = _mode_changes(res)
    assert [q for _, q in found] == [p.mode for p in phases]
    late = PERIOD / 256 if mode == "cosim" else 1e-6
    np.testing.assert_allclose([t for t, _ in found], [p.t for p in phases], rtol=0, atol=late)


@pytest.mark.parametrize("mode", ["me", "monolithic"])
def test_the_transient_events_a_step_end_check_missed(mode):
    # from rest, the step-end check of the event driver missed the 0.05 ms stick at
    # t = 11.5919 (period 37) and settled 3 % slow; start at period 35 instead of 0
    block = CoulombOnTable(HarmonicTable(U, OMEGA, CONVEYOR), MU, MU, G)
    state, _, _ = block.advance(block.start(0.0, 0.0), 35 * PERIOD)
    _, _, phases = block.advance(state, 38 * PERIOD)
    assert any(p.mode == 0 for p in phases)  # the short sticks are in this window
    asm, stop = _conveyor_from(state.v, 3)
    found = _mode_changes(_run(mode, asm, stop))
    assert [q for _, q in found] == [p.mode for p in phases]
    np.testing.assert_allclose([t + 35 * PERIOD for t, _ in found], [p.t for p in phases],
                               rtol=0, atol=1e-6)
