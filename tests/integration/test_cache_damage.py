"""A damaged cache (issue 25): every cached library and FMU is checked against the
checksum its build recorded before it is used; a damaged one is rebuilt (or extracted
again) and said once, and the run goes on as if nothing happened.

Before: a truncated cached library crashed every later run with SIGBUS and no output, a
garbage engine library was an OSError traceback, and a truncated cached FMU was copied
out by `mechfmu build -o` with exit 0. Every run here is a fresh process on a cache of
its own (a crash must not take the test run with it, nor damage the shared cache)."""
from __future__ import annotations

import ctypes
import os
import shutil
import subprocess
import sys
import warnings
import zipfile
from pathlib import Path

import pytest
from fmpy.validation import validate_fmu

from fmus import integrity
from fmus.build import cached_library


@pytest.fixture(autouse=True)
def warnings_not_printed(monkeypatch):
    """A repair is a CacheRepaired warning in Python: `mechfmu`'s main, run in-process by
    other test files, leaves fmus.build.announce printing to stderr instead."""
    import fmus.build
    monkeypatch.setattr(fmus.build, "announce", None)


def truncate(path: Path, keep: float = 0.4) -> None:
    data = path.read_bytes()
    path.write_bytes(data[:int(len(data) * keep)])


# --- a library of the cache, by itself ------------------------------------------------
def _tiny(tmp_path) -> Path:
    source = tmp_path / "tiny.c"
    source.write_text("__attribute__((visibility(\"default\"))) int answer(void) { return 42; }\n")
    return source


def _load_in_child(path: Path) -> subprocess.CompletedProcess:
    code = f"import ctypes; print(ctypes.CDLL({str(path)!r}).answer())"
    return subprocess.run([sys.executable, "-c", code], capture_output=True, text=True)


@pytest.mark.parametrize("damage", ["truncated", "garbage"])
def test_a_damaged_library_is_rebuilt_once_and_loads(tmp_path, monkeypatch, damage):
    monkeypatch.setenv("MECHFMU_CACHE", str(tmp_path / "cache"))
    source = _tiny(tmp_path)
    path = cached_library("hpy", "libtiny", [source], [], "the tiny library")
    assert _load_in_child(path).stdout.strip() == "42"
    if damage == "truncated":
        truncate(path)
    else:
        path.write_bytes(b"this is not a shared library\n" * 100)
    with pytest.warns(integrity.CacheRepaired, match=r"the cached library of the tiny "
                      r"library .*libtiny-.*\.so was damaged .*; rebuilding it"):
        again = cached_library("hpy", "libtiny", [source], [], "the tiny library")
    assert again == path
    child = _load_in_child(path)
    assert child.returncode == 0 and child.stdout.strip() == "42", child.stderr[-300:]
    with warnings.catch_warnings():
        warnings.simplefilter("error")  # intact now: no second word about it
        assert cached_library("hpy", "libtiny", [source], [], "the tiny library") == path


def test_an_intact_library_is_neither_rebuilt_nor_rehashed_twice(tmp_path, monkeypatch):
    """A library from before checksums were recorded is trusted when its ELF file is all
    there, and recorded then; one truncated without a record is rebuilt."""
    monkeypatch.setenv("MECHFMU_CACHE", str(tmp_path / "cache"))
    source = _tiny(tmp_path)
    path = cached_library("hpy", "libtiny", [source], [], "the tiny library")
    record = path.with_name(path.name + integrity.SUFFIX)
    record.unlink()
    built = path.stat().st_mtime_ns
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        assert cached_library("hpy", "libtiny", [source], [], "the tiny library") == path
    assert path.stat().st_mtime_ns == built and record.exists()
    record.unlink()
    truncate(path)
    with pytest.warns(integrity.CacheRepaired):
        cached_library("hpy", "libtiny", [source], [], "the tiny library")
    assert _load_in_child(path).stdout.strip() == "42"


# --- the command line on a damaged cache --------------------------------------------------
@pytest.fixture
def own_cache(tmp_path):
    """A cache of its own holding the engine library (copied from the usual cache, where
    it is built once per machine; an FMU build here costs seconds)."""
    from assemblies.engine.build import library_path
    engine = library_path()
    cache = tmp_path / "cache"
    (cache / "engine").mkdir(parents=True)
    shutil.copy2(engine, cache / "engine" / engine.name)
    return cache


def mechfmu(cache: Path, *args) -> subprocess.CompletedProcess:
    env = {**os.environ, "MECHFMU_CACHE": str(cache)}
    return subprocess.run([sys.executable, "-m", "assemblies.cli", *args], capture_output=True,
                          text=True, env=env)


def damaged_lines(stderr: str) -> list[str]:
    return [line for line in stderr.splitlines() if "was damaged" in line]


def test_runs_go_on_after_the_libraries_they_load_are_damaged(own_cache, tmp_path):
    out = tmp_path / "out"
    first = mechfmu(own_cache, "run", "stick_slip", "--stop-time", "14", "--out", str(out))
    assert first.returncode == 0, first.stderr[-500:]
    engine = next((own_cache / "engine").glob("libmfengine-*.so"))
    member = next((own_cache / "prepared").glob("SpringBlock-*/binaries/*/SpringBlock.so"))
    engine.write_bytes(b"garbage\n")  # before: an OSError traceback
    truncate(member)  # before: SIGBUS in dlopen, every run, no output
    second = mechfmu(own_cache, "run", "stick_slip", "--stop-time", "14", "--out", str(out))
    assert second.returncode == 0, (second.returncode, second.stderr[-500:])
    assert second.stdout.splitlines()[-1] == "all 3 figures pass"
    lines = damaged_lines(second.stderr)
    assert len(lines) == 2, second.stderr
    assert any(f"library of the engine {engine}" in line and "rebuilding it" in line
               for line in lines)
    assert any(f"extracted FMU {member.parents[2]}" in line and "extracting it again" in line
               for line in lines)
    third = mechfmu(own_cache, "run", "stick_slip", "--stop-time", "14", "--out", str(out))
    assert third.returncode == 0 and damaged_lines(third.stderr) == []


def test_build_never_copies_out_a_damaged_fmu(own_cache, tmp_path):
    target = tmp_path / "b.fmu"
    assert mechfmu(own_cache, "build", "SpringBlock", "-o", str(target)).returncode == 0
    (cached,) = (own_cache / "fmus").glob("SpringBlock-*.fmu")
    truncate(cached)
    target.unlink()
    again = mechfmu(own_cache, "build", "SpringBlock", "-o", str(target))
    assert again.returncode == 0, again.stderr[-500:]
    assert damaged_lines(again.stderr) == [
        f"the cached FMU {cached} was damaged (its bytes differ from what its build wrote); "
        "rebuilding it"]
    with zipfile.ZipFile(target) as zf:
        assert zf.testzip() is None
    assert validate_fmu(str(target)) == []


@pytest.mark.parametrize("entry", ["[]", '{"fmu": "../../elsewhere.fmu", "facts": {}}',
                                   '{"fmu": "X.fmu", "facts": {"autonomous": true}}'],
                         ids=["not a dict", "path out of the cache", "facts cut short"])
def test_a_damaged_recipe_entry_is_no_entry(tmp_path, monkeypatch, entry):
    """A recipe file of the cache is read as input: an entry of the wrong shape is as
    good as none (the FMU is found by its content and filed anew), never a KeyError or
    a path outside the cache. Before: TypeError/KeyError, or the path taken as given."""
    from components import ConstantSpeed
    from fmus.build import component_facts, fetch_fmu, fmu_recipe, recipes
    monkeypatch.setenv("MECHFMU_CACHE", str(tmp_path / "cache"))
    built = fetch_fmu(ConstantSpeed())
    key = fmu_recipe(ConstantSpeed())
    (recipes().folder / f"{key[:40]}.json").write_text(entry)
    again = fetch_fmu(ConstantSpeed())
    assert again.path == built.path and again.facts == built.facts
    assert recipes().get(key)["fmu"] == built.path.name
    (recipes().folder / f"{key[:40]}.json").write_text(entry)
    assert component_facts(ConstantSpeed()) == built.facts
