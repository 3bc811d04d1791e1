"""Result tables: ``time`` plus ``<instance>.<variable>`` columns, indexable by name."""
from __future__ import annotations

import csv
from pathlib import Path
from typing import Callable

import numpy as np


def _column(values) -> np.ndarray:
    """Numbers as floats (every numeric FMI type, Booleans as 0/1); text (a String
    variable's values) as an object array."""
    values = np.asarray(values)
    return values.astype(object) if values.dtype.kind in "OUS" else np.asarray(values, dtype=float)


class Table:
    """Columns of equal length, by name; ``table['block.x']`` is a numpy array."""

    def __init__(self, columns: dict[str, np.ndarray]):
        self._columns = {k: _column(v) for k, v in columns.items()}

    @classmethod
    def from_rows(cls, names: list[str], rows: list[list]) -> "Table":
        """Rows of numbers (and text, for String variables), a column per name."""
        data = np.array(rows, dtype=object).reshape(len(rows), len(names))
        return cls({name: _column(list(data[:, i])) for i, name in enumerate(names)})

    @classmethod
    def from_array(cls, names: list[str], values: np.ndarray) -> "Table":
        """A 2-D float array of the caller's, a column per name, each a view of it: no
        value goes through Python (an engine run's event rows, where from_rows'
        per-value conversion cost more than a short run's integration)."""
        table = cls.__new__(cls)
        # the views are made where a column is first asked for (__getattr__): a run's
        # event tables are mostly never read, and 13 views cost a short run ~5 us
        table._array = np.asarray(values, dtype=float).reshape(-1, len(names))
        table._names = list(names)
        return table

    def __getattr__(self, name):
        # only for what the instance lacks: a from_array table's columns, once
        if name == "_columns" and "_array" in self.__dict__:
            values = self.__dict__["_array"]
            self._columns = {n: values[:, i] for i, n in enumerate(self.__dict__["_names"])}
            return self._columns
        raise AttributeError(f"{type(self).__name__!r} object has no attribute {name!r}")

    @property
    def columns(self) -> list[str]:
        return list(self._columns)

    def __getitem__(self, name: str) -> np.ndarray:
        try:
            return self._columns[name]
        except KeyError:
            raise KeyError(f"no column '{name}'; columns: {', '.join(self._columns)}") from None

    def __contains__(self, name: str) -> bool:
        return name in self._columns

    def __len__(self) -> int:
        return len(next(iter(self._columns.values()))) if self._columns else 0

    def to_structured(self) -> np.ndarray:
        """The fmpy/numpy shape: a structured array with one field per column."""
        out = np.zeros(len(self), dtype=[(name, v.dtype) for name, v in self._columns.items()])
        for name, values in self._columns.items():
            out[name] = values
        return out

    def to_csv(self, path: str | Path) -> None:
        with open(path, "w", newline="") as fh:
            writer = csv.writer(fh)
            writer.writerow(self.columns)
            for row in zip(*self._columns.values()):
                writer.writerow([v if isinstance(v, str) else repr(float(v)) for v in row])


class Result(Table):
    """A simulation result: the table at communication points, plus the events.

    ``events[instance]`` is a Table of that instance's outputs at each event its
    FMU located inside a step (time first), reported through FMI 3 intermediate
    update, so event times are known to solver precision whatever the step.
    """

    def __init__(self, columns: dict[str, np.ndarray], events: dict[str, Table] | None = None,
                 settings: dict | None = None):
        super().__init__(columns)
        self.events = events or {}
        self.settings = settings or {}

    @property
    def settings(self) -> dict:
        """How the run went: its solver, tolerance, step counts, wall time..."""
        settings = self._settings
        if callable(settings):  # of_columns' maker, called once, when first read
            settings = self._settings = settings()
        return settings

    @settings.setter
    def settings(self, value: dict) -> None:
        self._settings = value

    def __getstate__(self):
        # a maker is a closure, which pickle (dask's engine) and copy cannot take
        return {**self.__dict__, "_settings": self.settings}

    @classmethod
    def of_columns(cls, columns: dict[str, np.ndarray], events: dict[str, Table],
                   settings: dict | Callable[[], dict]) -> "Result":
        """A result of columns that are already what a Table holds (float arrays, object
        arrays of text), taken as they are: an engine run's, whose conversion one by one
        cost a short run a microsecond or two. `settings` may be a function that makes
        them: it is called when they are first read (a parameter study's runs mostly
        never read them, and their dict costs a short run ~5 us)."""
        result = cls.__new__(cls)
        result._columns, result.events, result._settings = columns, events, settings
        return result
