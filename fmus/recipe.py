"""What decides a component's FMU, known without flattening: the key of a cached FMU.

The content hash of :mod:`fmus.build` names an FMU by what it contains, so finding it
takes flattening and code generation (0.02-0.3 s). A *recipe* names it by what it is
made from instead, which is cheap to read:

- the toolchain: the builder's own sources (``fmus/*.py``, ``components/dae.py``, and
  every project module they import), the C runtime (``fmus/runtime/*.c, *.h``), the
  compiler flags, the versions of Python and of every third-party package the sources
  import (CasADi, NumPy, fmpy, ...);
- the component's class: its module and qualified name, the source of every project
  module that defines one of its bases or that those modules import (found by reading
  their ``import`` statements, those inside functions included), and its declarations;
- the instance: everything it holds but its name (profile, options, parameter values
  and starts, which the FMU carries as start values; a beam's coordinates);
- the FMI version and tolerance.

A class made at run time (``type(...)``, a class inside a function) cannot be named by
its source: it has no recipe (``None``) and is always keyed by content. A recipe is
only a shortcut: :class:`RecipeStore` maps it to the content-named FMU and to facts
about the flat model read when it was built, and a missing entry costs the slow path
once. What is not in the recipe, and so must not change an FMU: the instance's name
(checked: no generated file mentions it), the C compiler's version, external files a
component might read (none does).
"""
from __future__ import annotations

import hashlib
import importlib.util
import json
import os
import re
import sys
from pathlib import Path

RECIPE_VERSION = "1"  # bump when the meaning of a recipe changes

_IMPORT = re.compile(r"^[ \t]*(?:from[ \t]+([.\w]+)[ \t]+import[ \t]+(\([^)]*\)|[^\n#;]+)"
                     r"|import[ \t]+([^\n#;]+))", re.M)
_ADDRESS = re.compile(r" at 0x[0-9a-fA-F]+")
_OUTSIDE = tuple({f(p) + os.sep for p in (sys.prefix, sys.base_prefix, sys.exec_prefix)
                  for f in (os.path.abspath, os.path.realpath)})
# what a class declares; its source says the same, unless a program changed it since
# what an instance holds that no generated file depends on (checked for the name: the
# model is named by its class; whether the profile was chosen by hand or by an assembly)
_NOT_IN_THE_FMU = ("name", "profile_explicit")
_DECLARATIONS = ("parameters", "options", "states", "ports", "profiles", "constraints",
                 "modes", "default_stop_time", "__doc__")


def _module_file(name: str, roots: set[str]) -> str | None:
    """The .py file of module `name`, None for one that is not a Python source file (or
    a name imported from a module). A module not imported yet is looked for beside its
    package, or, at top level, in `roots` (the folders the program's packages are in):
    never by a search of sys.path, which lists every installed package."""
    module = sys.modules.get(name)
    if module is not None:
        path = getattr(module, "__file__", None)
        return os.path.abspath(path) if path and path.endswith(".py") else None
    parent_name, _, child = name.rpartition(".")
    if parent_name:
        parent = sys.modules.get(parent_name)
        if parent is not None:
            folders = list(getattr(parent, "__path__", []))
        else:
            parent_file = _module_file(parent_name, roots)
            is_package = parent_file is not None and parent_file.endswith("__init__.py")
            folders = [os.path.dirname(parent_file)] if is_package else []
    else:
        folders = list(roots)
    for folder in folders:
        for candidate in (os.path.join(folder, f"{child}.py"),
                          os.path.join(folder, child, "__init__.py")):
            if os.path.isfile(candidate):
                return os.path.abspath(candidate)
    return None


def _is_project(path: str) -> bool:
    """A file of the program itself, not of Python or of an installed package."""
    return not path.startswith(_OUTSIDE)


def _imported_names(module: str, is_package: bool, text: str) -> set[str]:
    """Absolute names of the modules `text` imports (and of the names it imports from
    them, which may be submodules)."""
    names = set()
    package = module if is_package else module.rpartition(".")[0]
    for source, imported, plain in _IMPORT.findall(text):
        if plain:
            names.update(n.split()[0] for n in plain.split(",") if n.strip())
            continue
        if source.startswith("."):
            level = len(source) - len(source.lstrip("."))
            base = package.split(".")
            base = base[:len(base) - (level - 1)] if level > 1 else base
            source = ".".join([*base, source.lstrip(".")]).strip(".")
        names.add(source)
        for item in imported.strip("()").replace("\n", " ").split(","):
            item = item.split()[0] if item.split() else ""
            if item and item != "*":
                names.add(f"{source}.{item}")
    return names


# modules -> (((path, stat), ...), external, ((module, path), ...)): found again once a
# file changes or a module is another file
_closures: dict = {}


def _stat(path: str) -> tuple:
    st = os.stat(path)
    return st.st_mtime_ns, st.st_size


def source_closure(modules: list[str]) -> tuple[list[Path], set[str]]:
    """(project source files, third-party top-level packages) that `modules` are built
    from: the modules' own files and those of every project module they import,
    transitively. Memoised in the process until one of the files changes on disk."""
    memo = _closures.get(tuple(modules))
    if memo is not None:
        ordered, external, located = memo
        try:
            if all(_stat(path) == stat for path, stat in ordered) and \
                    all(_module_file(name, set()) == path for name, path in located):
                return [Path(p) for p, _ in ordered], external
        except OSError:
            pass
    files, external, seen, roots, located = {}, set(), set(), set(), []
    pending = list(modules)
    while pending:
        name = pending.pop()
        if name in seen or not name:
            continue
        seen.add(name)
        path = _module_file(name, roots)
        top = name.partition(".")[0]
        if path is None or not _is_project(path):
            top_file = _package_file(top)
            if top not in sys.stdlib_module_names and top != "__future__" and \
                    (top_file and not _is_project(os.path.abspath(top_file))):
                external.add(top)
            continue
        if path in files:
            continue
        stat = _stat(path)
        with open(path, encoding="utf-8") as fh:
            text = fh.read()
        files[path] = stat
        located.append((name, path))
        depth = name.count(".") + (2 if path.endswith("__init__.py") else 1)
        roots.add(path.rsplit(os.sep, depth)[0])
        pending.extend(_imported_names(name, path.endswith("__init__.py"), text))
    ordered = tuple(sorted(files.items()))
    _closures[tuple(modules)] = (ordered, external, located)
    return [Path(p) for p, _ in ordered], external


def _package_file(top: str) -> str:
    """The file of top-level package `top` ('' if there is none), found without importing
    it: whether a program has loaded a package yet must not change a key (a cached run
    loads neither CasADi nor scipy)."""
    module = sys.modules.get(top)
    if module is not None:
        return getattr(module, "__file__", None) or ""
    try:
        spec = importlib.util.find_spec(top)
    except (ImportError, ValueError):
        return ""
    return (spec.origin or "") if spec is not None and spec.has_location else ""


_installed: dict = {}  # top-level package -> its version, as _package_version read it


def _package_version(top: str) -> str:
    """The version of the installed distribution of `top`, read from the name of its
    metadata folder beside it (``casadi-3.8.2.dist-info``), never by importing it; where
    there is none, the package file's size and time of change (a reinstall changes
    them); ``-`` for a package that is not installed."""
    if top in _installed:
        return _installed[top]
    version, path = "-", _package_file(top)
    if path:
        package = os.path.dirname(path)
        folder = os.path.dirname(package) if os.path.basename(path) == "__init__.py" else package
        wanted = top.lower().replace("-", "_") + "-"
        try:
            entries = os.listdir(folder)
        except OSError:
            entries = []
        found = [e for e in entries if e.lower().startswith(wanted)
                 and e.endswith((".dist-info", ".egg-info"))]
        if found:
            version = found[0][len(wanted):].rsplit(".", 1)[0].split("-")[0]
        else:
            stat = os.stat(path)
            version = f"file {stat.st_size} {stat.st_mtime_ns}"
    _installed[top] = version
    return version


def _versions(packages: set[str]) -> list[str]:
    """`package==version` of each third-party package (``-`` where not installed), the
    same whether or not the program has imported it yet."""
    return [f"{top}=={_package_version(top)}" for top in sorted(packages)]


def _stable_repr(value) -> str:
    """repr without memory addresses (a lambda's repr names one)."""
    return _ADDRESS.sub("", repr(value))


def class_is_named(cls) -> bool:
    """Is `cls` the class its module defines under its qualified name? Not so for a
    class made at run time, whose source does not say what it is."""
    module = sys.modules.get(cls.__module__)
    obj = module
    for part in cls.__qualname__.split("."):
        obj = getattr(obj, part, None)
    return obj is cls and _module_file(cls.__module__, set()) is not None


def recipe(component, fmi_version: int, tolerance: float, toolchain: list[str],
           runtime_files: list[Path], cflags: list[str]) -> str | None:
    """The recipe key (hex) of `component`'s FMU, or None for a class made at run time.
    `toolchain`: the builder's modules; `runtime_files`: the C runtime; `cflags`: the
    compiler's flags (all as :mod:`fmus.build` uses them, passed in so that a test can
    point them elsewhere)."""
    cls = type(component)
    if not class_is_named(cls):
        return None
    bases = [c.__module__ for c in cls.__mro__ if c is not object]
    instance = [(key, _stable_repr(value)) for key, value in sorted(vars(component).items())
                if key not in _NOT_IN_THE_FMU]
    return combine("mechfmu-recipe", RECIPE_VERSION, f"python {sys.version_info[:2]}",
                   _versions({"casadi", "numpy", "fmpy"}), modules_digest(toolchain),
                   modules_digest(bases), files_digest(runtime_files), list(cflags),
                   f"fmi{fmi_version}", float(tolerance), cls.__module__, cls.__qualname__,
                   [(attr, _stable_repr(getattr(cls, attr, None))) for attr in _DECLARATIONS],
                   instance)


_digests: dict = {}  # (path, mtime, size) -> digest of the file's name and content


def files_digest(paths: list[Path]) -> str:
    """Hex digest of the files' names and contents (each read once per process while
    it is unchanged on disk)."""
    parts = []
    for path in paths:
        path = os.fspath(path)
        stamp = (path, *_stat(path))
        digest = _digests.get(stamp)
        if digest is None:
            with open(path, "rb") as fh:
                digest = _digests[stamp] = hashlib.sha256(
                    os.path.basename(path).encode() + b"\0" + fh.read()).hexdigest()
        parts.append(digest)
    return combine(*parts)


_module_digests: dict = {}  # modules -> (((path, stat), ...), ((module, path), ...), digest)


def modules_digest(modules: list[str]) -> str:
    """Hex digest of the sources `modules` are built from (:func:`source_closure`) and
    of the versions of the third-party packages they import; memoised in the process
    until one of the files changes or a module is another file."""
    key = tuple(modules)
    memo = _module_digests.get(key)
    if memo is not None:
        stats, located, digest = memo
        try:
            if all(_stat(path) == stat for path, stat in stats) and \
                    all(_module_file(name, set()) == path for name, path in located):
                return digest
        except OSError:
            pass
    files, external = source_closure(modules)
    ordered, _, located = _closures[key]
    digest = combine(_versions(external), files_digest(files))
    _module_digests[key] = (ordered, located, digest)
    return digest


def combine(*parts) -> str:
    """One key from several (recipes, names, numbers)."""
    h = hashlib.sha256()
    for part in parts:
        h.update(_stable_repr(part).encode())
        h.update(b"\0")
    return h.hexdigest()


class RecipeStore:
    """recipe key -> JSON entry (the FMU's file name, facts about its model), one small
    file per key under `folder`, each written atomically."""

    def __init__(self, folder: Path):
        self.folder = Path(folder)

    def _file(self, key: str) -> Path:
        return self.folder / f"{key[:40]}.json"

    def get(self, key: str | None) -> dict:
        if key is None:
            return {}
        try:
            entry = json.loads(self._file(key).read_text())
        except (OSError, ValueError):
            return {}
        return entry if isinstance(entry, dict) else {}  # a damaged file is no entry

    def update(self, key: str | None, **entries) -> None:
        if key is None:
            return
        merged = {**self.get(key), **entries}
        self.folder.mkdir(parents=True, exist_ok=True)
        partial = self._file(key).with_suffix(f".{os.getpid()}.partial")
        partial.write_text(json.dumps(merged, sort_keys=True))
        partial.replace(self._file(key))  # atomic: a reader sees the old entry or the new
