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
