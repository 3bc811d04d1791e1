"""The co-simulation run's structure is memoised by the assembly's structure (issue 27):
new values reuse it, a new wiring or option never does, and the memo stays bounded.

Checked on a mass hung by a spring from a constant-speed drive, against the closed form of
its oscillation relative to the drive, y = y0 cos(w t) + (y0' / w) sin(w t)."""
import numpy as np
import pytest

import assemblies.engine.cosim as engine_cosim
from assemblies import Assembly
from assemblies.engine.cosim import SHAPES_KEPT, cosimulate, run_shape
from assemblies.engine.prepare import prepared
from components import ConstantSpeed, Mass, Spring, SpringBlock

TOL = 1e-4
STOP, STEP = 20.0, 0.05


def _hung(drive: str, c: float = 8.0, name: str = "hung_shape") -> Assembly:
    """The mass on a spring from `drive`: "belt" (v = 0.5 from 0) or "lift" (v = 0.37 from
    1.5); the other drive stands unconnected."""
    asm = Assembly(name)
    asm.add("belt", ConstantSpeed(v=0.5))
    asm.add("lift", ConstantSpeed(v=0.37, s0=1.5))
    asm.add("spring", Spring(c=c))
    asm.add("mass", Mass(m=2.0))
    asm.connect(f"{drive}.flange", "spring.flange_a")
    asm.connect("spring.flange_b", "mass.flange_a")
    asm.component("mass").set("s", 0.2)
    return asm


def _closed_form(t, drive: str, c: float):
    v, s0 = (0.5, 0.0) if drive == "belt" else (0.37, 1.5)
    w = np.sqrt(c / 2.0)
    return s0 + v * t + (0.2 - s0) * np.cos(w * t) - v / w * np.sin(w * t)


def _run(asm):
    return cosimulate(asm, STOP, STEP, 1e-10, record=["mass.s"], adaptive=True, tol=TOL,
                      extrapolation=2)


def _shape(asm):
    asm.resolve_causality()
    return run_shape(asm, {n: prepared(c) for n, c in asm.components.items()})


def test_new_values_reuse_the_shape_and_a_new_wiring_does_not():
    for drive, c in (("belt", 8.0), ("belt", 18.0), ("lift", 8.0)):
        result = _run(_hung(drive, c))
        # within the adaptive master's tolerance (3.5e-5 to 4.7e-5 off, measured); the
        # other drive's motion would be metres off
        np.testing.assert_allclose(result["mass.s"], _closed_form(result["time"], drive, c),
                                   rtol=0, atol=TOL, err_msg=f"{drive}, c = {c}")
    belt, stiffer, lift = _shape(_hung("belt")), _shape(_hung("belt", 18.0)), _shape(_hung("lift"))
    assert stiffer is belt  # values are set per run
    assert lift is not belt
    feeds = [c.source[0] for c in lift.couplings if c.target == ("spring", "flange_a.s")]
    assert feeds == ["lift"]


def test_an_option_is_part_of_the_shape_and_a_setting_is_not():
    """An option shapes the binary, and the binary the variables the plan points at; the
    FMU's solver is a value set per run."""
    def block(**options):
        asm = Assembly("block_shape")
        asm.add("belt", ConstantSpeed(v=0.5))
        asm.add("block", SpringBlock(**options))
        asm.connect("belt.flange", "block.flange_a")
        return asm
    coulomb = _shape(block())
    assert _shape(block(friction="smooth")) is not coulomb
    solver = block()
    solver.component("block").set("solver", "1")
    assert _shape(solver) is coulomb


def test_the_memo_keeps_the_latest_shapes_only():
    first = _hung("belt", name="hung_shape_0")
    _shape(first)
    for i in range(1, SHAPES_KEPT + 5):
        _shape(_hung("belt", name=f"hung_shape_{i}"))
    assert len(engine_cosim._shapes) <= SHAPES_KEPT
    # the oldest went first: asking again builds it anew, equal to what it was
    again = _shape(_hung("belt", name="hung_shape_0"))
    assert again.plan.pairs == _shape(first).plan.pairs


def test_a_wiring_mistake_is_named_before_any_fmu_is_built(monkeypatch):
    """An input fed twice is refused from the couplings, before the FMUs are prepared
    (building them can take minutes on a cold cache)."""
    from assemblies import AssemblyError
    from components import PositionSensor

    asm = Assembly("fed_twice_shape")
    asm.add("belt", ConstantSpeed(v=0.5))
    asm.add("lift", ConstantSpeed(v=0.3))
    asm.add("sensor", PositionSensor())
    asm.connect("belt.flange", "sensor.flange")
    asm.connect("lift.flange", "sensor.flange")
    built = []
    monkeypatch.setattr(engine_cosim, "prepared", lambda c: built.append(c) or prepared(c))
    with pytest.raises(AssemblyError, match=r"input sensor\.flange\.s is fed twice"):
        cosimulate(asm, 1.0, 0.1)
    assert built == []
