"""MSL's Rotational.Examples First and Backlash (assemblies/scenes/msl_rotational_examples.py):
every figure passes in every mode, and the references agree with closed forms."""
import math

import numpy as np
import pytest
from scipy.optimize import brentq

from assemblies.run import run_scene_full
from assemblies.scenes import SCENES
from assemblies.scenes import msl_rotational_examples_references as ref
from assemblies.scenes.msl_rotational_examples import MSL_ROTATIONAL_EXAMPLE_SCENES

NAMES = list(MSL_ROTATIONAL_EXAMPLE_SCENES)
_RUNS: dict = {}


def run(name, mode):
    if (name, mode) not in _RUNS:
        _RUNS[name, mode] = run_scene_full(name, mode=mode, plot=False)
    return _RUNS[name, mode]


def test_registered_with_references():
    assert set(NAMES) == {"rotational_first", "rotational_backlash"}
    for name in NAMES:
        assert SCENES[name].reference and "MSL Rotational.Examples" in SCENES[name].description


@pytest.mark.parametrize("mode", ("cosim", "me", "monolithic"))
@pytest.mark.parametrize("name", NAMES)
def test_every_figure_passes_in_every_mode(name, mode):
    r = run(name, mode)
    assert r.passed, r.table()
    assert len(r.result.figures) >= 9


def test_backlash_contacts_follow_the_reference_into_the_same_contact():
    """Each of the 21 changes of contact of both backlash elements in the run is the
    reference's change, in order (the figures hold their times)."""
    figures = {f.name: f for f in run("rotational_backlash", "monolithic").result.figures}
    for element in ("elastoBacklash", "elastoBacklash2"):
        assert figures[f"{element}_contacts"].measured == 21
        assert all(np.isfinite(figures[f"{element}_{n}"].measured) for n in range(1, 22))


def test_backlash_reference_lets_go_and_flies_the_gap_as_the_closed_form():
    """From 90 deg at rest the inertia is in contact beyond +b/2: x = phi - b/2 follows
    J x'' + d x' + c x = 0 until the torque c x + d x' reaches 0 (MSL: no pull), then
    flies at its speed until phi = -b/2. Both references (the law is the same until
    then) meet those two instants of the closed form to 1e-9 s."""
    p = ref.BACKLASH
    J, c, d, b = p["J"], p["c"], p["d"], p["b"]
    sigma = d / (2 * J)
    wd = math.sqrt(c / J - sigma**2)
    x0 = p["phi0"] - b / 2

    def x(t):
        return x0 * math.exp(-sigma * t) * (math.cos(wd * t) + sigma / wd * math.sin(wd * t))

    def v(t):
        return -x0 * math.exp(-sigma * t) * (wd + sigma**2 / wd) * math.sin(wd * t)

    release = brentq(lambda t: c * x(t) + d * v(t), 1e-6, math.pi / wd, xtol=1e-15)
    arrival = release + (x(release) + b) / -v(release)
    t = np.arange(0.0, 1.0005, 1e-3)
    for bounded in (True, False):
        contacts = ref.backlash(t, bounded).contacts
        assert contacts[0][1] == 0 and abs(contacts[0][0] - release) < 1e-9
        assert contacts[1][1] == -1 and abs(contacts[1][0] - arrival) < 1e-9


def test_first_reference_turns_the_motor_ratio_times_faster_and_balances_its_energy():
    """Sanity of the First reference against its linear algebra: the gear makes the
    motor turn ratio x faster than inertia2, and the work of the torque is the energy
    stored plus the bearing damper's loss (written here from the states)."""
    p = ref.FIRST
    t = np.linspace(0.0, p["stop"], 2001)
    r = ref.first(t)
    np.testing.assert_allclose(r["w1"], p["ratio"] * r["w2"])
    J = p["J2"] + p["ratio"]**2 * p["Jmotor"]
    stored = (J * r["w2"]**2 + p["Jload"] * r["w3"]**2 + p["c"] * (r["phi2"] - r["phi3"])**2) / 2
    loss = np.concatenate([[0.0], np.cumsum(np.diff(t) * p["damping"]
                                            * (r["w2"][1:]**2 + r["w2"][:-1]**2) / 2)])
    assert np.abs(r["work"] - stored - loss).max() < 1e-4 * r["work"].max()
