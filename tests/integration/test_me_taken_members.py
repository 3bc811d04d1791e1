"""What the engine's me says it took from time or as a linear map is what it took.

A member is only a candidate until its first read at an event: a stateless gain whose
directional derivative fails (tests/handmade/lm_gain, dd_mode 1) cannot give the map's
coefficient, so the engine evaluates it as any other member, and the settings must not
list it. Either way the motion is the closed form: a ramp (an ml2_affine block with
a = 0, b = 1: x' = 1, so u = x = t) through the gain (y = k t) into a sink (ml2_affine,
a = 1, b = 0: x' = y, so x = k t^2 / 2).
"""
from __future__ import annotations

import numpy as np
import pytest
from fmpy.validation import validate_fmu

import assemblies.engine.me as engine_me
from assemblies import FMU, Assembly
from assemblies.engine.me import simulate_me
from handmade_fmus import handmade_fmu


def test_the_gain_is_valid():
    assert validate_fmu(str(handmade_fmu("lm_gain"))) == []


@pytest.mark.parametrize("dd_mode, taken", [(0, True), (1, False)])
def test_a_member_whose_first_read_fails_is_not_listed(monkeypatch, dd_mode, taken):
    asm = Assembly("ramp_gain")
    asm.add("ramp", FMU(handmade_fmu("ml2_affine"), a=0.0, b=1.0))
    asm.add("gain", FMU(handmade_fmu("lm_gain"), k=3.0, dd_mode=float(dd_mode)))
    asm.add("sink", FMU(handmade_fmu("ml2_affine"), a=1.0, b=0.0))
    asm.connect("ramp.x", "gain.u")
    asm.connect("gain.y", "sink.u")
    # foreign FMUs are never candidates (evaluated_members asks for our equations):
    # the gain is offered as one here, as a component of ours would be
    real = engine_me.evaluated_members
    monkeypatch.setattr(engine_me, "evaluated_members", lambda a, fmus, columns, couplings,
                        linear: [int(linear and name == "gain") for name in a.components]
                        if linear else real(a, fmus, columns, couplings, linear))
    result = simulate_me(asm, 2.0, 0.25, 1e-10, record=["gain.y", "sink.x"], jacobian="fd")
    assert result.settings["evaluated_as_linear_maps"] == (["gain"] if taken else [])
    assert result.settings["evaluated_until"] == {}
    t = result["time"]
    np.testing.assert_allclose(result["gain.y"], 3.0 * t, rtol=1e-12, atol=1e-12)
    # DOPRI5 integrates a quadratic exactly: what is left is rounding and the tolerance
    np.testing.assert_allclose(result["sink.x"], 1.5 * t ** 2, rtol=0, atol=1e-10)
