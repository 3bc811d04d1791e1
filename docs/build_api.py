"""Write the API reference, generated from the docstrings by pdoc: `make docs`, or
`python docs/build_api.py [OUTPUT]` (default docs/api) from the repository root.

Every public module of the three packages gets a page: pdoc alone follows a package's
``__all__``, which names the functions a user imports, not the modules that hold them.
The modules are found by their files, not by importing packages, and importing them for
pdoc compiles nothing (FMUs and the engine are built only when a run needs them).
"""
from __future__ import annotations

import sys
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]
PACKAGES = ("components", "fmus", "assemblies")


def public_modules(root: Path = ROOT) -> list[str]:
    """Dotted names of every module under PACKAGES whose path has no part starting with
    an underscore (``__init__`` stands for its package)."""
    names = []
    for package in PACKAGES:
        for path in sorted((root / package).rglob("*.py")):
            parts = list(path.relative_to(root).with_suffix("").parts)
            if parts[-1] == "__init__":
                parts.pop()
            if not any(part.startswith("_") for part in parts):
                names.append(".".join(parts))
    return names


def main(argv: list[str]) -> int:
    import warnings

    import pdoc

    # a package whose __all__ names a function after one of its modules (assemblies.scenes'
    # `scene`) makes pdoc add that module once more: one page all the same
    warnings.filterwarnings("ignore", message="The module specification")
    output = Path(argv[0]) if argv else ROOT / "docs" / "api"
    sys.path.insert(0, str(ROOT))  # this checkout's modules, whatever is installed
    pdoc.pdoc(*public_modules(), output_directory=output)
    print(f"wrote {output / 'index.html'} ({len(public_modules())} modules)")
    return 0


if __name__ == "__main__":
    sys.exit(main(sys.argv[1:]))
