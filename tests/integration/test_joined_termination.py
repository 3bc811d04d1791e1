"""A joined model ends its run where a member would end its own (issue 26): each member's
terminate flag is carried into the composite FMU under the member's reason, prefixed by
its instance name; the run stops at the same time as the members' own FMUs in cosim and
me, at the physics' time, and says which instance ended it."""
import math

import pytest

from assemblies import Assembly
from assemblies.engine.me import simulate_me, simulate_monolithic
from assemblies.masters.monolithic import composite, simulate_monolithic as python_monolithic
from assemblies.run import run_scene_full
from components.dae import flatten
from components.bodies.seed_bodies import RodOnRollers

from conftest import drop_component

Drop = drop_component()

# the scenes monolithic mode refused before, each with starts under which its body ends
# the run: the coin falls flat, the shell's rim touches the table, the rod leaves the
# rollers, the disk's axis reaches the singular orientation of its Euler angles
ENDING = {
    "coin_rolling": ({"coin.theta": 0.5, "coin.phi_dot": 0.0, "coin.psi_dot": 0.0},
                     "coin", "coin fell flat"),
    "coin_upright": ({"coin.theta": 1.2, "coin.psi_dot": 0.0}, "coin", "coin fell flat"),
    "coin_circle": ({"coin.theta": 0.5, "coin.phi_dot": 0.1, "coin.psi_dot": -1.0},
                    "coin", None),  # leans but rolls on: no end
    "shell_rolling": ({"shell.w": 6.0}, "shell", "the rim touched the table"),
    "shell_frictionless": ({"shell.w": 6.0}, "shell", "the rim touched the table"),
    "rod_on_rollers": ({"rod.v": 2.0}, "rod", "the rod left"),
    "wobbling_disk": ({"disk.theta": 0.01, "disk.theta_dot": -0.5}, "disk",
                      "disk axis reached the X axis"),
    "thrown_disk": ({"disk.theta": 0.01, "disk.theta_dot": -0.5}, "disk",
                    "disk axis reached the X axis"),
}


@pytest.mark.parametrize("name", sorted(ENDING))
def test_joined_scene_ends_where_its_member_ends_in_cosim_and_me(name):
    params, instance, why = ENDING[name]
    runs = {(mode, engine): run_scene_full(name, mode=mode, engine=engine, params=params)
            for mode, engine in (("cosim", "c"), ("me", "c"), ("monolithic", "c"),
                                 ("monolithic", "fmpy"))}
    mono = runs[("monolithic", "c")]
    assert mono.result.settings["scheme"] == "monolithic"
    ends = {key: run.result.settings["terminated"] for key, run in runs.items()}
    if why is None:
        assert all(end is None for end in ends.values()), ends
        return
    for key, end in ends.items():
        assert end["instance"] == instance and why in end["message"], (key, end)
    # the reason reads as the member's own run's: the composite's own instance name and
    # the member-name prefix of its reason are told in the member's terms
    assert "assembly" not in ends[("monolithic", "c")]["message"]
    assert (ends[("monolithic", "c")]["message"].split(" at t = ")[0]
            == ends[("me", "c")]["message"].split(" at t = ")[0])
    tolerance = runs[("me", "c")].result.settings["tolerance"]
    reference = ends[("me", "c")]["time"]
    for key, end in ends.items():
        # the same indicator located by the same engine: the same time; the Python
        # reference master locates it on its own solution, to its tolerance
        assert end["time"] == pytest.approx(reference, abs=max(1e-9, 100 * tolerance)), key
    for key, run in runs.items():
        assert run.result["time"][-1] <= ends[key]["time"] + 1e-12, key
    # the figures say the same in every mode (the ending starts break some on purpose)
    verdicts = {key: [f.passed for f in run.figures] for key, run in runs.items()}
    assert len({tuple(v) for v in verdicts.values()}) == 1, verdicts


def _rod_leaves(x0, v0, m=1.0, L=2.0, D=1.0, mu=0.3, g=9.81):
    """When x0 cos(w t) + (v0 / w) sin(w t) first reaches min(D/2, (L - D)/2), or None."""
    w = math.sqrt(2 * g * mu / D)
    edge, amplitude = min(D / 2, (L - D) / 2), math.hypot(x0, v0 / w)
    if amplitude <= edge:
        return None
    phase = math.atan2(x0, v0 / w)  # x = A sin(w t + phase)
    return (math.asin(edge / amplitude) - phase) / w


def test_rod_leaves_the_rollers_at_the_closed_form_time_in_monolithic_mode():
    run = run_scene_full("rod_on_rollers", mode="monolithic", params={"rod.v": 2.0})
    end = run.result.settings["terminated"]
    assert end["instance"] == "rod"
    assert end["time"] == pytest.approx(_rod_leaves(0.2, 2.0), abs=1e-9)


def _two_that_can_end(rod_v):
    """A drop (first: its flag is mode 0 of the composite) and a rod (mode 1), unconnected:
    the one that ends first ends the joined run."""
    asm = Assembly("two_ends")
    asm.add("drop", Drop(g=100.0))  # h = 2 - 50 t^2: on the ground at t = 0.2
    asm.add("rod", RodOnRollers(x=0.2, v=rod_v))
    return asm


def test_composite_carries_each_members_flag_under_its_remapped_mode_and_named_reason():
    model = flatten(composite(_two_that_can_end(2.0)))
    modes = [v.name for v in model.modes]
    assert [(modes[q], why) for q, why in model.terminate] == [
        ("drop.terminated", "drop: the mass hit the ground"),
        ("rod.terminated",
         "rod: the rod left |x| < min(D/2, (L - D)/2): it tips or falls off")]


def test_the_joined_fmu_alone_tells_fmpy_which_member_ended_it(capfd):
    """No master of ours: fmpy's own Model Exchange loop on the composite FMU stops where
    the rod leaves, and the FMU's log names the rod; the FMU validates."""
    from fmpy.validation import validate_fmu

    from conftest import simulate_in_fmpy
    from fmus import build_fmu
    joined = composite(_two_that_can_end(2.0))
    assert validate_fmu(str(build_fmu(joined))) == []
    res = simulate_in_fmpy(joined, "ModelExchange", stop_time=1.0, output_interval=0.01,
                           output=["rod.x", "drop.h"])
    t_end = _rod_leaves(0.2, 2.0)
    assert res["time"][-1] == pytest.approx(t_end, abs=1e-6)
    assert res["rod.x"][-1] == pytest.approx(0.5, abs=1e-6)
    assert res["drop.h"][-1] == pytest.approx(2 - 50 * t_end**2, abs=1e-6)  # still falling
    assert f"rod: the rod left |x| < min(D/2, (L - D)/2): it tips or falls off at t = " \
           f"{t_end:.6f}" in capfd.readouterr().out


@pytest.mark.parametrize("rod_v, first, t_end", [
    (2.0, "rod", _rod_leaves(0.2, 2.0)),  # 0.162 s: the second member's flag ends it
    (1.0, "drop", 0.2),                   # the rod stays on (A = 0.46 m < 0.5 m)
])
def test_the_member_that_ends_first_ends_the_joined_run_and_is_named(rod_v, first, t_end):
    asm = _two_that_can_end(rod_v)
    record = ["drop.h", "rod.x"]
    mono = simulate_monolithic(asm, 1.0, 0.01, 1e-10, record=record)
    me = simulate_me(asm, 1.0, 0.01, 1e-10, record=record)
    python = python_monolithic(asm, 1.0, 0.01, 1e-10, record=record)
    fmpy_fmu = python_monolithic(asm, 1.0, 0.01, 1e-10, record=record, engine="fmu")
    for res in (mono, me, python, fmpy_fmu):
        end = res.settings["terminated"]
        assert end["instance"] == first, end
        assert end["time"] == pytest.approx(t_end, abs=1e-9), end
    assert mono.settings["terminated"]["time"] == pytest.approx(
        me.settings["terminated"]["time"], abs=1e-12)
    # fmpy read the composite FMU's own log: the member's reason, in the member's terms
    message = fmpy_fmu.settings["terminated"]["message"]
    why = {"drop": "the mass hit the ground", "rod": "the rod left"}[first]
    assert f": {why}" in message and f"{first}: {why}" not in message, message


def test_command_line_names_the_instance_and_what_ran(tmp_path, capsys):
    """`--engine fmpy --mode monolithic` runs the Python master on the joined CasADi model
    (no FMU, no fmpy call): the settings line says so, not 'engine reference'."""
    from assemblies.cli import main
    for engine, label in (("fmpy", "engine fmpy (the joined CasADi model under scipy's "
                                   "DOP853, no FMU)"), ("c", "monolithic, engine c,")):
        code = main(["run", "rod_on_rollers", "--mode", "monolithic", "--engine", engine,
                     "--param", "rod.v=2", "--out", str(tmp_path)])
        out = capsys.readouterr().out
        assert code == 1  # the rod leaves: the scene's oscillation figures cannot hold
        assert label in out and "engine reference" not in out, out
        ended = next(line for line in out.splitlines() if line.startswith("terminated by"))
        assert ended.startswith(f"terminated by rod at t = {_rod_leaves(0.2, 2.0):.6f}")
        assert "the rod left" in ended and "assembly" not in ended
