"""The engine's time loops under long and absurd requests (issue 25): a long run in the
default mode is not refused for a step the horizon calls too short, and the guards are
budgets and progress checks, not limits that grow with the experiment's length."""
import math

import numpy as np

from assemblies.engine.cosim import DEFAULT_SCHEME, cosimulate
from assemblies.scenes import scene
from assemblies.scenes.references import stick_slip_first_cycle


def test_stick_slip_runs_1000_s_in_the_default_mode_and_keeps_its_cycle():
    """The adaptive co-simulation's shortest step was 1e-12 x the horizon: at 1000 s it
    refused the steps a slip onset needs ("adaptive step fell below 1e-09 s at t =
    44.3"). Its shortest step is now the time's resolution where it stands. The run is
    checked against seed 9.2's closed form: after each re-stick the spring must stretch
    back to the static limit, so the block slips every T = t2 + (mu_s m g / k - (v t2 -
    x2)) / v - t1 seconds, the first time at t1; every slip onset in 1000 s must fall on
    t1 + n T (to 1e-6 s: the members' tolerance 1e-10 summed over 100 cycles, with room)."""
    sc = scene("stick_slip")
    res = cosimulate(sc.build(), 1000.0, sc.step, sc.tolerance, record=["block.x"],
                     **DEFAULT_SCHEME)
    assert res["time"][-1] == 1000.0
    m, k, g, mu_k, mu_s, v = 1.0, 1.0, 1.0, 0.3, 0.4, 0.05  # the scene's, as built
    t1, t2, x2 = stick_slip_first_cycle(m, k, g, mu_k, mu_s, v)
    period = t2 + (mu_s * m * g / k - (v * t2 - x2)) / v - t1
    ev = res.events["block"]
    slips = np.array([t for t, mode, before in zip(ev["time"], ev["block.mode"],
                                                   np.r_[0, ev["block.mode"][:-1]])
                      if mode == 1 and before == 0])
    expected = t1 + period * np.arange(len(slips))
    assert len(slips) == math.floor((1000.0 - t1) / period) + 1
    assert np.abs(slips - expected).max() < 1e-6
