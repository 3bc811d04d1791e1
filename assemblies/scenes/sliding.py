"""Seed 9.8, planar sliding: a rod (Eqs. 9.14-9.16) and a disk under a uniform and a
parabolic pressure, each sliding and spinning on a table until it comes to rest.

The known result they hold: a flat slider's translation and rotation stop at the same
instant (the speed over the spin tends to a finite, nonzero ratio as both vanish). Each
run ends where |v_G| + |omega| a falls to v_stop; the figures hold that time, the ratio
there and the work done against friction to an independent integration written from
the seed's integrals (:mod:`.sliding_references`), and the energy to the friction work.
"""
from __future__ import annotations

import functools
import math

import numpy as np

from components.bodies.planar_sliding import SlidingDisk, SlidingRod

from ..assembly import Assembly
from ..result import Result
from .scene import DRIFT, Figure, Scene, solver_accuracy
from .sliding_references import disk_stop, rod_stop

ROD = dict(m=1.0, L=1.0, mu=0.3, g=9.81)
ROD_START = dict(theta=0.0, v_x=1.0, v_y=0.0, omega=4.0)
DISK = dict(m=1.0, R=0.1, mu=0.3, g=9.81)
DISK_START = dict(v_x=1.0, v_y=0.0, omega=10.0)
INTEGRATION = ("independent integration (scipy DOP853, 1e-11) of the seed's 9.8 integrals, "
               "evaluated here in closed form")
ENERGY = "energy balance (kinetic energy lost = work against friction: 0)"


def _rod() -> Assembly:
    asm = Assembly("sliding_rod")
    asm.add("rod", SlidingRod(**ROD, **ROD_START, v_stop=STOP_LEVEL))
    return asm


def _disk(pressure: str):
    def build() -> Assembly:
        asm = Assembly("sliding_disk" if pressure == "uniform" else f"sliding_disk_{pressure}")
        asm.add("disk", SlidingDisk(**DISK, **DISK_START, v_stop=STOP_LEVEL, pressure=pressure))
        return asm
    return build


@functools.lru_cache(maxsize=8)
def _rod_reference(m, L, mu, g, theta, vx, vy, omega, level):
    return rod_stop(m, L, mu, g, theta, vx, vy, omega, level)


@functools.lru_cache(maxsize=8)
def _disk_reference(m, R, mu, g, pressure, v, omega, level):
    return disk_stop(m, R, mu, g, pressure, v, omega, level)


@functools.lru_cache(maxsize=8)
def _disk_rule_reference(m, R, mu, g, pressure, v, omega, level):
    """The same motion with the model's quadrature rule in place of the exact integrals:
    how far the rule alone moves each figure (a modelling error, not a run's)."""
    return disk_stop(m, R, mu, g, pressure, v, omega, level, rule=True)


STOP_LEVEL = 1e-3  # [m/s] v_stop: |v_G| + |omega| a at the end of the run, a thousandth of
# the start's; lower, the solver's absolute error (~100 tol) would swamp the ratio there


def _rest_state(result: Result, name: str) -> dict:
    """The slider's state where its run ended at rest: the located event's row (the
    output grid stops short of it); NaN everywhere if it never came to rest."""
    ended = result.settings.get("terminated")
    events = result.events.get(name)
    if not ended or ended.get("instance") != name or events is None or not len(events):
        return {"time": math.nan, "ratio": math.nan, "W": math.nan, "speed": math.nan,
                "omega": math.nan}
    return {"time": float(events["time"][-1]),
            **{k: float(events[f"{name}.{k}"][-1]) for k in ("ratio", "W", "speed", "omega")}}


def _figures(result: Result, name: str, size: float, ref, rule, E0: float) -> list[Figure]:
    """`rule`: the reference motion under the model's quadrature rule (None: no rule)."""
    rest = _rest_state(result, name)
    E, W = result[f"{name}.E"], result[f"{name}.W"]
    # the solver errs by ~100 tol in |v_G| and |omega| a (absolute, being below 1): at the
    # stop level the ratio v / (omega a) moves by that over each, relative
    level = STOP_LEVEL
    ratio_solver = (ref.ratio * solver_accuracy(result, 1.0) * (1 + ref.ratio)
                    * (1 / ref.ratio + 1) / level)
    shift = {k: abs(getattr(rule, k) - getattr(ref, k)) if rule else 0.0
             for k in ("t", "ratio", "work")}
    return [
        Figure("t_rest", f"time at which |v_G| + |omega| a falls to {level:g} m/s [s] "
               f"(a = {size:g} m)", rest["time"], ref.t,
               solver_accuracy(result, ref.t) + shift["t"], source=INTEGRATION),
        Figure("ratio", "|v_G| / (|omega| a) there (a finite limit: both stop together; "
               "-> 0: v_G vanishes faster, yet at the same instant)", rest["ratio"], ref.ratio,
               ratio_solver + shift["ratio"],
               source=INTEGRATION),
        Figure("W_rest", "work done against friction until then [J]", rest["W"], ref.work,
               solver_accuracy(result, E0) + shift["work"], source=INTEGRATION),
        Figure("E_balance", "largest |E(0) - E - W| / E(0): the energy lost is the friction "
               "work", float(np.abs(E[0] - E - W).max()) / E0, 0.0,
               solver_accuracy(result, 1.0, DRIFT), source=ENERGY)]


def _rod_figures(result: Result, asm: Assembly) -> list[Figure]:
    rod = asm.component("rod")
    p, s = rod.values, rod.starts
    ref = _rod_reference(p["m"], p["L"], p["mu"], p["g"], s["theta"], s["v_x"], s["v_y"],
                         s["omega"], p["v_stop"])
    E0 = p["m"] * (s["v_x"]**2 + s["v_y"]**2) / 2 + p["m"] * p["L"]**2 / 24 * s["omega"]**2
    # Eqs. 9.14-9.16 are closed forms: no quadrature in the model, nothing for it to add
    return _figures(result, "rod", p["L"] / 2, ref, None, E0)


def _disk_figures(result: Result, asm: Assembly) -> list[Figure]:
    disk = asm.component("disk")
    p, s, pressure = disk.values, disk.starts, disk.option("pressure")
    v0 = math.hypot(s["v_x"], s["v_y"])
    ref = _disk_reference(p["m"], p["R"], p["mu"], p["g"], pressure, v0, abs(s["omega"]),
                          p["v_stop"])
    rule = _disk_rule_reference(p["m"], p["R"], p["mu"], p["g"], pressure, v0,
                                abs(s["omega"]), p["v_stop"])
    E0 = p["m"] * v0**2 / 2 + p["m"] * p["R"]**2 / 4 * s["omega"]**2
    return _figures(result, "disk", p["R"], ref, rule, E0)


_RECORD = ["x", "y", "theta", "v_x", "v_y", "omega", "W", "E", "speed", "ratio"]

SLIDING_SCENES: dict[str, Scene] = {
    "sliding_rod": Scene(
        "sliding_rod", "seed 9.8: a rod sliding and spinning on a table (Eqs. 9.14-9.16, "
        "uniform reaction) stops translating and rotating at the same instant",
        _rod, stop_time=1.0, step=1e-3, tolerance=1e-10,
        record=[f"rod.{n}" for n in _RECORD], figures=_rod_figures,
        plot=["rod.speed", "rod.omega", "rod.ratio"], seed="9.8, Eqs. 9.14–9.16",
        reference="time to rest, |v_G|/(ωL/2) there (→ 0.5774) and the friction work from an "
                  "independent integration of the seed's integrals; energy lost = friction work"),
    "sliding_disk": Scene(
        "sliding_disk", "seed 9.8: a disk sliding and spinning on a table under a uniform "
        "pressure, its friction integrals by quadrature in the model, stops translating and "
        "rotating at the same instant",
        _disk("uniform"), stop_time=1.0, step=1e-3, tolerance=1e-10,
        record=[f"disk.{n}" for n in _RECORD], figures=_disk_figures,
        plot=["disk.speed", "disk.omega", "disk.ratio"], seed="9.8",
        reference="time to rest, |v_G|/(ωR) there (→ 0.6530) and the friction work from an "
                  "independent integration (ring integrals in elliptic closed form); energy "
                  "lost = friction work"),
    "sliding_disk_parabolic": Scene(
        "sliding_disk_parabolic", "seed 9.8: the disk of sliding_disk under a parabolic "
        "pressure p ~ 1 - r^2/R^2: it too stops translating and rotating at once, its speed "
        "vanishing faster (the ratio tends to 0)",
        _disk("parabolic"), stop_time=1.0, step=1e-3, tolerance=1e-10,
        record=[f"disk.{n}" for n in _RECORD], figures=_disk_figures,
        plot=["disk.speed", "disk.omega", "disk.ratio"], seed="9.8",
        reference="as sliding_disk, for p(r) = 2 m g (1 − r²/R²)/(π R²): the ratio → 0"),
}

__all__ = ["SLIDING_SCENES"]
