"""Bad input, from the command line and from Python: one line naming what is wrong and what
is allowed; exit 2 from `mechfmu`, one of our errors (a ValueError where it is a value)
from the API, the same message from both. Every case here is refused before any FMU is
built or run, so the module costs no build."""
from __future__ import annotations

import subprocess
import sys

import pytest

from assemblies import Assembly, composite, cosimulate, run_scene, scene, simulate_me
from conftest import cli, one_line_error  # noqa: F401 (test_limits imports them from here)
from components import SpringBlock
from components.errors import MechfmuError
from fmus import build_fmu


# (command line, the words its one line must hold: what is wrong and what is allowed)
CLI_ONLY = [
    (["run", "stick_slip", "--out", "/etc/passwd"], ["--out /etc/passwd is a file", "a folder"]),
    (["build", "SpringBlock", "-o", "/proc/x.fmu"], ["/proc/x.fmu", "cannot write", ".fmu path"]),
    (["export", "stick_slip", "--ssp", "/proc/x.ssp"], ["/proc/x.ssp", "cannot write", ".ssp path"]),
    (["export", "stick_slip"], ["--ssp FILE.ssp", "--fmu FILE.fmu", "--composite FILE.fmu"]),
    (["run", "no_such_scene"], ["unknown scene 'no_such_scene'", "stick_slip"]),
    (["run"], ["required: scene"]),
    (["run", "stick_slip", "--mode", "cosmic"], ["--mode", "'cosim'", "'me'"]),
    (["run", "stick_slip", "--stop-time", "ten"], ["--stop-time", "'ten'"]),
    (["bench", "friction_damping"], ["no work-precision case", "stick_slip"]),
    (["show", "Flywheel"], ["unknown component 'Flywheel'", "SpringBlock"]),
]


@pytest.mark.parametrize("argv, words", CLI_ONLY, ids=[" ".join(a) for a, _ in CLI_ONLY])
def test_command_line_mistakes_are_one_line(capsys, argv, words):
    one_line_error(capsys, argv, words)


def test_an_existing_folder_is_not_an_fmu_file(capsys, tmp_path):
    one_line_error(capsys, ["build", "SpringBlock", "-o", str(tmp_path)],
                   [f"{tmp_path} is a folder", "the .fmu file to write"])
    assert list(tmp_path.iterdir()) == []


# (Python call, the same input on the command line or None, words of the message, ValueError?)
STICK_SLIP = scene("stick_slip").build
API = [
    (lambda: cosimulate(STICK_SLIP(), stop_time="10", step=0.1), None,
     ["stop time", "positive finite number", "str '10'"]),
    (lambda: cosimulate(STICK_SLIP(), stop_time=10, step=None), None,
     ["communication step", "positive finite number", "None"]),
    (lambda: simulate_me(STICK_SLIP(), stop_time=10, step=None), None,
     ["output step", "positive finite number"]),
    (lambda: Assembly("x").add("x", 42), None, ["instance 'x' must be a component", "int 42"]),
    (lambda: run_scene("stick_slip", params="block.m=2"), None,
     ["params must be a dict", "'block.m'", "str 'block.m=2'"]),
    (lambda: build_fmu("SpringBlock"), None, ["component must be a component instance",
                                              "SpringBlock()", "str 'SpringBlock'"]),
    (lambda: build_fmu(SpringBlock(), "/proc/x.fmu"), None,
     ["build_fmu: output /proc/x.fmu", "cannot write", ".fmu path"]),
    (lambda: build_fmu(SpringBlock(), "/"), None, ["build_fmu: output / is a folder"]),
    (lambda: composite(Assembly("a/b")), None, ["assembly name 'a/b'", "identifier"]),
    (lambda: composite(Assembly("empty")), None, ["'empty' has no instances", "Assembly.add"]),
    (lambda: cosimulate(Assembly("empty"), 1.0, 0.1), None, ["'empty' has no instances"]),
    (lambda: simulate_me(Assembly("empty"), 1.0, 0.1), None, ["'empty' has no instances"]),
    (lambda: run_scene("stick_slip", tolerance=1e-300),
     ["run", "stick_slip", "--tolerance", "1e-300"], ["tolerance", "[1e-14, 1)", "1e-300"]),
    (lambda: run_scene("stick_slip", tolerance=0.0),
     ["run", "stick_slip", "--tolerance", "0"], ["tolerance", "[1e-14, 1)"]),
    (lambda: run_scene("stick_slip", adaptive=0.0),
     ["run", "stick_slip", "--adaptive", "0"], ["adaptive tolerance", "(0, 1)", "--fixed-step"]),
    (lambda: run_scene("stick_slip", mode="me", scheme="gauss-seidel"),
     ["run", "stick_slip", "--mode", "me", "--scheme", "gauss-seidel"],
     ["scheme (--scheme)", "mode 'cosim' only", "'me'"]),
    (lambda: run_scene("stick_slip", mode="me", adaptive=1e-6),
     ["run", "stick_slip", "--mode", "me", "--adaptive", "1e-6"],
     ["--adaptive/--fixed-step", "mode 'cosim' only", "'me'"]),
    (lambda: run_scene("stick_slip", mode="monolithic", adaptive=False),
     ["run", "stick_slip", "--mode", "monolithic", "--fixed-step"],
     ["--adaptive/--fixed-step", "mode 'cosim' only", "'monolithic'"]),
    (lambda: run_scene("stick_slip", mode="me", extrapolation=2),
     ["run", "stick_slip", "--mode", "me", "--extrapolation", "2"],
     ["--extrapolation", "mode 'cosim' only"]),
    (lambda: run_scene("stick_slip", params={"block.m": -1}),
     ["run", "stick_slip", "--param", "block.m=-1"], ["block", "m", "> 0"]),
]


@pytest.mark.parametrize("call, argv, words", API, ids=range(len(API)))
def test_api_mistakes_raise_our_value_error(capsys, call, argv, words):
    with pytest.raises(MechfmuError) as caught:
        call()
    assert isinstance(caught.value, ValueError)
    message = str(caught.value)
    assert "\n" not in message
    for word in words:
        assert word in message, (word, message)
    if argv is not None:  # the command line says the same thing
        assert one_line_error(capsys, argv, words) == f"mechfmu: error: {message}"


def test_build_fmu_refuses_a_bad_tolerance_and_writes_nothing(tmp_path):
    target = tmp_path / "b.fmu"
    for bad in (-1, 0.0, 1.0, float("nan"), "1e-6"):
        with pytest.raises(MechfmuError, match=r"build_fmu: tolerance must be .*\[1e-14, 1\)"):
            build_fmu(SpringBlock(), target, tolerance=bad)
    assert not target.exists()


def test_help_and_argparse_errors_load_nothing_heavy():
    """`import assemblies.cli` and `mechfmu --help` load neither CasADi, numpy nor fmpy: the
    command answers at once (measured: README / the report); a bad option is one line."""
    probe = ("import sys; import assemblies.cli as c\n"
             "heavy = [m for m in ('casadi', 'numpy', 'fmpy', 'matplotlib') if m in sys.modules]\n"
             "print(heavy)\n"
             "try:\n    c.main(['run', 'stick_slip', '--stop-time'])\n"
             "except SystemExit as e:\n    print('exit', e.code)\n"
             "print([m for m in ('casadi', 'numpy', 'fmpy') if m in sys.modules])\n")
    proc = subprocess.run([sys.executable, "-c", probe], capture_output=True, text=True)
    out = proc.stdout.splitlines()
    assert out == ["[]", "exit 2", "[]"], proc.stdout + proc.stderr
    assert proc.stderr.strip().splitlines() == [
        "mechfmu run: error: argument --stop-time: expected one argument "
        "(see mechfmu run --help)"]


def test_a_bad_input_through_the_installed_entry_point_has_no_traceback(tmp_path):
    """One run through a fresh interpreter, as a user would: exit 2, one line."""
    proc = subprocess.run([sys.executable, "-m", "assemblies.cli", "build", "SpringBlock",
                           "-o", str(tmp_path)], capture_output=True, text=True)
    assert proc.returncode == 2
    assert proc.stderr.strip().splitlines() == [
        f"mechfmu: error: -o/--output {tmp_path} is a folder; -o/--output takes the .fmu file "
        "to write"]
