"""Plots of a scene's result: one panel per recorded quantity, its unit on the y axis,
events marked."""
from __future__ import annotations

import sys
import textwrap
from pathlib import Path

import numpy as np

from .result import Result

def pyplot():
    """matplotlib.pyplot, loaded on the first plot rather than with the modules that plot:
    it takes 0.4 s, and a run that a bad setting ends must answer at once (assemblies.run
    and the scene registry import every plotting module)."""
    import matplotlib
    matplotlib.use("Agg")  # files only: runs headless on CI and servers
    if "matplotlib.pyplot" in sys.modules:
        return sys.modules["matplotlib.pyplot"]
    import matplotlib.artist
    # Each artist class matplotlib defines writes a docstring of every property its set()
    # takes (artist.kwdoc): 0.15-0.3 s of the import, for help() texts a plot to a file
    # never reads. Skipped while pyplot loads, then put back for whatever comes later.
    kwdoc = getattr(matplotlib.artist, "kwdoc", None)
    if callable(kwdoc):
        matplotlib.artist.kwdoc = lambda artist: ""
    try:
        import matplotlib.pyplot as plt
    finally:
        if callable(kwdoc):
            matplotlib.artist.kwdoc = kwdoc
    return plt


# the suptitle's font size, and the characters of it that fit on one line of an 8 in figure
TITLE_SIZE, TITLE_WIDTH = 10, 95


def column_units(assembly, columns: list[str]) -> dict[str, str]:
    """The unit each ``instance.variable`` column is declared with: by one of our
    components' equations, or by a foreign FMU's model description (or the units= it was
    added with); a column nobody declares a unit for is left out."""
    units, declared = {}, {}
    for column in columns:
        instance, _, name = column.partition(".")
        component = assembly.components.get(instance)
        if component is None:
            continue
        if instance not in declared:
            declared[instance] = _declared_units(component)
        unit = declared[instance].get(name)
        if unit:
            units[column] = unit
    return units


def _declared_units(component) -> dict[str, str]:
    from components.component import Component
    if isinstance(component, Component):
        from fmus.build import component_facts

        from .engine.prepare import class_defaults
        # filed with the FMU the run fetched (its class, profile and options): read, not
        # flattened, so a plot does not load CasADi
        return component_facts(class_defaults(component))["units"]
    md = getattr(component, "model_description", None)  # assemblies.foreign.FMU
    if md is None:
        return {}
    units = {v.name: v.unit or (v.declaredType.unit if v.declaredType is not None else None)
             for v in md.modelVariables}
    for port in getattr(component, "ports", ()):  # a signal port's unit, units= included
        if port.domain.flow is None and port.domain.across[0][1]:
            units[port.name] = port.domain.across[0][1]
    return units


# a column that stays within this fraction of its size is drawn as its change from the
# start: matplotlib would otherwise label its ticks with an offset (1e-9+1.520398e-2)
NEARLY_CONSTANT = 1e-3


def panel_series(values, column: str, unit: str | None = None):
    """(y values, y label, offset subtracted) of one panel. A nearly constant column (a
    conserved energy) is drawn as its change from its first value, which the label
    states, so the axis reads the drift in the column's unit."""
    values = np.asarray(values, float)
    finite = values[np.isfinite(values)]
    unit_text = f" [{unit}]" if unit else ""
    if len(finite) and finite[0] != 0 and (
            np.ptp(finite) <= NEARLY_CONSTANT * np.max(np.abs(finite))):
        start = float(values[0]) if np.isfinite(values[0]) else float(finite[0])
        return values - start, f"{column} - {start:.10g}{unit_text}", start
    return values, f"{column}{unit_text}", 0.0


def plot_result(result: Result, columns: list[str], title: str, path: str | Path,
                units: dict[str, str] | None = None) -> None:
    plt = pyplot()
    units = units or {}
    fig, axes = plt.subplots(len(columns), 1, sharex=True, figsize=(8, 2.2 * len(columns) + 0.8),
                             squeeze=False)
    for ax, column in zip(axes[:, 0], columns):
        values, ylabel, offset = panel_series(result[column], column, units.get(column))
        ax.plot(result["time"], values, lw=1.2, label=column)
        instance = column.split(".")[0]
        events = result.events.get(instance)
        if events is not None and column in events:
            ax.plot(events["time"], np.asarray(events[column], float) - offset, "o", ms=3.5,
                    color="tab:red", label="events located by the FMU")
        ax.set_ylabel(ylabel)
        ax.ticklabel_format(axis="y", useOffset=False)  # a tick reads as its value
        ax.grid(alpha=0.3)
        ax.legend(loc="upper left", fontsize=8)
    axes[-1, 0].set_xlabel("time [s]")
    # a scene's description can outrun the figure: wrapped to its width
    fig.suptitle(textwrap.fill(title, TITLE_WIDTH), fontsize=TITLE_SIZE)
    fig.tight_layout()
    fig.savefig(path, dpi=110)
    plt.close(fig)
