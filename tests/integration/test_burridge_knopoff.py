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
