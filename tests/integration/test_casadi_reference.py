"""CasADi's own CVODES on the joined model (monolithic, method="CVODES") as a reference."""
import numpy as np

from assemblies.masters.monolithic import simulate_monolithic
from assemblies.scenes import scene
from conftest import SEED_94, SEED_94_SPEED, coulomb_drag_reference


def test_cvodes_follows_the_exact_stick_slip_through_its_events():
    res = simulate_monolithic(scene("stick_slip").build(), stop_time=20.0, step=0.1,
                              tolerance=1e-10, record=["block.x"], method="CVODES")
    phases, exact = coulomb_drag_reference(**SEED_94, v=SEED_94_SPEED, t_end=20.0)
    # every change of phase inside the run is one event, none counted twice
    changes = sum(1 for _, _, t_end in phases if t_end < 20.0)
    assert res.settings["method"] == "CVODES" and res.settings["events"] == changes >= 3
    assert np.abs(res["block.x"] - exact(res["time"])).max() < 1e-7


def test_cvodes_and_dop853_agree_on_a_joined_scene():
    runs = {m: simulate_monolithic(scene("moving_table").build(), stop_time=5.0, step=0.01,
                                   tolerance=1e-10, record=["block.s"], method=m)
            for m in ("CVODES", "DOP853")}
    assert runs["CVODES"].settings["events"] == runs["DOP853"].settings["events"] > 10
    assert np.abs(runs["CVODES"]["block.s"] - runs["DOP853"]["block.s"]).max() < 1e-5
