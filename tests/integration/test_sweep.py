"""Parameter studies (assemblies.sweep) on Dask: the seed's thresholds found by a sweep and
held to their closed forms, a failed run kept as a row, a scheduler started on its own.

Kept small for the default suite: one scheduler with two workers for the module, one local
cluster (through the command line), a few milliseconds a run.
"""
from __future__ import annotations

import json
import math
import os
import subprocess
import sys
import time
from pathlib import Path

import numpy as np
import pytest

pytest.importorskip("distributed")

from assemblies import Assembly  # noqa: E402
from assemblies.cli import main  # noqa: E402
from assemblies.engine.prepare import binary_key  # noqa: E402
from assemblies.scenes import scene  # noqa: E402
from assemblies.scenes.references import stick_slip_first_cycle  # noqa: E402
from assemblies.sweep import (SMALLEST_SHARE, SweepError, chunk_sizes, crossings,  # noqa: E402
                              design, refine, sweep, worker_state)
from components import ConstantSpeed, SpringBlock  # noqa: E402

ROOT = Path(__file__).resolve().parents[2]
START_TIMEOUT = 90  # [s] a scheduler and two workers importing on a loaded 2-core machine


def _stop(proc: subprocess.Popen) -> None:
    """End a process this test started, and its children (a worker's nanny starts one),
    by its own process group."""
    if proc.poll() is None:
        os.killpg(proc.pid, 15)
        try:
            proc.wait(timeout=20)
        except subprocess.TimeoutExpired:
            os.killpg(proc.pid, 9)
            proc.wait()


@pytest.fixture(scope="module")
def scheduler(tmp_path_factory):
    """`dask scheduler` and two `dask worker` processes on localhost, started apart from
    the study (as on a cluster), able to import this checkout; stopped whatever happens."""
    from distributed import Client
    folder = tmp_path_factory.mktemp("dask")
    file = folder / "scheduler.json"
    env = {**os.environ, "PYTHONPATH": os.pathsep.join(filter(None, [
        str(ROOT), os.environ.get("PYTHONPATH", "")]))}
    started = []

    def spawn(*args):
        proc = subprocess.Popen([sys.executable, "-m", "dask", *args], cwd=ROOT, env=env,
                                stdout=subprocess.DEVNULL, stderr=folder.joinpath(
                                    f"log{len(started)}.txt").open("w"),
                                start_new_session=True)
        started.append(proc)
        return proc

    try:
        spawn("scheduler", "--host", "127.0.0.1", "--port", "0", "--no-dashboard",
              "--scheduler-file", str(file))
        deadline = time.monotonic() + START_TIMEOUT
        while not file.exists() and time.monotonic() < deadline:
            time.sleep(0.1)
        assert file.exists(), (folder / "log0.txt").read_text()
        address = json.loads(file.read_text())["address"]
        for _ in range(2):
            spawn("worker", address, "--nworkers", "1", "--nthreads", "1", "--no-dashboard")
        with Client(address) as client:
            client.wait_for_workers(2, timeout=START_TIMEOUT)
            yield client
    finally:
        for proc in reversed(started):
            _stop(proc)


def test_the_resonance_threshold_is_4_mu_over_pi(scheduler):
    """Seed 9.5: in phase, |x| changes at (U pi - 4 mu m g / k)/(2 pi) per unit time, so the
    growth rate measured over U crosses zero at U* = 4 mu / pi (m = k = g = 1, mu = 0.6).
    Runs on the separately started scheduler, each worker loading each FMU once."""
    before = scheduler.run(worker_state)
    address = scheduler.scheduler.address
    table = sweep("resonance_below", {"drive_locked.U": "0.6:1.0:5"}, scheduler=address,
                  progress=False)
    assert list(table["status"]) == ["ok"] * 5
    [threshold] = crossings(table, "drive_locked.U", "rate_locked")
    mu = 0.6
    assert threshold == pytest.approx(4 * mu / math.pi, rel=0.01)
    assert table.attrs["scheduler"] == address and table.attrs["workers"] == 2
    # both FMUs of the scene (a sine drive, a spring-block) prepared once per worker:
    # their count does not grow with the runs a worker did
    distinct = {binary_key(c) for c in scene("resonance_below").build().components.values()}
    after = scheduler.run(worker_state)
    assert sum(a["runs"] - before[w]["runs"] for w, a in after.items()) == 5
    assert all(a["fmus_loaded"] <= len(distinct) for a in after.values())
    # the same study again on the same client: the scene it scatters has the same content,
    # and must not be taken away with the first study's (all runs failed, once)
    again = sweep("resonance_below", {"drive_locked.U": "0.6:1.0:5"}, scheduler=scheduler,
                  progress=False)
    assert list(again["status"]) == ["ok"] * 5
    assert list(again["rate_locked"]) == list(table["rate_locked"])


def test_the_coin_stays_upright_above_the_critical_speed(scheduler):
    """Seed ch. 6: straight rolling is stable for v^2 > g R / 3. A coarse sweep over the
    spin, refined by bisection (every round a sweep), finds where a lean of 1e-5 rad stops
    growing a thousandfold within 20 s."""
    lean0 = 1e-5
    boundary = refine("coin_upright", "coin.psi_dot", -1.6, -2.0,
                      lambda row: row["coin.lean@absmax"] > 1e3 * lean0, rounds=3, points=5,
                      fixed={"coin.theta": math.pi / 2 - lean0}, scheduler=scheduler,
                      outputs=["coin.lean@absmax"], progress=False)
    R, g = 1.0, 9.81  # coin_upright's coin
    assert abs(boundary.value) * R == pytest.approx(math.sqrt(g * R / 3), rel=0.01)
    assert abs(boundary.hi - boundary.lo) < 0.01 and len(boundary.table) == 15


def test_a_failed_run_is_a_row_with_its_error_and_the_others_complete(tmp_path, capsys):
    """On a local cluster of two workers, through the command line: m = -1 and m = nan
    fail with the component's one-line error, m = 1 and 2 slip first at
    t1 = mu_s m g / (k v) (seed 9.2)."""
    code = main(["sweep", "stick_slip", "--param", "block.m=1,-1,nan,2", "--workers", "2",
                 "--out", str(tmp_path)])
    assert code == 0
    csv = tmp_path / "sweep_stick_slip.csv"
    import pandas as pd
    table = pd.read_csv(csv, keep_default_na=False)
    assert list(table["status"]) == ["ok", "failed", "failed", "ok"]
    negative, nan = table["error"][1], table["error"][2]
    assert negative.startswith("SpringBlock 'block': parameter m = -1 is not allowed; m (")
    assert nan.startswith("SpringBlock 'block': parameter m = nan is not allowed; m (")
    assert "must be a finite number" in nan and "\n" not in negative + nan
    for m, t1 in zip((1.0, 2.0), table["t1"][[0, 3]]):
        assert float(t1) == pytest.approx(0.4 * m * 1.0 / (1.0 * 0.05), abs=1e-6)
    summary = json.loads((tmp_path / "sweep_stick_slip.json").read_text())
    assert summary["failed"] == 2
    assert summary["failed_runs"] == [{"run": 1, "error": negative}, {"run": 2, "error": nan}]
    assert summary["workers"] == 2
    assert (tmp_path / "sweep_stick_slip.png").read_bytes()[:4] == b"\x89PNG"
    assert "2 failed" in capsys.readouterr().out


def test_an_assembly_sweeps_in_process_and_reads_outputs_at_times(tmp_path):
    """workers=0 runs without Dask. Seed 9.2: between the first re-stick t2 and the next
    slip the block rests at x(t2), whatever the driver's speed; a 2 x 2 grid is a map."""
    asm = Assembly("dragged")
    asm.add("driver", ConstantSpeed(v=0.05))
    asm.add("block", SpringBlock(m=1, k=1, g=1, mu_k=0.3, mu_s=0.4))
    asm.connect("driver.flange", "block.flange_a")
    table = sweep(asm, {"driver.v": [0.05, 0.1], "block.mu_s": [0.4, 0.5]}, workers=0,
                  stop_time=40.0, step=0.1, tolerance=1e-10, progress=False, out=tmp_path,
                  measure=_rest_position)
    assert len(table) == 4 and set(table["status"]) == {"ok"}
    for _, row in table.iterrows():
        t1, t2, x2 = stick_slip_first_cycle(1, 1, 1, 0.3, row["block.mu_s"], row["driver.v"])
        assert row["x_rest"] == pytest.approx(x2, abs=1e-6)
    assert (tmp_path / "sweep_dragged.png").exists()


def _rest_position(result, values):
    """x just after the first re-stick: t2 + a tenth of the stick that follows."""
    t1, t2, x2 = stick_slip_first_cycle(1, 1, 1, 0.3, values["block.mu_s"], values["driver.v"])
    t = t2 + 0.1 * (x2 / values["driver.v"] - (t2 - t1))
    return {"x_rest": float(np.interp(t, result["time"], result["block.x"]))}


def test_a_latin_hypercube_puts_one_run_in_each_slice_of_each_range():
    runs = design({"driver.v": "0.02:0.1", "block.mu_s": "0.35:0.6", "block.m": "1"},
                  random=8, seed=3)
    assert len(runs) == 8 and all(r["block.m"] == "1" for r in runs)
    for name, (lo, hi) in {"driver.v": (0.02, 0.1), "block.mu_s": (0.35, 0.6)}.items():
        slices = sorted(int((r[name] - lo) / (hi - lo) * 8) for r in runs)
        assert slices == list(range(8))
    assert runs == design({"driver.v": "0.02:0.1", "block.mu_s": "0.35:0.6", "block.m": "1"},
                          random=8, seed=3)


@pytest.mark.parametrize("n_runs, n_workers", [(400, 2), (16, 2), (400, 16), (1, 4), (7, 3)])
def test_tasks_shrink_so_workers_finish_together(n_runs, n_workers):
    sizes = chunk_sizes(n_runs, n_workers)
    assert sum(sizes) == n_runs and min(sizes) >= 1
    assert all(a >= b for a, b in zip(sizes, sizes[1:]))  # long tasks go out first
    # no task is longer than half a worker's share, and the last ones are short
    assert sizes[0] <= max(1, math.ceil(n_runs / (2 * n_workers)))
    assert sizes[-1] <= max(1, n_runs // (n_workers * SMALLEST_SHARE))
    assert chunk_sizes(10, 2, chunk=3) == [3, 3, 3, 1]


@pytest.mark.parametrize("args, message", [
    (["--param", "block.mass=1:2:3"], "parameter 'block.mass': block has no 'mass'; settable: "),
    (["--param", "block.m=1:2:x"], "--param block.m=1:2:x: COUNT must be a whole number >= 1"),
    (["--param", "block.m=1:2", "--output", "block.y@max"],
     "output 'block.y@max': scene 'stick_slip' records time, block.x,"),
])
def test_a_study_that_cannot_start_is_one_line_and_exit_2(args, message, capsys):
    assert main(["sweep", "stick_slip", *args, "--workers", "1"]) == 2
    err = capsys.readouterr().err
    assert err.startswith(f"mechfmu: error: {message}") and err.count("\n") == 1


def test_refine_says_when_the_bracket_holds_no_change():
    with pytest.raises(SweepError, match="no change between"):
        refine("stick_slip", "block.m", 1.0, 2.0, lambda row: row["t1"] > 0, rounds=1,
               points=2, workers=0, progress=False)


def test_the_bar_counts_runs_on_a_terminal():
    import io

    from assemblies.progress import ProgressReport

    class Terminal(io.StringIO):
        def isatty(self):
            return True

    screen = Terminal()
    bar = ProgressReport(3, stream=screen, quiet_for=0.0, name="runs", unit="")
    sweep("stick_slip", {"block.m": [1.0, 1.5, 2.0]}, workers=0, progress=bar)
    bar.close()
    frames = screen.getvalue().split("\r")
    assert [f.split("] ")[1].split()[:5] for f in frames[1:]] == [
        ["runs", "=", "1", "/", "3"], ["runs", "=", "2", "/", "3"], ["runs", "=", "3", "/", "3"]]
    assert "[" + "#" * 30 + "] runs = 3 / 3 (100.0 %)" in screen.getvalue()
