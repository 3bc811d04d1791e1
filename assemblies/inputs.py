"""Inputs from a table: an assembly's open signal inputs fed by TimeTable instances.

A table (a numpy structured array or a pandas DataFrame with a ``time`` column, or the
path of a CSV file with a header row, as fmpy's ``_in.csv`` files are) names in each
other column an open input: ``<instance>.<input>``, or ``<input>`` alone in an assembly
of one instance. Each column becomes a :class:`components.sources.table.TimeTable`
connected to that input, so the run's masters, every mode and engine and an exported
assembly FMU, see an ordinary FMU with its own events. fmpy's rules
(:class:`fmpy.simulation.Input`): continuous Float64 inputs interpolated linearly,
discrete and Int32 ones held; two rows at one time are a discontinuity, with an event there;
before the first row the first value, after the last the last.

The table is input, not code: its size is bounded, its times must be finite and
non-decreasing, its values finite, and every column must name an open input.
"""
from __future__ import annotations

import csv
import re
from pathlib import Path

import numpy as np

from components.interfaces import SIGNAL_IN, ComponentError
from components.sources.table import MAX_ROWS, TimeTable

from .assembly import Assembly, AssemblyError, Connection

MAX_COLUMNS = 256            # inputs fed from one table
MAX_CSV_BYTES = 16 * 2**20   # a CSV of MAX_ROWS x MAX_COLUMNS numbers fits well within
TIME = "time"


def read_table(inputs) -> tuple[np.ndarray, dict[str, np.ndarray]]:
    """(times, {column: values}) of `inputs`, checked; one line on what is wrong."""
    if isinstance(inputs, (str, Path)):
        names, data = _read_csv(Path(inputs))
    elif hasattr(inputs, "columns") and hasattr(inputs, "to_numpy"):  # a pandas DataFrame
        names = [str(c) for c in inputs.columns]
        data = [inputs[c].to_numpy() for c in inputs.columns]
    elif isinstance(inputs, np.ndarray) and inputs.dtype.names:
        names = list(inputs.dtype.names)
        data = [inputs[n] for n in names]
    else:
        raise AssemblyError(f"inputs must be a numpy structured array, a pandas DataFrame or "
                            f"the path of a CSV file, with a '{TIME}' column, not "
                            f"{type(inputs).__name__}")
    if TIME not in names:
        raise AssemblyError(f"inputs: no '{TIME}' column; columns: {', '.join(names) or '(none)'}")
    if len(names) - 1 > MAX_COLUMNS:
        raise AssemblyError(f"inputs: {len(names) - 1} input columns, more than the "
                            f"{MAX_COLUMNS} allowed")
    if len(set(names)) != len(names):
        twice = sorted({n for n in names if names.count(n) > 1})
        raise AssemblyError(f"inputs: column {twice[0]!r} appears more than once")
    columns = {}
    for name, values in zip(names, data):
        try:
            values = np.asarray(values, dtype=float)
        except (TypeError, ValueError):
            raise AssemblyError(f"inputs: column {name!r} is not numbers") from None
        if values.ndim != 1:
            raise AssemblyError(f"inputs: column {name!r} must hold one number per row")
        columns[name] = values
    times = columns.pop(TIME)
    if not 1 <= len(times) <= MAX_ROWS:
        raise AssemblyError(f"inputs: {len(times)} rows; a table has 1 to {MAX_ROWS} rows")
    for name, values in [(TIME, times), *columns.items()]:
        bad = np.flatnonzero(~np.isfinite(values))
        if bad.size:
            raise AssemblyError(f"inputs: column {name!r} row {bad[0] + 1} is {values[bad[0]]}, "
                                "not a finite number")
    back = np.flatnonzero(np.diff(times) < 0)
    if back.size:
        k = int(back[0]) + 1
        raise AssemblyError(f"inputs: times must not decrease; row {k + 1} (time {times[k]:g}) "
                            f"comes after row {k} (time {times[k - 1]:g})")
    return times, columns


def _read_csv(path: Path) -> tuple[list[str], list[list[str]]]:
    try:
        size = path.stat().st_size
    except OSError as exc:
        raise AssemblyError(f"inputs: cannot read {path}: {exc.strerror or exc}") from None
    if size > MAX_CSV_BYTES:
        raise AssemblyError(f"inputs: {path} has {size} bytes, more than the "
                            f"{MAX_CSV_BYTES} allowed")
    try:
        with path.open(newline="", encoding="utf-8") as f:
            rows = list(csv.reader(f))
    except (OSError, UnicodeDecodeError, csv.Error) as exc:
        raise AssemblyError(f"inputs: cannot read {path}: {exc}") from None
    rows = [r for r in rows if r]
    if not rows:
        raise AssemblyError(f"inputs: {path} is empty; it needs a header row naming "
                            f"'{TIME}' and the inputs")
    names = [n.strip().strip('"') for n in rows[0]]
    values = []
    for k, row in enumerate(rows[1:], start=2):
        if len(row) != len(names):
            raise AssemblyError(f"inputs: {path} line {k} has {len(row)} fields, the header "
                                f"{len(names)}")
        try:
            values.append([float(x) for x in row])
        except ValueError:
            raise AssemblyError(f"inputs: {path} line {k} holds a field that is not a "
                                "number") from None
        if len(values) > MAX_ROWS:
            raise AssemblyError(f"inputs: {path} has more than {MAX_ROWS} rows")
    if not values:
        raise AssemblyError(f"inputs: {path} has a header and no rows")
    return names, [list(c) for c in zip(*values)]


def open_inputs(assembly: Assembly) -> dict[str, tuple[str, str]]:
    """The assembly's signal inputs that no connection feeds: ``"inst.port"`` ->
    (instance, port), under the profiles the components have now."""
    connected = {ref for c in assembly.connections for ref in (c.a, c.b)}
    found = {}
    for name, comp in assembly.components.items():
        for port in comp.ports:
            ref = f"{name}.{port.name}"
            if (port.domain.flow is None and comp.profile.ports.get(port.name) == SIGNAL_IN
                    and ref not in connected):
                found[ref] = (name, port.name)
    return found


def _held(component, port: str) -> bool:
    """Is this input discrete (held between rows, as fmpy holds it)?"""
    md = getattr(component, "model_description", None)
    if md is None:
        return False  # our components' signal inputs are continuous
    v = next((v for v in md.modelVariables if v.name == port), None)
    return v is not None and v.variability in ("discrete", "tunable")


def with_inputs(assembly: Assembly, inputs) -> Assembly:
    """A copy of `assembly` (same name and instances) with a TimeTable on each input
    `inputs` names; `assembly` itself is left as it was. None: `assembly`."""
    if inputs is None:
        return assembly
    times, columns = read_table(inputs)
    allowed = open_inputs(assembly)
    single = len(assembly.components) == 1
    fed = Assembly(assembly.name)
    fed.components = dict(assembly.components)
    fed.connections = list(assembly.connections)
    fed.signals_from_outside = assembly.signals_from_outside
    for column, values in columns.items():
        ref = column if "." in column and column in allowed else (
            f"{next(iter(assembly.components))}.{column}" if single else column)
        if ref not in allowed:
            names = [r.split(".", 1)[1] for r in allowed] if single else list(allowed)
            raise AssemblyError(f"inputs: column {column!r} is not an open input of assembly "
                                f"'{assembly.name}'; open inputs: {', '.join(names) or '(none)'}")
        instance, port = allowed[ref]
        domain = next(p.domain for p in assembly.components[instance].ports if p.name == port)
        integer = domain.value_type == "Int32"
        if integer:
            _check_int32(column, values)
        elif domain.value_type != "Float64":
            raise AssemblyError(f"inputs: column {column!r} feeds {ref}, a {domain.value_type} "
                                "input; a table feeds Float64 and Int32 inputs")
        table = _table_name(fed, instance, port)
        held = integer or _held(assembly.components[instance], port)
        try:
            fed.add(table, TimeTable(table=np.column_stack([times, values]),
                                     interpolation="hold" if held else "linear"))
        except ComponentError as exc:  # the table was checked: only a bound can be left
            raise AssemblyError(f"inputs: column {column!r}: {exc}") from None
        if integer:
            # the table's Float64 output set on an Int32 input: the masters set the
            # nearest integer, and the held values are whole, so it is each row's value
            fed.connections.append(Connection(f"{table}.y", ref))
        else:
            fed.connect(f"{table}.y", ref)
    return fed


def _check_int32(column: str, values: np.ndarray) -> None:
    bad = np.flatnonzero((values != np.round(values)) | (np.abs(values) > 2**31 - 1))
    if bad.size:
        raise AssemblyError(f"inputs: column {column!r} feeds an Int32 input, and row "
                            f"{bad[0] + 1} holds {values[bad[0]]:g}, not a whole number within "
                            f"+-{2**31 - 1}")


def _table_name(assembly: Assembly, instance: str, port: str) -> str:
    """An instance name for the table feeding ``instance.port`` not taken yet."""
    base = re.sub(r"\W", "_", f"{instance}_{port}_table")
    name, k = base, 2
    while name in assembly.components:
        name, k = f"{base}{k}", k + 1
    return name

