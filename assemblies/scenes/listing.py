"""README's generated tables: the scenes from their registry, and the components from
theirs (:mod:`components.listing`), so that README and the code cannot drift.

``mechfmu scenes --markdown`` prints the scene table; ``python -m assemblies.scenes.listing
README.md`` rewrites both tables in place, each below its marker line; a test holds README
to them. ``python -m assemblies.scenes.listing --index`` rewrites
:mod:`assemblies.scene_names`, the registry's names, families and descriptions that the
command line reads without importing a scene (a test holds it to the registry too).
"""
from __future__ import annotations

import sys
import textwrap
from pathlib import Path

from . import FAMILIES, SCENES, family
from .scene import Scene

MARKER = "<!-- generated from the scene registry: python -m assemblies.scenes.listing README.md -->"
HEADER = ("| scene | seed | reference |", "| --- | --- | --- |")


def _cell(text: str) -> str:
    # a bare | would end the cell; a line break would end the row
    return " ".join(text.split()).replace("|", "\\|")


def markdown_table(scenes: dict[str, Scene] | None = None) -> str:
    """One row per scene, in the registry's order: its name, the seed's section(s) it
    reproduces and the independent references its figures are held to."""
    rows = [f"| `{name}` | {_cell(sc.seed)} | {_cell(sc.reference)} |"
            for name, sc in (SCENES if scenes is None else scenes).items()]
    return "\n".join([*HEADER, *rows])


def readme_table(text: str, marker: str = MARKER) -> str:
    """The table that follows the marker line in README's text ('' if none)."""
    lines = text.splitlines()
    if marker not in lines:
        return ""
    start = lines.index(marker) + 1
    end = start
    while end < len(lines) and lines[end].startswith("|"):
        end += 1
    return "\n".join(lines[start:end])


def _tables() -> list[tuple[str, str]]:
    """(marker, table) of each generated table, scenes first."""
    from components.listing import MARKER as COMPONENT_MARKER
    from components.listing import markdown_table as component_table
    return [(MARKER, markdown_table()), (COMPONENT_MARKER, component_table())]


def rewrite(path: str | Path, tables: list[tuple[str, str]] | None = None) -> bool:
    """Put each registry's table under its marker in `path` (every marker must be there);
    True if the file changed. `tables`: (marker, table) pairs, by default the scenes' and
    the components'."""
    path = Path(path)
    text = new = path.read_text()
    for marker, table in _tables() if tables is None else tables:
        if marker not in new.splitlines():
            raise SystemExit(f"{path}: no line '{marker}' to put the table under")
        old = readme_table(new, marker)
        new = (new.replace(f"{marker}\n{old}", f"{marker}\n{table}", 1) if old
               else new.replace(marker, f"{marker}\n{table}", 1))
    if new != text:
        path.write_text(new)
    return new != text


INDEX_PATH = Path(__file__).parent.parent / "scene_names.py"
INDEX_HEAD = '''"""The registry's scenes, not imported: name -> (family module, description).

Generated from the registry (:mod:`assemblies.scenes`) by
``python -m assemblies.scenes.listing --index``; a test holds it to the registry, so the
two cannot drift. The scenes import the components, their references scipy and their
plots matplotlib: the command line checks and lists a scene, and
:func:`assemblies.scenes.scene` finds the one family module to import, from this file alone.
"""
'''


def index_source() -> str:
    """The text of :mod:`assemblies.scene_names`, from the registry."""
    lines = [INDEX_HEAD, "SCENE_INDEX = {"]
    for module in FAMILIES:
        for name, sc in family(module).items():
            lines.append(f"    {name!r}: ({module!r},")
            # wrapped at spaces into adjacent literals, each kept whole (spaces included)
            parts = textwrap.wrap(sc.description, 80, drop_whitespace=False) or [""]
            lines += [f"        {part!r}" for part in parts]
            lines[-1] += "),"
    lines += ["}", "SCENE_NAMES = tuple(SCENE_INDEX)", ""]
    return "\n".join(lines)


def main(argv: list[str]) -> int:
    if not argv:
        print(markdown_table())
        return 0
    if argv == ["--index"]:
        text = index_source()
        changed = INDEX_PATH.read_text() != text
        if changed:
            INDEX_PATH.write_text(text)
        print(f"{INDEX_PATH}: {'rewritten' if changed else 'already current'}")
        return 0
    usage = ("usage: python -m assemblies.scenes.listing [--index | FILE.md ...]: no argument "
             "prints the scene table; --index rewrites assemblies/scene_names.py; each FILE.md "
             "gets the table after its generated-table marker")
    if any(a.startswith("-") for a in argv):
        print(usage, file=sys.stderr if argv not in (["-h"], ["--help"]) else sys.stdout)
        return 0 if argv in (["-h"], ["--help"]) else 2
    for name in argv:
        if not Path(name).is_file():
            print(f"{name}: no such file\n{usage}", file=sys.stderr)
            return 2
        print(f"{name}: {'table rewritten' if rewrite(name) else 'table already current'}")
    return 0


if __name__ == "__main__":  # pragma: no cover
    sys.exit(main(sys.argv[1:]))
