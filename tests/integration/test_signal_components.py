"""MSL-style signal sources and sensors (Force, Position, Speed, PositionSensor,
SpeedSensor, ForceSensor) in assemblies, against closed forms.

Our own signal outputs come from sensors, so a constant-speed drive read by a sensor
gives the sources a constant (Speed) or ramp (Position) reference. Every run is the
engine's me mode at tolerance 1e-10; the asserted 1e-8 is 100 x that, the accuracy the
project's figures state for the solver.
"""
import math

import numpy as np

from assemblies import Assembly, simulate_me
from components import (ConstantForce, ConstantSpeed, ForceSensor, MassWithFriction, Position,
                        PositionSensor, Speed, SpeedSensor, Spring)

V, F_CRIT = 0.3, 1.0
W = 2 * math.pi * F_CRIT
AF, BF = 1.3617, 0.6180  # MSL's filter coefficients, as written in Position's docstring


def test_speed_follows_its_signal_through_msl_first_order_filter():
    asm = Assembly("speed")
    asm.add("drive", ConstantSpeed(v=V))
    asm.add("read", SpeedSensor())
    asm.add("src", Speed(f_crit=F_CRIT))
    asm.add("pos", PositionSensor())
    asm.connect("drive.flange", "read.flange")
    asm.connect("read.v", "src.v_ref")
    asm.connect("src.flange", "pos.flange")
    res = simulate_me(asm, 3.0, 0.05, 1e-10)
    t = res["time"]
    decay = np.exp(-W * t)
    assert np.abs(res["src.v"] - V * (1 - decay)).max() < 1e-8        # v' = (v_ref - v) w
    assert np.abs(res["pos.s"] - V * (t - (1 - decay) / W)).max() < 1e-8  # s = integral of v


def test_position_follows_a_ramp_with_msl_second_order_filter_lag():
    """A ramp s_ref = V t through s/s_ref = 1 / (1 + (af/w) S + (bf/w²) S²) lags by
    V af / w once the transient (decay rate af w / (2 bf) = 6.9 /s) has gone; the whole
    response against the filter's equations integrated by scipy."""
    from scipy.integrate import solve_ivp

    asm = Assembly("position")
    asm.add("drive", ConstantSpeed(v=V))
    asm.add("read", PositionSensor())
    asm.add("src", Position(f_crit=F_CRIT))
    asm.add("speed", SpeedSensor())
    asm.connect("drive.flange", "read.flange")
    asm.connect("read.s", "src.s_ref")
    asm.connect("src.flange", "speed.flange")
    res = simulate_me(asm, 5.0, 0.05, 1e-10)
    t = res["time"]
    ref = solve_ivp(lambda t, y: [y[1], ((V * t - y[0]) * W - AF * y[1]) * W / BF],
                    (0.0, t[-1]), [0.0, 0.0], t_eval=t, rtol=1e-12, atol=1e-14, method="DOP853")
    assert np.abs(res["src.s"] - ref.y[0]).max() < 1e-8
    assert np.abs(res["speed.v"] - ref.y[1]).max() < 1e-8
    assert abs(V * t[-1] - res["src.s"][-1] - V * AF / W) < 1e-8
    assert abs(res["speed.v"][-1] - V) < 1e-8


def test_force_sensor_reads_the_force_it_passes_whichever_side_moves_it():
    # motion from b: a force source pushes through the sensor on a free mass
    asm = Assembly("push")
    asm.add("push", ConstantForce(F=2.0))
    asm.add("sensor", ForceSensor())
    asm.add("mass", MassWithFriction(m=4.0, mu_k=0.0, mu_s=0.0))
    asm.connect("push.flange", "sensor.flange_a")
    asm.connect("sensor.flange_b", "mass.flange_a")
    assert asm.resolve_causality()["sensor"] == "motion_at_b"
    res = simulate_me(asm, 2.0, 0.5, 1e-10)
    assert np.all(res["sensor.f"] == 2.0)                          # MSL: f = flange_a.f
    assert np.abs(res["mass.v_abs"] - 0.5 * res["time"]).max() < 1e-8  # F / m = 0.5 m/s2
    # motion from a: a drive pulls a spring-held mass through the sensor
    asm = Assembly("pull")
    asm.add("drive", ConstantSpeed(v=V))
    asm.add("sensor", ForceSensor())
    asm.add("spring", Spring(c=10.0))
    asm.add("mass", MassWithFriction(m=1.0, mu_k=0.0, mu_s=0.0))
    asm.connect("drive.flange", "sensor.flange_a")
    asm.connect("sensor.flange_b", "spring.flange_a")
    asm.connect("spring.flange_b", "mass.flange_a")
    assert asm.resolve_causality()["sensor"] == "motion_at_a"
    res = simulate_me(asm, 2.0, 0.1, 1e-10)
    # the sensor passes the spring's pull on to the drive: f = flange_a.f = -tension
    # to rounding: between events the engine takes the sensor and the spring as linear
    # maps, value at the last event + J (u - u_event) (settings["evaluated_as_linear_maps"])
    assert np.abs(res["sensor.f"] + res["spring.f"]).max() <= 1e-14 * np.abs(res["spring.f"]).max()
    # mass-spring driven at constant speed from rest: x'' = (c/m)(V t - x)
    wn = math.sqrt(10.0)
    t = res["time"]
    assert np.abs(res["mass.s"] - V * (t - np.sin(wn * t) / wn)).max() < 1e-8
