"""One default FMI version, 3, for every command and function that writes an FMU (issue 26:
`build` wrote FMI 3 and `export --fmu`/`--composite` FMI 2). Read from the files written,
as an importer reads them (fmpy's read_model_description), not from our signatures."""
from __future__ import annotations

import inspect

from fmpy import read_model_description

from assemblies import export_fmu, scene
from assemblies.cli import _parser, main
from fmus import build_fmu
from fmus.model_description import DEFAULT_FMI
from components import SpringBlock


def _version(path) -> str:
    return read_model_description(str(path), validate=False).fmiVersion


def test_every_command_writes_fmi_3_unless_told(tmp_path, capsys):
    build, fmu, composite = tmp_path / "b.fmu", tmp_path / "a.fmu", tmp_path / "c.fmu"
    assert main(["build", "SpringBlock", "-o", str(build)]) == 0
    assert main(["export", "stick_slip", "--fmu", str(fmu), "--composite", str(composite)]) == 0
    assert [_version(p) for p in (build, fmu, composite)] == ["3.0"] * 3
    # and FMI 2 where asked for
    assert main(["export", "stick_slip", "--fmu", str(fmu), "--fmi", "2"]) == 0
    assert _version(fmu) == "2.0"


def test_every_function_writes_fmi_3_unless_told(tmp_path):
    assert _version(build_fmu(SpringBlock(), tmp_path / "b.fmu")) == "3.0"
    assert _version(export_fmu(scene("stick_slip").build(), tmp_path / "a.fmu")) == "3.0"
    for fn, name in ((build_fmu, "fmi_version"), (export_fmu, "fmi")):
        assert inspect.signature(fn).parameters[name].default == DEFAULT_FMI == 3


def test_the_help_states_the_default(capsys):
    for command in ("build", "export"):
        sub = _parser()._subparsers._group_actions[0].choices[command]
        fmi = next(a for a in sub._actions if a.dest == "fmi")
        assert fmi.default == DEFAULT_FMI and "default: 3" in fmi.help
