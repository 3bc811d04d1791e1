"""The limits on every number a caller gives that sizes memory or work, with their reasons.

A request beyond one is refused before anything is allocated or started, in one line
that names the limit (``assemblies.limits.NAME``), the number asked for and what to
change. Each limit is far above what a scene or a study of this project needs and far
below what takes a machine down: an output table of ``MAX_OUTPUT_ROWS`` rows of a
scene's usual ten columns is under 1 GB, and one of ``MAX_SWEEP_RUNS`` runs is minutes
of work and a few hundred MB of rows. The C side bounds what a file declares (counts
and indices in ``assembly.txt``, model descriptions) in its own parser.
"""
from __future__ import annotations

import math
import numbers
import os

from .assembly import AssemblyError

#: rows of a run's output table (times 0, step, ..., stop time): every master allocates
#: them up front (the engine writes into numpy buffers), and a row is 8 bytes per column;
#: 10 million rows of 10 columns are 0.8 GB. 1e-4 s steps over 1000 s fit.
MAX_OUTPUT_ROWS = 10_000_000
#: numbers of one run's output table (rows x columns): 2**28 doubles are 2 GiB, about a
#: tenth of a workstation's memory, so two runs side by side and their copies still fit
MAX_OUTPUT_VALUES = 2 ** 28
#: runs of one parameter study: the design is made and every run kept as a row of a table
#: in this process (about 2 kB each with its figures: 0.2 GB), and the cheapest scene
#: runs about 1000 times a second on a core, so this many runs are minutes of a
#: machine; a larger study is several studies (a seeded --random design, split ranges)
MAX_SWEEP_RUNS = 100_000
#: worker processes of a local Dask cluster per core: each worker is a Python process of
#: about 200 MB (CasADi, numpy, the engine), and the runs are CPU-bound, so more processes
#: than cores only wait for one another; twice the cores leaves room for a run that waits
WORKERS_PER_CORE = 2


class LimitError(AssemblyError):
    """A request beyond one of this module's limits (a ValueError, one line)."""


def max_workers() -> int:
    """The most worker processes a local cluster may start on this machine."""
    return WORKERS_PER_CORE * (os.cpu_count() or 1)


def output_rows(stop_time: float, step: float) -> float:
    """How many rows a run from 0 to `stop_time` with a row every `step` writes (as a
    float: an absurd request is inf or 1e300, not an integer to allocate)."""
    return math.ceil(min(stop_time / step, 1e300) - 1e-9) + 1.0


def check_output_rows(duration: float, step: float, step_name: str = "output step",
                      start_time: float = 0.0) -> int:
    """The number of output rows of a run of `duration` seconds (from `start_time`), or
    LimitError if it is over MAX_OUTPUT_ROWS."""
    rows = output_rows(duration, step)
    if rows > MAX_OUTPUT_ROWS:
        span = (f"stop time {duration:g} s" if start_time == 0 else
                f"a run of {duration:g} s (start time {start_time:g} s)")
        raise LimitError(
            f"{span} with {step_name} {step:g} s asks for {rows:.3g} output "
            f"rows; at most {MAX_OUTPUT_ROWS:,} (assemblies.limits.MAX_OUTPUT_ROWS, what fits "
            f"in memory): a longer {step_name} (--step) or a shorter run (--stop-time, "
            "--start-time)")
    return int(rows)


def check_output_values(rows: int, columns: int, what: str) -> None:
    """LimitError if a table of `rows` x `columns` numbers is over MAX_OUTPUT_VALUES."""
    if rows * columns > MAX_OUTPUT_VALUES:
        raise LimitError(
            f"{what}: {rows:,} output rows of {columns} columns are {rows * columns:.3g} "
            f"numbers; at most {MAX_OUTPUT_VALUES:,} (assemblies.limits.MAX_OUTPUT_VALUES, "
            "2 GiB): a longer output step, a shorter stop time or fewer recorded variables")


def check_sweep_runs(runs: float, what: str) -> None:
    """LimitError if a study of `runs` runs is over MAX_SWEEP_RUNS."""
    if runs > MAX_SWEEP_RUNS:
        raise LimitError(
            f"{what} makes {runs:.3g} runs; a study has at most {MAX_SWEEP_RUNS:,} "
            "(assemblies.limits.MAX_SWEEP_RUNS, minutes of a machine and the rows in "
            "memory): fewer values, or several studies")


def check_workers(workers) -> int:
    """`workers` as the number of local worker processes, or LimitError naming the range."""
    most = max_workers()
    if (isinstance(workers, bool) or not isinstance(workers, numbers.Integral)
            or not 1 <= workers <= most):
        raise LimitError(
            f"workers must be a whole number from 1 to {most} ({WORKERS_PER_CORE} per core "
            f"of this machine's {os.cpu_count() or 1}: assemblies.limits.WORKERS_PER_CORE; "
            f"0 runs in this process), not {workers!r}")
    return int(workers)
