"""Pictures of the seed 9.2, 9.3 and 9.5 scenes, drawn as the book draws them: the
resonant growth with its dashed line of slope 0.118 (Figs. 9.6, 9.7), displacement and
velocity of the smooth law with the exact slip and stick instants (Fig. 9.4), steady
sliding as a centre and a focus, and the distinguished limit's first slips against K.

Reference lines are the run's figures' references, so a picture follows any --param
(a run sets its figures before it draws)."""
from __future__ import annotations

import math
from pathlib import Path

import numpy as np

from ..plot import pyplot
from ..result import Result


def _figure(result: Result, name: str):
    return next((f for f in getattr(result, "figures", []) if f.name == name), None)


def _reference(result: Result, name: str) -> float:
    f = _figure(result, name)
    return f.reference if f is not None else math.nan


def _save(fig, title: str, path: str | Path) -> None:
    plt = pyplot()
    import textwrap
    fig.suptitle(textwrap.fill(title, 110), fontsize=10)
    fig.tight_layout()
    fig.savefig(path, dpi=110)
    plt.close(fig)


def plot_resonance(result: Result, title: str, path: str | Path) -> None:
    """Left: x(t) of each block (Fig. 9.6/9.7's heavy line) with the seed's dashed lines
    of the predicted rate. Right: |x| at the turning points, measured, beside the
    half-period law's closed-form points."""
    plt = pyplot()
    from .friction_seed import turning_points  # the scene module imports this one

    t = result["time"]
    blocks = [b for b in ("block", "locked") if f"{b}.x" in result]
    fig, (left, right) = plt.subplots(1, 2, figsize=(13, 4.8))
    for b, colour in zip(blocks, ("k", "tab:blue")):
        left.plot(t, result[f"{b}.x"], lw=1.6 if b == "block" else 1.0, color=colour, label=b)
        pts = np.array(turning_points(result, b) or np.empty((0, 2)))
        if len(pts):
            right.plot(pts[:, 0], np.abs(pts[:, 1]), "o", ms=4, color=colour,
                       label=f"{b}: turning points of the run")
    rate, name = _reference(result, "rate"), "rate"
    if math.isnan(rate):
        rate, name = _reference(result, "rate_locked"), "rate_locked"
    if name == "rate":  # the seed's dashed line through the locked growth
        a_end, t_end = _reference(result, "A_last"), _reference(result, "t_last")
        line = abs(a_end) + rate * (t - t_end)
    else:               # the locked block's |x| falls along the law from |x(0)|
        line = abs(result["locked.x"][0]) + rate * t
    keep = line > 0
    for sign in (1, -1):
        left.plot(t[keep], sign * line[keep], "--", color="tab:red", lw=1,
                  label=f"slope {rate:+.4f} (U pi - 4 mu)/(2 pi)" if sign > 0 else None)
    right.plot(t[keep], line[keep], "--", color="tab:red", lw=1)
    law = [(_reference(result, f"t_A{j}"), _reference(result, f"A{j}")) for j in range(1, 20)]
    law = [(a, b) for a, b in law if math.isfinite(a)]
    if law:
        tl, xl = zip(*law)
        right.plot(tl, np.abs(xl), "x", ms=8, color="tab:green",
                   label="half-period law: |x| falls by U pi/2 + 2 mu")
    left.set_xlabel("t [s]")
    left.set_ylabel("x [m]")
    left.grid(alpha=0.3)
    left.legend(loc="upper right", fontsize=8)
    right.set_xlabel("t [s]")
    right.set_ylabel("|x| at turning points [m]")
    right.grid(alpha=0.3)
    if right.get_legend_handles_labels()[0]:  # a run stopped before a turning point has none
        right.legend(loc="best", fontsize=8)
    _save(fig, title, path)


def plot_smooth(result: Result, title: str, path: str | Path) -> None:
    """Fig. 9.4: displacement (left), velocity (middle), and the velocity near zero
    (right) of the smooth law, with the exact Coulomb slip t1 and stick t2 (dashed)."""
    plt = pyplot()
    t = result["time"]
    t1, t2 = _reference(result, "t1"), _reference(result, "t2")
    fig, axes = plt.subplots(1, 3, figsize=(15, 4.5))
    for name, colour in (("smooth", "k"), ("finer", "tab:blue")):
        if f"{name}.x" not in result:
            continue
        axes[0].plot(t, result[f"{name}.x"], color=colour, lw=1.2, label=name)
        for ax in axes[1:]:
            ax.plot(t, result[f"{name}.v"], color=colour, lw=1.2, label=name)
    for ax in axes:
        for when in (t1, t2):
            ax.axvline(when, color="tab:red", ls="--", lw=0.9)
        ax.set_xlabel("t [s]")
        ax.grid(alpha=0.3)
    axes[0].set_ylabel("x [m]")
    axes[1].set_ylabel("x' [m/s]")
    axes[2].set_ylabel("x' [m/s] near zero")
    axes[2].set_xlim(t1 - 1.0, t2 + 1.0)
    axes[2].set_ylim(-0.002, 0.01)
    axes[0].legend(loc="upper left", fontsize=8)
    axes[1].set_title("dashed: exact Coulomb t1, t2", fontsize=9)
    _save(fig, title, path)


def plot_sliding(result: Result, title: str, path: str | Path) -> None:
    """Left: how far each block trails its driven end, v t - x, about x_ss. Right: the
    deviation from steady sliding in its phase plane: a centre without damping, a focus
    with it."""
    plt = pyplot()
    t = result["time"]
    x_ss = _reference(result, "lag")
    fig, (left, right) = plt.subplots(1, 2, figsize=(13, 4.8))
    for name, colour in (("steady", "k"), ("neutral", "tab:blue"), ("damped", "tab:orange")):
        eta = result[f"{name}.x"] - result["steady.x"]  # steady is exactly v t - x_ss
        left.plot(t, x_ss - eta, color=colour, lw=1.2, label=name)
        right.plot(eta, result[f"{name}.v"] - result["steady.v"], color=colour, lw=1.0,
                   label=name)
    left.axhline(x_ss, color="tab:red", ls="--", lw=0.9, label="x_ss = mu_k m g / k")
    left.set_xlabel("t [s]")
    left.set_ylabel("v t - x [m]")
    right.set_xlabel("eta = x - (v t - x_ss) [m]")
    right.set_ylabel("eta' [m/s]")
    right.set_aspect("equal", adjustable="datalim")
    for ax in (left, right):
        ax.grid(alpha=0.3)
        ax.legend(loc="upper right", fontsize=8)
    _save(fig, title, path)


def plot_distinguished_limit(result: Result, title: str, path: str | Path) -> None:
    """Left: the pull on the front mass and the tension inside the block, for each K:
    the front slips at mu_s m g / n, the block's inner springs then load step by step.
    Right: the first slip time against K beside mu_s m g / (n k v) and the rigid block's."""
    plt = pyplot()
    from .friction_seed import mode_changes  # the scene module imports this one

    t = result["time"]
    prefixes = sorted({c.split("_")[0] for c in result.columns if c.endswith("pull.f")})
    n = sum(1 for c in result.columns if c.startswith(prefixes[0] + "_mass") and c.endswith(".s"))
    fig, (left, right) = plt.subplots(1, 2, figsize=(13, 4.8))
    colours = ("tab:blue", "tab:orange", "tab:green")
    t_ref = math.nan
    for pre, colour in zip(prefixes, colours):
        K = 10.0 ** int(pre[1:])
        # the pulled spring runs from the driven end back to the front mass: its tension
        # is -f in MSL's orientation (flange_b behind flange_a)
        left.plot(t, -result[f"{pre}_pull.f"], color=colour, lw=1.2, label=f"pull, K = {K:g}")
        if n > 1:
            left.plot(t, result[f"{pre}_link1.f"], color=colour, lw=0.9, ls=":",
                      label=f"tension between masses 1 and 2, K = {K:g}")
        f = _figure(result, f"t_slip_{pre}")
        if f is not None:
            right.plot([K], [f.measured], "o", color=colour, ms=7)
            t_ref = f.reference
        rear = [t for t, _, before, after in mode_changes(result, f"{pre}_mass{n}")
                if before == 0 != after][:1]
        if rear:
            right.plot([K], rear, "s", color=colour, ms=7, mfc="none",
                       label=None if pre != prefixes[0] else "squares: the rear mass's first "
                       "slip (the whole block slides)")
    if math.isfinite(t_ref):
        pull_at_slip = float(np.interp(t_ref, t, -result[f"{prefixes[0]}_pull.f"]))
        left.axhline(pull_at_slip, color="tab:red", ls="--", lw=0.9,
                     label=f"front mass's static limit mu_s m g / {n}")
        left.axvline(t_ref, color="tab:red", ls="--", lw=0.6)
        Ks = np.array([10.0 ** int(p[1:]) for p in prefixes])
        span = np.array([Ks.min() / 3, Ks.max() * 3])
        right.plot(span, [t_ref] * 2, "--", color="tab:red",
                   label=f"mu_s m g / (n k v), n = {n}: {t_ref:g} s")
        right.plot(span, [n * t_ref] * 2, ":", color="k",
                   label=f"rigid block (n = 1): {n * t_ref:g} s")
        limit = _figure(result, "t_rear_K4")
        if limit is not None:
            right.plot(span, [limit.reference] * 2, "-.", color="tab:purple",
                       label=f"rear half's first slip as K -> oo: {limit.reference:g} s")
        right.set_ylim(0, n * t_ref * 1.2)
    right.set_xscale("log")
    right.set_xlabel("K [N/m]")
    right.set_ylabel("first slip [s]")
    left.set_xlabel("t [s]")
    left.set_ylabel("force [N]")
    for ax in (left, right):
        ax.grid(alpha=0.3)
        ax.legend(loc="best", fontsize=8)
    _save(fig, title, path)
