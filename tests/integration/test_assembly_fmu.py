"""An assembly exported as one Co-Simulation FMU (assemblies/fmu_export.py): it validates,
fmpy runs it, and it gives what the assembly gives when run from Python, for FMI 2 and 3.

The exported FMU runs the engine's co-simulation master in its doStep on the same
description of the coupling, so its outputs equal the Python-side run with the same
settings to round-off (asserted to 1e-12 of each column's scale). Physics is asserted
against independent references where the assembly has one: a block pushed by the FMU's
own input, solved by hand; the foreign pythonfmu PI loop, which at fixed steps is
forward Euler on the loop exactly.
"""
import subprocess
import sys
import zipfile

import numpy as np
import pytest
from fmpy import simulate_fmu
from fmpy.validation import validate_fmu

from assemblies import Assembly, AssemblyError
from assemblies.engine import cosim as engine_cosim
from assemblies.engine.cosim import DEFAULT_SCHEME, cosimulate
from assemblies.experiment import FixedStepFallback
from assemblies.foreign import FMU
from assemblies import export_fmu
from assemblies.scenes import scene
from assemblies.scenes.speed_control import pi_speed_loop
from components import Force, MassWithFriction

from foreign_fmus import euler_pi_on_sliding_mass

FMI_VERSIONS = (2, 3)


def same_as(fmu_result, python_result, columns):
    for column in columns:
        a, b = fmu_result[column], python_result[column]
        assert len(a) == len(b), column
        scale = max(1.0, float(np.abs(b).max()))
        assert np.abs(a - b).max() <= 1e-12 * scale, column


@pytest.mark.parametrize("fmi", FMI_VERSIONS)
def test_friction_assembly_fmu_equals_the_run_from_python(tmp_path, fmi, monkeypatch):
    """two_block_belt: two friction blocks joined by a spring on a moving belt, the
    scene whose slip onsets the default co-simulation must place right. Its events are
    moved back inside doStep (a probe at each communication point finds an onset that
    crossed in the last internal step), so it matches the Python-side run exactly; the
    scene's own first-slip figure is checked on the FMU's output too. The exported master
    steps every member (its description carries no evaluated members: cosim.h
    time_function / linear_map are NULL there), so the Python-side run does too; with
    the belts taken from time it differs by their stepped travel's roundings (1.2e-10)."""
    sc = scene("two_block_belt")
    path = export_fmu(sc.build(), tmp_path / f"belt{fmi}.fmu", fmi=fmi, outputs=sc.record,
                      stop_time=sc.stop_time, step=sc.step, tolerance=sc.tolerance)
    assert validate_fmu(str(path)) == []
    names = zipfile.ZipFile(path).namelist()
    assert "resources/assembly.txt" in names
    assert any(n.startswith("resources/block1/binaries/") for n in names)  # members carried
    via_fmu = simulate_fmu(str(path), stop_time=sc.stop_time, output_interval=sc.step)
    monkeypatch.setattr(engine_cosim, "EVALUATE_MEMBERS", False)
    python = cosimulate(sc.build(), sc.stop_time, sc.step, sc.tolerance, record=sc.record,
                        **DEFAULT_SCHEME)
    same_as(via_fmu, python, sc.record)
    # the belt drags block 1 until its static limit: the slip is a mode change 0 -> 1
    mode = via_fmu["block1.mode"]
    assert mode[0] == 0 and np.any(mode != 0)


@pytest.mark.parametrize("fmi,mode", [(2, "cosim"), (3, "cosim"), (2, "me"), (3, "me")])
def test_the_fmu_input_pushes_a_block_as_the_closed_form_says(tmp_path, fmi, mode):
    """The assembly's unconnected input (force.f) is the FMU's input. Below the static
    limit mu_s m g the block stays stuck; from t = 1 a force F > mu_s m g slides it with
    a = (F - mu_k m g)/m, so s = a (t - 1)^2 / 2: asserted to 1e-8 (100 x the members'
    tolerance, as the scene figures state). In mode 'me' the new input value starts the
    next step with an event, so the slip begins exactly at t = 1 there too."""
    m, g, mu_k, mu_s, F = 2.0, 9.81, 0.3, 0.4, 12.0
    asm = Assembly("pushed_block")
    asm.add("force", Force())
    asm.add("block", MassWithFriction(m=m, g=g, mu_k=mu_k, mu_s=mu_s))
    asm.connect("force.flange", "block.flange_a")
    path = export_fmu(asm, tmp_path / f"pushed{fmi}{mode}.fmu", fmi=fmi, mode=mode,
                      outputs=["block.s", "block.mode"], stop_time=3.0, step=0.1, tolerance=1e-10)
    assert validate_fmu(str(path)) == []
    signal = np.array([(0.0, 0.5 * mu_s * m * g), (1.0, 0.5 * mu_s * m * g), (1.0, F), (3.0, F)],
                      dtype=[("time", float), ("force.f", float)])
    res = simulate_fmu(str(path), stop_time=3.0, output_interval=0.1, input=signal)
    t, s = res["time"], res["block.s"]
    a = (F - mu_k * m * g) / m
    expected = np.where(t < 1.0 - 1e-9, 0.0, 0.5 * a * (t - 1.0) ** 2)
    assert np.abs(s - expected).max() < 1e-8
    assert np.all(res["block.mode"][t < 1.0 - 1e-9] == 0) and np.all(res["block.mode"][t > 1.05] == 1)


@pytest.mark.parametrize("fmi", FMI_VERSIONS)
def test_an_fmu_with_a_foreign_member_is_forward_euler_on_the_pi_loop(tmp_path, fmi, pythonfmu_pi):
    """A foreign member (pythonfmu's FMI 2 CS PI controller, which cannot roll back)
    travels inside the assembly FMU; the export falls back to fixed steps, as a run does,
    and says so. At fixed steps with held inputs the loop is exactly forward Euler on
    (v, I): asserted to 1e-12 (round-off), and equal to the run from Python."""
    loop = dict(m=1.0, friction=0.3, v_ref=1.0, k=2.0, Ti=0.5)
    h, stop = 0.01, 5.0

    def build():
        return pi_speed_loop("pi_loop", FMU(pythonfmu_pi),
                             MassWithFriction(m=loop["m"], g=1.0, mu_k=0.3, mu_s=0.3))

    with pytest.warns(FixedStepFallback, match="cannot get and set its state"):
        path = export_fmu(build(), tmp_path / f"pi{fmi}.fmu", fmi=fmi,
                          outputs=["block.v_abs", "ctrl.f"], stop_time=stop, step=h,
                          extrapolation=0)
    assert validate_fmu(str(path)) == []
    assert any(n.startswith("resources/ctrl/") for n in zipfile.ZipFile(path).namelist())
    res = simulate_fmu(str(path), stop_time=stop, output_interval=h)
    v, f = euler_pi_on_sliding_mass(len(res["time"]) - 1, h, **loop)
    assert np.abs(res["block.v_abs"] - v).max() < 1e-12
    assert np.abs(res["ctrl.f"] - f).max() < 1e-12
    with pytest.warns(FixedStepFallback):
        python = cosimulate(build(), stop, h, 1e-8, record=["block.v_abs", "ctrl.f"],
                            adaptive=True, extrapolation=0)
    same_as(res, python, ["block.v_abs", "ctrl.f"])


@pytest.mark.parametrize("fmi", FMI_VERSIONS)
def test_speed_control_exported_runs_the_one_integrator_in_dostep(tmp_path, fmi, casadi_pi):
    """The speed_control loop with the CasADi FMI 3 ME controller: Model Exchange only, so
    the export runs the engine's integrator from one communication point to the next.
    Against the closed loop solved by hand (pi_on_sliding_mass) within 1e-8 at
    tolerance 1e-10, as the Python-side me run is held to; and against that run within
    2e-8 (both are within 1e-8 of the truth; the FMU's steps end at every communication
    point, the run's step freely, so they agree to the tolerance, not to the bit)."""
    from foreign_fmus import pi_on_sliding_mass
    from assemblies.engine.me import simulate_me
    loop = dict(m=1.0, friction=0.3, v_ref=1.0, k=2.0, Ti=0.5)

    def build():
        return pi_speed_loop("pi_loop", FMU(casadi_pi),
                             MassWithFriction(m=loop["m"], g=1.0, mu_k=0.3, mu_s=0.3))

    path = export_fmu(build(), tmp_path / f"pi{fmi}.fmu", fmi=fmi, outputs=["block.v_abs", "ctrl.f"],
                      stop_time=10.0, step=0.1, tolerance=1e-10)
    assert validate_fmu(str(path)) == []
    assert "mode me" in zipfile.ZipFile(path).read("resources/assembly.txt").decode()
    res = simulate_fmu(str(path), stop_time=10.0, output_interval=0.1)
    v, f = pi_on_sliding_mass(res["time"], **loop)
    assert np.abs(res["block.v_abs"] - v).max() < 1e-8
    assert np.abs(res["ctrl.f"] - f).max() < 1e-8
    python = simulate_me(build(), 10.0, 0.1, 1e-10, record=["block.v_abs", "ctrl.f"])
    assert np.abs(res["block.v_abs"] - python["block.v_abs"]).max() < 2e-8


@pytest.mark.parametrize("fmi", FMI_VERSIONS)
def test_model_exchange_members_make_a_model_exchange_fmu_too(tmp_path, fmi, casadi_pi):
    """Exported in mode 'me', the FMU offers Model Exchange as well: the members'
    continuous states are its states, their indicators its indicators, and an importer's
    event runs the engine's event iteration through the couplings. Run by fmpy's own
    Model Exchange loop (CVode at relative tolerance 1e-10): the PI loop against its
    closed form, and the friction belt against the Python-side me run, the friction modes
    equal at every output point. CVode's global error is not bounded by its tolerance;
    asserted 1e-6 (1e4 x the tolerance, the drift factor the scene figures state for
    long runs; measured 2.3e-9 and 1.4e-7)."""
    from foreign_fmus import pi_on_sliding_mass
    from assemblies.engine.me import simulate_me
    loop = dict(m=1.0, friction=0.3, v_ref=1.0, k=2.0, Ti=0.5)
    pi = pi_speed_loop("pi_loop", FMU(casadi_pi), MassWithFriction(m=1.0, g=1.0, mu_k=0.3, mu_s=0.3))
    path = export_fmu(pi, tmp_path / f"pi_me{fmi}.fmu", fmi=fmi, outputs=["block.v_abs", "ctrl.f"],
                      stop_time=10.0, step=0.1, tolerance=1e-10)
    assert validate_fmu(str(path)) == []
    res = simulate_fmu(str(path), fmi_type="ModelExchange", stop_time=10.0, output_interval=0.1,
                       relative_tolerance=1e-10, record_events=False)
    v, f = pi_on_sliding_mass(res["time"], **loop)
    assert np.abs(res["block.v_abs"] - v).max() < 1e-6
    assert np.abs(res["ctrl.f"] - f).max() < 1e-6

    sc = scene("two_block_belt")
    path = export_fmu(sc.build(), tmp_path / f"belt_me{fmi}.fmu", fmi=fmi, mode="me",
                      outputs=sc.record, stop_time=sc.stop_time, step=sc.step,
                      tolerance=sc.tolerance)
    assert validate_fmu(str(path)) == []
    res = simulate_fmu(str(path), fmi_type="ModelExchange", stop_time=sc.stop_time,
                       output_interval=sc.step, relative_tolerance=1e-10, record_events=False)
    python = simulate_me(sc.build(), sc.stop_time, sc.step, sc.tolerance, record=sc.record)
    assert np.array_equal(res["time"], python["time"])
    for column in ("block1.mode", "block2.mode"):
        assert np.array_equal(res[column], python[column])
    for column in ("block1.s", "block2.s", "coupling.f"):
        assert np.abs(res[column] - python[column]).max() < 1e-6


def test_a_co_simulated_assembly_refuses_model_exchange(tmp_path):
    """Its members are Co-Simulation FMUs: there are no states to hand an importer."""
    from fmpy import extract, read_model_description
    from fmpy.fmi2 import FMU2Model
    path = export_fmu(scene("stick_slip").build(), tmp_path / "s.fmu", fmi=2)
    md = read_model_description(str(path))
    assert md.modelExchange is None
    model = FMU2Model(guid=md.guid, unzipDirectory=extract(str(path)),
                      modelIdentifier=md.coSimulation.modelIdentifier, instanceName="asm")
    with pytest.raises(Exception, match="Failed to instantiate"):
        model.instantiate()


def test_a_mode_that_cannot_run_a_member_is_refused_in_one_line(tmp_path, casadi_pi):
    asm = pi_speed_loop("me_loop", FMU(casadi_pi), MassWithFriction())
    with pytest.raises(AssemblyError, match=r"^export_fmu: assembly 'me_loop': mode 'cosim' steps "
                                            r"Co-Simulation FMUs, but instance 'ctrl' "
                                            r"\(PIController.fmu\) is ModelExchange only; run "
                                            r"it with mode 'me'$"):
        export_fmu(asm, tmp_path / "x.fmu", mode="cosim")
    assert not (tmp_path / "x.fmu").exists()


def test_unknown_outputs_and_settings_are_named(tmp_path):
    sc = scene("stick_slip")
    with pytest.raises(AssemblyError, match="cannot record 'block.nope'"):
        export_fmu(sc.build(), tmp_path / "x.fmu", outputs=["block.nope"])
    with pytest.raises(AssemblyError, match="unknown setting.*adaptiv"):
        export_fmu(sc.build(), tmp_path / "x.fmu", adaptiv=True)
    with pytest.raises(AssemblyError, match="fmi must be 2 or 3"):
        export_fmu(sc.build(), tmp_path / "x.fmu", fmi=4)


FMI_MISUSE = r'''
import sys, numpy as np
from fmpy import read_model_description, extract
from fmpy.fmi2 import FMU2Slave
from fmpy.fmi3 import FMU3Slave
path, fmi = sys.argv[1], int(sys.argv[2])
md = read_model_description(path)
cls = FMU2Slave if fmi == 2 else FMU3Slave
fmu = cls(guid=md.guid, unzipDirectory=extract(path), modelIdentifier=md.coSimulation.modelIdentifier,
          instanceName="asm")
fmu.instantiate()
outcomes = []
for call in (lambda: fmu.doStep(0.0, 0.1),                    # before initialization
             lambda: fmu.setReal([1], [1.0]) if fmi == 2 else fmu.setFloat64([1], [1.0]),
             lambda: fmu.getReal([999]) if fmi == 2 else fmu.getFloat64([999])):
    try:
        call()
        outcomes.append("ok")
    except Exception as exc:
        outcomes.append(type(exc).__name__)
if fmi == 2:
    fmu.setupExperiment(startTime=0.0)
fmu.enterInitializationMode()
fmu.exitInitializationMode()
fmu.doStep(0.0, 0.5)
try:
    fmu.doStep(0.2, 0.1)                                        # not where the FMU stands
    outcomes.append("ok")
except Exception as exc:
    outcomes.append(type(exc).__name__)
fmu.doStep(0.5, 0.5)
x = fmu.getReal([1])[0] if fmi == 2 else fmu.getFloat64([1])[0]
fmu.terminate()
fmu.freeInstance()
print("RESULT", " ".join(outcomes), repr(x))
'''


@pytest.mark.parametrize("fmi", FMI_VERSIONS)
def test_fmi_calls_in_the_wrong_order_get_errors_not_crashes(tmp_path, fmi):
    """doStep before initialization, setting an output, an unknown value reference and a
    doStep from a time the FMU is not at each return an error status (fmpy raises); the
    instance goes on and finishes the run. Run in a subprocess: a crash would show as a
    signal, not take the test runner with it."""
    sc = scene("stick_slip")
    path = export_fmu(sc.build(), tmp_path / f"s{fmi}.fmu", fmi=fmi, outputs=["block.x"],
                      stop_time=2.0, step=0.5)
    done = subprocess.run([sys.executable, "-c", FMI_MISUSE, str(path), str(fmi)],
                          capture_output=True, text=True, timeout=120)
    assert done.returncode == 0, done.stderr
    result = [line for line in done.stdout.splitlines() if line.startswith("RESULT")][-1].split()
    outcomes, x = result[1:-1], float(result[-1])
    assert outcomes == ["FMICallException"] * 4
    assert np.isfinite(x)


def test_cli_exports_a_scene_as_one_fmu(tmp_path, capsys):
    from assemblies.cli import main
    for fmi in FMI_VERSIONS:
        path = tmp_path / f"stick{fmi}.fmu"
        assert main(["export", "stick_slip", "--fmu", str(path), "--fmi", str(fmi)]) == 0
        assert validate_fmu(str(path)) == []
        res = simulate_fmu(str(path))  # its default experiment: the scene's
        sc = scene("stick_slip")
        assert res["time"][-1] == pytest.approx(sc.stop_time)
        assert set(sc.record) <= set(res.dtype.names)
