"""Pictures of the seed 9.6 scenes as the seed draws them (Figs. 9.8, 9.10): the block's
absolute velocity, its mean over each cycle of the table, and the reference the scene's
figures are held to. The block's own state is its velocity relative to the table, which
swings with the table and hides what the section is about.

No event markers: the block sticks and slips once or twice in every cycle of the table,
and a dot per event would cover the curve (the run's CSV and JSON keep the events)."""
from __future__ import annotations

import math
from dataclasses import dataclass
from pathlib import Path

import numpy as np

from ..plot import pyplot
from ..result import Result


@dataclass
class TableSeries:
    """What the picture draws, each in m/s against time in s."""
    time: np.ndarray
    velocity: np.ndarray        # the block's absolute velocity
    cycle_time: np.ndarray      # the middle of each whole cycle of the table
    cycle_mean: np.ndarray      # the block's mean absolute velocity over that cycle
    reference_time: np.ndarray
    reference: np.ndarray
    reference_label: str


def _figure(result: Result, name: str):
    return next((f for f in getattr(result, "figures", []) if f.name == name), None)


def table_series(result: Result, period: float) -> TableSeries:
    """The series of a run of moving_table or conveyor; `period` is the table's 2 pi / omega.

    The reference is the one the run's figures were held to, so it follows any --param:
    moving_table's is the seed's averaged law V' = -rate V from V(0) (figure
    ``decay_rate``), conveyor's the exact periodic speed (figure ``V_steady``)."""
    from .table import cycle_averaged_velocity  # the scene module imports this one
    t = result["time"]
    velocity = result["block.v"] + result["table.flange.v"]  # block.v is relative to the table
    cycle_time, cycle_mean = cycle_averaged_velocity(result, period)
    decay, steady = _figure(result, "decay_rate"), _figure(result, "V_steady")
    if decay is not None:
        reference = velocity[0] * np.exp(-decay.reference * t)
        label = (f"seed's averaged law V(0) exp(-{decay.reference:.4g} t), "
                 f"rate 2 mu g / (pi omega U)")
        return TableSeries(t, velocity, cycle_time, cycle_mean, t, reference, label)
    if steady is not None:
        ends = np.array([t[0], t[-1]])
        return TableSeries(t, velocity, cycle_time, cycle_mean, ends,
                           np.full(2, steady.reference),
                           f"exact periodic Coulomb speed {steady.reference:.6g}")
    return TableSeries(t, velocity, cycle_time, cycle_mean, t[:0], t[:0], "")


def plot_table(result: Result, title: str, path: str | Path) -> None:
    """One panel: absolute velocity (thin), cycle means (dots), the reference (dashed)."""
    plt = pyplot()
    import textwrap
    period = 2 * math.pi / result.assembly.component("table").values["omega"]
    s = table_series(result, period)
    fig, ax = plt.subplots(figsize=(9, 4.6))
    ax.plot(s.time, s.velocity, lw=0.6, color="0.55", label="absolute velocity of the block")
    ax.plot(s.cycle_time, s.cycle_mean, "o-", ms=3, lw=1.2, color="k",
            label="its mean over each cycle of the table")
    if len(s.reference):
        ax.plot(s.reference_time, s.reference, "--", lw=1.2, color="tab:red",
                label=s.reference_label)
    ax.set_xlabel("time [s]")
    ax.set_ylabel("velocity [m/s]")
    ax.grid(alpha=0.3)
    ax.legend(loc="best", fontsize=8)
    fig.suptitle(textwrap.fill(title, 100), fontsize=10)
    fig.tight_layout()
    fig.savefig(path, dpi=110)
    plt.close(fig)
