"""RigidBodyOnAxle: seed 8.5's disk, an arbitrary body, and Newton-Euler checked independently."""
import math

import numpy as np
import pytest
from scipy.optimize import minimize_scalar
from scipy.spatial.transform import Rotation

from components import ComponentError, flatten
from components.bodies.axle import RigidBodyOnAxle

K = np.array([0.0, 0.0, 1.0])


def disk(m=1.0, R=1.0, g=9.81, **kw):
    """Seed 8.5: uniform disk flat in X-Y (I_zz = m R^2/2, I_xx = I_yy = m R^2/4), r_GP = R j."""
    return RigidBodyOnAxle(m=m, I_xx=m * R**2 / 4, I_yy=m * R**2 / 4, I_zz=m * R**2 / 2,
                           r_y=R, n_x=0.0, n_y=math.sqrt(0.5), n_z=math.sqrt(0.5), g=g, **kw)


def arbitrary_body(seed=3, **kw):
    """A lopsided body: principal moments (1, 2, 2.5) turned by a random rotation."""
    rng = np.random.default_rng(seed)
    Q = Rotation.random(random_state=seed).as_matrix()
    I_cm = Q @ np.diag([1.0, 2.0, 2.5]) @ Q.T
    n = rng.normal(size=3)
    n /= np.linalg.norm(n)
    r = rng.normal(size=3)
    values = dict(m=1.7, I_xx=I_cm[0, 0], I_yy=I_cm[1, 1], I_zz=I_cm[2, 2], I_xy=I_cm[0, 1],
                  I_xz=I_cm[0, 2], I_yz=I_cm[1, 2], r_x=r[0], r_y=r[1], r_z=r[2],
                  n_x=n[0], n_y=n[1], n_z=n[2], g=9.81)
    return RigidBodyOnAxle(**{**values, **kw}), I_cm, n, r


def rigid_body(body):
    """(m, g, I_cm, r_GP, n) as numpy, read back from the component's parameters."""
    v = body.values
    I_cm = np.array([[v["I_xx"], v["I_xy"], v["I_xz"]], [v["I_xy"], v["I_yy"], v["I_yz"]],
                     [v["I_xz"], v["I_yz"], v["I_zz"]]])
    return (v["m"], v["g"], I_cm, np.array([v["r_x"], v["r_y"], v["r_z"]]),
            np.array([v["n_x"], v["n_y"], v["n_z"]]))


def newton_euler(body, theta, omega, alpha):
    """Independent: rotate with scipy, a_G = alpha x r + omega x omega x r, H_P = I_P omega."""
    m, g, I_cm, r_ref, n = rigid_body(body)
    Rm = Rotation.from_rotvec(theta * n).as_matrix()
    r = Rm @ r_ref
    I_P = Rm @ (I_cm + m * (r_ref @ r_ref * np.eye(3) - np.outer(r_ref, r_ref))) @ Rm.T
    w_vec, a_vec = omega * n, alpha * n
    a_G = np.cross(a_vec, r) + np.cross(w_vec, np.cross(w_vec, r))
    dH = I_P @ a_vec + np.cross(w_vec, I_P @ w_vec)
    gravity_moment = np.cross(r, -m * g * K)
    return r, a_G, dH, gravity_moment, n @ I_P @ n


def evaluate(body, x, u, q=()):
    model = flatten(body)
    f = model.functions()
    _, _, _, p = model.start_vectors()
    given = iter(u)  # 0 for the rate inputs, which only a co-simulation step reads
    u = [0.0 if v.rate_of is not None else next(given) for v in model.inputs]
    xdot = np.array(f["ode"](0.0, x, list(q), u, p)).ravel()
    y = np.array(f["out"](0.0, x, list(q), u, p)).ravel()
    return xdot, dict(zip([v.name for v in model.outputs], y))


@pytest.mark.parametrize("m, R, g", [(1.0, 1.0, 9.81), (2.5, 0.3, 9.81), (0.1, 4.0, 1.62)])
def test_seed_disk_frequency_is_sqrt_4g_over_7R(m, R, g):
    body = disk(m, R, g)
    assert body.equilibrium_angle() == 0.0  # the seed's reference pose is its equilibrium
    assert body.small_oscillation_frequency() == pytest.approx(math.sqrt(4 * g / (7 * R)), rel=1e-12)


def test_seed_disk_full_equation_is_a_pendulum():
    """Derived by hand: J_n = 3mR^2/8 + mR^2/2 = 7mR^2/8, z_G = R(1 - cos theta)/2."""
    body = disk(m=1.3, R=0.7, tau_c=0.0)
    for theta, omega, tau in ((0.0, 0.0, 0.0), (1.0, -2.0, 0.0), (2.9, 0.4, 0.8), (-0.6, 3.0, -1.1)):
        xdot, out = evaluate(body, [theta, omega], [tau])
        J = 7 * 1.3 * 0.7**2 / 8
        assert xdot[0] == omega
        assert xdot[1] == pytest.approx((-1.3 * 9.81 * 0.7 / 2 * math.sin(theta) + tau) / J,
                                        rel=1e-13, abs=1e-13)
        assert out["E"] == pytest.approx(J * omega**2 / 2 + 1.3 * 9.81 * 0.35 * (1 - math.cos(theta)),
                                         rel=1e-13, abs=1e-14)


def test_arbitrary_body_equilibrium_found_by_minimising_potential():
    body, I_cm, n, r = arbitrary_body()
    m, g = 1.7, 9.81

    def V(theta):
        return m * g * (Rotation.from_rotvec(theta * n).apply(r))[2]

    grid = np.linspace(-math.pi, math.pi, 721)
    start = grid[np.argmin([V(t) for t in grid])]
    best = minimize_scalar(V, bounds=(start - 0.02, start + 0.02), method="bounded",
                           options={"xatol": 1e-12})
    theta_eq = body.equilibrium_angle()
    assert abs(theta_eq - best.x) < 1e-6
    assert theta_eq != pytest.approx(0.0, abs=1e-3)  # the reference pose is not an equilibrium
    h = 1e-4
    stiffness = (V(theta_eq + h) - 2 * V(theta_eq) + V(theta_eq - h)) / h**2
    J_n = n @ I_cm @ n + m * np.linalg.norm(np.cross(n, r)) ** 2
    assert body.small_oscillation_frequency() == pytest.approx(math.sqrt(stiffness / J_n), rel=1e-6)


def test_frequency_does_not_depend_on_the_chosen_reference_pose():
    """Describing the same body turned by beta about n moves theta_eq by -beta, nothing else."""
    body, I_cm, n, r = arbitrary_body(seed=5)
    beta = 0.9
    Rb = Rotation.from_rotvec(beta * n).as_matrix()
    I2, r2 = Rb @ I_cm @ Rb.T, Rb @ r
    turned = RigidBodyOnAxle(**{**body.values, "I_xx": I2[0, 0], "I_yy": I2[1, 1], "I_zz": I2[2, 2],
                                "I_xy": I2[0, 1], "I_xz": I2[0, 2], "I_yz": I2[1, 2],
                                "r_x": r2[0], "r_y": r2[1], "r_z": r2[2]})
    shift = math.remainder(turned.equilibrium_angle() - body.equilibrium_angle() + beta, 2 * math.pi)
    assert abs(shift) < 1e-12
    assert turned.small_oscillation_frequency() == pytest.approx(body.small_oscillation_frequency(),
                                                                 rel=1e-12)


@pytest.mark.parametrize("theta, omega, tau", [(0.3, 1.2, 0.0), (-2.0, -0.7, 2.5), (2.8, 4.0, -1.0)])
def test_equation_of_motion_and_reactions_satisfy_newton_euler(theta, omega, tau):
    body, *_ = arbitrary_body(c=0.2)
    m, g, *_ = rigid_body(body)
    xdot, out = evaluate(body, [theta, omega], [tau])
    alpha = xdot[1]
    r, a_G, dH, gravity_moment, J_n = newton_euler(body, theta, omega, alpha)
    n = rigid_body(body)[4]
    # moment balance about P along n: bearings carry no moment along n but friction
    assert n @ dH == pytest.approx(n @ gravity_moment + tau - 0.2 * omega, rel=1e-12, abs=1e-12)
    assert out["axle.a"] == alpha and out["axle.phi"] == theta
    np.testing.assert_allclose([out["G_x"], out["G_y"], out["G_z"]], r, rtol=0, atol=1e-14)
    reaction = np.array([out["R_x"], out["R_y"], out["R_z"]])
    np.testing.assert_allclose(reaction - m * g * K, m * a_G, rtol=0, atol=1e-12)
    moment = np.array([out["M_x"], out["M_y"], out["M_z"]])
    expected = dH - gravity_moment
    np.testing.assert_allclose(moment, expected - (n @ expected) * n, rtol=0, atol=1e-12)
    assert abs(moment @ n) < 1e-12


def test_inverse_profile_returns_the_torque_the_motion_needs():
    body = disk(m=2.0, R=0.5, c=0.3, profile="driven_by_motion")
    J = 7 * 2.0 * 0.25 / 8
    for phi, w, a in ((0.0, 0.0, 0.0), (1.2, 0.5, -3.0), (-2.5, -1.0, 4.0)):
        xdot, out = evaluate(body, [0.0, 0.0], [phi, w, a])
        assert list(xdot) == [w, a]  # the states integrate the prescribed motion
        expected = J * a + 2.0 * 9.81 * 0.25 * math.sin(phi) + 0.3 * w
        assert out["axle.tau"] == pytest.approx(expected, rel=1e-13, abs=1e-13)


def test_coulomb_bearing_modes():
    body = disk(bearing_friction="coulomb", tau_c=0.5)
    J, k = 7 / 8, 9.81 / 2
    theta, tau = 0.4, 0.3
    xdot, out = evaluate(body, [theta, 0.0], [tau], q=[0])
    assert xdot[1] == 0.0  # stuck: exactly no rotation
    assert out["tau_bearing"] == pytest.approx(k * math.sin(theta) - tau, rel=1e-14)
    for mode in (1, -1):
        xdot, out = evaluate(body, [theta, 0.7 * mode], [tau], q=[mode])
        assert xdot[1] == pytest.approx((-k * math.sin(theta) + tau - 0.5 * mode) / J, rel=1e-13)


@pytest.mark.parametrize("changes, message", [
    (dict(I_xx=-0.25), "positive definite"),
    (dict(I_xy=0.3), "positive definite"),
    (dict(I_zz=0.6), "triangle inequality"),
    (dict(n_y=0.8), "unit vector"),
    (dict(n_y=0.0, n_z=1.0), "vertical"),
    (dict(m=0.0), "m "),
])
def test_impossible_bodies_are_rejected_with_a_one_line_reason(changes, message):
    with pytest.raises(ComponentError) as err:
        RigidBodyOnAxle(name="body", **{**disk().values, **changes})
    assert "RigidBodyOnAxle 'body'" in str(err.value) and message in str(err.value)
    assert "\n" not in str(err.value)


def test_flat_disk_on_the_triangle_boundary_is_accepted_by_the_fmu_check():
    """A flat disk has I_x + I_y = I_z exactly; the runtime check must accept it, reject worse."""
    body = disk(m=3.0, R=0.37)
    model = flatten(body)
    check = model.functions()["check"]
    _, _, _, p = model.start_vectors()
    names = [v.name for v in model.parameters]
    strict = np.array([c.strict for c in model.constraints])

    def passes(values):
        g = np.array(check(0.0, [0.0, 0.0], [], [0.0], values)).ravel()
        return bool(np.all(np.where(strict, g > 0, g >= 0)))

    assert passes(p)
    too_flat = p.copy()
    too_flat[names.index("I_zz")] *= 1.01
    assert not passes(too_flat)
    not_unit = p.copy()
    not_unit[names.index("n_x")] = 1e-4
    assert not passes(not_unit)


def test_theta0_is_the_start_of_theta():
    assert disk(theta0=0.7).starts["theta"] == 0.7
