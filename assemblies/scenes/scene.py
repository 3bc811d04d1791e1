"""What a scene is: a named assembly with an experiment, recorded outputs and figures."""
from __future__ import annotations

import math
import re
from dataclasses import dataclass, field
from pathlib import Path
from typing import Callable

from ..assembly import Assembly, AssemblyError
from ..result import Result


@dataclass
class Figure:
    """One measured number beside its independent reference and the accuracy it must meet.

    `accuracy` is the largest |measured - reference| the figure's method promises, in the
    figure's unit, or, with `relative`, as a fraction of |reference|. It is derived from
    the physics and the numerics (a solver tolerance, a stated modelling error, a
    quadrature error estimate), never fitted to a run's error. A figure passes when its error is finite and within the accuracy: a NaN
    measurement (an event that never came, too few samples to measure) fails, and so does
    a figure whose accuracy was never stated (NaN, the default).

    `source` names where the reference comes from, so that a reader can tell the seed's
    own numbers from ours: "seed Eq. 9.9", "closed form derived here from ...",
    "independent integration (scipy, written from the seed's Eqs. 9.14-9.16)", "conservation
    law", "the exact event-driven solution (ours)". The run's table prints it after the
    description; an empty source prints as "not stated".
    """
    name: str
    description: str
    measured: float
    reference: float
    accuracy: float = math.nan
    relative: bool = False
    source: str = ""

    def __post_init__(self):
        if self.accuracy < 0:  # False for NaN: an unstated accuracy is allowed, and fails
            raise ValueError(f"figure '{self.name}': accuracy must be >= 0, not {self.accuracy}")

    @property
    def unit(self) -> str | None:
        """The unit the description states, as "[unit]" (its first bracket), or None."""
        found = re.search(r"\[([^\[\]]+)\]", self.description)
        return found.group(1) if found else None

    @property
    def error(self) -> float:
        return abs(self.measured - self.reference)

    @property
    def bound(self) -> float:
        """The accuracy as an absolute error bound, in the figure's unit."""
        return self.accuracy * abs(self.reference) if self.relative else self.accuracy

    @property
    def passed(self) -> bool:
        error, bound = self.error, self.bound
        return bool(math.isfinite(error) and math.isfinite(bound) and error <= bound)


def solver_accuracy(result: Result, scale: float = 1.0, factor: float = 100.0) -> float:
    """What an error-controlled solver promises for a figure of size `scale`: `factor`
    times the run's relative tolerance, as the solvers weigh errors (atol = rtol = tol),
    so max(1, |scale|) carries the unit.

    The default 100 covers an event time or a state at an event, located on a solution
    whose global error is a few times the local tolerance. A drift that accumulates over a
    long run (energy, a constraint) states its own larger factor.
    """
    return factor * result.settings["tolerance"] * max(1.0, abs(scale))


def coupling_accuracy(result: Result, scale: float = 1.0) -> float:
    """solver_accuracy, or, co-simulated, what the coupling allows: adaptive, 100 x its
    own tolerance (the communication step's error control: an input extrapolated over a
    step, a lock across FMUs held to it); on fixed steps an input is one step late at
    worst."""
    s = result.settings
    if s.get("scheme") not in ("jacobi", "gauss-seidel"):
        return solver_accuracy(result, scale)
    if s.get("adaptive"):
        return 100 * max(s["tolerance"], s["tol"]) * max(1.0, abs(scale))
    return solver_accuracy(result, scale) + s["step"]


DRIFT = 1e4  # conservation over a run of 1e4-1e6 steps: per-step errors of ~tol add up,
            # partly cancelling


@dataclass(frozen=True)
class SceneParameter:
    """A value that shapes a scene's assembly itself (a chain's length), given on the
    command line as ``--param NAME=VALUE`` with no instance prefix and passed to `build`.

    `most` bounds it per mode where a mode cannot run the largest values in reasonable
    time (mode -> (largest value, why)); it is checked before anything is built."""
    name: str
    default: float
    low: float
    high: float
    unit: str
    description: str
    integer: bool = False
    most: dict = field(default_factory=dict)

    def allowed(self) -> str:
        if self.integer:
            return f"an integer in [{int(self.low)}, {int(self.high)}]"
        return f"a number in [{self.low:g}, {self.high:g}]"

    def value(self, scene: str, given, mode: str):
        """`given` (a number or the command line's text) checked and converted, or one
        line (ValueError) naming the scene, the parameter and what is allowed."""
        where = f"scene '{scene}': parameter {self.name} ({self.description})"
        try:
            number = float(given)
        except (TypeError, ValueError):
            raise ValueError(f"{where} must be {self.allowed()}, not {given!r}") from None
        if self.integer and number.is_integer():
            number = int(number)
        if (not math.isfinite(number) or not self.low <= number <= self.high
                or (self.integer and not isinstance(number, int))):
            raise ValueError(f"{where} must be {self.allowed()}, not {given!r}")
        if mode in self.most and number > self.most[mode][0]:
            largest, why = self.most[mode]
            raise ValueError(f"{where} = {number:g} is too large for mode '{mode}' (at most "
                             f"{largest:g}: {why})")
        return number


@dataclass(frozen=True)
class RunBudget:
    """A mode's bound on a run whose cost grows with a parameter and with the run's length
    alike (a chain whose events grow with n and with the time run, each costing n):
    parameter^power x (stop - start time) at most `most`. Refused in one line that says
    what the cost grows with, what was measured (`why`) and the longest run allowed."""
    parameter: str
    power: float
    most: float
    why: str

    def check(self, scene: str, mode: str, arguments: dict, length: float) -> None:
        value = arguments[self.parameter]
        size = float(value) ** self.power
        if size * length > self.most:
            raise ValueError(
                f"scene '{scene}': {self.parameter} = {value:g} over {length:g} s is too long "
                f"a run for mode '{mode}' (its cost grows as {self.parameter}^{self.power:g} x "
                f"the time run, at most {self.most:.4g}: {self.why}); at {self.parameter} = "
                f"{value:g} run at most {self.most / size:.3g} s (--stop-time), or a smaller "
                f"{self.parameter}")


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
    mode: str = "cosim"  # the master a run uses when none is asked for (cosim, me, monolithic)
    seed: str = ""       # the seed's section(s) the scene reproduces, as README's table shows them
    reference: str = ""  # the independent references its figures are held to, in a line
    #: values that shape the assembly: `build` takes them as keywords (SceneParameter)
    parameters: tuple[SceneParameter, ...] = ()
    #: modes the scene runs with a solver of its own: mode -> solve(assembly, arguments,
    #: **the masters' common keywords) -> Result
    solvers: dict = field(default_factory=dict)
    #: modes whose results the figures cannot judge: mode -> why, in a clause; a run in
    #: one of them is refused in one line rather than printing numbers known to be wrong
    refused: dict = field(default_factory=dict)
    #: mode -> RunBudget: a bound on parameter and run length together, checked with the
    #: parameters before anything is built
    budgets: dict = field(default_factory=dict)

    def check_mode(self, mode: str, assembly: str) -> None:
        """Refuse a mode of :attr:`refused` (AssemblyError, one line naming the assembly
        and the scene's own mode, which runs it)."""
        why = self.refused.get(mode)
        if why is not None:
            raise AssemblyError(f"scene '{self.name}' (assembly '{assembly}') is not run in "
                                f"mode '{mode}': {why}; its own mode '{self.mode}' runs it")

    def arguments(self, given: dict, mode: str) -> dict:
        """`build`'s keywords: every parameter's default, replaced by `given`'s (NAME:
        value, checked); one line (ValueError) for a name the scene does not have."""
        known = {p.name: p for p in self.parameters}
        for name in given:
            if name not in known:
                has = (f"its parameters: {', '.join(f'{p.name} ({p.allowed()})' for p in self.parameters)}"
                       if self.parameters else "it has none")
                raise ValueError(f"scene '{self.name}' has no parameter '{name}' ({has}; an "
                                 "instance's is INSTANCE.NAME)")
        return {p.name: p.value(self.name, given.get(p.name, p.default), mode)
                for p in self.parameters}

    def check_budget(self, mode: str, arguments: dict, length: float) -> None:
        """A run of `length` seconds with `arguments` within `mode`'s RunBudget, or one
        line (ValueError) that says how to shorten it."""
        if mode in self.budgets:
            self.budgets[mode].check(self.name, mode, arguments, length)

    def assemble(self, arguments: dict, given: dict) -> Assembly:
        """The assembly: `build` takes the parameters a run `given` (checked, in
        `arguments`) and its own defaults for the rest, so a scene copied with another
        `build` (dataclasses.replace) still runs when none is given."""
        return self.build(**{name: arguments[name] for name in given})


__all__ = ["DRIFT", "Figure", "RunBudget", "Scene", "SceneParameter", "solver_accuracy"]
