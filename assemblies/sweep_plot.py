"""Plots of a parameter study: each chosen column over one parameter, or a map over two;
failed runs marked where they lie."""
from __future__ import annotations

import textwrap
from pathlib import Path

import matplotlib

matplotlib.use("Agg")  # files only: runs headless on CI and servers
import matplotlib.pyplot as plt  # noqa: E402
import numpy as np  # noqa: E402
import pandas as pd  # noqa: E402

MAX_PANELS = 4
BOOKKEEPING = {"run", "status", "error", "passed", "wall_s", "worker"}


def default_columns(table: pd.DataFrame) -> list[str]:
    """What a plot shows unless told: the study's outputs and measured numbers, else the
    scene's figures (each beside its reference), at most MAX_PANELS, none all NaN."""
    params = set(table.attrs.get("params", {}))
    chosen = [c for c in table.columns if c not in params and c not in BOOKKEEPING
              and not c.endswith(".ref") and f"{c}.ref" not in table.columns]
    if not chosen:
        chosen = [c for c in table.columns if f"{c}.ref" in table.columns]
    numeric = [c for c in chosen if pd.api.types.is_numeric_dtype(table[c])
               and np.isfinite(table[c].to_numpy(float)).any()]
    return numeric[:MAX_PANELS]


def check_columns(table: pd.DataFrame, columns: list[str]) -> None:
    """SweepError naming the first of `columns` the table lacks, and the columns it has."""
    for column in columns:
        if column not in table.columns:
            from .sweep import SweepError
            raise SweepError(f"cannot plot '{column}': the study has no such column; "
                             f"columns: {', '.join(table.columns)}")


def labelled(table: pd.DataFrame, column: str) -> str:
    """`column` with its unit, as the study found it declared (``table.attrs["units"]``:
    a component's variable or a figure's description); bare where it has none."""
    unit = table.attrs.get("units", {}).get(column)
    return f"{column} [{unit}]" if unit else column


def plot_sweep(table: pd.DataFrame, varying: list[str], columns: list[str],
               path: str | Path) -> None:
    """One panel per column: over one parameter a line (with the figure's reference,
    dashed, where it has one), over two a coloured map (cells for a grid, points for a
    random design). Axes carry the columns' units."""
    check_columns(table, columns)
    ok, failed = table[table["status"] == "ok"], table[table["status"] == "failed"]
    fig, axes = plt.subplots(len(columns), 1, figsize=(7.5, 2.6 * len(columns) + 0.9),
                             squeeze=False, sharex=True)
    for ax, column in zip(axes[:, 0], columns):
        if len(varying) == 1:
            _line(ax, ok, failed, varying[0], column)
            ax.set_ylabel(labelled(table, column))
        else:
            _map(ax, fig, ok, failed, varying[0], varying[1], column,
                 table.attrs.get("design", "grid") == "grid", labelled(table, column))
            ax.set_ylabel(labelled(table, varying[1]))
    axes[-1, 0].set_xlabel(labelled(table, varying[0]))
    title = f"{table.attrs.get('scene', '')}: {table.attrs.get('description', '')}"
    fig.suptitle(textwrap.fill(f"{title} ({len(table)} runs, {len(failed)} failed)", 90),
                 fontsize=10)
    fig.tight_layout()
    fig.savefig(path, dpi=110)
    plt.close(fig)


def _line(ax, ok, failed, x, column):
    ordered = ok.sort_values(x)
    ax.plot(ordered[x], ordered[column], "o-", ms=3.5, lw=1.2, label=column)
    if f"{column}.ref" in ordered.columns:
        ax.plot(ordered[x], ordered[f"{column}.ref"], "--", lw=1.0, color="k",
                label="reference")
    if len(failed):
        ax.plot(failed[x], np.zeros(len(failed)), "x", color="tab:red", label="failed run")
    values = ordered[column].to_numpy(float)
    values = values[np.isfinite(values)]
    if len(values) and values.min() > 0 and values.max() > 1e3 * values.min():
        ax.set_yscale("log")  # a growth against a bounded motion spans decades
    ax.grid(alpha=0.3)
    ax.legend(loc="best", fontsize=8)


def _map(ax, fig, ok, failed, x, y, column, is_grid, label):
    if is_grid:  # cells; a failed run's is left blank
        grid = ok.pivot_table(index=y, columns=x, values=column, aggfunc="first",
                              dropna=False)
        mesh = ax.pcolormesh(grid.columns.to_numpy(float), grid.index.to_numpy(float),
                             grid.to_numpy(float), shading="nearest")
    else:
        mesh = ax.scatter(ok[x], ok[y], c=ok[column], s=28)
    fig.colorbar(mesh, ax=ax, label=label)
    if len(failed):
        ax.plot(failed[x], failed[y], "x", color="tab:red", label="failed run")
        ax.legend(loc="best", fontsize=8)


__all__ = ["check_columns", "default_columns", "labelled", "plot_sweep"]
