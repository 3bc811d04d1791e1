"""A run stopped early (`--stop-time` short of the scene's) is measured like any other: a
figure with nothing to measure is NaN and FAILs, and the run's files are written (issue 26:
resonance_growth, resonance_below and moving_table ended in an IndexError or TypeError
traceback from their figures at --stop-time 0.3 or 2)."""
from __future__ import annotations

import math
import warnings

import pytest

from assemblies.cli import main
from assemblies.run import run_scene_full
from assemblies.scenes import SCENES


@pytest.mark.parametrize("name", list(SCENES))
def test_every_scene_stopped_early_is_judged_not_crashed(name):
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")  # a foreign member's own warnings are not the point
        run = run_scene_full(name, stop_time=min(0.3, SCENES[name].stop_time))
    assert run.figures and run.verdict()
    for f in run.failed:  # a failed figure says so, NaN included
        assert not f.passed and (math.isnan(f.measured) or math.isnan(f.error)
                                 or f.error > f.bound or not math.isfinite(f.bound))


@pytest.mark.parametrize("name, stop", [("resonance_growth", "2"), ("resonance_below", "2"),
                                        ("moving_table", "0.3")])
def test_the_command_writes_a_short_run_and_exits_1(name, stop, tmp_path, capsys):
    assert main(["run", name, "--stop-time", stop, "--out", str(tmp_path)]) == 1
    out = capsys.readouterr()
    assert "Traceback" not in out.err and out.out.splitlines()[-1].startswith("FAILED")
    assert sorted(p.suffix for p in tmp_path.iterdir()) == [".csv", ".json", ".png"]
