"""Signal sources: each FMU's output against MSL's defining formula, in FMI 2 and 3, ME
and CS, at start times on, before and after the first output point."""
import math

import fmpy
import numpy as np
import pytest

from components.sources.signals import Constant, Ramp, Sine, Step
from fmus.build import build_fmu


def _msl(kind, v, t):
    """Modelica.Blocks.Sources, as its source text writes each block."""
    tau = t - v["startTime"] if "startTime" in v else t
    if kind is Constant:
        return np.full_like(t, v["k"])
    if kind is Step:
        return v["offset"] + np.where(t < v["startTime"], 0.0, v["height"])
    if kind is Ramp:
        slope = v["height"] / v["duration"] if v["duration"] > 0 else 0.0
        return v["offset"] + np.where(t < v["startTime"], 0.0, np.where(
            t < v["startTime"] + v["duration"], tau * slope, v["height"]))
    return v["offset"] + np.where(t < v["startTime"], 0.0, v["amplitude"] * np.sin(
        2 * math.pi * v["f"] * tau + v["phase"]))


CASES = [(Constant, {"k": -2.5}), (Step, {"height": 3.0, "offset": 0.5, "startTime": 0.3}),
         (Step, {"height": 3.0, "startTime": 0.0}),
         (Ramp, {"height": 2.0, "duration": 0.4, "offset": -1.0, "startTime": 0.25}),
         (Ramp, {"height": 2.0, "duration": 0.0, "startTime": 0.5}),
         (Sine, {"amplitude": 2.0, "f": 3.0, "phase": 0.7, "offset": 0.1, "startTime": 0.2})]


@pytest.mark.parametrize("version", [2, 3])
@pytest.mark.parametrize("fmi_type", ["ModelExchange", "CoSimulation"])
@pytest.mark.parametrize("kind, values", CASES, ids=[f"{k.__name__}{i}" for i, (k, _) in
                                                     enumerate(CASES)])
def test_signal_follows_msl_formula(kind, values, version, fmi_type):
    block = kind(**values)
    path = build_fmu(block, fmi_version=version)
    res = fmpy.simulate_fmu(str(path), fmi_type=fmi_type, stop_time=1.0, output_interval=0.05,
                            start_values=dict(block.values), output=["y"])
    t = res["time"]
    # a result row at an instant where y jumps reads the value after it (fmpy's rule);
    # the rows fmpy adds at an event carry the value before, then after: compare the last
    last = np.r_[t[1:] != t[:-1], True]
    # fmpy's grid time k * 0.05 may land a rounding below an instant: read it as on it
    expected = _msl(kind, block.values, t[last] + 1e-12)
    assert np.abs(res["y"][last] - expected).max() < 1e-9, (res["y"][last], expected)


@pytest.mark.parametrize("version", [2, 3])
@pytest.mark.parametrize("fmi_type", ["ModelExchange", "CoSimulation"])
def test_product_multiplies_its_inputs(version, fmi_type):
    """MSL Blocks.Math.Product, y = u1 u2, fed two ramps by fmpy (inputs interpolated
    linearly): y is their product at every output point, a parabola (in co-simulation
    the inputs fmpy set at the step's start: the product one step earlier)."""
    from components.sources.math import Product
    path = build_fmu(Product(), fmi_version=version)
    signals = np.array([(0.0, 0.0, 3.0), (1.0, 2.0, 1.0)],
                       dtype=[("time", float), ("u1", float), ("u2", float)])
    res = fmpy.simulate_fmu(str(path), fmi_type=fmi_type, stop_time=1.0, output_interval=0.1,
                            input=signals, output=["y"])
    t = res["time"]
    if fmi_type == "CoSimulation":
        t = np.maximum(t - 0.1, 0.0)
    assert np.abs(res["y"] - 2 * t * (3 - 2 * t)).max() < 1e-12
