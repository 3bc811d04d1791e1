"""A signal read from a table of time and value (MSL Modelica.Blocks.Sources.TimeTable).

Every element of an assembly is an FMU, so a tabulated input is one too: the table is
the FMU's parameters, and its breakpoints are found by the FMU's own event handling,
which works in any master and in any importer of an exported assembly FMU. Our runtime
has no time events, so the breakpoints are state events on time itself: a mode
``segment`` counts the rows at or before the current time, and one event indicator,
``time - startTime - (time of the next row)``, is linear in time, so the runtime
locates each breakpoint to rounding. At the event ``segment`` jumps past every row at
or before the time reached, which also steps over a discontinuity (two rows at one
time) in one event and leaves the indicator strictly negative afterwards.

A table of ``rows`` rows is ``rows`` times and values; tables are padded to the next
power of two with copies of their last row (a zero-size discontinuity at the last
time, where there is an event already), so that the few FMU binaries built cover
tables of every length up to :data:`MAX_ROWS`.
"""
from __future__ import annotations

import math

from ..component import Component
from ..interfaces import (SIGNAL_OUT, ComponentError, Constraint, Mode, Option, Parameter, Port,
                         Profile, signal)
from ..lazy import lazy

ca = lazy("casadi")  # loaded by the first equation written, not by an import
np = lazy("numpy")  # loaded by the first array: listing the components needs none

#: the longest table a TimeTable takes: each evaluation of its output walks the rows
MAX_ROWS = 4096
_CAPACITIES = tuple(2 ** k for k in range(1, int(math.log2(MAX_ROWS)) + 1))
_ROWS = Option("rows", 2, range(2, MAX_ROWS + 1), "rows of the table (a shorter table is "
               "padded with its last row; built per value, so a table's length is rounded "
               "up to a power of two)")
INTERPOLATIONS = ("linear", "hold")
# Event location brackets a crossing to 1e-13 (relative) on its far side, so an event at
# a row's time lands just after it and a result row sampled at that very time would read
# the value before the row. Each row's event fires this much earlier instead: a row at
# the time of a table row reads the value after it, fmpy's rule (after_event) and the
# value a fixed-step master sees at a communication point there.
EARLY = 2e-13


def capacity(n_rows: int) -> int:
    """The rows a table of `n_rows` is padded to (a power of two, at least 2)."""
    return next(c for c in _CAPACITIES if c >= n_rows)


def _table_parameters(rows: int) -> tuple[Parameter, ...]:
    return tuple(Parameter(f"table[{k},{j}]", 0.0, unit, f"{what} of row {k} of the table")
                 for k in range(1, rows + 1)
                 for j, unit, what in ((1, "s", "time"), (2, "", "value")))


class TimeTable(Component):
    """Signal interpolated in a table of time and value (MSL Blocks.Sources.TimeTable).

    ``y = offset + table(time - startTime)``: ``table`` rows ``[t, y]`` with times
    non-decreasing; two rows at one time are a discontinuity (MSL's and fmpy's rule).
    ``interpolation`` ``linear`` (MSL's TimeTable, fmpy's rule for continuous inputs)
    or ``hold`` (the last row at or before the time: CombiTimeTable's ConstantSegments,
    fmpy's rule for discrete inputs). Before the first row the first value, after the
    last the last value (CombiTimeTable's HoldLastPoint, as fmpy does; MSL's TimeTable
    instead gives ``offset`` before startTime and extrapolates after the end).
    Every row is an event (the FMU stops its solver there). Output: ``y`` (no unit, so
    it feeds any Float64 signal input).
    """

    options = (_ROWS,
               Option("interpolation", "linear", INTERPOLATIONS,
                      "between rows: linear, or hold the last row's value"))
    ports = (Port("y", signal(""), "the tabulated signal"),)
    profiles = (Profile("source", "signal out", {"y": SIGNAL_OUT}),)
    default_stop_time = 1.0

    def __init__(self, name: str | None = None, profile: str | None = None, table=None,
                 **values):
        rows = values.pop("rows", None)
        data = None
        if table is not None:
            data = check_table(table, name or "TimeTable")
            if rows is None:
                rows = capacity(len(data))
        parsed = _ROWS.parse(2 if rows is None else rows)
        if parsed is None:
            raise ComponentError(f"TimeTable '{name or 'TimeTable'}': option rows = {rows!r} is "
                                 f"not allowed; rows must be {_ROWS.allowed()}")
        rows = parsed
        # the parameters depend on the table's size: this instance's own, set before the
        # base class reads them
        self.parameters = (*_table_parameters(rows),
                           Parameter("offset", 0.0, "", "added to the tabulated value"),
                           Parameter("startTime", 0.0, "s", "the table's time 0"))
        super().__init__(name, profile, rows=rows, **values)
        if data is not None:
            self.set_table(data)

    @property
    def modes(self):
        rows = self.option("rows")
        return (Mode("segment", 0, "rows of the table at or before time - startTime",
                     values=tuple(range(rows + 1))),)

    def set_table(self, table) -> None:
        """Set the rows ``[t, y]`` (padded with the last row to the option ``rows``)."""
        data = check_table(table, self.name)
        rows = self.option("rows")
        if len(data) > rows:
            raise ComponentError(f"{self._where()}: table has {len(data)} rows, more than the "
                                 f"{rows} of option rows")
        padded = np.vstack([data, np.repeat(data[-1:], rows - len(data), axis=0)])
        for k, (t, y) in enumerate(padded, start=1):
            self.values[f"table[{k},1]"] = float(t)
            self.values[f"table[{k},2]"] = float(y)
        self.validate()

    def table(self) -> np.ndarray:
        rows = self.option("rows")
        return np.array([[self.values[f"table[{k},1]"], self.values[f"table[{k},2]"]]
                         for k in range(1, rows + 1)])

    def validate(self) -> None:
        super().validate()
        times = self.table()[:, 0]
        bad = np.flatnonzero(np.diff(times) < 0)
        if bad.size:
            k = int(bad[0]) + 1
            raise ComponentError(f"{self._where()}: table times must not decrease; row {k + 1} "
                                 f"(t = {times[k]:g}) comes before row {k} (t = {times[k - 1]:g})")

    def parameter_constraints(self):
        # the FMU checks the order of its rows too: a table set through an FMU's parameters
        # never reached validate(); one check (the smallest gap), not one per row
        rows = self.option("rows")

        def smallest_gap(ns):
            times = [getattr(ns, f"table[{k},1]") for k in range(1, rows + 1)]
            return ca.mmin(ca.vertcat(*[b - a for a, b in zip(times, times[1:])]))
        return super().parameter_constraints() + [
            Constraint(smallest_gap, "TimeTable: table times must not decrease")]

    def equations(self, e):
        rows = self.option("rows")
        T = [getattr(e.p, f"table[{k},1]") for k in range(1, rows + 1)]
        Y = [getattr(e.p, f"table[{k},2]") for k in range(1, rows + 1)]
        q, tau = e.q.segment, e.t - e.p.startTime

        def early(tk):  # a row's time less EARLY (relative): where its event fires
            return tk - EARLY * ca.fmax(1, ca.fabs(tk))

        e.jump("segment", sum(ca.if_else(early(tk) <= tau, 1, 0) for tk in T))
        # the next row's time, in the segment the mode says (none after the last row)
        t_next = sum(ca.if_else(q == k, T[k], 0) for k in range(rows))
        e.indicator(ca.if_else(q < rows, tau - early(t_next), -1),
                    "time past the next row of the table")
        value = Y[0] + sum(ca.if_else(q == k, Y[k - 1] - Y[0], 0) for k in range(2, rows + 1))
        if self.option("interpolation") == "linear":
            for k in range(1, rows):  # between rows k and k+1 (1-based): q == k
                dt = T[k] - T[k - 1]
                slope = (Y[k] - Y[k - 1]) / ca.if_else(dt > 0, dt, 1)
                value += ca.if_else(q == k, slope * (tau - T[k - 1]), 0)
        e.residual(e.port("y") - (e.p.offset + value))

    def vectorised_functions(self, model) -> dict:
        """out, zc, jump and check as MX over the table's columns: loops in C, so that
        the code and gcc's time do not grow with the rows (the unrolled SX of a 256-row
        table took gcc 30 s). The same formulas as equations(), which stay the reference."""
        rows = self.option("rows")
        t, q = ca.MX.sym("t"), ca.MX.sym("q", model.q.numel())
        x, u, p = (ca.MX.sym(n, v.numel()) for n, v in (("x", model.x), ("u", model.u),
                                                        ("p", model.p)))
        names = [v.name for v in model.parameters]
        T = p[names.index("table[1,1]"):names.index("table[1,1]") + 2 * rows:2]
        Y = p[names.index("table[1,2]"):names.index("table[1,2]") + 2 * rows:2]
        tau = t - p[names.index("startTime")]
        k, segment = ca.DM(range(rows)), q[0]

        def at(column, index):  # column[index] for a symbolic index
            return ca.sum1(ca.if_else(k == index, column, 0))

        def early(tk):
            return tk - EARLY * ca.fmax(1, ca.fabs(tk))

        count = ca.sum1(ca.if_else(early(T) <= tau, 1, 0))
        z = ca.if_else(segment < rows, tau - early(at(T, segment)), -1)
        held = at(Y, ca.fmax(segment - 1, 0))
        if self.option("interpolation") == "linear":
            ta, tb = at(T, segment - 1), at(T, segment)
            ya, yb = held, at(Y, segment)
            inside = ca.logic_and(segment >= 1, segment < rows)
            dt = ca.if_else(tb - ta > 0, tb - ta, 1)
            value = ca.if_else(inside, ya + (yb - ya) / dt * (tau - ta), held)
        else:
            value = held
        y = p[names.index("offset")] + value
        args, labels = [t, x, q, u, p], ["t", "x", "q", "u", "p"]
        return {"out": ca.Function("mf_out", args, [ca.vertcat(y, z)], labels, ["y"]),
                "zc": ca.Function("mf_zc", args, [z], labels, ["z"]),
                "jump": ca.Function("mf_jump", args, [ca.MX(0, 1), count], labels,
                                    ["x_new", "q_new"]),
                "check": ca.Function("mf_check", args, [ca.mmin(T[1:] - T[:-1])], labels, ["g"])}


def check_table(table, where: str) -> np.ndarray:
    """`table` as an (n, 2) float array of rows [t, y], or one line saying what is wrong."""
    try:
        data = np.array(table, dtype=float)
    except (TypeError, ValueError):
        raise ComponentError(f"TimeTable '{where}': table must be rows [t, y] of numbers") from None
    if data.ndim != 2 or data.shape[1] != 2 or not 1 <= data.shape[0] <= MAX_ROWS:
        raise ComponentError(f"TimeTable '{where}': table must be 1 to {MAX_ROWS} rows [t, y], "
                             f"not an array of shape {data.shape}")
    if not np.isfinite(data).all():
        k = int(np.flatnonzero(~np.isfinite(data).all(axis=1))[0]) + 1
        raise ComponentError(f"TimeTable '{where}': table row {k} is not finite ({data[k - 1]})")
    return data
