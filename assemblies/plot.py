"""Plots of a scene's result: one panel per recorded quantity, events marked."""
from __future__ import annotations

import textwrap
from pathlib import Path

import matplotlib

matplotlib.use("Agg")  # files only: runs headless on CI and servers
import matplotlib.pyplot as plt  # noqa: E402

from .result import Result  # noqa: E402


def plot_result(result: Result, columns: list[str], title: str, path: str | Path) -> None:
    fig, axes = plt.subplots(len(columns), 1, sharex=True, figsize=(8, 2.2 * len(columns) + 0.8),
                             squeeze=False)
    for ax, column in zip(axes[:, 0], columns):
        ax.plot(result["time"], result[column], lw=1.2, label=column)
        instance = column.split(".")[0]
        events = result.events.get(instance)
        if events is not None and column in events:
            ax.plot(events["time"], events[column], "o", ms=3.5, color="tab:red",
                    label="events located by the FMU")
        ax.set_ylabel(column)
        ax.grid(alpha=0.3)
        ax.legend(loc="upper left", fontsize=8)
    axes[-1, 0].set_xlabel("time [s]")
    fig.suptitle(textwrap.fill(title, 90))  # a scene's description can outrun the figure
    fig.tight_layout()
    fig.savefig(path, dpi=110)
    plt.close(fig)
