"""The checks every master makes on the experiment it is asked to run."""
from __future__ import annotations

import math
import numbers

import numpy as np

from components.errors import check_tolerance, positive_finite

from .assembly import AssemblyError
from .limits import check_output_rows


#: the setting each check names, as run_scene and `mechfmu run` spell it: a refusal says
#: which option to change whichever way the run was asked for
OPTIONS = {"stop time": "stop_time=, --stop-time", "start time": "start_time=, --start-time",
           "communication step": "step=, --step", "output step": "step=, --step",
           "tolerance": "tolerance=, --tolerance"}
#: the shortest step, relative to the run's largest time: the output times are
#: start + k * step in doubles, and far below this they no longer differ by a step (at
#: --start-time 1e17 a step of 0.1 s wrote hundreds of rows at one time); it is the
#: FMUs' own shortest step (MF_MIN_STEP in fmus/runtime/solver.h), about 45 roundings
MIN_RELATIVE_STEP = 1e-14


def _named(check, value, what: str):
    """`check(value, what)`, its refusal naming the option that sets `what`."""
    try:
        return check(value, what, AssemblyError)
    except AssemblyError as exc:
        raise AssemblyError(f"{exc} ({OPTIONS[what]})") from None


def check_experiment(stop_time: float, step: float, tolerance: float,
                     step_name: str = "communication step", start_time: float = 0.0,
                     rows: bool = True) -> None:
    """Reject what no master can run, naming the setting, its option and what is allowed;
    with `rows`, also an output table beyond memory (a run writes one row per step from
    the start time; an exported FMU's default experiment writes none)."""
    _named(positive_finite, stop_time, "stop time")
    _named(positive_finite, step, step_name)
    _named(check_tolerance, tolerance, "tolerance")
    check_start_time(start_time, stop_time)
    if rows:  # before any master allocates them
        check_output_rows(stop_time - start_time, step, step_name, start_time)
    largest = max(abs(start_time), abs(stop_time))
    shortest = MIN_RELATIVE_STEP * largest
    if step < shortest:
        raise AssemblyError(
            f"{step_name} {step:g} s is below what times near {largest:g} s resolve: at "
            f"least {shortest:.3g} s ({MIN_RELATIVE_STEP:g} of the run's largest time), or "
            f"a start time nearer 0 ({OPTIONS[step_name]})")


def check_start_time(start_time: float, stop_time: float) -> None:
    """One line where the start time is not a finite number before the stop time."""
    where = f" ({OPTIONS['start time']})"
    # a float or int first: the ABC check costs a microsecond of every run
    if type(start_time) not in (float, int) and (
            isinstance(start_time, bool) or not isinstance(start_time, numbers.Real)):
        raise AssemblyError(f"start time must be a number, not {start_time!r}{where}")
    if not math.isfinite(start_time):
        raise AssemblyError(f"start time must be finite, not {start_time!r}{where}")
    if not start_time < stop_time:
        raise AssemblyError(f"start time {start_time:g} s must be before the stop time "
                            f"{stop_time:g} s{where}")


def output_times(stop_time: float, step: float, start_time: float = 0.0) -> np.ndarray:
    """start, start + step, ... and the stop time last (a last interval may be shorter);
    built by numpy, since a long run has millions of rows."""
    n_out = max(1, math.ceil((stop_time - start_time) / step - 1e-9))
    times = np.minimum(start_time + np.arange(n_out + 1) * step, stop_time)
    times[-1] = stop_time
    return times


def check_cosim_settings(scheme: str, extrapolation: int, adaptive: bool, tol: float) -> None:
    """Reject co-simulation settings that no co-simulation master can run."""
    from .masters.extrapolation import ORDERS  # here: the masters import this module
    if scheme not in ("jacobi", "gauss-seidel"):
        raise AssemblyError(f"scheme must be 'jacobi' or 'gauss-seidel', not '{scheme}'")
    if extrapolation not in ORDERS:
        raise AssemblyError(f"extrapolation must be 0 (constant), 1 (linear), 2 (quadratic) or "
                            f"3 (cubic), not {extrapolation!r}")
    if adaptive and not (isinstance(tol, (int, float)) and math.isfinite(tol) and 0 < tol < 1):
        # 0 is not "off": it would ask for an error no step can meet
        raise AssemblyError(f"adaptive tolerance tol must be in (0, 1), not {tol!r} (fixed "
                            "communication steps: adaptive=False, --fixed-step)")


class FixedStepFallback(UserWarning):
    """An adaptive or event-synchronised co-simulation ran fixed steps instead: an FMU
    cannot roll back (``settings["fallback"]`` of the result says which and why). Raised
    by both co-simulation masters (engine "c" and "fmpy")."""


def fixed_step_fallback(adaptive: bool, stateless: list[str], step: float,
                        inexact: dict[str, str] | None = None) -> str:
    """What a co-simulation asked for `adaptive` steps or event synchronisation, with
    the instances `stateless` unable to get and set their FMU state and the instances
    of `inexact` (name -> why) unable to restore it exactly (:func:`restore_mismatch`),
    says it ran instead (fixed steps of `step`): the text of the warning and of
    ``settings["fallback"]``, the same from both masters."""
    why = []
    if stateless:
        many = len(stateless) > 1
        why.append(f"FMU instance{'s' if many else ''} {', '.join(repr(n) for n in stateless)} "
                   f"cannot get and set {'their' if many else 'its'} state "
                   "(canGetAndSetFMUstate is false)")
    for name, reason in (inexact or {}).items():
        why.append(f"FMU instance {name!r} declares canGetAndSetFMUstate but does not restore "
                   f"its state exactly ({reason})")
    return (f"{'adaptive' if adaptive else 'event-synchronised'} co-simulation rolls "
            f"steps back, but {'; '.join(why)}: ran fixed communication steps of {step:g} s "
            "without event synchronisation instead")


def restore_mismatch(variable: str, after_step: bool, expected: float, got: float) -> str:
    """Why a state restore is not exact, as the restore check found it (both masters):
    the state saved at t = 0, one doStep, the state set back (and the same doStep
    again), and `variable` read `got` where it had read `expected`."""
    if after_step:
        return (f"set back to its state at t = 0 and stepped again the same, {variable} "
                f"reads {got:.10g} instead of {expected:.10g}")
    return (f"set back to its state at t = 0 after a doStep, {variable} reads {got:.10g} "
            f"instead of {expected:.10g}")
