"""Issue 30: the Burridge-Knopoff fault, a chain of FaultBlocks dragged by a plate.

    plate1      plate2            platen       ConstantSpeed V, one per leaf spring
      |kp         |kp               |kp
    block1 -kc- block2 -kc- ... - blockn       FaultBlock: C&L velocity-weakening friction
                                               with exact stick/slip modes; free ends

The scene (n = 2, in ``me``, ``monolithic`` or ``cosim``) runs the chain as FMUs and
holds its slides to an independent scipy integration of the equations
(:mod:`.fault_references`) and its first break-away to the closed form; beside it the
event-driven fault solver (:mod:`assemblies.engine.fault`) runs the same values, held
to the same reference and to the energy balance. Another length or other values are
the scene's parameters (SCENE_PARAMETERS): ``mechfmu run burridge_knopoff --param n=6
--param ell=1``. Mode ``fault`` runs the chain in the fault solver alone, its event
catalogue as the result table, held to the energy balance, to scipy's slides for n <=
SCIPY_N and, on long chains, to Carlson & Langer's b: ``mechfmu run burridge_knopoff
--mode fault --param n=1000 --param ell=10 --param sigma=0.01 --param nu=0.01 --param
events=20000``; the FMU modes refuse a run beyond what they run here in about a minute
(me and monolithic bound n^2 x the stop time: ``--param n=1000 --stop-time 45``).
:func:`fault_study` adds a warm-up and runs the C&L model (no backward slides):
``python -m assemblies.scenes.burridge_knopoff --n 1000 --events 10000 --out DIR``.
"""
from __future__ import annotations

import argparse
import json
import math
import sys
from pathlib import Path

import numpy as np

from components import ConstantSpeed, FaultBlock, Spring

from ..assembly import Assembly
from ..engine.fault import FaultError, FaultRun, carlson_langer, run_fault, thresholds
from ..result import Result
from .scene import (DRIFT, Figure, RunBudget, Scene, SceneParameter, coupling_accuracy,
                    solver_accuracy)

#: the scene's chain: C&L units (m = kp = F0 = 1), short coupling and a fast plate so a
#: run of a few minutes' worth of events takes seconds as FMUs
SCENE_CHAIN = dict(n=2, ell=2.0, alpha=2.5, sigma=0.1, nu=0.05, heterogeneity=0.1, seed=3)
SCENE_STOP = 75.0  # [s]: a dozen slides, before the chain's chaos amplifies solver errors
#: Carlson & Langer 1989: small (localised) events follow Gutenberg-Richter with b = 1 in
#: the magnitude mu = ln(moment): a moment density ~ M^-(1 + b)
CL_B = 1.0


def fault_chain(n: int = 2, *, ell: float = 10.0, alpha: float = 2.5, sigma: float = 0.01,
                nu: float = 0.01, heterogeneity: float = 0.0, seed: int = 0) -> Assembly:
    """`n` FaultBlocks in Carlson & Langer's units (module doc), thresholds
    1 + heterogeneity u_i (u_i uniform in [-1, 1], from `seed`)."""
    F = thresholds(n, 1.0, heterogeneity, seed)
    p = carlson_langer(ell, alpha, sigma, nu)
    asm = Assembly(f"burridge_knopoff_{n}")
    for i in range(1, n + 1):
        asm.add(f"plate{i}", ConstantSpeed(v=p["V"]))
        asm.add(f"block{i}", FaultBlock(m=p["m"], kp=p["kp"], F_s=float(F[i - 1]),
                                        sigma=sigma, alpha=alpha, v_w=p["vw"]))
        asm.connect(f"plate{i}.flange", f"block{i}.plate")
        if i > 1:
            asm.add(f"link{i - 1}", Spring(c=p["kc"]))
            asm.connect(f"block{i - 1}.flange_b", f"link{i - 1}.flange_a")
            asm.connect(f"link{i - 1}.flange_b", f"block{i}.flange_a")
    return asm


def chain_values(asm: Assembly) -> dict:
    """The fault solver's arguments from a chain's instance values (as a run set them)."""
    blocks = sorted((name for name in asm.components if name.startswith("block")),
                    key=lambda name: int(name[5:]))
    b = [asm.component(name).values for name in blocks]
    first = b[0]
    for name, values in zip(blocks, b):
        for key in ("m", "kp", "sigma", "alpha", "v_w"):
            if values[key] != first[key]:
                raise FaultError(f"{name}.{key} = {values[key]:g} differs from block1's "
                                 f"{first[key]:g}: the fault solver takes one value per chain")
    plates = {asm.component(f"plate{i + 1}").values["v"] for i in range(len(blocks))}
    links = {asm.component(f"link{i}").values["c"] for i in range(1, len(blocks))}
    if len(plates) != 1 or len(links) > 1:
        raise FaultError("the plates' speeds and the links' stiffnesses must each be one value "
                         "for the fault solver")
    return dict(F=np.array([v["F_s"] for v in b]), m=first["m"], kp=first["kp"],
                kc=links.pop() if links else 0.0, V=plates.pop(), sigma=first["sigma"],
                alpha=first["alpha"], vw=first["v_w"],
                x0=np.array([asm.component(name).starts["x"] for name in blocks]))


def _fmu_slides(result: Result, n: int) -> list[tuple[int, float, float]]:
    """(block, start, end) of every slide the FMUs' located events show, in end order."""
    slides = []
    for i in range(n):
        ev = result.events.get(f"block{i + 1}")
        if ev is None:
            continue
        start = None
        for t, mode in zip(ev["time"], ev[f"block{i + 1}.mode"]):
            if mode != 0 and start is None:
                start = float(t)
            elif mode == 0 and start is not None:
                slides.append((i, start, float(t)))
                start = None
    return sorted(slides, key=lambda s: s[2])


def _by_block(slides) -> dict:
    """block -> its slides' (start, end), in order: slides are matched as each block's
    k-th, so two blocks' ends that swap order within the accuracy still match."""
    out: dict = {}
    for block, t0, t1 in sorted(slides, key=lambda s: s[2]):
        out.setdefault(block, []).append((t0, t1))
    return out


def _slide_error(measured, reference, gains) -> float:
    """Largest |start or end time| difference of matching slides (each block's k-th),
    each divided by the chain's amplification at that slide (`gains`, in `reference`'s
    order); NaN where a block of `reference` has fewer slides in `measured` or none."""
    if not reference:
        return math.nan
    ours, k_of, worst = _by_block(measured), {}, 0.0
    for (block, t0, t1), gain in zip(reference, gains):
        k = k_of[block] = k_of.get(block, -1) + 1
        if k >= len(ours.get(block, ())):
            return math.nan
        m0, m1 = ours[block][k]
        worst = max(worst, abs(m0 - t0) / gain, abs(m1 - t1) / gain)
    return worst


#: the chain's amplification up to which slides are compared one by one: beyond it a
#: solver's error of the run's tolerance has grown ten-thousandfold, and the chain's
#: chaos (Lyapunov growth through each slide that triggers the next) soon decides which
#: block slides next by it (n = 5 at tol 1e-10: 1e5 by t = 55 s, other slides soon after)
GAIN_HORIZON = 1e4


def slide_gains(F, *, stop_time: float, x0, tol: float, **values):
    """The reference's slides and the chain's amplification of an error at each.

    The reference is scipy's integration at tol/100 (:func:`scipy_slides`); run again
    from a start moved by delta = tol (alternately + and -: a uniform move is a mere
    time shift), the change of each slide's times, over the change delta / V that the
    same move makes in one uncoupled block's break-away, is the chain's amplification
    of an error of the run's tolerance at that slide (linear: the variational equation
    by finite differences, measured on the reference, not on the run under test); the
    gain of a slide is the largest up to it, and at least 1. Returns (the slides within
    GAIN_HORIZON as (block, start, end), their gains, the number of reference slides);
    the horizon also ends where the moved run's slides differ (which block slides)."""
    from .fault_references import scipy_slides
    x0 = np.asarray(x0, dtype=float)
    run = dict(values, stop_time=stop_time, rtol=tol / 100, atol=tol / 1e4)
    ref = [(b, t0, t1) for b, t0, t1, _ in scipy_slides(F, x0=x0, **run)[0]]
    delta = tol
    moved = [(b, t0, t1) for b, t0, t1, _ in
             scipy_slides(F, x0=x0 + delta * (-1.0) ** np.arange(x0.size), **run)[0]]
    one_block = delta / values["V"] if values["V"] > 0 else math.inf
    theirs, k_of, kept, gains, gain = _by_block(moved), {}, [], [], 1.0
    for block, t0, t1 in ref:
        k = k_of[block] = k_of.get(block, -1) + 1
        if k >= len(theirs.get(block, ())):
            break
        m0, m1 = theirs[block][k]
        gain = max(gain, abs(m0 - t0) / one_block, abs(m1 - t1) / one_block)
        if gain > GAIN_HORIZON:
            break
        kept.append((block, t0, t1))
        gains.append(gain)
    return kept, gains, len(ref)


#: the longest chain whose slides are held slide by slide to scipy's: beyond it a
#: scipy run over every block is slow, and the chain's chaos lets 1e-10 differences grow
#: into other slide sequences within the scene's run
SCIPY_N = 6


def _figures(result: Result, asm: Assembly) -> list[Figure]:
    values = chain_values(asm)
    F, x0 = values.pop("F"), values.pop("x0")
    n, tol = F.size, result.settings["tolerance"]
    fault = getattr(result, "fault_run", None)
    own = fault is not None  # mode fault: the solver's run is the result itself
    stop = fault.totals["time"] if own else float(result["time"][-1])
    if not own:
        fault = run_fault(F, **values, tol=tol, stop_time=stop, x0=x0)
    solver = sorted(((int(s["block"]), float(s["t0"]), float(s["t1"])) for s in fault.slides),
                    key=lambda s: s[2])
    # from rest with relaxed couplings each block's force is kp (V t - x0) + coupling
    first = min((F[i] - (values["kc"] * _lap(x0, i) - values["kp"] * x0[i]))
                / (values["kp"] * values["V"]) for i in range(n)) if values["V"] > 0 else math.nan
    fmu = [] if own else _fmu_slides(result, n)
    measured_first = min((s[1] for s in (solver if own else fmu)), default=math.nan)
    who = "fault solver" if own else "FMUs"
    figures = [Figure("t_first", f"{who}: first break-away [s] (closed form (F_i - B_i) / "
                      "(kp V))", measured_first, first, coupling_accuracy(result, first),
                      source='closed form (stuck chain under a uniformly moving plate, '
                             'derived here)')]
    if n <= SCIPY_N:
        # the reference: the equations in scipy, 100 times tighter than the run; each
        # slide's error is held to the run's accuracy times the chain's amplification
        # there (slide_gains), over the slides the amplification leaves determined
        ref, gains, total = slide_gains(F, **values, stop_time=stop, x0=x0, tol=tol)
        span = ref[-1][2] if ref else stop
        over = (f"over the {total} slides" if len(ref) == total else
                f"over the first {len(ref)} of {total} slides (to t = {span:.4g} s, where "
                f"the chain's amplification passes {GAIN_HORIZON:g}x)")
        over += (f" [s], each divided by the chain's amplification there (up to "
                 f"{max(gains, default=1.0):.3g}x: scipy's run from a start moved by tol)")
        if not own:
            figures.append(Figure(
                "slides", f"FMUs: largest slide start/end error {over} (vs scipy's "
                "event-driven integration at tol/100)",
                _slide_error(fmu, ref, gains), 0.0, coupling_accuracy(result, span),
                source='independent integration (scipy event-driven, fault_references)'))
        figures.append(Figure(
            "solver", f"fault solver: largest slide start/end error {over} (vs scipy)",
            _slide_error(solver, ref, gains), 0.0, solver_accuracy(result, span),
            source='independent integration (scipy event-driven, fault_references)'))
    t = fault.totals
    figures.append(Figure(
        "energy", "fault solver: friction dissipation + change in stored energy [J] "
        "(vs the plate's work)", t["dissipated"] + t["E_end"] - t["E_start"],
        t["plate_work"], DRIFT * tol, relative=True,
        source='conservation law (plate work = dissipation + stored energy)'))
    if own and n >= B_MIN_N and values["V"] > 0:
        # C&L's scaling is of the statistically steady chain: the events after the plate
        # has reloaded every leaf spring past its threshold 2.5 times (fault_study's warm-up)
        cat = fault.catalogue
        steady = cat[cat["start"] >= 2.5 * float(F.max()) / (values["kp"] * values["V"])]
        ell = math.sqrt(values["kc"] / values["kp"])
        lo, hi = localised_range(values["sigma"], ell)
        if np.count_nonzero((steady["moment"] >= lo) & (steady["moment"] <= hi)) >= B_MIN_EVENTS:
            figures.append(small_event_b(steady, values["sigma"], ell))
    return figures


#: the b figure (mode fault): a chain long enough for localised events of ell blocks to
#: be many per event, and enough of them in the fit range for a 99% half-width below ~0.3
B_MIN_N, B_MIN_EVENTS = 100, 1000


def _lap(x, i):
    n, f = len(x), 0.0
    if i > 0:
        f += x[i - 1] - x[i]
    if i + 1 < n:
        f += x[i + 1] - x[i]
    return f


# --- large chains: the fault solver alone ------------------------------------
def gutenberg_richter_b(moments: np.ndarray, lo: float, hi: float) -> tuple[float, float, int]:
    """Maximum-likelihood b of a moment density ~ M^-(1 + b) truncated to [lo, hi], its
    standard error (Fisher information) and the number of events used."""
    from scipy.optimize import brentq  # scipy: only for a study
    m = moments[(moments >= lo) & (moments <= hi)]
    k = m.size
    if k < 10:
        return math.nan, math.nan, int(k)
    r, mean_log = hi / lo, float(np.mean(np.log(m / lo)))

    def score(b):  # d/db of the mean log-likelihood of the truncated Pareto density
        return 1 / b - mean_log - math.log(r) * r**-b / (1 - r**-b)
    # the density's b may come out negative in a short stretch (more large than small
    # events there): the likelihood is the same formula on either side of 0
    for lo_b, hi_b in ((1e-3, 20.0), (-20.0, -1e-3)):
        if score(lo_b) * score(hi_b) < 0:
            b = brentq(score, lo_b, hi_b)
            break
    else:
        return math.nan, math.nan, int(k)
    info = 1 / b**2 - math.log(r)**2 * r**-b / (1 - r**-b)**2
    return b, 1 / math.sqrt(k * info) if info > 0 else math.nan, int(k)


def fault_study(n: int = 1000, events: int = 10_000, *, ell: float = 10.0,
                alpha: float = 2.5, sigma: float = 0.01, nu: float = 0.01,
                heterogeneity: float = 0.01, seed: int = 1, tol: float = 1e-8,
                warmup: float | None = None,
                backward: bool = False) -> tuple[FaultRun, list[Figure]]:
    """Run `events` slip events after a warm-up and measure the figures: the energy
    balance and the small events' b against Carlson & Langer's b = 1. As in their model,
    blocks never slide backward unless `backward` (then friction holds both ways, as
    FaultBlock's exact Coulomb modes do).

    The warm-up lets the chain forget its uniform start: until the plate has moved
    `warmup` (default 2.5 / nu, i.e. 2.5 F0/kp: every leaf spring reloaded past its
    threshold more than twice), in runs of 1000 events that each end with every block
    stuck, so the next starts exactly where it ended (positions shifted by the plate's
    travel, which is all the leaf springs see). The measured run starts from there; its
    catalogue's times count from its own start."""
    warmup = 2.5 / nu if warmup is None else warmup
    F = thresholds(n, 1.0, heterogeneity, seed)
    law = carlson_langer(ell, alpha, sigma, nu)
    x, travelled, chunks = np.zeros(n), 0.0, 0
    while travelled < warmup * nu and nu > 0:
        r = run_fault(F, **law, tol=tol, max_events=1000, x0=x, slides=0, backward=backward)
        x = r.x - law["V"] * r.totals["time"]
        travelled += law["V"] * r.totals["time"]
        chunks += 1
    run = run_fault(F, **law, tol=tol, max_events=events, x0=x, backward=backward)
    run.settings.update(warmup_travel=travelled, warmup_runs=chunks, ell=ell, nu=nu,
                        heterogeneity=heterogeneity, seed=seed)
    t = run.totals
    figures = [Figure("energy", "friction dissipation + change in stored energy [J] (vs the "
                      "plate's work)", t["dissipated"] + t["E_end"] - t["E_start"],
                      t["plate_work"], DRIFT * tol, relative=True,
           source='conservation law (plate work = dissipation + stored energy)'),
               small_event_b(run.catalogue, sigma, ell)]
    return run, figures


def small_event_b(cat: np.ndarray, sigma: float, ell: float, batches: int = 10) -> Figure:
    """The b of the localised events against Carlson & Langer's b = 1.

    Range: from 3 times the smallest moment (one block sliding through its threshold drop,
    2 sigma / (kp + 2 kc), whose spike the range leaves out) to ell^2 times it, the scale
    of a slide of ell blocks, below C&L's crossover to delocalised events. Accuracy: the
    99% confidence half-width that the run's events allow, the larger of two: 3 standard
    errors of the maximum-likelihood estimate (as if the events were independent), and
    Student's t (batches - 1 degrees of freedom) times the standard error of the mean of
    `batches` consecutive stretches of the run measured alone (events are correlated: a
    large one resets a region, so a run's b wanders more than independent events would
    let it)."""
    from scipy.stats import t as student  # scipy: only for a study
    lo, hi = localised_range(sigma, ell)
    b, err, used = gutenberg_richter_b(cat["moment"], lo, hi)
    edges = np.linspace(cat["start"][0], cat["start"][-1], batches + 1) if cat.size else []
    parts = [gutenberg_richter_b(cat["moment"][(cat["start"] >= a) & (cat["start"] <= z)],
                                 lo, hi)[0] for a, z in zip(edges[:-1], edges[1:])]
    parts = [p for p in parts if math.isfinite(p)]  # a stretch with too few events: out
    spread = (float(np.std(parts, ddof=1) / math.sqrt(len(parts))) if len(parts) >= 3
              else math.nan)
    batches = max(len(parts), 2)
    quantile = float(student.ppf(0.995, batches - 1))
    return Figure("b", f"Gutenberg-Richter b of the {used} events with moment in "
                  f"[{lo:.2g}, {hi:.2g}] (maximum likelihood; accuracy: 99% half-width, "
                  f"{quantile:.2f} x {spread:.2g} over {batches} stretches or 3 x {err:.2g}; "
                  "Carlson & Langer 1989: b = 1)", b, CL_B, max(quantile * spread, 3 * err),
           source='Carlson & Langer 1989 (small-event scaling b = 1)')


def _distribution(alpha: float, n: int, events: int, edges: np.ndarray, study: dict) -> dict:
    """One point of the weakening sweep: the size distribution and its b at `alpha`."""
    run, figures = fault_study(n, events, alpha=alpha, **study)
    cat, b = run.catalogue, figures[1]
    lo, hi = localised_range(run.settings["sigma"], study.get("ell", 10.0))
    counts, _ = np.histogram(np.log(cat["moment"][cat["moment"] > 0]), bins=edges)
    return dict(alpha=alpha, events=int(cat.size), b=b.measured, b_accuracy=b.bound,
                b_passed=b.passed, mean_blocks=float(cat["blocks"].mean()),
                delocalised=float(np.mean(cat["moment"] > hi)),
                largest_moment=float(cat["moment"].max()), rate=cat.size / run.totals["time"],
                counts=counts.tolist(), cpu_s=run.settings["cpu_s"])


def weakening_sweep(alphas, n: int = 300, events: int = 5000, *, workers: int | None = None,
                    scheduler=None, **study) -> dict:
    """The size distribution at each weakening alpha, one fault run per point on Dask
    (a local cluster of `workers` processes, or `scheduler`'s): {"edges": ln-moment bin
    edges, "points": one dict per alpha, as _distribution gives}. Dask is the `sweep`
    extra: without it, one line that says so."""
    try:
        from ..sweep import dask_client
        import distributed  # noqa: F401  (the client below needs it)
    except ImportError:
        raise FaultError("the weakening sweep runs on Dask, which is not installed: "
                         "pip install 'mechfmu[sweep]'") from None
    alphas = [float(a) for a in alphas]
    if not alphas or any(not (math.isfinite(a) and a >= 0) for a in alphas):
        raise FaultError(f"the sweep's alphas must be finite numbers >= 0, not {alphas!r}")
    edges = np.linspace(-10.0, 8.0, 37)
    with dask_client(workers, scheduler) as client:
        futures = client.map(_distribution, alphas, n=n, events=events, edges=edges,
                             study=study, pure=False)
        points = client.gather(futures)
    return {"edges": edges.tolist(), "points": points}


def plot_sweep(sweep: dict, png: Path) -> None:
    """Events per unit ln moment per unit time against ln moment, one line per alpha."""
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
    edges = np.array(sweep["edges"])
    centres, width = (edges[1:] + edges[:-1]) / 2, np.diff(edges)
    fig, ax = plt.subplots(figsize=(7, 5))
    for p in sweep["points"]:
        counts = np.array(p["counts"], dtype=float)
        rate = counts / width / (p["events"] / p["rate"])
        ax.semilogy(centres[counts > 0], rate[counts > 0], "o-", ms=3,
                    label=f"alpha = {p['alpha']:g} (b = {p['b']:.2f})")
    ax.set_xlabel("mu = ln(moment)")
    ax.set_ylabel("events per unit mu per unit time")
    ax.set_title("Burridge-Knopoff: size distribution against the weakening alpha")
    ax.legend()
    fig.tight_layout()
    fig.savefig(png, dpi=90)
    plt.close(fig)


def localised_range(sigma: float, ell: float) -> tuple[float, float]:
    """The moments of C&L's small events that b is measured on (see small_event_b)."""
    one_block = 2 * sigma / (1 + 2 * ell**2)
    return 3 * one_block, one_block * ell**2


def plot_fault(run: FaultRun, title: str, png: Path) -> None:
    """Size distribution (events per unit ln moment, the fit range shaded, C&L's slope
    through its lower end) and a space-time picture of the slides."""
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
    cat = run.catalogue
    fig, (ax1, ax2) = plt.subplots(1, 2, figsize=(13, 5))
    mu = np.log(cat["moment"][cat["moment"] > 0])
    counts, edges = np.histogram(mu, bins=40)
    centres = (edges[1:] + edges[:-1]) / 2
    duration = cat["end"][-1] - cat["start"][0] if cat.size else 1.0
    rate = counts / np.diff(edges) / duration
    ax1.semilogy(centres[counts > 0], rate[counts > 0], "o-", label="events")
    lo, hi = localised_range(run.settings["sigma"], math.sqrt(run.settings["kc"]
                                                               / run.settings["kp"]))
    ax1.axvspan(math.log(lo), math.log(hi), alpha=0.15, label="fit range (localised events)")
    if counts.any():
        k = int(np.argmin(np.abs(centres - math.log(lo))))
        ax1.semilogy(centres, rate[k] * np.exp(-CL_B * (centres - centres[k])), "--",
                     label=f"C&L: e^(-{CL_B:g} mu)")
    ax1.set_xlabel("mu = ln(moment)")
    ax1.set_ylabel("events per unit mu per unit time")
    ax1.legend()
    sl = run.slides
    if sl.size:
        t_lo = cat["start"][0] if cat.size else 0.0
        keep = sl[sl["t0"] >= t_lo][:20000]
        ax2.scatter(keep["block"], keep["t0"], s=1, c=np.log10(np.abs(keep["slip"]) + 1e-12),
                    cmap="viridis")
        ax2.set_xlabel("block")
        ax2.set_ylabel(f"time [s] (colour: log10 slip; the first {keep.size} slides)")
    fig.suptitle(title)
    fig.tight_layout()
    fig.savefig(png, dpi=90)
    plt.close(fig)


def main(argv: list[str] | None = None) -> int:
    ap = argparse.ArgumentParser(prog="python -m assemblies.scenes.burridge_knopoff",
                                 description="A long Burridge-Knopoff run with the fault solver: "
                                 "catalogue, figures, size distribution and space-time picture.")
    ap.add_argument("--n", type=int, default=1000)
    ap.add_argument("--events", type=int, default=10_000)
    ap.add_argument("--ell", type=float, default=10.0)
    ap.add_argument("--alpha", type=float, default=2.5)
    ap.add_argument("--sigma", type=float, default=0.01)
    ap.add_argument("--nu", type=float, default=0.01)
    ap.add_argument("--heterogeneity", type=float, default=0.01)
    ap.add_argument("--seed", type=int, default=1)
    ap.add_argument("--tol", type=float, default=1e-8)
    ap.add_argument("--backward", action="store_true",
                    help="friction holds both ways (exact Coulomb, as FaultBlock); default: "
                         "Carlson & Langer's blocks, which never slide backward")
    ap.add_argument("--out", type=Path)
    a = ap.parse_args(argv)
    try:
        run, figures = fault_study(a.n, a.events, ell=a.ell, alpha=a.alpha, sigma=a.sigma,
                                   nu=a.nu, heterogeneity=a.heterogeneity, seed=a.seed,
                                   tol=a.tol, backward=a.backward)
    except FaultError as exc:
        print(f"error: {exc}", file=sys.stderr)
        return 2
    for f in figures:
        print(f"{f.name:<8} {f.measured:>14.8g} {f.reference:>14.8g} {f.error:>10.2e} "
              f"{f.bound:>10.2e}  {'pass' if f.passed else 'FAIL'}  {f.description}")
    s = run.settings
    print(f"n = {s['n']}, {s['events']} events (after a warm-up of {s['warmup_travel']:.3g} "
          f"of plate travel) in t = "
          f"{run.totals['time']:.6g}, CPU {s['cpu_s']:.3g} s, {s['steps']} steps; blocks "
          f"stuck {100 * s['slept_fraction']['mean']:.1f}% of the time (least "
          f"{100 * s['slept_fraction']['min']:.1f}%)")
    if a.out is not None:
        a.out.mkdir(parents=True, exist_ok=True)
        cat = run.catalogue
        np.savetxt(a.out / "catalogue.csv", np.column_stack([cat[k] for k in cat.dtype.names]),
                   delimiter=",", header=",".join(cat.dtype.names), comments="")
        (a.out / "burridge_knopoff.json").write_text(json.dumps(
            {"settings": s, "totals": run.totals,
             "figures": [dict(name=f.name, description=f.description, measured=f.measured,
                              reference=f.reference, bound=f.bound, passed=f.passed)
                         for f in figures]}, indent=2, default=float) + "\n")
        plot_fault(run, f"Burridge-Knopoff, n = {s['n']}", a.out / "burridge_knopoff.png")
    return 0 if all(f.passed for f in figures) else 1


#: me's bound on n^2 x stop time: a run within it takes under a minute of CPU here
#: (n = 1000 over the default 75 s: 101 s CPU, 14,227 events; over 45 s: 46 s, the
#: whole `mechfmu run` with its figures)
ME_BUDGET = RunBudget("n", 2, 4.5e7, "n = 1000 over 75 s took 101 s CPU here, 14,227 "
                                      "events; mode fault runs long chains by events")
#: monolithic's engine steps the joined chain as me does, at under half of me's CPU
#: (n = 1000 over 75 s: 41-46 s), after a plan that builds the joined FMU once per n
#: (n = 1000: 92 s CPU, cached for the next run; 500: 45 s)
MONOLITHIC_BUDGET = RunBudget("n", 2, 1.0e8, "n = 1000 over 75 s took 41-46 s CPU here "
                                             "after building its FMU; mode fault runs long "
                                             "chains by events")
MONOLITHIC_MOST = (1000, "its joined FMU is built once per n, in time linear in n: n = "
                         "1000 took 92 s CPU to build (once), then 46 s to run; run mode "
                         "fault")

#: the scene's parameters (--param NAME=VALUE): its chain's shape and the run's length
#: in events. The FMU masters are bounded by runs measured here (CPU on 2 loaded cores,
#: FMUs cached; `python -m benchmarks.burridge_knopoff --fmu-modes`): me steps every
#: block in its one integrator at every event, and events grow with n and with the time
#: run, so its CPU grows as n^2 x the stop time (ME_BUDGET); monolithic builds the
#: joined model anew for each n (its plan, linear in n), then runs as me does
SCENE_PARAMETERS = (
    SceneParameter("n", SCENE_CHAIN["n"], 1, 100_000, "1", "number of blocks", integer=True,
                   most={"monolithic": MONOLITHIC_MOST,
                         "cosim": (100, "every block is coupled at every communication "
                                        "step: n = 100 took 34 s here; run mode fault")}),
    SceneParameter("ell", SCENE_CHAIN["ell"], 0.0, 1e3, "1",
                   "coupling/leaf stiffness ratio sqrt(kc/kp), kp = 1"),
    SceneParameter("alpha", SCENE_CHAIN["alpha"], 0.0, 1e3, "1",
                   "velocity weakening, Carlson & Langer's alpha"),
    SceneParameter("sigma", SCENE_CHAIN["sigma"], 1e-6, 0.999, "1",
                   "drop from static to kinetic friction at the onset of slip, / F0"),
    SceneParameter("nu", SCENE_CHAIN["nu"], 1e-6, 1e3, "1", "plate speed, / vw"),
    SceneParameter("heterogeneity", SCENE_CHAIN["heterogeneity"], 0.0, 0.999, "1",
                   "thresholds F0 (1 + h u), u uniform in [-1, 1]"),
    SceneParameter("seed", SCENE_CHAIN["seed"], 0, 2**31 - 1, "1",
                   "random seed of the thresholds", integer=True),
    SceneParameter("events", 0, 0, 10_000_000, "1",
                   "slip events to run, 0: to the stop time", integer=True,
                   most={m: (0, "its master runs to a stop time (--stop-time); events "
                                "is mode fault's") for m in ("me", "monolithic", "cosim")}),
)


def _scene_chain(n: int = SCENE_CHAIN["n"], ell: float = SCENE_CHAIN["ell"],
                 alpha: float = SCENE_CHAIN["alpha"], sigma: float = SCENE_CHAIN["sigma"],
                 nu: float = SCENE_CHAIN["nu"],
                 heterogeneity: float = SCENE_CHAIN["heterogeneity"],
                 seed: int = SCENE_CHAIN["seed"], events: int = 0) -> Assembly:
    # events is the run's length, not the chain's: mode fault reads it from its arguments
    return fault_chain(n, ell=ell, alpha=alpha, sigma=sigma, nu=nu,
                       heterogeneity=heterogeneity, seed=seed)


def _solve_fault(asm: Assembly, arguments: dict, *, stop_time: float, step: float,
                 tolerance: float, record=None, progress=None,
                 start_time: float = 0.0) -> Result:
    """Mode fault: the chain's values through the event-driven fault solver, as FaultBlock
    models it (friction holds both ways); the result table is the event catalogue (one
    row per slip event: its start time, end, blocks, moment and energy)."""
    if start_time != 0.0:
        raise FaultError("mode fault runs the chain from rest at t = 0: leave --start-time out")
    values = chain_values(asm)
    events = arguments.get("events") or None
    F, x0 = values.pop("F"), values.pop("x0")
    run = run_fault(F, **values, tol=tolerance, x0=x0,
                    stop_time=math.inf if events else stop_time, max_events=events)
    cat, s = run.catalogue, run.settings
    result = Result({"time": cat["start"], "event.end": cat["end"],
                     "event.blocks": cat["blocks"].astype(float), "event.moment": cat["moment"],
                     "event.energy": cat["energy"]},
                    settings=dict(stop_time=run.totals["time"], step=step, tolerance=tolerance,
                                  scheme="fault solver (event-driven, the catalogue as result)",
                                  engine="c", wall_s=s["wall_s"], cpu_s=s["cpu_s"],
                                  events=s["events"], steps=s["steps"], status=s["status"],
                                  slept_fraction=s["slept_fraction"], n=s["n"]))
    result.settings["lines"] = [
        f"n = {s['n']}: {s['events']} slip events to t = {run.totals['time']:.6g} s in CPU "
        f"{s['cpu_s']:.3g} s, {s['steps']} steps; blocks stuck "
        f"{100 * s['slept_fraction']['mean']:.1f}% of the time (least "
        f"{100 * s['slept_fraction']['min']:.1f}%)"]
    result.fault_run = run
    return result


def _picture(result: Result, title: str, png: Path) -> None:
    """Mode fault: the size distribution and the space-time picture; else the panels."""
    if getattr(result, "fault_run", None) is not None:
        plot_fault(result.fault_run, title, png)
        return
    from ..plot import column_units, plot_result  # matplotlib: only for a plot
    panels = [c for c in PANELS if c in result.columns]
    plot_result(result, panels, title, png, column_units(result.assembly, panels))


PANELS = ["block1.x", "block2.x", "block1.v", "block2.v"]


BURRIDGE_KNOPOFF_SCENES: dict[str, Scene] = {
    "burridge_knopoff": Scene(
        "burridge_knopoff", "issue 30: Burridge-Knopoff chain, C&L velocity-weakening friction, "
        "exact stick-slip", _scene_chain, stop_time=SCENE_STOP, step=0.1, tolerance=1e-10,
        record=None, figures=_figures, plot=PANELS, picture=_picture, mode="me",
        seed="9.2 (its block, chained)",
        reference="slides vs scipy event-driven integration; first break-away closed form; "
                  "energy balance; mode fault: Carlson & Langer's b",
        parameters=SCENE_PARAMETERS, solvers={"fault": _solve_fault},
        budgets={"me": ME_BUDGET, "monolithic": MONOLITHIC_BUDGET}),
}

if __name__ == "__main__":
    sys.exit(main())
