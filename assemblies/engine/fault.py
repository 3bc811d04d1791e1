"""The Burridge-Knopoff chain's event-driven solver (issue 30): one C call per run.

The C source (``fault_c/fault.c``) says how it works: stuck blocks cost nothing between
events (their break-away times are closed forms in a min tree), sliding blocks are
integrated by the FMU runtime's DOPRI5 with its event location, in groups that each keep
their own clock (one group's switches do not cut another's steps), and the run hands back
the event catalogue, each block's stuck time and an energy account. It is compiled by
gcc once per machine and cached like the engine (:func:`fmus.build.cached_library`).

Units are the caller's (SI for the component's parameters); :func:`carlson_langer` gives
the parameters of Carlson & Langer's dimensionless model (Phys. Rev. A 40, 6470, 1989):
m = kp = F0 = 1, so lengths are in F0/kp, times in sqrt(m/kp), kc = l^2, V = nu, and the
weakening's velocity scale is F0/sqrt(kp m) = 1, where the kinetic friction is
F_i (1 - sigma) / (1 + 2 alpha v / (1 - sigma)): C&L's phi for v > 0 (their Eq. 2.4).
"""
from __future__ import annotations

import ctypes
import functools
import math
import time
from dataclasses import dataclass, field
from pathlib import Path

import numpy as np

from fmus.build import RUNTIME_DIR, BuildError, cached_library

from ..assembly import AssemblyError

C_FILE = Path(__file__).parent / "fault_c" / "fault.c"
_RUNTIME = ("events", "solver")  # the FMU runtime's DOPRI5 and event location, shared
PARAMS = ("m", "kc", "kp", "V", "sigma", "alpha", "vw", "tol", "stop_time", "backward")
TOTALS = ("time", "plate_work", "dissipated", "E_start", "E_end", "steps", "rejected",
          "rhs", "block_rhs", "located", "breakaways", "slips_dropped", "status", "created",
          "slides", "sliding")
STATUS = ("stop time reached", "max_events reached", "catalogue full",
          "every block stuck for good (the plate does not move)")


class FaultError(AssemblyError):
    """A fault run that cannot be done as asked: one line naming the setting."""


def sources() -> list[Path]:
    return [C_FILE] + [RUNTIME_DIR / f"{name}.{ext}" for name in _RUNTIME for ext in ("c", "h")]


@functools.lru_cache(maxsize=None)
def library() -> ctypes.CDLL:
    path = cached_library("fault", "libmffault", sources(), [RUNTIME_DIR],
                          "the fault solver")
    try:
        lib = ctypes.CDLL(str(path))
    except OSError as exc:
        raise BuildError(f"cannot load the fault solver {path} ({exc}); remove it and run "
                         "again to rebuild it") from None
    p_count, t_count = ctypes.c_int(), ctypes.c_int()
    lib.mf_fault_layout(ctypes.byref(p_count), ctypes.byref(t_count))
    if (p_count.value, t_count.value) != (len(PARAMS), len(TOTALS)):
        raise BuildError(f"the fault solver {path} has another layout: remove it to rebuild")
    d, i, L = (np.ctypeslib.ndpointer(np.float64, flags="C"),
               np.ctypeslib.ndpointer(np.int32, flags="C"), ctypes.c_long)
    lib.mf_fault_run.argtypes = [ctypes.c_int, d, d, d, L, L, d, d, d, d, i, i, L, i, i, d,
                                 d, d, d, d, L, ctypes.c_char_p, ctypes.c_int]
    lib.mf_fault_run.restype = ctypes.c_int
    return lib


@dataclass
class FaultRun:
    """What one run gives: the catalogue, the slides, the stuck times and the account."""
    catalogue: np.ndarray  # start, end, blocks, moment, energy, first (merged ones removed)
    slides: np.ndarray     # event, block, t0, t1, slip: one row per slide of one block
    slept: np.ndarray      # time each block was stuck [s]
    x: np.ndarray          # final positions
    totals: dict
    settings: dict = field(default_factory=dict)

    @property
    def energy_residual(self) -> float:
        """plate work - (friction dissipation + change in stored energy): zero exactly."""
        t = self.totals
        return t["plate_work"] - (t["dissipated"] + t["E_end"] - t["E_start"])


def _positive(name: str, value: float, strict: bool = True) -> float:
    value = float(value)
    if not math.isfinite(value) or value < 0 or (strict and value == 0):
        raise FaultError(f"fault: {name} must be a finite number {'> 0' if strict else '>= 0'}"
                         f", not {value!r}")
    return value


def run_fault(F, *, m: float = 1.0, kc: float = 100.0, kp: float = 1.0, V: float = 0.01,
              sigma: float = 0.01, alpha: float = 2.5, vw: float = 1.0, tol: float = 1e-8,
              stop_time: float = math.inf, max_events: int | None = None, x0=None,
              max_steps: int = 50_000_000, slides: int = 200_000,
              backward: bool = True) -> FaultRun:
    """Run the chain with thresholds `F` (one per block) from rest at `x0` (default 0)
    until `stop_time` or until `max_events` slip events have ended (one is needed).
    `slides`: how many single-block slides to keep for the space-time picture.
    `backward`: True, friction holds both ways with the same law (exact Coulomb modes,
    as FaultBlock); False, a block never slides backward (Carlson & Langer's model, whose
    friction is unbounded for v < 0: a block pushed back stays stuck)."""
    F = np.ascontiguousarray(F, dtype=np.float64)
    n = F.size
    if F.ndim != 1 or n < 1 or not np.all(np.isfinite(F)) or np.any(F <= 0):
        raise FaultError("fault: the thresholds F must be one finite number > 0 per block")
    values = dict(m=_positive("m", m), kc=_positive("kc", kc, False), kp=_positive("kp", kp),
                  V=_positive("V", V, False), sigma=float(sigma),
                  alpha=_positive("alpha", alpha, False), vw=_positive("vw", vw),
                  tol=_positive("tol", tol))
    if not 0.0 <= values["sigma"] < 1.0:
        raise FaultError(f"fault: sigma (the drop from static to kinetic friction at the "
                         f"onset of slip) must be in [0, 1), not {sigma!r}")
    if max_steps > 10**9:  # the C side counts steps and stamps in int
        raise FaultError(f"fault: max_steps must be at most 1e9, not {max_steps!r}")
    if not values["tol"] < 1:
        raise FaultError(f"fault: tol must be in (0, 1), not {tol!r}")
    if math.isinf(stop_time) and max_events is None:
        raise FaultError("fault: give a stop_time or max_events, or the run never ends")
    stop_time = float(stop_time)
    if not stop_time > 0:
        raise FaultError(f"fault: stop_time must be > 0, not {stop_time!r}")
    if max_events is not None and not (isinstance(max_events, (int, np.integer))
                                       and max_events >= 1):
        raise FaultError(f"fault: max_events must be an integer >= 1, not {max_events!r}")
    x = np.zeros(n) if x0 is None else np.array(x0, dtype=np.float64)
    if x.shape != (n,) or not np.all(np.isfinite(x)):
        raise FaultError(f"fault: x0 must hold one finite position per block ({n})")
    wanted = int(max_events) if max_events is not None else 2**62
    # events are created as they start: room for the asked count, events still sliding at
    # the end, and merged ones; a time-limited run grows its catalogue by rerunning
    cap = min(wanted, 10_000_000) + n + 1000 if max_events is not None else 100_000 + n
    par = np.array([values[k] for k in PARAMS[:-2]] + [stop_time, 1.0 if backward else 0.0])
    lib = library()
    while True:
        ev = {k: np.zeros(cap) for k in ("start", "end", "moment", "energy")}
        ev_blocks, ev_first = np.zeros(cap, np.int32), np.zeros(cap, np.int32)
        sl = {k: np.zeros(slides) for k in ("t0", "t1", "slip")}
        sl_event, sl_block = np.zeros(slides, np.int32), np.zeros(slides, np.int32)
        slept, totals = np.zeros(n), np.zeros(len(TOTALS))
        xr = x.copy()
        msg = ctypes.create_string_buffer(512)
        cpu0, wall0 = time.process_time(), time.perf_counter()
        rc = lib.mf_fault_run(n, par, F, xr, wanted if max_events is not None else 2**62,
                              cap, ev["start"], ev["end"], ev["moment"], ev["energy"],
                              ev_blocks, ev_first, slides, sl_event, sl_block, sl["t0"],
                              sl["t1"], sl["slip"], slept, totals, max_steps, msg, len(msg))
        cpu, wall = time.process_time() - cpu0, time.perf_counter() - wall0
        if rc != 0:
            raise FaultError(msg.value.decode())
        if int(totals[TOTALS.index("status")]) == 2 and max_events is None and cap < 10**7:
            cap *= 4  # the time-limited run filled its catalogue: again, with room
            continue
        break
    tot = dict(zip(TOTALS, totals.tolist()))
    made = int(tot["created"])
    keep = (ev_blocks[:made] >= 0) & np.isfinite(ev["end"][:made])  # merged, unfinished out
    catalogue = np.zeros(int(keep.sum()), dtype=[("start", "f8"), ("end", "f8"),
                                                 ("blocks", "i4"), ("moment", "f8"),
                                                 ("energy", "f8"), ("first", "i4")])
    for name, column in (("start", ev["start"]), ("end", ev["end"]), ("blocks", ev_blocks),
                         ("moment", ev["moment"]), ("energy", ev["energy"]),
                         ("first", ev_first)):
        catalogue[name] = column[:made][keep]
    n_slides = int(tot["slides"])
    slide_table = np.zeros(n_slides, dtype=[("event", "i4"), ("block", "i4"), ("t0", "f8"),
                                            ("t1", "f8"), ("slip", "f8")])
    slide_table["event"], slide_table["block"] = sl_event[:n_slides], sl_block[:n_slides]
    for name in ("t0", "t1", "slip"):
        slide_table[name] = sl[name][:n_slides]
    run_time = tot["time"]
    settings = dict(solver="fault (event-driven: closed-form break-aways, DOPRI5 on sliding "
                           "blocks only, each group on its own clock)", n=n, **values, stop_time=stop_time,
                    max_events=max_events, status=STATUS[int(tot["status"])],
                    cpu_s=cpu, wall_s=wall, events=int(catalogue.size),
                    steps=int(tot["steps"]), rhs=int(tot["rhs"]),
                    block_rhs=int(tot["block_rhs"]), located=int(tot["located"]),
                    backward=bool(backward),
                    slept_fraction={"min": float(slept.min() / run_time) if run_time else 1.0,
                                    "mean": float(slept.mean() / run_time) if run_time else 1.0,
                                    "max": float(slept.max() / run_time) if run_time else 1.0})
    return FaultRun(catalogue, slide_table, slept, xr, tot, settings)


def thresholds(n: int, F0: float = 1.0, heterogeneity: float = 0.0, seed: int = 0) -> np.ndarray:
    """Static thresholds F0 (1 + h u_i), u_i uniform in [-1, 1] from `seed` (h = 0: all F0)."""
    if not (isinstance(n, (int, np.integer)) and n >= 1):
        raise FaultError(f"fault: n (blocks) must be an integer >= 1, not {n!r}")
    if not 0.0 <= heterogeneity < 1.0:
        raise FaultError(f"fault: heterogeneity must be in [0, 1) (a fraction of F0), not "
                         f"{heterogeneity!r}")
    u = np.random.default_rng(seed).uniform(-1.0, 1.0, int(n))
    return F0 * (1.0 + heterogeneity * u)


def carlson_langer(ell: float = 10.0, alpha: float = 2.5, sigma: float = 0.01,
                   nu: float = 0.01) -> dict:
    """run_fault's keywords for Carlson & Langer's dimensionless chain (module doc)."""
    return dict(m=1.0, kp=1.0, kc=ell**2, V=nu, sigma=sigma, alpha=alpha, vw=1.0)


__all__ = ["FaultError", "FaultRun", "carlson_langer", "library", "run_fault", "thresholds"]
