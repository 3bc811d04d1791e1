"""`make docs`: the API reference is generated from the docstrings (pdoc, docs/build_api.py),
a page for every public module, and writing it compiles nothing."""
from __future__ import annotations

import ast
import html
import os
import re
import shutil
import subprocess
import sys
from pathlib import Path

import pytest

ROOT = Path(__file__).resolve().parents[2]
sys.path.insert(0, str(ROOT / "docs"))
from build_api import public_modules  # noqa: E402

pytest.importorskip("pdoc", reason="pdoc comes with the test extra: pip install -e '.[test]'")


def page_text(path: Path) -> str:
    """What a reader sees of a page: tags, entities and markup quotes gone, spaces folded."""
    text = html.unescape(re.sub(r"<[^>]+>", " ", path.read_text()))
    return " ".join(text.replace("`", "").split())


def first_line(docstring: str) -> str:
    return " ".join(docstring.strip().split("\n\n")[0].replace("`", "").split())


@pytest.fixture(scope="module")
def api(tmp_path_factory):
    """The reference, written as `make docs` writes it, with an empty cache and no gcc on
    PATH: importing the modules must not build an FMU or the engine."""
    tmp = tmp_path_factory.mktemp("docs")
    bare = tmp / "bin"
    bare.mkdir()
    env = {**os.environ, "PYTHONPATH": str(ROOT), "MECHFMU_CACHE": str(tmp / "cache"),
           "PATH": str(bare)}
    venv = Path(sys.prefix)
    if (venv / ".installed").exists() and shutil.which("make"):
        # the target itself, on the environment `make test` set up (CI's): make alone on PATH
        (bare / "make").symlink_to(shutil.which("make"))
        # (-o: the environment is taken as it is, never set up again from a newer pyproject)
        command = ["make", "-s", "-o", f"{venv}/.installed", "docs", f"VENV={venv}",
                   f"DOCS_OUT={tmp / 'api'}"]
    else:  # an environment make did not set up: the command the target runs
        command = [sys.executable, "docs/build_api.py", str(tmp / "api")]
    done = subprocess.run(command, cwd=ROOT, env=env, capture_output=True, text=True,
                          timeout=300)
    assert done.returncode == 0, done.stderr
    assert not (tmp / "cache").exists(), "writing the docs built something into the cache"
    return tmp / "api"


def test_make_docs_runs_the_same_command():
    makefile = (ROOT / "Makefile").read_text()
    assert re.search(r"^DOCS_OUT \?= docs/api\ndocs: .*\n\t\$\(PY\) docs/build_api\.py "
                     r"\$\(DOCS_OUT\)$", makefile, re.M)
    assert "docs/api/" in (ROOT / ".gitignore").read_text().split()


def test_every_public_module_has_its_page_with_its_docstring(api):
    modules = public_modules()
    assert {"components", "fmus", "assemblies", "assemblies.run", "fmus.build",
            "assemblies.engine", "components.translational.spring_block"} <= set(modules)
    assert not any("._" in m for m in modules)
    for module in modules:
        path = ROOT / module.replace(".", "/")
        source = path / "__init__.py" if path.is_dir() else path.with_suffix(".py")
        page = api / (module.replace(".", "/") + ".html")
        assert page.exists(), f"no page for {module}"
        doc = ast.get_docstring(ast.parse(source.read_text()))
        if doc:
            assert first_line(doc)[:60] in page_text(page), f"{module}: docstring not on its page"
    index = page_text(api / "index.html")
    assert all(top in index for top in ("components", "fmus", "assemblies"))


def test_the_functions_a_user_calls_are_documented(api):
    """The members, not only the modules: the run functions and a component class."""
    from assemblies.run import run_scene
    from components.translational.spring_block import SpringBlock
    from fmus.build import build_fmu
    for page, obj in (("assemblies/run.html", run_scene), ("fmus/build.html", build_fmu),
                      ("components/translational/spring_block.html", SpringBlock)):
        text = page_text(api / page)
        assert obj.__name__ in text and first_line(obj.__doc__) in text, (page, obj.__name__)
