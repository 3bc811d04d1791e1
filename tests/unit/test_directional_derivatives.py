"""Directional and adjoint derivatives of real FMUs (FMI 2 and 3, Model Exchange), checked
two independent ways on random states and inputs: against central finite differences
of the FMU's own outputs, and against CasADi's symbolic Jacobian of the flat model."""
from ctypes import c_double

import casadi as ca
import numpy as np
import pytest
from fmpy import extract
from fmpy.fmi1 import FMICallException
from fmpy.fmi2 import FMU2Model
from fmpy.fmi3 import FMU3Model

from components import RigidBodyOnAxle, RollingCoin, SpringBlock
from components.dae import flatten
from fmus import build_fmu
from fmus.codegen import variable_table

# (component, mode value to hold or None, state starts consistent with that mode)
CASES = [
    (lambda: SpringBlock(profile="driven_on_moving_support"), -1, {"x": 0.3, "v": -0.4}),
    (lambda: SpringBlock(profile="driven_on_moving_support"), 0, {"x": 0.05, "v": 0.0}),
    (lambda: SpringBlock(profile="driven_on_moving_support"), 1, {"x": -0.2, "v": 0.5}),
    # eps = 1e-2: central differences with h = 1e-6 resolve tanh(3 v / eps) to 1e-6 only
    # where h is small against eps / 3 (the random points reach |v| ~ eps)
    (lambda: SpringBlock(profile="driven", friction="tanh", eps=1e-2), None,
     {"x": 0.1, "v": 0.002}),
    (lambda: RigidBodyOnAxle(profile="driven_by_torque", c=0.1), None, {"theta": 0.4, "omega": 1.2}),
    (lambda: RigidBodyOnAxle(profile="driven_by_motion"), None, {}),
    (lambda: RollingCoin(), None, {}),
]
IDS = ["block-back", "block-stuck", "block-fwd", "block-tanh", "axle-torque", "axle-motion", "coin"]


class Instance:
    """One Model Exchange instance in Continuous-Time Mode, driven by value references."""

    def __init__(self, component, version, mode, tmp_path):
        self.model = flatten(component)
        self.table = variable_table(self.model)
        path = build_fmu(component, tmp_path / "m.fmu", fmi_version=version)
        cls = FMU2Model if version == 2 else FMU3Model
        md_id = type(component).__name__
        self.fmu = cls(guid=_token(path, version), unzipDirectory=extract(str(path)),
                       modelIdentifier=md_id, instanceName="dd")
        self.version = version
        self.messages = []
        f = self.fmu
        if version == 2:
            # fmpy's default callbacks: an FMI 2 logger needs fmpy's native printf proxy,
            # which forwards to the logger registered last, process-wide; registering one
            # here would take over test_fmi2's. Successful calls log nothing anyway.
            f.instantiate()
        else:
            f.instantiate(logMessage=lambda env, status, category, message:
                          self.messages.append(message.decode()))
        if version == 2:
            f.setupExperiment()
            f.enterInitializationMode()
        else:
            f.enterInitializationMode()
        if mode is not None:
            mode_vr = self.vrs("MF_DISCRETE")[0]
            (f.setInteger if version == 2 else f.setInt32)([mode_vr], [mode])
        f.exitInitializationMode()
        if version == 2:
            f.newDiscreteStates()
        else:
            f.updateDiscreteStates()
        f.enterContinuousTimeMode()
        if mode is not None:  # the initial event iteration kept the mode asked for
            assert (f.getInteger if version == 2 else f.getInt32)([mode_vr])[0] == mode

    def vrs(self, *kinds, indicators=True):
        return [r.vr for r in self.table if r.kind in kinds and (indicators or not r.is_indicator)]

    def set_point(self, x, u):
        n = len(x)
        self.fmu.setContinuousStates((c_double * n)(*x), n)
        if len(u):
            self.fmu.setReal(self.vrs("MF_INPUT"), list(u)) if self.version == 2 else \
                self.fmu.setFloat64(self.vrs("MF_INPUT"), list(u))

    def get(self, vrs):
        return np.array(self.fmu.getReal(vrs) if self.version == 2 else self.fmu.getFloat64(vrs))

    def directional(self, unknowns, knowns, seed):
        return np.array(self.fmu.getDirectionalDerivative(unknowns, knowns, list(seed)))


def _token(path, version):
    from fmpy import read_model_description
    return read_model_description(str(path)).guid if version == 2 else \
        read_model_description(str(path)).instantiationToken


def _symbolic_jacobian(inst, x, q, u):
    """CasADi's Jacobian of the unknowns (der, computed, states) w.r.t. [x; u]."""
    m = inst.model
    unknown_exprs = []
    for r in inst.table:
        if r.kind == "MF_DERIVATIVE":
            unknown_exprs.append(m.xdot[r.index])
        elif r.kind == "MF_COMPUTED":
            unknown_exprs.append(ca.vertcat(m.y, m.z)[r.index])
        elif r.kind == "MF_STATE":
            unknown_exprs.append(m.x[r.index])
    jac = ca.Function("J", m.args, [ca.jacobian(ca.vertcat(*unknown_exprs), ca.vertcat(m.x, m.u))])
    p = [v.start for v in m.parameters]
    return np.array(jac(0.0, x, q, u, p))


@pytest.mark.parametrize("version", (2, 3))
@pytest.mark.parametrize("make, mode, starts", CASES, ids=IDS)
def test_directional_derivatives_match_finite_differences_and_casadi(make, mode, starts, version,
                                                                     tmp_path):
    rng = np.random.default_rng(5)
    component = make()
    for k, val in starts.items():
        component.set(k, val)
    inst = Instance(component, version, mode, tmp_path)
    unknowns = inst.vrs("MF_DERIVATIVE", "MF_COMPUTED", "MF_STATE")
    states, inputs = inst.vrs("MF_STATE"), inst.vrs("MF_INPUT")
    knowns = states + inputs
    x0 = np.array([v.start for v in inst.model.states])
    q = np.array([v.start for v in inst.model.modes])
    if mode is not None:
        q[0] = mode
    for trial in range(3):
        # random point near the start; a sliding block keeps the sign of its velocity
        x = x0 + 0.05 * rng.standard_normal(len(x0)) * np.maximum(1.0, np.abs(x0))
        if mode is not None:
            x[1] = 0.0 if mode == 0 else mode * abs(x[1]) + 0.1 * mode
        u = rng.standard_normal(len(inputs))
        inst.set_point(x, u)

        # full Jacobian, column by column with unit seeds
        J = np.column_stack([inst.directional(unknowns, knowns, np.eye(len(knowns))[j])
                             for j in range(len(knowns))])
        # (1) CasADi's symbolic Jacobian of the same flat model
        J_ref = _symbolic_jacobian(inst, x, q, u)
        np.testing.assert_allclose(J, J_ref, rtol=1e-12, atol=1e-12)

        # (2) central differences of the FMU's own values
        for j, vr in enumerate(knowns):
            h = 1e-6 * max(1.0, abs((list(x) + list(u))[j]))
            values = []
            for sign in (1, -1):
                xp, up = x.copy(), u.copy()
                if j < len(states):
                    xp[j] += sign * h
                else:
                    up[j - len(states)] += sign * h
                inst.set_point(xp, up)
                values.append(inst.get(unknowns))
            fd = (values[0] - values[1]) / (2 * h)
            assert np.all(np.abs(fd - J[:, j]) <= 1e-6 * np.maximum(1.0, np.abs(J[:, j]))), \
                (vr, fd, J[:, j])
        inst.set_point(x, u)

        # a random seed over all knowns is J s; FMI 3's adjoint is J^T w
        s = rng.standard_normal(len(knowns))
        np.testing.assert_allclose(inst.directional(unknowns, knowns, s), J @ s,
                                   rtol=1e-12, atol=1e-12)
        if version == 3:
            w = rng.standard_normal(len(unknowns))
            # fmpy's default nSensitivity is len(unknowns); the standard's is one per known
            adj = np.array(inst.fmu.getAdjointDerivative(unknowns, knowns, list(w),
                                                         nSensitivity=len(knowns)))
            np.testing.assert_allclose(adj, J.T @ w, rtol=1e-12, atol=1e-12)
    inst.fmu.terminate()
    inst.fmu.freeInstance()


def test_bad_knowns_and_unknowns_are_refused_with_a_log(tmp_path):
    """Through FMI 3, whose logger takes the message as is. FMI 2 reaches the same
    runtime function (its adapter only passes the arguments on), but its variadic logger
    needs fmpy's process-wide native proxy, which other tests own."""
    component = SpringBlock(profile="driven")
    inst = Instance(component, 3, None, tmp_path)
    param = inst.vrs("MF_PARAMETER")[0]
    der, state = inst.vrs("MF_DERIVATIVE")[0], inst.vrs("MF_STATE")[0]
    mode = inst.vrs("MF_DISCRETE")[0]
    for unknowns, knowns in [([der], [param]),       # a parameter is not a known here
                             ([param], [state]),     # nor an unknown
                             ([der], [mode]),        # an Int32 mode is neither
                             ([der], [10_000])]:     # no such value reference
        with pytest.raises(FMICallException):
            inst.directional(unknowns, knowns, [1.0])
    log = "\n".join(inst.messages)
    fn = "fmi3GetDirectionalDerivative"
    assert f"{fn}: known 'm' (value reference {param}) is not a continuous state or an input" \
        in log
    assert f"{fn}: unknown 'm' (value reference {param}) is not a state derivative" in log
    assert "has type" in log and "unknown value reference 10000" in log
    with pytest.raises(FMICallException):  # one seed per known
        inst.directional([der], [state], [1.0, 2.0])
    assert "nSeed (2) must equal the number of knowns (1)" in "\n".join(inst.messages)
    # the instance is unharmed: der(x) = v
    assert inst.directional([der], [inst.vrs("MF_STATE")[1]], [1.0])[0] == 1.0
