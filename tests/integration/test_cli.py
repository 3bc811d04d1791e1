"""The `mechfmu` command: listings, a scene run's files, and one-line errors."""
import json
import subprocess
import sys

import pytest

from assemblies import Assembly, AssemblyError
from components import COMPONENTS, ConstantSpeed, SpringBlock


def mechfmu(*args, cwd=None):
    return subprocess.run([sys.executable, "-m", "assemblies.cli", *args], capture_output=True,
                          text=True, cwd=cwd)


def test_listings_name_what_build_and_run_take():
    comps = mechfmu("components")
    assert comps.returncode == 0
    assert [line.split()[0] for line in comps.stdout.splitlines()] == list(COMPONENTS)
    scenes = mechfmu("scenes")
    assert scenes.returncode == 0
    assert {line.split()[0] for line in scenes.stdout.splitlines()} >= {"stick_slip", "friction_damping"}


def test_run_writes_csv_png_json(tmp_path):
    proc = mechfmu("run", "stick_slip", "--stop-time", "14", "--step", "0.5",
                   "--param", "block.mu_k=0.3", "--out", str(tmp_path))
    assert proc.returncode == 0, proc.stderr
    assert "t2" in proc.stdout and "x(t2)" in proc.stdout
    header = (tmp_path / "stick_slip.csv").read_text().splitlines()[0].split(",")
    assert header[0] == "time" and "block.x" in header and "block.v" in header
    summary = json.loads((tmp_path / "stick_slip.json").read_text())
    errors = {f["name"]: f["error"] for f in summary["figures"]}
    assert errors["t1"] < 1e-6 and errors["t2"] < 1e-6 and errors["x(t2)"] < 1e-6
    assert summary["settings"]["step"] == 0.5 and summary["settings"]["wall_s"] > 0
    assert (tmp_path / "stick_slip.png").read_bytes()[:8] == b"\x89PNG\r\n\x1a\n"
    # closed forms against located events: each stated to the solver's tolerance
    assert summary["passed"] is True
    assert all(f["passed"] and 0 < f["accuracy"] <= 1e-6 for f in summary["figures"])
    assert proc.stdout.splitlines()[-1] == "all 3 figures pass"


def test_a_figure_outside_its_accuracy_fails_the_run(tmp_path):
    # stopped at 10 s, before the re-stick at t2 = 12.07 s: t2 and x(t2) are not measured
    proc = mechfmu("run", "stick_slip", "--stop-time", "10", "--out", str(tmp_path))
    assert proc.returncode == 1, proc.stderr  # not 2: the input was fine, the figures not
    lines = proc.stdout.splitlines()
    assert lines[-1] == "FAILED: 2 of 3 figures outside their accuracy: t2, x(t2)"
    rows = {line.split()[0]: line.split() for line in lines[1:4]}
    assert rows["t1"][5] == "pass" and rows["t2"][5] == "FAIL" and rows["x(t2)"][5] == "FAIL"
    assert rows["t2"][1] == "nan"
    summary = json.loads((tmp_path / "stick_slip.json").read_text())
    assert summary["passed"] is False
    assert [f["passed"] for f in summary["figures"]] == [True, False, False]


def test_build_writes_an_fmu(tmp_path):
    proc = mechfmu("build", "SpringBlock", "-o", str(tmp_path / "b.fmu"), "--param", "friction=tanh")
    assert proc.returncode == 0, proc.stderr
    assert (tmp_path / "b.fmu").exists()


@pytest.mark.parametrize("args, words", [
    (["run", "stick_slip", "--param", "block.m=-1"], ["block", "m", "> 0"]),
    (["run", "stick_slip", "--param", "block.mu_s=0.1"], ["mu_k <= mu_s"]),
    (["run", "stick_slip", "--param", "block.eps=0"], ["eps", "> 0"]),
    (["run", "stick_slip", "--param", "block.k=nan"], ["k", ">= 0"]),
    (["run", "no_such_scene"], ["unknown scene", "stick_slip"]),
    (["run", "stick_slip", "--param", "block.mass=2"], ["unknown name 'mass'", "settable"]),
    (["run", "stick_slip", "--param", "blok.m=2"], ["no instance 'blok'", "block"]),
    (["run", "stick_slip", "--param", "m=2"], ["INSTANCE.NAME"]),
    (["run", "stick_slip", "--step", "-0.1"], ["communication step", "positive"]),
    (["run", "stick_slip", "--tolerance", "0"], ["tolerance"]),
    (["build", "Flywheel", "-o", "x.fmu"], ["unknown component", "SpringBlock"]),
    (["build", "SpringBlock", "-o", "x.fmu", "--param", "friction=viscous"], ["friction", "coulomb"]),
])
def test_bad_input_is_one_line_and_nonzero(args, words, tmp_path):
    proc = mechfmu(*args, cwd=tmp_path)
    assert proc.returncode != 0
    assert "Traceback" not in proc.stderr
    lines = proc.stderr.strip().splitlines()
    assert len(lines) == 1, proc.stderr
    for word in words:
        assert word in lines[0]


def test_incompatible_connections_name_the_ports():
    asm = Assembly("bad")
    asm.add("a", SpringBlock())
    asm.add("b", SpringBlock(profile="driven"))  # named, so its support stays grounded
    asm.add("drv", ConstantSpeed())
    with pytest.raises(AssemblyError, match=r"a.flange_a \(motion\) to b.flange_a \(motion\)"):
        asm.connect("a.flange_a", "b.flange_a")
    with pytest.raises(AssemblyError, match=r"b.support is grounded"):
        asm.connect("drv.flange", "b.support")
    with pytest.raises(AssemblyError, match=r"has no port 'flange_b'; ports: flange_a, support"):
        asm.connect("drv.flange", "a.flange_b")
