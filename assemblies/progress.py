"""Progress of a long run on the terminal: a bar that redraws in place on a terminal,
and a plain line every few seconds when the output is a log file or a pipe (a bar's
carriage returns would fill a log with thousands of partial lines)."""
from __future__ import annotations

import sys
import time as wallclock
from typing import TextIO


class ProgressReport:
    """``report(t)`` for a run from 0 to `stop_time`; call :meth:`close` when it ends.

    The engines call it about every 0.25 s of wall time; a bar redraws on each call,
    a log gets a line at most every `log_interval` seconds, and a run shorter than
    `quiet_for` seconds prints nothing at all. `name` and `unit` say what is counted
    (a parameter study counts runs: ``name="runs", unit=""``).
    """

    def __init__(self, stop_time: float, stream: TextIO | None = None, log_interval: float = 5.0,
                 quiet_for: float = 1.0, width: int = 30, name: str = "t", unit: str = " s"):
        self.name, self.unit = name, unit
        self.stop_time, self.stream = stop_time, stream or sys.stderr
        self.log_interval, self.quiet_for, self.width = log_interval, quiet_for, width
        self.terminal = bool(getattr(self.stream, "isatty", lambda: False)())
        self.started = wallclock.perf_counter()
        self.last_line = self.started
        self.drawn = False

    def __call__(self, t: float) -> None:
        now = wallclock.perf_counter()
        elapsed = now - self.started
        if elapsed < self.quiet_for:
            return
        fraction = min(1.0, max(0.0, t / self.stop_time)) if self.stop_time > 0 else 1.0
        if self.terminal:
            filled = round(fraction * self.width)
            bar = "#" * filled + "-" * (self.width - filled)
            print(f"\r  [{bar}] {100 * fraction:5.1f} %  {self.name} = {t:.6g} / "
                  f"{self.stop_time:g}{self.unit}  "
                  f"{elapsed:6.1f} s", end="", file=self.stream, flush=True)
            self.drawn = True
        elif now - self.last_line >= self.log_interval:
            print(f"  {self.name} = {t:.6g} / {self.stop_time:g}{self.unit} ({100 * fraction:.1f} %), "
                  f"{elapsed:.1f} s elapsed", file=self.stream, flush=True)
            self.last_line = now

    def close(self) -> None:
        if self.drawn:
            print(file=self.stream, flush=True)
            self.drawn = False
