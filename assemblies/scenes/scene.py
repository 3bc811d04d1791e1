"""What a scene is: a named assembly with an experiment, recorded outputs and figures."""
from __future__ import annotations

from dataclasses import dataclass, field
from pathlib import Path
from typing import Callable

from ..assembly import Assembly
from ..result import Result


@dataclass
class Figure:
    """One measured number beside its independent reference."""
    name: str
    description: str
    measured: float
    reference: float

    @property
    def error(self) -> float:
        return abs(self.measured - self.reference)


@dataclass
class Scene:
    name: str
    description: str
    build: Callable[[], Assembly]
    stop_time: float
    step: float
    tolerance: float
    record: list[str] | None  # None: every output of every instance
    figures: Callable[[Result, Assembly], list[Figure]]
    plot: list[str] = field(default_factory=list)
    picture: Callable[[Result, str, Path], None] | None = None  # replaces the panel plot


__all__ = ["Figure", "Scene"]
