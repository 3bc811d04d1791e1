"""Component declarations, parameter checks, and the flattened equations per mode."""
import math

import casadi as ca
import numpy as np
import pytest

from components import COMPONENTS, ComponentError, ConstantSpeed, SpringBlock, flatten

from conftest import SEED_94


@pytest.mark.parametrize("name, value, allowed", [
    ("m", 0.0, "> 0"), ("m", -1.0, "> 0"), ("k", -0.1, ">= 0"), ("d", -1.0, ">= 0"),
    ("mu_k", -0.1, ">= 0"), ("eps", 0.0, "> 0"), ("g", -9.81, ">= 0"),
    ("m", math.nan, "> 0"), ("k", math.inf, ">= 0"),
])
def test_invalid_parameter_names_component_parameter_and_range(name, value, allowed):
    with pytest.raises(ComponentError) as err:
        SpringBlock(name="blk", **{name: value})
    text = str(err.value)
    assert "SpringBlock 'blk'" in text and f"{name} " in text and allowed in text
    assert "\n" not in text


def test_static_friction_below_kinetic_is_rejected():
    with pytest.raises(ComponentError, match=r"mu_k <= mu_s"):
        SpringBlock(mu_k=0.5, mu_s=0.4)


def test_unknown_names_list_what_is_settable():
    with pytest.raises(ComponentError, match=r"unknown name 'mass'.*settable names: m, k"):
        SpringBlock(mass=2.0)
    with pytest.raises(ComponentError, match=r"friction = 'viscous'.*coulomb, smooth, tanh"):
        SpringBlock(friction="viscous")
    with pytest.raises(ComponentError, match=r"unknown profile 'upside_down'"):
        SpringBlock(profile="upside_down")


def test_every_component_flattens_under_every_profile():
    for cls in COMPONENTS.values():
        for profile in cls.profiles:
            model = flatten(cls(profile=profile.name))
            assert model.xdot.numel() == len(cls.states)


def _evaluate(model, x, q, u):
    f = model.functions()
    _, _, _, p = model.start_vectors()
    u = _with_rates(model, u)
    out = np.array(f["out"](0.0, x, q, u, p)).ravel()
    names = [v.name for v in model.outputs]
    return np.array(f["ode"](0.0, x, q, u, p)).ravel(), dict(zip(names, out))


def _with_rates(model, u):
    """`u` for the inputs the equations read, 0 for the rate inputs (only a
    co-simulation step reads them)."""
    if len(u) == len(model.inputs):  # given for every input
        return list(u)
    given = iter(u)
    return [0.0 if v.rate_of is not None else next(given) for v in model.inputs]


def test_coulomb_modes_give_the_seeds_equations():
    """Eq. 9.1 with Eq. 9.3, mode by mode, at an arbitrary state and spring-end motion."""
    model = flatten(SpringBlock(**SEED_94))
    x, v, s_end, v_end = 0.3, 0.02, 0.9, 0.05
    for mode, f_expected in ((1, -0.3), (-1, 0.3)):
        xdot, out = _evaluate(model, [x, v], [mode], [s_end, v_end, 0.0])
        assert xdot[0] == v
        assert xdot[1] == pytest.approx((s_end - x) + f_expected, abs=1e-15)
        assert out["f_friction"] == pytest.approx(f_expected, abs=1e-15)
    xdot, out = _evaluate(model, [x, 0.0], [0], [s_end, v_end, 0.0])
    assert xdot[0] == 0.0 and xdot[1] == 0.0  # exactly: stuck is not a steep curve
    assert out["f_friction"] == pytest.approx(-(s_end - x), abs=1e-15)


def test_smooth_laws_are_the_seeds_eq_9_5_and_9_7():
    eps = 1e-3
    for law in ("smooth", "tanh"):
        model = flatten(SpringBlock(**SEED_94, friction=law, eps=eps))
        for v in (-2e-3, -3e-4, 0.0, 5e-4, 1e-3, 0.1):
            _, out = _evaluate(model, [0.0, v], [0], [0.0, 0.0, 0.0])
            r = v / eps
            mu = 0.3 * math.tanh(3 * r)
            if law == "smooth":
                mu += 0.1 * r * math.exp(0.5 - r * r / 2)
            assert out["f_friction"] == pytest.approx(-mu, rel=1e-14, abs=1e-16)


def test_moving_support_enters_through_its_acceleration():
    """Seed 9.6: in the table's frame the block feels -m a_table."""
    model = flatten(SpringBlock(**{**SEED_94, "k": 0.0}, profile="driven_on_moving_support"))
    names = [v.name for v in model.inputs]
    u = np.zeros(len(names))
    u[names.index("support.a")] = -40.0
    xdot, out = _evaluate(model, [0.0, -0.5], [-1], u)
    assert xdot[1] == pytest.approx(40.0 + 0.3, abs=1e-12)  # relative: -a_table + mu_k g
    assert out["s"] == 0.0


def test_constant_speed_source():
    """s = s0 + travel with travel' = v: no explicit time, so the model is autonomous."""
    model = flatten(ConstantSpeed(v=0.05, s0=0.1))
    f = model.functions()
    travel = 0.05 * 8.0  # what travel' = v gives by t = 8
    y = np.array(f["out"](8.0, [travel], [], [1.0], [0.05, 0.1])).ravel()
    assert list(y) == pytest.approx([0.5, 0.05, 0.0])
    assert np.array(f["ode"](8.0, [travel], [], [1.0], [0.05, 0.1])).ravel().tolist() == [0.05]
    assert not ca.depends_on(ca.vertcat(model.xdot, model.y), model.t)
