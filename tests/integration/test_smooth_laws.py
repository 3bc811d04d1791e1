"""stick_slip under the smooth friction laws (seed Eq. 9.5 and 9.7), the way a user asks
for them on the command line (``--param block.friction=smooth --param block.eps=1e-8``).

References, independent of the FMUs: the exact Coulomb first cycle (closed form), and for
the first slip the law's own rigorous bracket (friction_references.smooth_mode_slip_bracket:
bounds from the friction's supremum and the creep the mode allows). The runs must
- report the first slip inside that bracket (a proof, not a tolerance),
- pass every figure against exact Coulomb within what the law allows,
- switch mode once per slip and once per re-stick (the hysteresis between 3 eps and
  1.5 eps: no event followed at once by its reversal), and
- finish in a few thousand communication steps although eps = 1e-8 makes the law's
  slope 1e8 times the kinetic friction (the FMU's solver finds the stiffness by itself).
"""
import math

import numpy as np
import pytest

from assemblies.run import run_scene_full
from assemblies.scenes.friction_references import smooth_mode_slip_bracket

CASES = [("smooth", 1e-6), ("smooth", 1e-8), ("tanh", 1e-8)]


def _run(law, eps, **kw):
    return run_scene_full("stick_slip", params={"block.friction": law, "block.eps": eps}, **kw)


@pytest.mark.parametrize("law, eps", CASES)
def test_the_first_slip_lies_in_the_laws_own_bracket_and_every_figure_passes(law, eps):
    run = _run(law, eps)
    p = {**run.result.settings, "v": 0.05}
    lo, hi = smooth_mode_slip_bracket(law, 1.0, 1.0, 1.0, 0.3, 0.4, p["v"], eps)
    t1 = next(f for f in run.figures if f.name == "t1").measured
    assert lo <= t1 <= hi, (lo, t1, hi)
    assert all(f.passed for f in run.figures), [(f.name, f.measured, f.reference, f.accuracy)
                                               for f in run.figures]
    # the stiff law costs what exact Coulomb friction does, give or take (about 600
    # communication steps over 40 s; without the switch to the implicit method the
    # explicit one needs about 1e7 internal steps per simulated second)
    assert run.result.settings["steps"] < 2000


@pytest.mark.parametrize("law, eps", CASES)
def test_each_slip_and_stick_is_one_mode_change(law, eps):
    events = run_scene_full("stick_slip", stop_time=30.0,
                            params={"block.friction": law, "block.eps": eps}).result.events["block"]
    # from the start, stuck (mode 0), through every event the block's FMU located
    t = np.concatenate([[0.0], events["time"]])
    mode = np.concatenate([[0.0], events["block.mode"]])
    changes = t[1:][np.diff(mode) != 0]
    assert len(changes) >= 1
    assert np.all(np.diff(changes) > 0.1), changes  # no switch undone at once


def test_the_smooth_law_converges_to_coulomb_with_its_peak_as_mu_s():
    """As eps -> 0 Eq. 9.5 is Coulomb friction with mu_s replaced by its peak (0.39868):
    t2 approaches that closed form, not the seed's mu_s = 0.4 one."""
    from assemblies.scenes.friction_references import smooth_law_peak
    from assemblies.scenes.references import stick_slip_first_cycle
    limit = stick_slip_first_cycle(1.0, 1.0, 1.0, 0.3, smooth_law_peak(0.3, 0.4)[1], 0.05)
    errors = []
    for eps in (1e-5, 1e-7):
        t2 = next(f for f in _run("smooth", eps).figures if f.name == "t2").measured
        errors.append(abs(t2 - limit[1]))
    assert errors[1] < errors[0] / 5 and errors[1] < 1e-3, errors
    assert math.isfinite(errors[0])


@pytest.mark.parametrize("mode", ["me", "monolithic"])
def test_the_engine_integrates_the_stiff_law_with_exact_jacobians(mode):
    """In one integrator (me, monolithic) RODAS3's Jacobian comes from the FMUs'
    directional derivatives carried through the couplings. Forward differences with an
    increment of sqrt(eps) |v| step across the whole law (1e-8 wide) and took 6.5 million
    steps for the first 0.2 s, about an hour and a half for the scene. With the implicit
    method throughout, the first slip lies in the law's bracket and every figure passes."""
    run = run_scene_full("stick_slip", mode=mode, params={
        "block.friction": "smooth", "block.eps": 1e-8, "block.solver": 1})
    settings = run.result.settings
    assert settings["jacobian"] == "directional derivatives"
    assert settings["method"] == "RODAS3"
    lo, hi = smooth_mode_slip_bracket("smooth", 1.0, 1.0, 1.0, 0.3, 0.4, 0.05, 1e-8)
    t1 = next(f for f in run.figures if f.name == "t1").measured
    assert lo <= t1 <= hi, (lo, t1, hi)
    assert all(f.passed for f in run.figures), [(f.name, f.measured, f.reference, f.accuracy)
                                               for f in run.figures]
    # 9948 steps here; the bound guards against the failure this replaces (6.5 million
    # steps in the first 0.2 s), not against a few per cent more steps
    assert settings["steps"] < 50_000


@pytest.mark.parametrize("fmi_version", [2, 3])
def test_both_interfaces_offer_directional_derivatives(fmi_version):
    """FMI 3 spells the flag providesDirectionalDerivatives, which fmpy does not read:
    the engine reads it itself, or it would fall back to finite differences."""
    from assemblies.engine.prepare import prepared
    from components import SpringBlock
    fmu = prepared(SpringBlock(name="block"), fmi_version)
    assert fmu.me_directional_derivative and fmu.provides_directional_derivative


def test_the_engines_automatic_choice_sees_no_slip_in_the_stick_phase():
    """`mechfmu run stick_slip --mode me --param block.friction=smooth --param
    block.eps=1e-8`: the automatic choice runs the stick phase with RODAS3 in steps up
    to 0.9 s. Its former dense output, a Hermite cubic through the end slopes, turned an
    end point within the tolerance of the slow manifold (slope rho delta, rho ~ 3e7)
    into a bulge of h rho delta / 4 ~ 3e-4 past the 3 eps indicator: event pairs 4e-8 s
    apart from t = 0.45 on, and a first slip at 7.939. Without them an L-stable step
    jumped the law's peak instead (first slip 7.984) until RODAS3 refused steps that
    end where J loses most of its stiffness."""
    run = _run("smooth", 1e-8, mode="me")
    assert run.result.settings["method"] == "auto"
    lo, hi = smooth_mode_slip_bracket("smooth", 1.0, 1.0, 1.0, 0.3, 0.4, 0.05, 1e-8)
    t1 = next(f for f in run.figures if f.name == "t1").measured
    assert lo <= t1 <= hi, (lo, t1, hi)
    assert all(f.passed for f in run.figures), [(f.name, f.measured, f.reference, f.accuracy)
                                               for f in run.figures]
    # one event per slip and per re-stick over 40 s
    assert run.result.settings["events"] == 8


@pytest.mark.parametrize("mode", ["cosim", "me", "monolithic"])
def test_tanh_law_at_the_default_eps_dips_towards_rest_but_never_reaches_it(mode):
    """Eq. 9.7 at eps = 1e-3: after its first slip the block's slide touches rest as
    Coulomb's with mu_s = mu_k does, so it dips into |x'| < 1.5 eps (its mode turns 0)
    every cycle; but friction vanishes at rest while the spring pulls on, so x' never
    reaches 0. The figure follows each dip from its located event: no rest, every figure
    passes (counting mode changes reported 5 re-sticks and failed)."""
    run = run_scene_full("stick_slip", mode=mode, params={"block.friction": "tanh"})
    events = run.result.events["block"]
    t1 = next(f for f in run.figures if f.name == "t1").measured
    dips = [t for t, mode_ in zip(events["time"], events["block.mode"]) if t > t1 and mode_ == 0]
    assert len(dips) >= 3
    assert next(f for f in run.figures if f.name == "rests").measured == 0
    assert all(f.passed for f in run.figures), run.table()


def test_the_rest_count_sees_a_block_that_does_come_to_rest():
    """The same count on friction_damping under Eq. 9.7, whose block stops and turns back
    at each of its five turning points after the release: five rests."""
    from assemblies.scenes import SCENES
    from assemblies.scenes.friction import _rests
    run = run_scene_full("friction_damping", params={"block.friction": "tanh"})
    asm = SCENES["friction_damping"].build()
    asm.component("block").set("friction", "tanh")
    assert _rests(run.result, asm, 0.0, end="wall") == 5
