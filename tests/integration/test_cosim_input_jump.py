"""A co-simulated clutch released by an input that jumps at a communication point.

A constant torque tau0 drives inertiaIn (J_in), locked by a clutch (fn_max) to the
clutch's own inertia J; a step takes the normal force to 0 at T, while the clutch is
stuck. MSL's law then frees the clutch at T exactly: before, the pair accelerates as
one, w = tau0 t / (J_in + J), and the clutch carries J tau0 / (J_in + J) (within its
static limit peak mu cgeo fn_max); after, the clutch keeps w(T) and inertiaIn takes all
of tau0: w_in = w(T) + tau0 (t - T) / J_in. The step's time event lands on a
communication point, where the clutch (another FMU) sees fn = 0 with the loop between
the two inertias still solved for the locked pair: the master must let the clutch leave
its stick and the loop settle with the free clutch before stepping on, so that no row
shows a clutch that carries torque with no normal force, and the release is recorded at
T, in both masters.
"""
import numpy as np
import pytest

from fmpy import simulate_fmu

from assemblies import Assembly, export_fmu
from assemblies.engine.cosim import DEFAULT_SCHEME, cosimulate
from assemblies.masters.cosim import cosimulate as reference_cosimulate
from components.rotational.friction import Clutch
from components.rotational.rigid import Inertia
from components.sources.rotational import Torque
from components.sources.signals import Constant, Step

J_IN, J, TAU0, FN_MAX, MU, T, STOP = 1.0, 1.0, 2.0, 10.0, 0.5, 0.5, 1.0
TOL = 1e-8


def _assembly() -> Assembly:
    asm = Assembly("released_clutch")
    asm.add("motor", Constant(k=TAU0))
    asm.add("torque", Torque())
    asm.add("inertiaIn", Inertia(J=J_IN, w=0.0))
    asm.add("release", Step(height=-1.0, offset=1.0, startTime=T))
    asm.add("clutch", Clutch(J=J, w=0.0, fn_max=FN_MAX, **{"mu_pos[1,2]": MU}))
    asm.connect("motor.y", "torque.tau")
    asm.connect("torque.flange", "inertiaIn.flange_a")
    asm.connect("inertiaIn.flange_b", "clutch.flange_a")
    asm.connect("release.y", "clutch.f_normalized")
    return asm


@pytest.mark.parametrize("run", [cosimulate, reference_cosimulate], ids=["c", "fmpy"])
def test_a_locked_clutch_whose_normal_force_drops_at_a_communication_point_releases_there(run):
    assert J * TAU0 / (J_IN + J) < MU * FN_MAX  # stuck until T
    res = run(_assembly(), STOP, 0.01, TOL, record=["clutch.mode", "clutch.fn", "clutch.tau",
                                                    "clutch.w", "inertiaIn.w"],
              **DEFAULT_SCHEME)
    acc = 100 * max(TOL, DEFAULT_SCHEME["tol"])  # scene.coupling_accuracy's rule
    t = np.asarray(res["time"])
    mode, fn, tau = (np.asarray(res[c]) for c in ("clutch.mode", "clutch.fn", "clutch.tau"))
    # Coulomb: no row carries more than the static limit (0 without normal force)
    assert np.all(np.abs(tau) <= MU * fn + 1e-12), [(t[k], fn[k], tau[k]) for k in
                                                    np.nonzero(np.abs(tau) > MU * fn + 1e-12)[0]]
    # stuck before T, released (MSL's free mode: no normal force) from T on
    assert np.all(mode[t < T - 1e-9] == 0) and np.all(mode[t >= T - 1e-9] != 0)
    released = [te for te, q in zip(np.asarray(res.events["clutch"]["time"]),
                                    np.asarray(res.events["clutch"]["clutch.mode"])) if q != 0]
    assert released and abs(released[0] - T) < acc, released
    w_t = TAU0 * T / (J_IN + J)
    w_in = np.where(t < T, TAU0 * t / (J_IN + J), w_t + TAU0 * (t - T) / J_IN)
    w_out = np.where(t < T, TAU0 * t / (J_IN + J), w_t)
    assert np.abs(np.asarray(res["inertiaIn.w"]) - w_in).max() < acc * max(1.0, w_in.max())
    assert np.abs(np.asarray(res["clutch.w"]) - w_out).max() < acc


def test_an_assembly_fmu_releases_the_clutch_at_the_end_of_a_dostep(tmp_path):
    """Exported as one FMU and stepped by fmpy in doSteps of 0.01 s, the release falls on
    a doStep's end: the modes settle without passing it (each doStep ends where fmpy asked)
    and the rows after it show the free clutch, with the closed form's speeds."""
    path = export_fmu(_assembly(), tmp_path / "released.fmu", fmi=3,
                      outputs=["clutch.mode", "clutch.w", "inertiaIn.w"], stop_time=STOP,
                      step=0.01, tolerance=TOL)
    res = simulate_fmu(str(path), stop_time=STOP, output_interval=0.01)
    acc = 100 * max(TOL, DEFAULT_SCHEME["tol"])
    t, mode = res["time"], res["clutch.mode"]
    assert np.all(mode[t < T - 1e-9] == 0) and np.all(mode[t > T + 1e-9] != 0)
    w_t = TAU0 * T / (J_IN + J)
    w_in_end = w_t + TAU0 * (STOP - T) / J_IN
    assert abs(res["inertiaIn.w"][-1] - w_in_end) < acc * max(1.0, w_in_end)  # as above
    assert abs(res["clutch.w"][-1] - w_t) < acc
