"""FMI variable types as the assemblies carry them: the engine's type codes, the
names of array elements, the ranges values are checked against, and which output type
may feed which input type.

Every value travels through the engine as a double (c/engine.h): exact for Float32,
the 8/16/32-bit integers, Boolean (0/1) and Int64/UInt64 (and FMI 3 Enumeration, an
Int64) up to 2^53 in magnitude. A start value beyond that is refused here; an FMU
output beyond it fails the run, naming it, rather than being rounded. Strings travel
as indices into the engine's string table and come back as text (object columns).
"""
from __future__ import annotations

import math

#: FMI 2 names of the FMI 3 types they are
_FMI2 = {"Real": "Float64", "Integer": "Int32"}
#: the engine's type code of each type (c/engine.h: ENG_FLOAT64 ...)
CODES = {"Float64": 0, "Int32": 1, "Float32": 2, "Int8": 3, "UInt8": 4, "Int16": 5,
         "UInt16": 6, "UInt32": 7, "Int64": 8, "UInt64": 9, "Boolean": 10,
         "Enumeration": 11, "String": 12}
STRING = CODES["String"]
#: the largest magnitude of a whole number a double carries exactly
EXACT = 2 ** 53
#: whole-number types: the values each can hold (as the engine carries them)
RANGES = {"Int8": (-2 ** 7, 2 ** 7 - 1), "UInt8": (0, 2 ** 8 - 1),
          "Int16": (-2 ** 15, 2 ** 15 - 1), "UInt16": (0, 2 ** 16 - 1),
          "Int32": (-2 ** 31, 2 ** 31 - 1), "UInt32": (0, 2 ** 32 - 1),
          "Int64": (-EXACT, EXACT), "UInt64": (0, EXACT), "Enumeration": (-EXACT, EXACT),
          "Boolean": (0, 1)}
#: types whose values move between events (extrapolated, differentiated)
CONTINUOUS = ("Float64", "Float32")
#: the largest array the engine couples and records, element by element
MAX_ARRAY = 4096


def canonical(fmi_type: str) -> str:
    """The FMI 3 name of an FMI 2 or 3 type name (Real -> Float64, Integer -> Int32)."""
    return _FMI2.get(fmi_type, fmi_type)


def code(fmi_type: str) -> int | None:
    """The engine's code of a type; None for one it does not carry (Binary, Clock)."""
    return CODES.get(canonical(fmi_type))


def element_names(name: str, shape: tuple) -> list[str]:
    """The elements of array `name` of `shape` in row-major order (FMI 3 serialises arrays
    so), named as FMI's structured names index them: 1-based, ``x[2]``, ``m[1,2]``."""
    if not shape:
        return [name]
    names = [""]
    for n in shape:
        names = [f"{prefix},{i}" if prefix else str(i) for prefix in names for i in range(1, n + 1)]
    return [f"{name}[{index}]" for index in names]


def size(shape: tuple) -> int:
    return math.prod(shape) if shape else 1


def check_value(value_type: str, value) -> str | None:
    """Why `value` is not a value of `value_type` (None: it is one): what
    ``FMU.set`` tells the user. Strings take str; the others numbers (Boolean also
    True/False), whole numbers within range for the integer types."""
    if value_type == "String":
        return None if isinstance(value, str) else "takes text (a str)"
    if isinstance(value, str):
        return "takes a number, not text"
    try:
        number = float(value)
    except (TypeError, ValueError):
        return "takes a number"
    if isinstance(value, int) and not isinstance(value, bool):
        number = value  # compared as the integer it is: a double would round 2^53 + 1
    if value_type == "Boolean":
        return None if number in (0.0, 1.0) else "takes True/False (1/0)"
    if value_type in RANGES:
        lo, hi = RANGES[value_type]
        if not (isinstance(number, int) or (math.isfinite(number) and number.is_integer())):
            return "takes whole numbers"
        if not lo <= number <= hi:
            beyond = " (the engine carries values as doubles, exact to 2^53)" \
                if value_type in ("Int64", "UInt64", "Enumeration") else ""
            return f"takes whole numbers from {lo} to {hi}{beyond}"
    return None


def feeds(source: str, target: str) -> bool:
    """May an output of type `source` feed an input of type `target`? The same type;
    any number into a float (Float64 and Float32 both ways: they are one quantity at two
    precisions; an integer becomes its value); an integer into a wider integer that
    holds every value of it. Never a float into an integer (no silent rounding),
    nor a Boolean, an Enumeration or a String into anything but its own type."""
    if source == target:
        return True
    if source in ("Boolean", "Enumeration", "String") or target in ("Boolean", "Enumeration", "String"):
        return False
    if target in CONTINUOUS:
        return True
    if source in CONTINUOUS:
        return False
    (lo_s, hi_s), (lo_t, hi_t) = RANGES[source], RANGES[target]
    return lo_t <= lo_s and hi_s <= hi_t


def article(value_type: str) -> str:
    """``an Int8``, ``a UInt64``, ``a Boolean``: a type named in a sentence."""
    return f"{'an' if value_type[0] in 'AEIO' else 'a'} {value_type}"


def coupling_rule() -> str:
    """The rule of :func:`feeds` in one line, for error messages."""
    return ("an output feeds an input of its own type, any float input (an integer as its "
            "value), or a wider integer; never a float into an integer, and Boolean, "
            "Enumeration and String only their own type")


__all__ = ["CODES", "CONTINUOUS", "EXACT", "MAX_ARRAY", "RANGES", "STRING", "article", "canonical",
           "check_value", "code", "coupling_rule", "element_names", "feeds", "size"]
