"""The checks every master makes on the experiment it is asked to run."""
from __future__ import annotations

import math

import numpy as np

from components.errors import check_tolerance, positive_finite

from .assembly import AssemblyError
from .limits import check_output_rows


def check_experiment(stop_time: float, step: float, tolerance: float,
                     step_name: str = "communication step", rows: bool = True) -> None:
    """Reject what no master can run, naming the setting and what is allowed; with
    `rows`, also an output table beyond memory (a run writes one row per step; an
    exported FMU's default experiment writes none)."""
    positive_finite(stop_time, "stop time", AssemblyError)
    positive_finite(step, step_name, AssemblyError)
    check_tolerance(tolerance, "tolerance", AssemblyError)
    if rows:
        check_output_rows(stop_time, step, step_name)  # before any master allocates them


def output_times(stop_time: float, step: float) -> np.ndarray:
    """0, step, 2 step, ... and the stop time last (a last interval may be shorter);
    built by numpy, since a long run has millions of rows."""
    n_out = max(1, math.ceil(stop_time / step - 1e-9))
    times = np.minimum(np.arange(n_out + 1) * step, stop_time)
    times[-1] = stop_time
    return times


def check_cosim_settings(scheme: str, extrapolation: int, adaptive: bool, tol: float) -> None:
    """Reject co-simulation settings that no co-simulation master can run."""
    from .masters.extrapolation import ORDERS  # here: the masters import this module
    if scheme not in ("jacobi", "gauss-seidel"):
        raise AssemblyError(f"scheme must be 'jacobi' or 'gauss-seidel', not '{scheme}'")
    if extrapolation not in ORDERS:
        raise AssemblyError(f"extrapolation must be 0 (constant), 1 (linear) or 2 (quadratic), "
                            f"not {extrapolation!r}")
    if adaptive and not (isinstance(tol, (int, float)) and math.isfinite(tol) and 0 < tol < 1):
        # 0 is not "off": it would ask for an error no step can meet
        raise AssemblyError(f"adaptive tolerance tol must be in (0, 1), not {tol!r} (fixed "
                            "communication steps: adaptive=False, --fixed-step)")


class FixedStepFallback(UserWarning):
    """An adaptive or event-synchronised co-simulation ran fixed steps instead: an FMU
    cannot roll back (``settings["fallback"]`` of the result says which and why). Raised
    by both co-simulation masters (engine "c" and "fmpy")."""


def fixed_step_fallback(adaptive: bool, stateless: list[str], step: float) -> str:
    """What a co-simulation asked for `adaptive` steps or event synchronisation, with
    the instances `stateless` unable to get and set their FMU state, says it ran
    instead (fixed steps of `step`): the text of the warning and of
    ``settings["fallback"]``, the same from both masters."""
    many = len(stateless) > 1
    return (f"{'adaptive' if adaptive else 'event-synchronised'} co-simulation rolls "
            f"steps back, but FMU instance{'s' if many else ''} "
            f"{', '.join(repr(n) for n in stateless)} cannot get and set "
            f"{'their' if many else 'its'} state (canGetAndSetFMUstate "
            f"is false): ran fixed communication steps of {step:g} s without event "
            "synchronisation instead")
