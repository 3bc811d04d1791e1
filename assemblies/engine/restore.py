"""Whether a foreign FMU's state restore can be trusted: checked once per process.

A master that rolls back (adaptive steps, event synchronisation) sets saved FMU states
again, and several exporters declare ``canGetAndSetFMUstate`` while their restore does
nothing or restores part of the state: the run is then silently wrong. So before a run
rolls back through an FMU that our runtime did not build, the compiled engine checks
its restore once (``c/restore_check.h``: on an instance of its own, save, doStep,
restore, doStep again, the same values bit for bit). The verdict is memoised per FMU
file, start values, step and tolerance: what the check ran with.

Our own FMUs (built from a component, not a foreign :class:`~assemblies.foreign.FMU`)
are not checked: their runtime saves and restores the whole instance (fmus/runtime),
which the runtime's own tests check. A foreign FMU's check costs one instantiation,
initialisation and two doSteps, once: 0.3 ms for a small C FMU, 0.5 ms for one of ours
loaded from its file, 11 ms for a pythonfmu FMU (which starts Python objects); a
memoised verdict costs 10-20 us per run.
"""
from __future__ import annotations

import ctypes as C
import functools
import threading

from ..experiment import restore_mismatch
from ..foreign import FMU
from .binding import InstanceSpec, Keep, Variable, instance_spec, variable
from .build import library

_P = C.POINTER
_lock = threading.Lock()
_verdicts: dict = {}


class _Check(C.Structure):  # restore_check.h: eng_restore_check
    _fields_ = [("verdict", C.c_int), ("which", C.c_int), ("after_step", C.c_int),
                ("expected", C.c_double), ("got", C.c_double), ("message", C.c_char * 1024)]


@functools.lru_cache(maxsize=None)
def _check_fn():
    fn = library().eng_check_restore
    fn.argtypes = [_P(InstanceSpec), C.c_double, C.c_double, C.c_int, _P(Variable),
                   _P(_Check)]
    fn.restype = None
    return fn


def compared_variables(fmu) -> list[str]:
    """What the check compares: the outputs and the continuous states."""
    return list(dict.fromkeys([*fmu.outputs, *fmu.states]))


def restore_problem(name: str, component, fmu, step: float, tolerance: float) -> str | None:
    """Why instance `name` (`component`, prepared as `fmu`) cannot be trusted to restore
    its state, or None: it can, or it is ours, or it declares no restore at all (the
    masters' canGetAndSetFMUstate fallback covers that)."""
    if not isinstance(component, FMU) or not fmu.can_get_set_state:
        return None
    starts = component.fmu_starts()
    key = (fmu.path, fmu.unzip_dir, tuple(sorted((k, repr(v)) for k, v in starts.items())),
           float(step), float(tolerance))
    with _lock:
        if key in _verdicts:
            return _verdicts[key]
    names = compared_variables(fmu)
    refs = [variable(fmu, name, 0, v) for v in names]
    keep = Keep()
    spec = instance_spec(keep, name, fmu, False, starts)
    check = _Check()
    _check_fn()(C.byref(spec), float(step), float(tolerance), len(refs),
                keep.array(Variable, refs), C.byref(check))
    if check.verdict == 1:
        problem = None
    elif check.verdict == 0:
        problem = restore_mismatch(names[check.which], bool(check.after_step), check.expected,
                                   check.got)
    else:
        problem = ("its restore could not be checked: "
                   + check.message.decode("utf-8", "replace"))
    with _lock:
        _verdicts[key] = problem
    return problem


def inexact_restores(assembly, fmus: dict, step: float, tolerance: float) -> dict[str, str]:
    """instance -> why its restore cannot be trusted, for each such instance."""
    found = {}
    for name, component in assembly.components.items():
        problem = restore_problem(name, component, fmus[name], step, tolerance)
        if problem is not None:
            found[name] = problem
    return found


__all__ = ["compared_variables", "inexact_restores", "restore_problem"]
