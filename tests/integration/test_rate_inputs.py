"""A flange's rate inputs: the FMU runs its force (or a motion's acceleration) along
them over a co-simulation step, and the masters set them from the polynomial they
extrapolate a held input with (issue 27: a coupling of order p + 1).
"""
import math

import numpy as np
from fmpy import extract, read_model_description
from fmpy.fmi2 import FMU2Slave

from assemblies.engine.cosim import cosimulate as engine_cosimulate
from assemblies.engine.me import simulate_monolithic
from assemblies.masters.cosim import cosimulate as reference_cosimulate
from assemblies.pruning import prune_unrecorded
from assemblies.scenes import scene
from components.translational import Mass
from fmus.build import build_fmu


RATES = ("flange_a.f_rate", "flange_a.f_rate2", "flange_a.f_rate3")


def _mass_slave(tmp_path, m):
    """A free mass's FMI 2 Co-Simulation FMU, initialised at t = 0: (slave, value
    references by name, its variables by name)."""
    path = build_fmu(Mass(m=m), tmp_path / "mass.fmu", fmi_version=2)
    md = read_model_description(str(path))
    by_name = {v.name: v for v in md.modelVariables}
    slave = FMU2Slave(guid=md.guid, unzipDirectory=extract(str(path)),
                      modelIdentifier=md.coSimulation.modelIdentifier, instanceName="mass")
    slave.instantiate()
    slave.setupExperiment(tolerance=1e-10, startTime=0.0)
    slave.enterInitializationMode()
    slave.exitInitializationMode()
    vr = {n: by_name[n].valueReference for n in ("flange_a.f", "flange_b.f", *RATES, "s", "v")}
    return slave, vr, by_name


def _ends(slave, vr):
    s, v = slave.getReal([vr["s"], vr["v"]])
    slave.terminate()
    slave.freeInstance()
    return s, v


def _closed_form(m, f, r, q, j, t):
    """(s, v) of a mass at rest at t = 0 under f + r t + q t^2 / 2 + j t^3 / 6."""
    return ((f * t**2 / 2 + r * t**3 / 6 + q * t**4 / 24 + j * t**5 / 120) / m,
            (f * t + r * t**2 / 2 + q * t**3 / 6 + j * t**4 / 24) / m)


def test_a_free_mass_follows_a_force_ramp_within_one_step(tmp_path):
    # m s'' = f + r t + q t^2 / 2 + j t^3 / 6 over one doStep: s = s0 + v0 t + (f t^2/2
    # + r t^3/6 + q t^4/24 + j t^5/120) / m, the closed form, to the FMU's solver tolerance
    m, f, r, q, j, h = 2.0, 3.0, -4.0, 5.0, -6.0, 0.7
    slave, vr, by_name = _mass_slave(tmp_path, m)
    for name, unit in zip(RATES, ("N/s", "N/s2", "N/s3")):
        assert by_name[name].causality == "input" and by_name[name].unit == unit
        assert float(by_name[name].start) == 0.0  # an importer that never sets it holds f
    slave.setReal([vr[n] for n in ("flange_a.f", *RATES)], [f, r, q, j])
    slave.doStep(0.0, h)
    s, v = _ends(slave, vr)
    s_exact, v_exact = _closed_form(m, f, r, q, j, h)
    assert math.isclose(s, s_exact, abs_tol=1e-9)
    assert math.isclose(v, v_exact, abs_tol=1e-9)


def test_rates_run_on_across_steps_when_another_input_is_set(tmp_path):
    # An importer that sets f and its rates once, takes a step, sets another input (the
    # runtime moves every input's extrapolation base to that point) and steps on: the
    # force must go on along the same quintic. Rate inputs are read by no equation, so
    # the runtime's per-right-hand-side extrapolation skips them; moving the base must
    # not, or f_rate would restart from its value at t = 0 (r instead of r + q h1 +
    # j h1^2 / 2) and the mass end off by far more than the 1e-9 below.
    m, f, r, q, j, h1, h2 = 2.0, 3.0, -4.0, 5.0, -6.0, 0.4, 0.3
    slave, vr, _ = _mass_slave(tmp_path, m)
    slave.setReal([vr[n] for n in ("flange_a.f", *RATES)], [f, r, q, j])
    slave.doStep(0.0, h1)
    slave.setReal([vr["flange_b.f"]], [0.0])
    slave.doStep(h1, h2)
    s, v = _ends(slave, vr)
    s_exact, v_exact = _closed_form(m, f, r, q, j, h1 + h2)
    assert math.isclose(s, s_exact, abs_tol=1e-9)
    assert math.isclose(v, v_exact, abs_tol=1e-9)


def _belt(stop):
    sc = scene("two_block_belt")
    asm, _ = prune_unrecorded(sc.build(), sc.record)
    ref = simulate_monolithic(asm, stop_time=stop, step=0.1, tolerance=1e-12, record=sc.record)
    return sc, asm, ref


def test_force_rates_raise_the_coupling_to_the_extrapolations_order_plus_one():
    # two_block_belt's blocks take the springs' forces, held inputs with rates: the
    # polynomial of degree p itself goes into the step, so the coupling is of order
    # p + 1, against the composite at 1e-12. Measured at h = 0.1 / 2, / 4, / 8 over 30 s
    # (block positions): p = 1: 5.12e-3, 1.28e-3, 3.20e-4 (orders 2.00, 2.00); p = 2:
    # 2.73e-4, 3.42e-5, 4.30e-6 (2.99, 2.99); p = 3 (the default): 2.46e-5, 1.54e-6,
    # 1.06e-7 (4.00, 3.86; at h = 0.1 / 16 1.04e-8, 3.35, the friction events' location
    # taking over). Held as the step mean (before), p = 2 gave 7.8e-4 ... 7.6e-5 at
    # h = 0.1 / 4 ... / 32, orders 0.7-1.8.
    sc, asm, ref = _belt(30.0)
    for extrapolation in (1, 2, 3):
        errors = []
        for n in (2, 4, 8):
            res = engine_cosimulate(asm, stop_time=30.0, step=0.1 / n, tolerance=1e-12,
                                    record=sc.record, extrapolation=extrapolation)
            errors.append(max(float(np.max(np.abs(res[c][::n] - ref[c])))
                              for c in ("block1.s", "block2.s")))
        orders = [math.log2(a / b) for a, b in zip(errors, errors[1:])]
        assert all(abs(o - extrapolation - 1) < 0.3 for o in orders), (extrapolation, errors)
    assert errors[-1] < 1e-6, errors


def test_both_masters_set_the_same_rates():
    # the fmpy reference master mirrors the compiled one's rates (set_held, set_raw,
    # the chains' end values): the same steps and the same motion, fixed and adaptive
    sc, asm, _ = _belt(3.0)
    for options in (dict(step=0.05, extrapolation=2), dict(step=0.05, extrapolation=3),
                    dict(step=0.1, adaptive=True, tol=1e-4, extrapolation=3)):
        runs = [f(asm, stop_time=3.0, tolerance=1e-10, record=sc.record, event_sync=True,
                  **options)
                for f in (engine_cosimulate, reference_cosimulate)]
        assert runs[0].settings["steps"] == runs[1].settings["steps"], options
        for c in ("block1.s", "block2.s", "block1.v", "block2.v"):
            assert np.max(np.abs(runs[0][c] - runs[1][c])) < 1e-9, (options, c)
