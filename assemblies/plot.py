"""Plots of a scene's result: one panel per recorded quantity, its unit on the y axis,
events marked."""
from __future__ import annotations

import sys
import textwrap
from pathlib import Path

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
    """The unit each ``instance.variable`` column is declared with, where one of our
    components declares it (a foreign FMU's columns are left out: no equations to ask)."""
    from components.component import Component
    from fmus.build import component_facts

    from .engine.prepare import class_defaults
    units, flat = {}, {}
    for column in columns:
        instance, _, name = column.partition(".")
        component = assembly.components.get(instance)
        if not isinstance(component, Component):
            continue
        if instance not in flat:
            # filed with the FMU the run fetched (its class, profile and options): read, not
            # flattened, so a plot does not load CasADi
            flat[instance] = component_facts(class_defaults(component))["units"]
        unit = flat[instance].get(name)
        if unit:
            units[column] = unit
    return units


def plot_result(result: Result, columns: list[str], title: str, path: str | Path,
                units: dict[str, str] | None = None) -> None:
    plt = pyplot()
    units = units or {}
    fig, axes = plt.subplots(len(columns), 1, sharex=True, figsize=(8, 2.2 * len(columns) + 0.8),
                             squeeze=False)
    for ax, column in zip(axes[:, 0], columns):
        ax.plot(result["time"], result[column], lw=1.2, label=column)
        instance = column.split(".")[0]
        events = result.events.get(instance)
        if events is not None and column in events:
            ax.plot(events["time"], events[column], "o", ms=3.5, color="tab:red",
                    label="events located by the FMU")
        ax.set_ylabel(f"{column} [{units[column]}]" if column in units else column)
        ax.grid(alpha=0.3)
        ax.legend(loc="upper left", fontsize=8)
    axes[-1, 0].set_xlabel("time [s]")
    # a scene's description can outrun the figure: wrapped to its width
    fig.suptitle(textwrap.fill(title, TITLE_WIDTH), fontsize=TITLE_SIZE)
    fig.tight_layout()
    fig.savefig(path, dpi=110)
    plt.close(fig)
