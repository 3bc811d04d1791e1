"""The installed mechfmu's version: what ``mechfmu --version`` says and a run's JSON file
records. Standard library only: the command's ``--version`` must answer at once."""
from __future__ import annotations

from functools import lru_cache


@lru_cache(maxsize=None)  # the package metadata lookup takes milliseconds, a run less
def mechfmu_version() -> str:
    from importlib.metadata import PackageNotFoundError, version
    try:
        return version("mechfmu")
    except PackageNotFoundError:  # a source checkout that was never installed
        return "unknown (not installed)"
