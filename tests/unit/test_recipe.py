"""The recipe key of an FMU (fmus.recipe): every ingredient that shapes the FMU changes
it, what is set at run time does not, and a class made at run time has none. A stale
FMU served from the cache would be a wrong result, so each ingredient is changed alone."""
from __future__ import annotations

import shutil
import subprocess
import sys
import textwrap

import casadi
import pytest

import fmus.codegen
from assemblies.engine.prepare import class_defaults
from components import SpringBlock
from fmus import build
from fmus.build import fmu_recipe


def test_a_structural_option_is_a_new_fmu():
    assert fmu_recipe(SpringBlock(friction="smooth")) != fmu_recipe(SpringBlock())
    assert fmu_recipe(SpringBlock(friction="smooth")) == fmu_recipe(SpringBlock(friction="smooth"))


def test_the_fmi_version_and_profile_are_in_the_key():
    assert fmu_recipe(SpringBlock(), fmi_version=2) != fmu_recipe(SpringBlock(), fmi_version=3)
    moving = SpringBlock(profile="driven_on_moving_support")
    assert fmu_recipe(moving) != fmu_recipe(SpringBlock())


def test_values_baked_as_starts_are_in_the_key_but_not_in_the_runs_one():
    # build_fmu bakes the instance's values into the FMU as start values: another FMU
    assert fmu_recipe(SpringBlock(mu_s=0.5)) != fmu_recipe(SpringBlock())
    assert fmu_recipe(SpringBlock(x=1.0)) != fmu_recipe(SpringBlock())
    # a run builds the class defaults and sets values at run time: one binary for all
    assert fmu_recipe(class_defaults(SpringBlock(mu_s=0.5, x=1.0))) == fmu_recipe(SpringBlock())


def test_the_instance_name_is_not_in_the_key():
    # no generated file mentions it (the model is named by its class)
    assert fmu_recipe(SpringBlock(name="a")) == fmu_recipe(SpringBlock(name="b"))


def test_an_edited_runtime_source_is_a_new_fmu(tmp_path, monkeypatch):
    runtime = tmp_path / "runtime"
    shutil.copytree(build.RUNTIME_DIR, runtime)
    monkeypatch.setattr(build, "RUNTIME_DIR", runtime)
    before = fmu_recipe(SpringBlock())
    solver = runtime / "solver.c"
    solver.write_text(solver.read_text() + "\n/* edited */\n")
    assert fmu_recipe(SpringBlock()) != before


def test_an_edited_code_generator_is_a_new_fmu(tmp_path, monkeypatch):
    copy = tmp_path / "codegen.py"
    shutil.copyfile(fmus.codegen.__file__, copy)
    monkeypatch.setattr(fmus.codegen, "__file__", str(copy))
    before = fmu_recipe(SpringBlock())
    copy.write_text(copy.read_text() + "\n# edited\n")
    assert fmu_recipe(SpringBlock()) != before


def test_another_casadi_is_a_new_fmu(monkeypatch):
    import fmus.recipe
    before = fmu_recipe(SpringBlock())
    # the version as read from the installed distribution's metadata, not from the module
    monkeypatch.setitem(fmus.recipe._installed, "casadi", casadi.__version__ + ".post1")
    assert fmu_recipe(SpringBlock()) != before


def test_the_key_does_not_depend_on_what_is_imported_yet():
    """A cached run loads neither CasADi nor scipy; the build that filed its FMU did. The
    same component must key the same in both, and the installed CasADi's version is in
    the key either way (read from its metadata, not from the module)."""
    script = ("import sys, fmus.recipe; from components import SpringBlock; from fmus.build import "
              "fmu_recipe; key = fmu_recipe(SpringBlock()); "
              "print('casadi' in sys.modules, key, [v for v in fmus.recipe._versions({'casadi'})])")
    if_loaded = subprocess.run([sys.executable, "-c", "import casadi, scipy; " + script],
                               capture_output=True, text=True, check=True).stdout.split(" ", 1)
    lazily = subprocess.run([sys.executable, "-c", script], capture_output=True, text=True,
                            check=True).stdout.split(" ", 1)
    assert if_loaded[0] == "True" and lazily[0] == "False"
    assert if_loaded[1] == lazily[1]
    assert f"casadi=={casadi.__version__}" in lazily[1]


@pytest.fixture
def widget_package(tmp_path, monkeypatch):
    """A component in a package of its own whose equations come from a helper module
    imported inside a function: the recipe must follow that import too."""
    package = tmp_path / "widgetpkg"
    package.mkdir()
    (package / "__init__.py").write_text("")
    (package / "helper.py").write_text("GAIN = 2.0\n")
    (package / "widget.py").write_text(textwrap.dedent('''
        from components import Component
        from components.interfaces import Parameter, Profile, State

        class Widget(Component):
            """A first-order lag."""
            parameters = (Parameter("a", 1.0, "1/s", "rate"),)
            states = (State("x", 1.0, "m", "state"),)
            profiles = (Profile("free", "no ports"),)

            def equations(self, e):
                from .helper import GAIN
                e.residual(e.der.x + GAIN * e.p.a * e.x.x)
        '''))
    monkeypatch.syspath_prepend(str(tmp_path))
    yield package
    for name in [m for m in sys.modules if m.startswith("widgetpkg")]:
        del sys.modules[name]


def test_an_edited_module_the_class_builds_on_is_a_new_fmu(widget_package):
    from widgetpkg.widget import Widget
    before = fmu_recipe(Widget())
    (widget_package / "helper.py").write_text("GAIN = 3.0\n")
    assert fmu_recipe(Widget()) != before


def test_a_class_made_at_run_time_has_no_recipe():
    def make(gain):
        class Local(SpringBlock):
            pass
        return Local
    assert fmu_recipe(make(1.0)()) is None
    made = type("Made", (SpringBlock,), {})
    assert fmu_recipe(made()) is None
