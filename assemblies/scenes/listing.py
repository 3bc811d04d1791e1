"""README's table of scenes, generated from the registry so that the two cannot drift.

``mechfmu scenes --markdown`` prints the table; ``python -m assemblies.scenes.listing
README.md`` rewrites it in place, below the marker line; a test holds README to it.
"""
from __future__ import annotations

import sys
from pathlib import Path

from . import SCENES
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


def readme_table(text: str) -> str:
    """The table that follows the marker line in README's text ('' if none)."""
    lines = text.splitlines()
    if MARKER not in lines:
        return ""
    start = lines.index(MARKER) + 1
    end = start
    while end < len(lines) and lines[end].startswith("|"):
        end += 1
    return "\n".join(lines[start:end])


def rewrite(path: str | Path) -> bool:
    """Put the registry's table under the marker in `path`; True if the file changed."""
    path = Path(path)
    text = path.read_text()
    old = readme_table(text)
    if MARKER not in text.splitlines():
        raise SystemExit(f"{path}: no line '{MARKER}' to put the scene table under")
    table = markdown_table()
    new = (text.replace(f"{MARKER}\n{old}", f"{MARKER}\n{table}", 1) if old
           else text.replace(MARKER, f"{MARKER}\n{table}", 1))
    if new != text:
        path.write_text(new)
    return new != text


def main(argv: list[str]) -> int:
    if not argv:
        print(markdown_table())
        return 0
    for name in argv:
        print(f"{name}: {'table rewritten' if rewrite(name) else 'table already current'}")
    return 0


if __name__ == "__main__":  # pragma: no cover
    sys.exit(main(sys.argv[1:]))
