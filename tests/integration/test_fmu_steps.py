"""Every positive communication step is legal (FMI): the shortest are taken and right, the
longest end at once, with an error that names the step, or with the right state.

Tiny steps: a block sliding from rest, x = 10 on a unit spring, k x = 10 N beyond the
static limit mu_s m g: its acceleration is a = (-k x + mu_k m g) / m (sliding backward,
kinetic friction forward). Over a step h the exact state is x(h) = x + a h^2 / 2,
v(h) = a h; for h <= 1e-15 the h^2 term is below double precision of x = 10, so x is
unchanged and v = a h to rounding.
"""
import math

import pytest
from fmpy.fmi1 import FMICallException

from components import RollingCoin, SpringBlock
from cs_slave import initialize, open_slave

BLOCK = dict(m=2.0, k=1.0, g=9.81, mu_k=0.3, mu_s=0.4, x=10.0)


def _slave(component, version, messages, starts=None, tolerance=1e-8):
    fmu, vrs = open_slave(component, version, lambda message: messages.append(message.decode()),
                          instance_name="steps")
    set_f = fmu.setReal if version == 2 else fmu.setFloat64
    set_i = fmu.setInteger if version == 2 else fmu.setInt32
    for name, value in (starts or {}).items():
        (set_i if isinstance(value, int) else set_f)([vrs[name]], [value])
    initialize(fmu, version, tolerance)
    get_f = fmu.getReal if version == 2 else fmu.getFloat64
    return fmu, vrs, get_f


@pytest.mark.parametrize("version", [2, 3])
@pytest.mark.parametrize("solver", [0, 1], ids=["DOPRI5", "RODAS3"])
@pytest.mark.parametrize("h", [1e-300, 1.1e-16, 1e-15])
def test_tiny_steps_succeed_with_the_analytic_state(version, solver, h):
    p = BLOCK
    a = (-p["k"] * p["x"] + p["mu_k"] * p["m"] * p["g"]) / p["m"]
    fmu, vrs, get_f = _slave(SpringBlock(**p), version, [], {"solver": solver})
    try:
        fmu.doStep(0.0, h)
        x, v = get_f([vrs["x"], vrs["v"]])
        assert x == p["x"]
        assert v == pytest.approx(a * h, rel=1e-12)
        # and the run goes on from there with ordinary steps
        fmu.doStep(h, 0.5)
        x_half = get_f([vrs["x"]])[0]
        # sliding for 0.5 s: x = 10 + a t^2 / 2 while v < 0 (k x dominates), exactly the
        # kinetic phase of the seed's closed form, to the solver's tolerance
        omega = math.sqrt(p["k"] / p["m"])
        centre = p["mu_k"] * p["m"] * p["g"] / p["k"]
        assert x_half == pytest.approx(centre + (p["x"] - centre) * math.cos(omega * (0.5 + h)),
                                       abs=1e-6)
    finally:
        fmu.terminate()
        fmu.freeInstance()


@pytest.mark.parametrize("version", [2, 3])
def test_a_huge_step_of_a_rolling_coin_ends_at_once_with_an_error_naming_it(version):
    messages = []
    fmu, vrs, get_f = _slave(RollingCoin(), version, messages)
    try:
        with pytest.raises(FMICallException):
            fmu.doStep(0.0, 1e300)
        if version == 3:
            assert "communicationStepSize 1e+300" in messages[-1], messages[-1]
            assert "too long for this model" in messages[-1], messages[-1]
        # what is read afterwards with status OK is finite (the state it stopped at)
        values = get_f([vrs[n] for n in ("x", "theta", "psi_dot", "x_C", "E")])
        assert all(math.isfinite(v) for v in values)
    finally:
        fmu.freeInstance()


@pytest.mark.parametrize("version", [2, 3])
def test_a_huge_step_of_a_block_at_rest_gives_the_rest_state(version):
    # at rest at the spring's end, stuck: the exact state after any time is the same
    fmu, vrs, get_f = _slave(SpringBlock(), version, [])
    try:
        fmu.doStep(0.0, 1e300)
        assert get_f([vrs[n] for n in ("x", "v", "f_friction", "f_spring")]) == [0.0] * 4
    finally:
        fmu.terminate()
        fmu.freeInstance()


@pytest.mark.parametrize("tolerance", [1e-300, 0.0, 2.0])
def test_a_tolerance_double_precision_cannot_honour_is_refused_with_the_range(tolerance):
    messages = []
    with pytest.raises(FMICallException):
        _slave(SpringBlock(), 3, messages, tolerance=tolerance)
    assert "outside the allowed range [1e-14, 1]" in messages[-1], messages[-1]


@pytest.mark.parametrize("version", [2, 3])
@pytest.mark.parametrize("solver", [0, 1], ids=["DOPRI5", "RODAS3"])
def test_a_slip_a_rounding_error_before_the_step_end_is_taken_and_the_step_ends(version,
                                                                                 solver):
    """Seed 9.2 (m = k = g = 1, spring end at 0.1 t): the block breaks away at
    t1 = mu_s / 0.1. With mu_s = 0.45 - 1 ulp, t1 falls 1 ulp short of the communication
    point 4.5, leaving a step of one ulp after the event; that sliver once stalled the
    step ("advanced 0 s") in a sweep of the stick-slip map."""
    mu_s, speed = 0.44999999999999996, 0.1
    fmu, vrs, get_f = _slave(SpringBlock(m=1.0, k=1.0, g=1.0, mu_k=0.3, mu_s=mu_s), version,
                             [], {"solver": solver}, tolerance=1e-10)
    set_f = fmu.setReal if version == 2 else fmu.setFloat64
    get_i = fmu.getInteger if version == 2 else fmu.getInt32
    end = [vrs["flange_a.s"], vrs["flange_a.v"], vrs["flange_a.a"]]
    try:
        set_f(end, [0.0, speed, 0.0])
        fmu.doStep(0.0, 4.4000000000000004)
        assert get_i([vrs["mode"]])[0] == 0  # still stuck
        set_f(end, [0.4400000000000001, speed, 0.0])
        fmu.doStep(4.4, 0.09999999999999964)
        assert get_i([vrs["mode"]])[0] == 1  # sliding forward from t1 on
        # sliding from rest at t1: x = (k v t1 - mu_k g)(1 - cos dt) + v (dt - sin dt)
        # (m = k = 1, dt = t - t1), the seed's closed form of the first slide
        t1 = mu_s / speed
        fmu.doStep(4.5, 1.0)
        dt = 5.5 - t1
        exact = (speed * t1 - 0.3) * (1 - math.cos(dt)) + speed * (dt - math.sin(dt))
        # tolerance 1e-10 over 1 s of sliding: both solvers land within 5.1e-11; 1e-9 leaves
        # the global error ten tolerances (a slip located a step late would be off by ~1e-4)
        assert get_f([vrs["x"]])[0] == pytest.approx(exact, abs=1e-9)
    finally:
        fmu.terminate()
        fmu.freeInstance()


@pytest.mark.parametrize("version", [2, 3])
def test_no_step_follows_the_step_that_ended_the_run(version):
    """A coin tipped over from rest falls flat: the doStep that gets there ends the run
    (FMI 2: Discard, then fmi2Terminated is true; FMI 3: terminateSimulation). Neither
    standard allows another doStep after that (FMI 2's slave is terminated, FMI 3's
    importer must call fmi3Terminate): it is an error, with a line saying why. Before,
    FMI 2 answered Discard again and again with no line at all."""
    messages = []
    fmu, vrs, get_f = _slave(RollingCoin(theta=0.5, phi_dot=0.0, psi_dot=0.0), version, messages)
    try:
        if version == 2:
            with pytest.raises(FMICallException) as first:
                fmu.doStep(0.0, 10.0)
            assert first.value.status == 2  # fmi2Discard
            assert fmu.getBooleanStatus(3)  # fmi2Terminated
            t_end = fmu.getRealStatus(2)  # fmi2LastSuccessfulTime
        else:
            _, terminate, _, t_end = fmu.doStep(0.0, 10.0)
            assert terminate
        assert any("coin fell flat" in m for m in messages), messages
        assert 0.0 < t_end < 10.0
        n = len(messages)
        for _ in range(3):
            with pytest.raises(FMICallException) as again:
                fmu.doStep(t_end, 0.1)
            assert again.value.status == 3  # Error
        said = messages[n:]
        assert len(said) == 3, said
        assert all("ended the simulation" in m and "coin fell flat" in m and "no step can follow"
                   in m for m in said), said
        assert math.isfinite(get_f([vrs["theta"]])[0])  # still readable
    finally:
        fmu.freeInstance()
