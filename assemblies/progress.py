"""Progress of a long run on the terminal: a bar that redraws in place on a terminal,
and a plain line every few seconds when the output is a log file or a pipe (a bar's
carriage returns would fill a log with thousands of partial lines). Both say the
simulated time, the wall time so far and an estimate of the wall time left."""
from __future__ import annotations

import sys
import time as wallclock
from typing import Callable, TextIO


def _duration(seconds: float) -> str:
    """``42 s``, ``3 min 05 s``, ``2 h 03 min``: short enough for a bar's line."""
    seconds = max(0.0, seconds)
    if seconds < 60:
        return f"{seconds:.0f} s"
    minutes, secs = divmod(round(seconds), 60)
    if minutes < 60:
        return f"{minutes} min {secs:02d} s"
    hours, minutes = divmod(minutes, 60)
    return f"{hours} h {minutes:02d} min"


class ProgressReport:
    """``report(t)`` for a run from `start_time` (0) to `stop_time`; call :meth:`close`
    when it ends.

    The engines call it about every 0.25 s of wall time; a bar redraws on each call,
    a log gets its first line once the run has taken `quiet_for` seconds and then one
    at most every `log_interval` seconds; a run shorter than `quiet_for` prints nothing.
    The estimate of the time left assumes the rest of the run goes at the pace so far.
    `clock` is the wall clock (a test passes a fake one). `name` and `unit` say what is
    counted (a parameter study counts runs: ``name="runs", unit=""``).
    """

    def __init__(self, stop_time: float, stream: TextIO | None = None, log_interval: float = 5.0,
                 quiet_for: float = 2.0, width: int = 30,
                 clock: Callable[[], float] = wallclock.perf_counter, name: str = "t",
                 unit: str = " s", start_time: float = 0.0):
        self.name, self.unit, self.start_time = name, unit, start_time
        self.stop_time, self.stream = stop_time, stream or sys.stderr
        self.log_interval, self.quiet_for, self.width = log_interval, quiet_for, width
        self.clock = clock
        self.terminal = bool(getattr(self.stream, "isatty", lambda: False)())
        self.started = clock()
        self.last_line = None  # wall time of the last log line
        self.drawn = False

    def status(self, t: float, elapsed: float) -> str:
        """``t = 8 / 100 s (8.0 %), 12 s elapsed, about 2 min 18 s left``."""
        fraction = self._fraction(t)
        left = (f"about {_duration(elapsed * (1 - fraction) / fraction)} left" if fraction > 0
                else "time left not known yet")
        return (f"{self.name} = {t:.6g} / {self.stop_time:g}{self.unit} ({100 * fraction:.1f} %), "
                f"{_duration(elapsed)} elapsed, {left}")

    def __call__(self, t: float) -> None:
        now = self.clock()
        elapsed = now - self.started
        if elapsed < self.quiet_for:
            return
        if self.terminal:
            fraction = self._fraction(t)
            filled = round(fraction * self.width)
            bar = "#" * filled + "-" * (self.width - filled)
            # \033[K clears what a longer line before left behind
            print(f"\r  [{bar}] {self.status(t, elapsed)}\033[K", end="", file=self.stream,
                  flush=True)
            self.drawn = True
        elif self.last_line is None or now - self.last_line >= self.log_interval:
            print(f"  {self.status(t, elapsed)}", file=self.stream, flush=True)
            self.last_line = now

    def _fraction(self, t: float) -> float:
        span = self.stop_time - self.start_time
        return min(1.0, max(0.0, (t - self.start_time) / span)) if span > 0 else 1.0

    def close(self) -> None:
        if self.drawn:
            print(file=self.stream, flush=True)
            self.drawn = False
