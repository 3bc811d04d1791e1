"""Each command imports what it needs, and not the heavy rest (issue 26).

CasADi, scipy, matplotlib, fmpy, pandas and Dask take 0.05-0.6 s each to load; a
command that loads what it never uses makes a user (or a script calling it a hundred
times) wait for imports, not for physics. Each path runs in a fresh interpreter, and the
modules loaded at its end are held to what it needs: CasADi only to write equations
(a build, a flattening), matplotlib only for a plot, scipy only for the references of a
figure that uses it, fmpy and the Python masters only with ``--engine fmpy``. The times
are `python -m benchmarks.startup`'s; nothing here is timed.
"""
from __future__ import annotations

import json
import os
import subprocess
import sys
from pathlib import Path

import pytest

ROOT = Path(__file__).resolve().parents[2]
HEAVY = ("numpy", "casadi", "scipy", "matplotlib", "fmpy", "pandas", "dask", "distributed",
         "pythonfmu")
# the Python reference masters (fmpy, scipy's integrators); masters.loops and
# masters.extrapolation are plain numpy helpers the compiled engine shares
MASTERS = ("assemblies.masters.cosim", "assemblies.masters.me", "assemblies.masters.hybrid",
           "assemblies.masters.monolithic")

_REPORT = """
import json, sys
watched = {watched!r}
try:
{body}
finally:
    print("\\nLOADED " + json.dumps(sorted(m for m in watched if m in sys.modules)))
"""


def _loaded(body: str) -> set[str]:
    """The heavy modules (and masters) loaded by the end of `body`, run in a fresh
    interpreter with this checkout first on the path."""
    env = dict(os.environ, PYTHONPATH=os.pathsep.join(
        p for p in (str(ROOT), os.environ.get("PYTHONPATH")) if p))
    script = _REPORT.format(watched=[*HEAVY, *MASTERS],
                            body="\n".join("    " + line for line in body.splitlines()))
    done = subprocess.run([sys.executable, "-c", script], cwd=ROOT, env=env,
                          capture_output=True, text=True, timeout=300)
    lines = [line for line in done.stdout.splitlines() if line.startswith("LOADED ")]
    assert lines, f"no report: {done.stderr[-2000:]}"
    assert done.returncode == 0, done.stderr[-2000:]
    return set(json.loads(lines[-1][len("LOADED "):]))


def _command(*argv: str, codes=(0,)) -> set[str]:
    body = (f"from assemblies.cli import main\n"
            f"try:\n    code = main({list(argv)!r})\n"
            f"except SystemExit as exc:\n    code = exc.code\n"
            f"assert code in {tuple(codes)!r}, code")
    return _loaded(body)


@pytest.fixture(scope="module")
def cached(tmp_path_factory):
    """stick_slip run once, so that its FMUs are built and filed: what follows is a run
    of a cached scene (a first build loads CasADi, as it must)."""
    out = tmp_path_factory.mktemp("warm")
    _command("run", "stick_slip", "--no-plot", "--out", str(out))
    return out


def test_help_and_the_bare_packages_load_nothing_heavy():
    assert _command("--help") == set()
    assert _command("run", "--help") == set()
    assert _loaded("import assemblies, components, components.errors") == set()


def test_scenes_lists_without_importing_a_scene():
    assert _command("scenes") == set()


@pytest.mark.parametrize("argv", [("components",), ("show", "SpringBlock"),
                                  ("show", "AssumedModesBeam")])
def test_components_and_show_read_the_classes_not_their_equations(argv):
    # declarations only: no equation written (CasADi), no array made (numpy)
    assert _command(*argv) == set()


def test_a_cached_run_without_a_plot_needs_numpy_and_the_engine_only(cached, tmp_path):
    assert _command("run", "stick_slip", "--no-plot", "--out", str(tmp_path)) == {"numpy"}
    assert sorted(p.name for p in tmp_path.iterdir()) == ["stick_slip.csv", "stick_slip.json"]


def test_the_python_api_without_a_plot_is_as_light(cached, tmp_path):
    assert _loaded(f"import assemblies\nassemblies.run_scene('stick_slip', out={str(tmp_path)!r}, "
                   f"plot=False)") == {"numpy"}
    assert not (tmp_path / "stick_slip.png").exists()


def test_a_plot_adds_matplotlib_and_nothing_else(cached, tmp_path):
    assert _command("run", "stick_slip", "--out", str(tmp_path)) == {"numpy", "matplotlib"}
    assert (tmp_path / "stick_slip.png").stat().st_size > 0


def test_the_fmpy_engine_loads_fmpy_and_the_python_masters(cached, tmp_path):
    # a short run: its figures need the whole one (exit 1), the imports do not
    loaded = _command("run", "stick_slip", "--no-plot", "--engine", "fmpy", "--stop-time", "2",
                      "--out", str(tmp_path), codes=(0, 1))
    assert {"fmpy", "assemblies.masters.cosim"} <= loaded
    assert "matplotlib" not in loaded


def test_no_plot_says_so_and_writes_no_png(cached, tmp_path, capsys):
    from assemblies.cli import main
    assert main(["run", "stick_slip", "--no-plot", "--out", str(tmp_path)]) == 0
    wrote = [line for line in capsys.readouterr().out.splitlines() if line.startswith("wrote ")]
    assert wrote == [f"wrote {tmp_path / 'stick_slip.csv'}, {tmp_path / 'stick_slip.json'} "
                     "(no plot: --no-plot)"]
    assert not (tmp_path / "stick_slip.png").exists()
