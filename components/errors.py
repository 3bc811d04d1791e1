"""The errors mechfmu raises on purpose, under one root, and the checks of plain numbers.

Every error of ours is a :class:`MechfmuError`, so a caller (the ``mechfmu`` command
among them) catches one class and prints one line; an error about a value a caller
passed is also a ``ValueError``, one about a run that failed a ``RuntimeError``. The
message names what is wrong and what is allowed.
"""
from __future__ import annotations

import math
import numbers
import tempfile
from pathlib import Path


class MechfmuError(Exception):
    """The root of every error mechfmu raises on purpose."""


class ComponentError(MechfmuError, ValueError):
    """Bad input to a component: the message names the component and what is allowed."""


class SimulationError(MechfmuError, RuntimeError):
    """An FMU refused a call; the message carries what the FMU logged. (Here, not with the
    masters that raise it: the compiled engine raises it too, and must not load fmpy.)"""


def number(value, what: str, error: type[MechfmuError] = ComponentError,
           allowed: str = "a number") -> float:
    """`value` as a float if it is a real number (not a bool, not a string), else
    `error` naming `what` and the type it got: ``stop_time='10'`` is refused, not
    compared as a string or converted behind the caller's back."""
    if type(value) is float or type(value) is int:  # the usual case, before the ABC check
        return float(value)
    if isinstance(value, numbers.Real) and not isinstance(value, bool):
        return float(value)
    raise error(f"{what} must be {allowed}, not {type(value).__name__} {value!r}")


def positive_finite(value, what: str, error: type[MechfmuError] = ComponentError) -> float:
    """`value` as a float if it is a positive finite number, else `error` saying so."""
    x = number(value, what, error, "a positive finite number")
    if not (math.isfinite(x) and x > 0):
        raise error(f"{what} must be a positive finite number, not {value!r}")
    return x


#: the tightest relative tolerance a solver can meet: 1e-14 is about 50 machine epsilons of
#: a double; below it an error estimate is mostly round-off, the step size is cut until it
#: underflows, and the run fails with a message about the model instead of the tolerance
MIN_TOLERANCE = 1e-14


def check_tolerance(value, what: str = "tolerance",
                    error: type[MechfmuError] = ComponentError) -> float:
    """A relative solver tolerance in [MIN_TOLERANCE, 1), as a float; else `error`."""
    tol = number(value, what, error, f"a number in [{MIN_TOLERANCE:g}, 1)")
    if not (MIN_TOLERANCE <= tol < 1):
        raise error(f"{what} must be in [{MIN_TOLERANCE:g}, 1), not {value!r} (a relative "
                    f"tolerance under {MIN_TOLERANCE:g} is below what double precision "
                    "round-off lets a solver meet)")
    return tol


def writable_file(path, what: str, kind: str, error: type[MechfmuError] = ComponentError) -> Path:
    """`path` as a file that can be written, checked before seconds of work: not a folder,
    and in a folder one can write in (made if missing); else `error` saying which."""
    target = Path(path)
    if target.is_dir():
        raise error(f"{what} {path} is a folder; {what} takes the {kind} file to write")
    try:
        target.parent.mkdir(parents=True, exist_ok=True)
        with tempfile.TemporaryFile(dir=target.parent):
            pass
    except OSError as exc:
        raise error(f"{what} {path}: cannot write in {target.parent} ({exc.strerror}); "
                    f"{what} takes a {kind} path in a folder you can write in") from None
    return target


def writable_folder(path, what: str, error: type[MechfmuError] = ComponentError) -> Path:
    """`path` as a folder one can write in, made now if missing: a mistake is found before
    a long run, not after it; else `error` saying which."""
    folder = Path(path)
    if folder.exists() and not folder.is_dir():
        raise error(f"{what} {path} is a file; {what} takes a folder (made if missing)")
    try:
        folder.mkdir(parents=True, exist_ok=True)
        with tempfile.TemporaryFile(dir=folder):
            pass
    except OSError as exc:
        raise error(f"{what} {path}: cannot write there ({exc.strerror}); {what} takes "
                    "a folder you can write in (made if missing)") from None
    return folder
