"""What each benchmark scene runs: its model, its independent reference, its methods.

A case is a dict of methods, each ``fn(tol, count) -> (values, rhs_evals, steps)`` at the
scene's output times; ``count`` asks for a second, untimed run that counts work (the
runtime's log, fmpy's call log), so that counting never slows the timed run.
"""
from __future__ import annotations

import importlib.util
import math
from dataclasses import dataclass
from functools import partial
from typing import Callable

import numpy as np

from assemblies.assembly import Assembly
from assemblies.masters.monolithic import composite
from assemblies.scenes import scene
from components.bodies.beam import AssumedModesBeam

from . import baselines, references
from .c_limit import CLimit
from .runners import Masters, SingleFmu, engine_missing

FULL_TOLERANCES = tuple(10.0**-k for k in range(3, 11))   # 1e-3 ... 1e-10
QUICK_TOLERANCES = (1e-4, 1e-6, 1e-8)
BEAM_SIZES = (4, 8, 16, 32)
# methods --quick leaves out, per scene, to keep a quick run under a minute on two cores
# (measured: beam_N32 took 57 s with them when its FMU lookup missed the cache, 21 s of it
# setup; 28 s without them, cached); the full sweep runs them all
QUICK_SKIP = {"beam_N32": ("scipy_Radau", "master_me")}


@dataclass
class Case:
    name: str
    times: np.ndarray
    reference: np.ndarray
    reference_kind: str
    methods: dict[str, Callable]
    fmu_path: object = None      # the FMU, for the build-time report
    component: object = None
    masters: object = None       # the assembly's Masters, where the public calls run it


def _our_methods(fmu: SingleFmu | None, masters: Masters | None, times, smooth: bool):
    """(a) CS FMU with both embedded solvers, (b) ME FMU under CVode, (c) masters, CasADi,
    (d) c_limit: the FMU's own generated C under the runtime's solver, with nothing around."""
    methods = {}
    if fmu is not None:
        limit = CLimit(fmu.component, fmu.observed)
        methods["c_limit"] = lambda tol, count: limit.column(times, tol)
        for solver in ("DOPRI5", "RODAS3"):
            methods[f"fmu_cs_{solver.lower()}"] = (
                lambda tol, count, s=solver: fmu.cosim(times, tol, s, count))
        methods["fmu_me_cvode"] = lambda tol, count: fmu.cvode(times, tol, count)
        if smooth:
            methods["casadi_cvodes"] = lambda tol, count: fmu.casadi(times, tol)
    if masters is not None:
        if engine_missing() is None:
            methods["engine_me"] = lambda tol, count: masters.engine(times, tol, "me", count)
            methods["engine_monolithic"] = (
                lambda tol, count: masters.engine(times, tol, "monolithic", count))
        methods["master_me"] = lambda tol, count: masters.me(times, tol)
        methods["master_monolithic"] = lambda tol, count: masters.monolithic(times, tol)
    return methods


def _scipy(methods, runner, jit_runner=None):
    """scipy's methods on the hand-written numpy right-hand side; with `jit_runner`, and
    numba installed (the `bench` extra), on the numba-compiled one too (scipy_numba_*)."""
    for method in baselines.METHODS:
        methods[f"scipy_{method}"] = lambda tol, count, m=method: runner(m, tol)
    if jit_runner is None or importlib.util.find_spec("numba") is None:
        return
    for method in baselines.METHODS:
        methods[f"scipy_numba_{method}"] = lambda tol, count, m=method: jit_runner(m, tol)


# (stop time, output interval) of each scene; the beams' per-simulated-second cost uses it too
GRIDS = {"stick_slip": (100.0, 0.1), "stick_slip_smooth": (100.0, 0.1), "beam": (2.0, 0.01),
         "axle_pendulum": (10.0, 0.01), "coin_rolling": (10.0, 0.01)}


def _times(stop, step):
    n = int(round(stop / step))
    return np.arange(n + 1) * step


def beam_stop_time(quick: bool) -> float:
    """The beams run 2 s; --quick runs 0.5 s (N = 32 resolves ~1e4 rad/s: cost ∝ time)."""
    return GRIDS["beam"][0] / 4 if quick else GRIDS["beam"][0]


def output_times(name: str, quick: bool = False) -> np.ndarray:
    if name.startswith("beam_N"):
        return _times(beam_stop_time(quick), GRIDS["beam"][1])
    return _times(*GRIDS[name])


def stick_slip(smooth_law: bool = False) -> Case:
    asm = scene("stick_slip").build()
    block, speed = asm.component("block"), asm.component("driver").values["v"]
    if smooth_law:
        block.set("friction", "smooth")
        block.set("eps", 1e-3)
    p = dict(block.values)
    times = output_times("stick_slip")
    fmu = SingleFmu(composite(asm), "block.x")
    masters = Masters(asm, "block.x")
    methods = _our_methods(fmu, masters, times, smooth=smooth_law)
    if smooth_law:
        run = partial(baselines.smooth_block, p["m"], p["k"], p["g"], p["mu_k"], p["mu_s"],
                      p["eps"], speed, times)
        # no closed form: the hand-written law at the tightest tolerance DOP853 holds
        key = f"smooth block {sorted(p.items())} v={speed} times={times[-1]},{len(times)} DOP853 1e-13"
        reference = references.cached(key, lambda: run("DOP853", 1e-13)[0])
        kind = "hand-written Eq. 9.5, DOP853 rtol 1e-13 (cached)"
    else:
        block_model = baselines.CoulombBlock(p["m"], p["k"], p["g"], p["mu_k"], p["mu_s"],
                                             s_end=lambda t: speed * t)
        run = partial(baselines.coulomb_block, block_model, 0.0, 0.0, times)
        jit_run = partial(run, jit_speed=speed)
        _, exact = references.coulomb_drag(p["m"], p["k"], p["g"], p["mu_k"], p["mu_s"],
                                           speed, times[-1])
        reference = exact(times)
        kind = "piecewise analytic (seed 9.2)"
    _scipy(methods, run, None if smooth_law else jit_run)
    name = "stick_slip_smooth" if smooth_law else "stick_slip"
    return Case(name, times, reference, kind, methods, fmu.path, fmu.component, masters)


def beam(n_modes: int, quick: bool = False) -> Case:
    w_tip0 = 0.1
    # the seed's coordinates, the formulation scipy's baseline integrates too (M, K): the
    # growth of its cost with N is what this case measures (the modal default's is
    # benchmarks.beam_scaling's)
    component = AssumedModesBeam(name="beam", basis="sine", n_modes=n_modes, w_tip0=w_tip0,
                                 coordinates="assumed")
    asm = Assembly(f"beam_N{n_modes}")
    asm.add("beam", component)
    times = output_times("beam_N", quick)
    a0, w_tip = references.beam_free_vibration(n_modes, w_tip0)
    fmu = SingleFmu(component, "w_tip")
    methods = _our_methods(fmu, Masters(asm, "beam.w_tip"), times, smooth=True)
    M, K, tip = references.beam_matrices(n_modes)
    _scipy(methods, partial(baselines.beam, M, K, tip, a0, times))
    return Case(f"beam_N{n_modes}", times, w_tip(times),
                "modal solution of the discretised beam (eig of M, K by quadrature)",
                methods, fmu.path, component)


def axle_pendulum() -> Case:
    asm = scene("axle_pendulum").build()
    body = asm.component("body")
    p = body.values
    r, n = (p["r_x"], p["r_y"], p["r_z"]), (p["n_x"], p["n_y"], p["n_z"])
    I_cm = [[p["I_xx"], p["I_xy"], p["I_xz"]], [p["I_xy"], p["I_yy"], p["I_yz"]],
            [p["I_xz"], p["I_yz"], p["I_zz"]]]
    J_n = references.axle_inertia(p["m"], I_cm, r, n)
    rho, delta = references.axle_potential(p["m"], p["g"], r, n)
    theta_eq = delta + math.pi  # the potential rho cos(theta - delta) is least there
    theta_eq = math.remainder(theta_eq, 2 * math.pi)
    theta0 = body.starts["theta"]
    times = output_times("axle_pendulum")
    fmu = SingleFmu(body, "theta")
    masters = Masters(asm, "body.theta")
    methods = _our_methods(fmu, masters, times, smooth=True)
    axle_run = partial(baselines.axle, p["m"], p["g"], J_n, r, n, theta0, times)
    _scipy(methods, axle_run, partial(axle_run, jit=True))
    reference = references.pendulum(math.sqrt(rho / J_n), theta_eq, theta0)(times)
    return Case("axle_pendulum", times, reference, "exact pendulum, Jacobi sn (scipy ellipj)",
                methods, fmu.path, body, masters)


def coin_rolling() -> Case:
    asm = scene("coin_rolling").build()
    coin = asm.component("coin")
    times = output_times("coin_rolling")
    fmu = SingleFmu(coin, "theta")
    masters = Masters(asm, "coin.theta")
    methods = _our_methods(fmu, masters, times, smooth=True)
    p = coin.values
    y0 = [coin.starts[k] for k in ("x", "y", "phi", "theta", "psi", "phi_dot", "theta_dot",
                                   "psi_dot")]
    coin_run = partial(baselines.coin, p["m"], p["R"], p["g"], p["theta_min"], y0, times)
    _scipy(methods, coin_run, partial(coin_run, jit=True))
    # the reference is the joined CasADi model at the tightest tolerance DOP853 holds (the
    # hand-written RHS above agrees with it to round-off: tests/integration/test_bench.py)
    reference = masters.monolithic(times, 1e-13)[0]
    return Case("coin_rolling", times, reference, "monolithic DOP853 at rtol 1e-13",
                methods, fmu.path, coin, masters)


def moving_table() -> Case:
    asm = scene("moving_table").build()
    table, block = asm.component("table").values, asm.component("block")
    U, w = table["U"], table["omega"]
    period = 2 * math.pi / w
    times = _times(64 * period, period / 16)
    times[-1] = 64 * period
    fmu = SingleFmu(composite(asm), "block.x")
    masters = Masters(asm, "block.x")
    methods = _our_methods(fmu, masters, times, smooth=False)
    for substeps in (1, 4, 16):  # communication step = output interval / substeps
        methods[f"master_cosim_x{substeps}"] = (
            lambda tol, count, m=substeps: masters.cosim(times, tol, m))
    p = block.values
    model = baselines.CoulombBlock(p["m"], p["k"], p["g"], p["mu_k"], p["mu_s"],
                                   s_sup=lambda t: U * math.sin(w * t),
                                   a_sup=lambda t: -U * w * w * math.sin(w * t))
    _scipy(methods, partial(baselines.coulomb_block, model, block.starts["x"],
                            block.starts["v"], times))
    reference = masters.monolithic(times, 1e-12)[0]
    return Case("moving_table", times, reference, "monolithic DOP853 at rtol 1e-12",
                methods, fmu.path, fmu.component)


SCENES: dict[str, Callable[[], Case]] = {
    "stick_slip": stick_slip,
    "stick_slip_smooth": partial(stick_slip, smooth_law=True),
    **{f"beam_N{n}": partial(beam, n) for n in BEAM_SIZES},
    "axle_pendulum": axle_pendulum,
    "coin_rolling": coin_rolling,
    "moving_table": moving_table,
}
GROUPS = {"beam": [f"beam_N{n}" for n in BEAM_SIZES], "all": list(SCENES)}


def expand(name: str) -> list[str]:
    if name in GROUPS:
        return GROUPS[name]
    if name not in SCENES:
        raise KeyError(f"unknown benchmark scene '{name}'; scenes: "
                       f"{', '.join(list(SCENES) + list(GROUPS))}")
    return [name]
