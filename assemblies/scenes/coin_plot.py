"""The rolling coin's picture: its track on the ground beside its lean over time."""
from __future__ import annotations

import math
from pathlib import Path


from ..plot import pyplot
from ..result import Result


def plot_coin(result: Result, title: str, path: str | Path, instance: str = "coin") -> None:
    """Left: contact path and centre path seen from above (equal axes, so a circle looks
    like one), start and end marked. Right: lean from upright in degrees, and the end of
    the run if the coin fell flat."""
    plt = pyplot()
    t = result["time"]
    fig, (ground, lean) = plt.subplots(1, 2, figsize=(12, 5), gridspec_kw={"width_ratios": [1, 1.3]})
    xc, yc = result[f"{instance}.x_C"], result[f"{instance}.y_C"]
    ground.plot(result[f"{instance}.x"], result[f"{instance}.y"], lw=0.8, color="0.6",
                label="centre G (projected)")
    ground.plot(xc, yc, lw=1.6, color="tab:blue", label="contact point C")
    ground.plot(xc[:1], yc[:1], "o", color="tab:green", label="start")
    ground.plot(xc[-1:], yc[-1:], "s", color="tab:red", label="end")
    ground.set_aspect("equal", adjustable="datalim")
    ground.set_xlabel("x [m]")
    ground.set_ylabel("y [m]")
    ground.set_title("track on the ground")
    ground.grid(alpha=0.3)
    ground.legend(loc="best", fontsize=8)
    lean.plot(t, [math.degrees(v) for v in result[f"{instance}.lean"]], lw=1.2, color="tab:purple")
    lean.axhline(0.0, color="0.5", lw=0.8)
    end = (result.settings or {}).get("terminated")
    if end:
        lean.axvline(end["time"], color="tab:red", ls="--", lw=1,
                     label=f"{end['message']}")
        lean.legend(loc="best", fontsize=8)
    lean.set_xlabel("time [s]")
    lean.set_ylabel("lean from upright [deg]")
    lean.set_title("lean angle")
    lean.grid(alpha=0.3)
    fig.suptitle(title)
    fig.tight_layout()
    fig.savefig(path, dpi=110)
    plt.close(fig)
