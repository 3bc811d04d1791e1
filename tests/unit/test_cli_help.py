"""What `mechfmu` says about itself: a version, help on every option, the scene list in
run's help, a component's parameter sheet."""
import argparse
from importlib.metadata import version

import pytest

from assemblies.cli import _parser, main
from assemblies.scene_names import SCENE_NAMES


def _subparsers(parser):
    action = next(a for a in parser._actions if isinstance(a, argparse._SubParsersAction))
    return action.choices


def test_every_option_and_argument_has_help():
    parser = _parser()
    for name, sub in {"": parser, **_subparsers(parser)}.items():
        for action in sub._actions:
            if isinstance(action, argparse._SubParsersAction):
                continue
            assert action.help, f"mechfmu {name}: {action.dest} has no help text"


def test_version(capsys):
    with pytest.raises(SystemExit) as caught:
        main(["--version"])
    assert caught.value.code == 0
    assert capsys.readouterr().out.strip() == f"mechfmu {version('mechfmu')}"


def test_run_help_lists_every_scene(capsys):
    with pytest.raises(SystemExit):
        main(["run", "--help"])
    text = " ".join(capsys.readouterr().out.split())  # argparse wraps the list
    assert "scenes: " + ", ".join(SCENE_NAMES) in text


def test_show_lists_parameters_with_unit_default_range_and_meaning(capsys):
    assert main(["show", "SpringBlock"]) == 0
    lines = capsys.readouterr().out.splitlines()
    # SpringBlock's declarations (components/translational/spring_block.py): m > 0 kg, default 1;
    # mu_s >= 0, default 0.4, no unit; the friction option's three laws; both profiles
    assert lines[0].startswith("SpringBlock: Block on a")
    m = next(line.split() for line in lines if line.split()[:1] == ["m"])
    assert m[:4] == ["m", "1", "kg", "(0,"] and m[4] == "inf)" and "mass" in m
    mu_s = next(line.split() for line in lines if line.split()[:1] == ["mu_s"])
    assert mu_s[:5] == ["mu_s", "0.4", "1", "[0,", "inf)"]
    assert any(line.strip().startswith("friction = coulomb (one of coulomb, smooth, tanh)")
               for line in lines)
    assert any(line.strip().startswith("driven_on_moving_support:") for line in lines)
