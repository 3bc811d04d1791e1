"""SI units the components use, as FMI UnitDefinitions (exponents of the SI base units)."""
from __future__ import annotations

import math

# unit -> exponents of (kg, m, s, rad); "1" is dimensionless
UNITS: dict[str, dict[str, int]] = {
    "1": {},
    "s": {"s": 1},
    "m": {"m": 1},
    "m/s": {"m": 1, "s": -1},
    "m/s2": {"m": 1, "s": -2},
    "kg": {"kg": 1},
    "N": {"kg": 1, "m": 1, "s": -2},
    "N/m": {"kg": 1, "s": -2},
    "N.s/m": {"kg": 1, "s": -1},
    "rad": {"rad": 1},
    "rad/s": {"rad": 1, "s": -1},
    "rad/s2": {"rad": 1, "s": -2},
    "1/s": {"s": -1},
    "Hz": {"s": -1},
    "N.m": {"kg": 1, "m": 2, "s": -2},
    "N.m/rad": {"kg": 1, "m": 2, "s": -2, "rad": -1},
    "N.m.s/rad": {"kg": 1, "m": 2, "s": -1, "rad": -1},
    "kg.m2": {"kg": 1, "m": 2},
    "J": {"kg": 1, "m": 2, "s": -2},
    "W": {"kg": 1, "m": 2, "s": -3},
    "J/s": {"kg": 1, "m": 2, "s": -3},  # der(W) of an energy state
    "N.m2": {"kg": 1, "m": 3, "s": -2},
    "s/m": {"m": -1, "s": 1},  # MassWithStopAndFriction.fexp: the Stribeck decay
    # a force flange's rate inputs (components.dae: extrapolating the force in a step)
    "N/s": {"kg": 1, "m": 1, "s": -3},
    "N/s2": {"kg": 1, "m": 1, "s": -4},
    "N.m/s": {"kg": 1, "m": 2, "s": -3},
    "N/s3": {"kg": 1, "m": 1, "s": -5},
    "N.m/s2": {"kg": 1, "m": 2, "s": -4},
    "N.m/s3": {"kg": 1, "m": 2, "s": -5},
    "m/s3": {"m": 1, "s": -3},
    "m/s4": {"m": 1, "s": -4},
    "m/s5": {"m": 1, "s": -5},
    "rad/s3": {"rad": 1, "s": -3},
    "rad/s4": {"rad": 1, "s": -4},
    "rad/s5": {"rad": 1, "s": -5},
}


def unit_exponents(unit: str) -> dict[str, int]:
    if unit not in UNITS:
        raise ValueError(f"unit '{unit}' is not in fmus/units.py; known units: {', '.join(UNITS)}")
    return UNITS[unit]


# Display units FMI lets a tool offer next to the SI unit: value_display = factor * value_SI.
DISPLAY_UNITS: dict[str, tuple[tuple[str, float], ...]] = {
    "rad": (("deg", 180.0 / math.pi),),
    "rad/s": (("deg/s", 180.0 / math.pi), ("rpm", 30.0 / math.pi)),
    "rad/s2": (("deg/s2", 180.0 / math.pi),),
}

# The display unit a variable of this unit is shown in by default: angles read best in
# degrees; rates stay SI (rpm only suits spinning parts, and a tool can still offer it).
DEFAULT_DISPLAY_UNIT: dict[str, str] = {"rad": "deg"}
