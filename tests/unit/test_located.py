"""assemblies/scenes/located.py: continuing a located event's state by the block's own
equation, against a closed form of that equation."""
import math

import pytest

from assemblies import Assembly
from assemblies.scenes.located import continue_to_rest, continue_to_speed
from components import ConstantSpeed, SpringBlock

EPS, MU, G = 1e-3, 0.6, 1.0


def _free_block(friction="tanh"):
    """No spring (k = 0): under Eq. 9.7, v' = -mu g tanh(3 v / eps), so
    sinh(3 v / eps) = sinh(3 v0 / eps) exp(-3 mu g t / eps): v reaches v1 > 0 after
    eps / (3 mu g) ln(sinh(3 v0 / eps) / sinh(3 v1 / eps)) and never reaches 0."""
    asm = Assembly("free")
    asm.add("wall", ConstantSpeed(v=0.0))
    asm.add("block", SpringBlock(m=1, k=0, g=G, mu_k=MU, mu_s=MU, eps=EPS, friction=friction))
    asm.connect("wall.flange", "block.flange_a")
    return asm


def test_the_time_to_a_speed_is_the_closed_forms():
    v0, v1, t0 = 5 * EPS, 0.5 * EPS, 2.0
    exact = EPS / (3 * MU * G) * math.log(math.sinh(3 * v0 / EPS) / math.sinh(3 * v1 / EPS))
    t, x = continue_to_speed(_free_block(), "block", "wall", t0, 0.1, v0, v1, 1.0)
    assert t - t0 == pytest.approx(exact, rel=1e-11, abs=1e-15)
    assert 0.1 + v1 * (t - t0) < x < 0.1 + v0 * (t - t0)  # it moved, slowing down
    # backwards from there it comes back to v0 at t0
    back, _ = continue_to_speed(_free_block(), "block", "wall", t, x, v1, v0, -1.0)
    assert back == pytest.approx(t0, abs=1e-11)


def test_without_a_spring_the_block_never_comes_to_rest():
    t, x = continue_to_rest(_free_block(), "block", "wall", 0.0, 0.0, 5 * EPS)
    assert math.isnan(t) and math.isnan(x)
    t, _ = continue_to_speed(_free_block(), "block", "wall", 0.0, 0.0, 5 * EPS, 0.0, 10.0)
    assert math.isnan(t)


def test_coulomb_friction_is_refused():
    with pytest.raises(ValueError, match="Coulomb friction switches mode"):
        continue_to_speed(_free_block("coulomb"), "block", "wall", 0.0, 0.0, 1.0, 0.0, 1.0)
