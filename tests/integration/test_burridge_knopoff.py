"""Issue 30: the burridge_knopoff scene in every mode, its FaultBlock as a real FMU against
the seed's closed form, the large-run command and the Dask sweep over the weakening."""
import os
import subprocess
import sys
from pathlib import Path

import numpy as np
import pytest

from assemblies import Assembly
from assemblies.engine.fault import FaultError
from assemblies.engine.me import simulate_me
from assemblies.run import run_scene_full
from assemblies.scenes.references import stick_slip_first_cycle
from components import ConstantSpeed, FaultBlock

ROOT = Path(__file__).resolve().parents[2]


@pytest.mark.parametrize("mode", ["me", "monolithic", "cosim"])
def test_every_figure_passes_in_every_mode(mode):
    run = run_scene_full("burridge_knopoff", mode=mode)
    assert run.passed, run.table()
    figures = {f.name: f for f in run.figures}
    # the FMUs' slides and the fault solver's are both held to scipy's, slide by slide
    assert "9 slides" in figures["slides"].description


@pytest.mark.parametrize("n", [1, 6])
def test_other_chain_lengths_as_fmus(n):
    """The scene's figures for a chain of another length (fault_chain), in me: the FMUs'
    slides against scipy's, slide by slide, and the fault solver's too."""
    import dataclasses
    from assemblies.scenes import scene
    from assemblies.scenes.burridge_knopoff import fault_chain
    chain = dataclasses.replace(scene("burridge_knopoff"), name=f"burridge_knopoff_{n}",
                                build=lambda: fault_chain(n, ell=1.0, sigma=0.1, nu=0.05,
                                                          heterogeneity=0.05),
                                record=None)
    run = run_scene_full(chain, mode="me", stop_time=60.0)
    assert run.passed, run.table()


def test_the_block_fmu_is_the_seeds_stick_slip():
    """One FaultBlock with no weakening is seed 9.2's block: F_s = mu_s m g = 0.4,
    sigma = 1 - mu_k / mu_s = 0.25, pulled at 0.05 m/s through kp = 1."""
    asm = Assembly("fault_block_seed")
    asm.add("plate", ConstantSpeed(v=0.05))
    asm.add("block", FaultBlock(m=1, kp=1, F_s=0.4, sigma=0.25, alpha=0.0))
    asm.connect("plate.flange", "block.plate")
    tol = 1e-10
    res = simulate_me(asm, stop_time=20.0, step=0.1, tolerance=tol)
    ev = res.events["block"]
    t1, t2, x2 = stick_slip_first_cycle(1, 1, 1, 0.3, 0.4, 0.05)
    slip = ev["time"][ev["block.mode"] == 1][0]
    stick = ev["time"][ev["block.mode"] == 0][0]
    assert abs(slip - t1) < 100 * tol * t1
    assert abs(stick - t2) < 100 * tol * t2
    assert abs(ev["block.x"][ev["block.mode"] == 0][0] - x2) < 100 * tol


def test_weakening_speeds_the_slide_up():
    """With alpha > 0 the kinetic friction falls with speed: the slide goes further than
    the constant-friction one from the same threshold (an inequality from the law)."""
    ends = {}
    for alpha in (0.0, 2.0):
        asm = Assembly(f"fault_block_alpha_{alpha:g}")
        asm.add("plate", ConstantSpeed(v=0.05))
        asm.add("block", FaultBlock(m=1, kp=1, F_s=0.4, sigma=0.25, alpha=alpha))
        asm.connect("plate.flange", "block.plate")
        res = simulate_me(asm, stop_time=20.0, step=0.1, tolerance=1e-10)
        ev = res.events["block"]
        ends[alpha] = ev["block.x"][ev["block.mode"] == 0][0]
    assert ends[2.0] > ends[0.0]


def _cli(*args, cwd=ROOT):
    env = dict(os.environ, PYTHONPATH=str(ROOT))
    return subprocess.run([sys.executable, "-m", "assemblies.scenes.burridge_knopoff", *args],
                          capture_output=True, text=True, cwd=cwd, env=env, timeout=300)


def test_large_run_command_writes_catalogue_and_pictures(tmp_path):
    r = _cli("--n", "100", "--events", "800", "--out", str(tmp_path))
    assert r.returncode in (0, 1), r.stderr
    assert "energy" in r.stdout and "blocks stuck" in r.stdout
    cat = np.genfromtxt(tmp_path / "catalogue.csv", delimiter=",", names=True)
    assert cat.size >= 800
    assert set(cat.dtype.names) >= {"start", "end", "blocks", "moment", "energy"}
    assert np.all(cat["end"] >= cat["start"])
    assert (tmp_path / "burridge_knopoff.png").stat().st_size > 10_000
    energy = next(line for line in r.stdout.splitlines() if line.startswith("energy"))
    assert "pass" in energy


def test_large_run_command_refuses_bad_input_in_one_line(tmp_path):
    r = _cli("--n", "0", "--events", "10")
    assert r.returncode == 2
    assert r.stderr.strip().startswith("error: fault: n") and "Traceback" not in r.stderr
    assert len(r.stderr.strip().splitlines()) == 1


def test_weakening_sweep_on_dask():
    from assemblies.scenes.burridge_knopoff import weakening_sweep
    sweep = weakening_sweep([1.5, 3.5], n=40, events=300, workers=1)
    points = {p["alpha"]: p for p in sweep["points"]}
    assert set(points) == {1.5, 3.5}
    for p in points.values():
        assert p["events"] >= 300 and sum(p["counts"]) == p["events"]


def test_weakening_sweep_without_dask_says_so(monkeypatch):
    from assemblies.scenes.burridge_knopoff import weakening_sweep
    monkeypatch.setitem(sys.modules, "distributed", None)  # import distributed fails
    with pytest.raises(FaultError, match=r"mechfmu\[sweep\]"):
        weakening_sweep([2.5], n=10, events=10)


# --- the scene's own parameters (--param NAME=VALUE) and its mode fault -------------
@pytest.mark.parametrize("n, ell", [(1, 2.0), (3, 1.0)])
def test_scene_parameter_n_in_me_and_fault(n, ell):
    """`n` reshapes the chain: the FMUs' slides (me) and the fault solver's (fault) are
    each held slide by slide to scipy's independent integration of the same n blocks."""
    for mode in ("me", "fault"):
        run = run_scene_full("burridge_knopoff", mode=mode, params={"n": n, "ell": ell},
                             stop_time=60.0)
        assert run.passed, run.table()
        names = {f.name for f in run.figures}
        assert {"t_first", "solver", "energy"} <= names
        assert ("slides" in names) == (mode == "me")
        assert run.record["run"]["params"] == {"n": n, "ell": ell}
    assert sum(k.startswith("block") for k in run.result.assembly.components) == n


def test_mode_fault_runs_a_long_chain_by_events_and_reports_sleep():
    run = run_scene_full("burridge_knopoff", mode="fault",
                         params={"n": 200, "events": 500, "ell": 10, "sigma": 0.01, "nu": 0.01})
    assert run.passed, run.table()
    s = run.result.settings
    assert s["n"] == 200 and s["events"] >= 500
    assert run.result["event.moment"].size == s["events"]
    assert 0 < s["slept_fraction"]["min"] <= s["slept_fraction"]["mean"] <= 1
    assert "blocks stuck" in run.table()


def _mechfmu(*args):
    env = dict(os.environ, PYTHONPATH=str(ROOT))
    return subprocess.run([sys.executable, "-m", "assemblies.cli", *args], capture_output=True,
                          text=True, cwd=ROOT, env=env, timeout=120)


@pytest.mark.parametrize("args, says", [
    (["--param", "n=0"], "parameter n (number of blocks) must be an integer in [1, 100000]"),
    (["--param", "n=2.5"], "parameter n (number of blocks) must be an integer"),
    (["--param", "n=many"], "parameter n (number of blocks) must be an integer"),
    (["--param", "m=3"], "has no parameter 'm' (its parameters: n ("),
    (["--mode", "me", "--param", "n=5000"], "n = 5000 over 75 s is too long a run for mode 'me'"),
    (["--mode", "me", "--param", "n=1000"], "at n = 1000 run at most 45 s (--stop-time)"),
    (["--mode", "me", "--param", "n=1000", "--stop-time", "46"], "n = 1000 over 46 s is too"),
    (["--mode", "monolithic", "--param", "n=1001"], "too large for mode 'monolithic' (at most 1000"),
    (["--mode", "monolithic", "--param", "n=1000", "--stop-time", "101"],
     "at n = 1000 run at most 100 s (--stop-time)"),
    (["--mode", "me", "--param", "events=10"], "too large for mode 'me' (at most 0"),
])
def test_bad_scene_parameter_is_one_line_exit_2(args, says):
    r = _mechfmu("run", "burridge_knopoff", *args)
    assert r.returncode == 2, r.stderr
    err = r.stderr.strip()
    assert len(err.splitlines()) == 1 and "Traceback" not in err, err
    assert "scene 'burridge_knopoff'" in err and says in err, err


def test_me_bounds_n_and_run_length_together():
    """me's cost grows as n^2 x the time run (events ~ n t, each stepping n blocks), so
    its bound is on that product: n = 1000 runs for 45 s (monolithic, whose engine
    costs less once its FMU is built: 100 s), n = 250 the default 75 s and
    up to 720 s; mode fault has no
    such bound."""
    from assemblies.scenes import scene
    sc = scene("burridge_knopoff")
    sc.check_budget("me", {"n": 1000}, 45.0)
    sc.check_budget("me", {"n": 250}, 720.0)
    sc.check_budget("fault", {"n": 100_000}, 1e6)
    sc.check_budget("monolithic", {"n": 1000}, 100.0)
    for n, length in [(1000, 46.0), (250, 721.0), (2000, 12.0)]:
        with pytest.raises(ValueError, match=r"n\^2 x the time run"):
            sc.check_budget("me", {"n": n}, length)


def test_mode_fault_is_refused_by_scenes_without_it():
    from assemblies.assembly import AssemblyError
    with pytest.raises(AssemblyError, match=r"mode must be one of cosim, me, monolithic for "
                                            r"scene 'stick_slip', not 'fault'"):
        run_scene_full("stick_slip", mode="fault")
    with pytest.raises(AssemblyError, match="scene 'stick_slip' has no parameter 'n' "
                                            r"\(it has none"):
        run_scene_full("stick_slip", params={"n": 3})


def test_mode_fault_refuses_what_it_has_not():
    from assemblies.assembly import AssemblyError
    with pytest.raises(AssemblyError, match="mode 'fault' runs scene 'burridge_knopoff' with a "
                                            "solver of its own, which has no engine 'fmpy'"):
        run_scene_full("burridge_knopoff", mode="fault", engine="fmpy")
    with pytest.raises(FaultError, match="from rest at t = 0"):
        run_scene_full("burridge_knopoff", mode="fault", start_time=1.0)


def test_a_run_file_repeats_the_scene_parameters(tmp_path):
    """The run file records n and the chain's values: --from rebuilds the same chain and
    the fault solver gives the same catalogue."""
    from assemblies import rerun
    first = run_scene_full("burridge_knopoff", mode="fault", params={"n": 20, "events": 100},
                           out=tmp_path, plot=False)
    again = rerun(tmp_path / "burridge_knopoff.json")
    assert again.record["run"]["params"] == {"n": 20, "events": 100}
    assert np.array_equal(again.result["event.moment"], first.result["event.moment"])
    assert sum(k.startswith("block") for k in again.result.assembly.components) == 20


# --- slides held to scipy's for every short chain (issue 30, 2.) --------------------
@pytest.mark.parametrize("n, mode", [(3, "fault"), (4, "me"), (5, "fault"), (6, "fault")])
def test_slide_figures_hold_for_every_short_chain(n, mode):
    """At the default ell = 2 the chain's chaos amplifies solver errors past 100 tol t
    (n = 4, slide 11: the fault solver's error 4.5e-7 against 6.8e-7, scipy's own at tol
    7.5e-8):
    each slide is held to the run's accuracy times the amplification measured on scipy's
    run, over the slides it leaves determined."""
    run = run_scene_full("burridge_knopoff", mode=mode, params={"n": n})
    assert run.passed, run.table()
    slides = {f.name: f for f in run.figures}["slides" if mode == "me" else "solver"]
    assert "amplification" in slides.description


def test_a_wrong_run_fails_the_slide_figure():
    """The amplification loosens late slides only: a run whose block1 threshold is off
    by 1e-6 (the first break-away, 1e-6 / (kp V) = 2e-5 s late; the gain there ~1)
    fails against the chain it should have run."""
    from assemblies.scenes.burridge_knopoff import _figures, fault_chain
    chain = fault_chain(4, ell=2.0, alpha=2.5, sigma=0.1, nu=0.05, heterogeneity=0.1, seed=3)
    F1 = chain.component("block1").values["F_s"]
    run = run_scene_full("burridge_knopoff", mode="me", params={"n": 4,
                                                                "block1.F_s": F1 * (1 + 1e-6)})
    wrong = {f.name: f for f in _figures(run.result, chain)}["slides"]
    assert not wrong.passed and wrong.error > 2 * wrong.bound, wrong
    right = {f.name: f for f in _figures(run.result, run.result.assembly)}["slides"]
    assert right.passed, right


# --- a thousand blocks in me: what the plan asks of the assembly scales with it -------
def test_step_cap_follows_time_over_couplings_without_joining(monkeypatch):
    """Whether an indicator can move while the states stand still (steps capped at the
    output interval) is followed over the couplings on each member kind's own model: the
    same answer as the joined model's (its indicators' symbolic dependence on time) for
    the scenes of several members, and a 1000-block chain answers without being joined
    (joining it took 118 s of a 500-block chain's first me run)."""
    import casadi as ca
    from assemblies.engine.me import step_limit_needed
    from assemblies.masters import monolithic
    from assemblies.scenes import scene
    from assemblies.scenes.burridge_knopoff import fault_chain
    from components.dae import flatten
    names = ["stick_slip", "moving_table", "conveyor", "two_block_belt", "resonance_growth",
             "translational_friction", "coupled_clutches", "burridge_knopoff"]
    joined = {}
    for name in names:
        flat = flatten(monolithic.composite(scene(name).build()))
        joined[name] = bool(flat.z.numel()) and bool(ca.depends_on(flat.z, flat.t))
    assert set(joined.values()) == {True, False}

    def refuse(*args, **kwargs):
        raise AssertionError("the step cap joined the assembly")
    monkeypatch.setattr(monolithic, "join", refuse)
    assert {name: step_limit_needed(scene(name).build()) for name in names} == joined
    chain = fault_chain(1000)
    chain.name = "bk3_step_cap_chain"  # no answer kept from an earlier run
    assert step_limit_needed(chain) is False  # the plates' travel is a state
