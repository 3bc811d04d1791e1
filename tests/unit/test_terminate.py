"""A model that declares where it stops being valid ends the run there, and says why."""
import math

import pytest

from assemblies import Assembly, cosimulate
from conftest import drop_component, simulate_in_fmpy


Drop = drop_component()


def test_cosimulation_stops_at_the_located_time_with_the_message():
    asm = Assembly("drop")
    asm.add("mass", Drop())
    res = cosimulate(asm, stop_time=5.0, step=0.25, tolerance=1e-10)
    t_hit = math.sqrt(2 * 2.0 / 9.81)  # h = 2 - g t^2 / 2
    end = res.settings["terminated"]
    assert end["instance"] == "mass" and "hit the ground" in end["message"]
    assert end["time"] == pytest.approx(t_hit, abs=1e-9)
    assert res["time"][-1] < t_hit + 0.25 and res["mass.h"][-1] == pytest.approx(0.0, abs=1e-9)
    assert res.events["mass"]["mass.terminated"][-1] == 1


def test_model_exchange_importer_is_told_to_terminate(capfd):
    res = simulate_in_fmpy(Drop(), "ModelExchange", stop_time=5.0, output_interval=0.01,
                           output=["h", "terminated"])
    assert res["time"][-1] == pytest.approx(math.sqrt(2 * 2.0 / 9.81), abs=1e-6)
    assert "the mass hit the ground at t = 0.6385508" in capfd.readouterr().out  # fmpy's logger


def _landing(flag_name="landed"):
    """A drop whose own declared mode says it has landed; terminate_on makes that flag end
    the run (how a joined model carries each member's terminate flag)."""
    import casadi as ca
    from components import Component
    from components.interfaces import Mode, Parameter, Profile, State

    class Landing(Component):
        """Point mass falling from 2 m; its mode 'landed' ends the run."""

        parameters = (Parameter("g", 9.81, "m/s2", "gravity", min=0.0, min_strict=True),)
        states = (State("h", 2.0, "m", "height above the ground"),
                  State("w", 0.0, "m/s", "upward velocity"))
        modes = (Mode("landed", 0, "1 once on the ground", values=(0, 1)),)
        profiles = (Profile("free", "no ports"),)

        def equations(self, e):
            e.residual(e.der.h - e.x.w)
            e.residual(e.der.w + e.p.g)
            e.indicator(e.x.h, "height")
            e.jump("landed", ca.if_else(e.x.h <= 0, 1, e.q.landed))
            e.terminate_on(flag_name, "the mass landed")

    return Landing()


def test_a_declared_mode_ends_the_run_through_terminate_on():
    from components.dae import flatten
    assert flatten(_landing()).terminate == ((0, "the mass landed"),)
    asm = Assembly("landing")
    asm.add("mass", _landing())
    res = cosimulate(asm, stop_time=5.0, step=0.25, tolerance=1e-10)
    end = res.settings["terminated"]
    assert end["instance"] == "mass" and "the mass landed at t = " in end["message"]
    assert end["time"] == pytest.approx(math.sqrt(2 * 2.0 / 9.81), abs=1e-9)


def test_terminate_on_a_mode_the_component_lacks_is_one_line():
    from components.dae import flatten
    from components.interfaces import ComponentError
    with pytest.raises(ComponentError, match="terminate on unknown mode 'landing'") as info:
        flatten(_landing("landing"))
    assert "\n" not in str(info.value)
