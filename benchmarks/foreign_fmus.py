"""FMUs other tools made, obtained from PyPI by the ordinary client, and the ones built here
with other tools' exporters.

Every wheel is fetched with ``pip download --no-deps`` pinned by version and checked against
its sha256 (nothing is installed into the environment): an FMU shipped inside a wheel is
extracted from it; an exporter's wheel (pure Python) is unpacked into a cache folder that a
child process puts on its ``PYTHONPATH`` to build an FMU. Everything lands in
``$MECHFMU_CACHE/foreign/`` once per machine; a second call costs a hash of the file.

What each source gives (Linux x86_64 binaries needing only libc/libm, or the Python of the
process that loads them):

- gemseo-fmu 3.1.1: FMI 2.0 ME+CS FMUs exported by OpenModelica 1.19-1.21 and an FMI 3.0 CS
  FMU by PythonFMU3 0.2.2 (arrays, Int64, Boolean, String and Enumeration variables);
- pythonfmu3 0.3.4: the FMI 3.0 exporter of Python classes (CS and ME) - built here;
- fmu-manipulation-toolbox 2.0 and fmpy's container_fmu: FMU containers (FMI 2.0 and 3.0 CS;
  fmpy's FMI 3.0 only) run by their own C runtimes around an embedded FMU - built here;
- pythonfmu (FMI 2.0 CS) and CasADi's DaeBuilder.export_fmu (FMI 3.0 ME): the PI controllers
  of :mod:`assemblies.scenes.pi_controller`.
"""
from __future__ import annotations

import hashlib
import os
import subprocess
import sys
import tempfile
import zipfile
from pathlib import Path

from assemblies.scenes.pi_controller import _built

# wheel -> sha256 of the wheel file as PyPI serves it
WHEELS = {
    "gemseo-fmu==3.1.1": "940b0200fe13cd00cc2b0a318bc4f1c8ddc147357fe3fe7ef8e53ae6ace5728e",
    "pythonfmu3==0.3.4": "1723ec5937285de07121e1c4eb8e60efdd7b074063a6906a4133408a489ec1da",
    "fmu-manipulation-toolbox==2.0":
        "c9ace59e3e617942e84309e518ebb21243a7935ba5ac142666a435ff56ca4abf",
}
GEMSEO_FMU = "gemseo-fmu==3.1.1"
GEMSEO_FOLDER = "gemseo_fmu/problems/fmu_files/linux"
# FMUs of the gemseo-fmu wheel -> sha256 (the references and tests are written for these)
GEMSEO_FMUS = {
    "Mass_Damper.fmu": "319a1417576bc63ca148e688dd25cc1e834e0c112172405fc0f18132073f136e",
    "MassSpringSystem.fmu": "7c065b50a75b24dc58e14c86c63505700009b1f515172558eb21379e1755dd1f",
    "ramp.fmu": "9879b148929a6e353857a4a8816ffa20fd3ba970e96ef2117c1d1facf01ab663",
    "add.fmu": "c6288f0f2474891cf932f49b0213326eedffc0456d7e9766037e7c0f040d7c1a",
    "FMU3Model.fmu": "ba076f516e57fa90a795c403edfc0d6cfd46a764ed8458507fff741c2ab55a9b",
}


def _folder(*parts: str) -> Path:
    from fmus.build import cache_dir
    return cache_dir().joinpath("foreign", *parts)


def _sha256(path: Path) -> str:
    return hashlib.sha256(path.read_bytes()).hexdigest()


def wheel(spec: str, what: str | None = None) -> Path:
    """The pinned wheel `spec` (a key of :data:`WHEELS`), downloaded once. Raises
    RuntimeError with one line (naming `what` the wheel is fetched for) if PyPI cannot be
    reached or the file differs."""
    digest = WHEELS[spec]
    folder = _folder("wheels")
    stem = spec.split("==")[0].replace("-", "_")
    for found in folder.glob(f"{stem}-*.whl"):
        if _sha256(found) == digest:
            return found
    folder.mkdir(parents=True, exist_ok=True)
    with tempfile.TemporaryDirectory(dir=folder) as work:
        done = subprocess.run([sys.executable, "-m", "pip", "download", "--no-deps",
                               "--disable-pip-version-check", "-q", "--retries", "2",
                               spec, "-d", work], capture_output=True, text=True)
        wheels = list(Path(work).glob(f"{stem}-*.whl"))
        if done.returncode != 0 or not wheels:
            why = (done.stderr.strip().splitlines() or ["no wheel downloaded"])[-1]
            raise RuntimeError(f"cannot download {spec} from PyPI"
                               f"{f' (it ships {what})' if what else ''}: {why}")
        got = _sha256(wheels[0])
        if got != digest:
            raise RuntimeError(f"{wheels[0].name} is not the wheel pinned here "
                               f"(sha256 {got}, expected {digest})")
        target = folder / wheels[0].name
        os.replace(wheels[0], target)  # atomic: a half-written wheel is never seen
    return target


def wheel_member(spec: str, member: str, digest: str, what: str | None = None) -> Path:
    """File `member` of the pinned wheel `spec`, extracted once into
    ``foreign/<name>-<version>/`` and checked against `digest` (its sha256); `what` names
    it in the error line."""
    name = Path(member).name
    folder = _folder(spec.replace("==", "-"))
    target = folder / name
    if target.exists() and _sha256(target) == digest:
        return target
    whl = wheel(spec, what or name)
    with zipfile.ZipFile(whl) as zf:
        if member not in zf.namelist():
            raise RuntimeError(f"{whl.name} has no {member}")
        data = zf.read(member)
    got = hashlib.sha256(data).hexdigest()
    if got != digest:
        raise RuntimeError(f"{member} in {whl.name} is not the file pinned here "
                           f"(sha256 {got}, expected {digest})")
    folder.mkdir(parents=True, exist_ok=True)
    with tempfile.TemporaryDirectory(dir=folder) as work:
        (Path(work) / name).write_bytes(data)
        os.replace(Path(work) / name, target)
    return target


def wheel_site(spec: str) -> Path:
    """The pinned wheel `spec` unpacked (a folder for a child process's PYTHONPATH: the
    exporter runs from it without being installed)."""
    folder = _folder("site", spec.replace("==", "-"))
    if (folder / ".complete").exists():
        return folder
    whl = wheel(spec)
    folder.parent.mkdir(parents=True, exist_ok=True)
    with tempfile.TemporaryDirectory(dir=folder.parent) as work:
        with zipfile.ZipFile(whl) as zf:
            zf.extractall(work)
        (Path(work) / ".complete").write_text(whl.name)
        if not folder.exists():
            os.replace(work, folder)
            os.mkdir(work)  # for TemporaryDirectory's cleanup
    return folder


def gemseo_fmu(name: str) -> Path:
    """An FMU of the gemseo-fmu wheel (OpenModelica's, or PythonFMU3's FMU3Model)."""
    tool = "PythonFMU3" if name == "FMU3Model.fmu" else "OpenModelica"
    return wheel_member(GEMSEO_FMU, f"{GEMSEO_FOLDER}/{name}", GEMSEO_FMUS[name],
                        f"the {tool} FMU {name}")


def _run_tool(spec: str, args: list[str], work: Path, what: str) -> None:
    """`python args` in `work` with the exporter `spec` importable; one line if it fails."""
    env = {**os.environ, "PYTHONPATH": os.pathsep.join(
        [str(wheel_site(spec)), os.environ.get("PYTHONPATH", "")])}
    done = subprocess.run([sys.executable, *args], cwd=work, env=env, capture_output=True,
                          text=True, timeout=300)
    if done.returncode != 0:
        why = ((done.stderr or done.stdout).strip().splitlines() or ["no message"])[-1]
        raise RuntimeError(f"{spec} could not build {what}: {why}")


# --- PythonFMU3: FMI 3.0 from Python classes (the FMU runs in the loading process's Python) -
LAG3 = '''
import math
from pythonfmu3 import Fmi3Causality, Fmi3Slave, Fmi3Variability, Float64


class Lag3(Fmi3Slave):
    """First-order lag x' = (u - x) / T, stepped exactly for the input held over a step:
    the result does not depend on the communication step."""

    def __init__(self, **kwargs):
        super().__init__(**kwargs)
        self.time, self.u, self.x, self.T = 0.0, 1.0, 0.0, 0.5
        self.register_variable(Float64("time", causality=Fmi3Causality.independent))
        self.register_variable(Float64("u", causality=Fmi3Causality.input, start=1.0))
        self.register_variable(Float64("T", causality=Fmi3Causality.parameter,
                                       variability=Fmi3Variability.tunable))
        self.register_variable(Float64("x", causality=Fmi3Causality.output))

    def do_step(self, current_time, step_size):
        self.x = self.u + (self.x - self.u) * math.exp(-step_size / self.T)
        return True
'''

OSCILLATOR3 = '''
from pythonfmu3 import (Fmi3Causality, Fmi3Initial, Fmi3SlaveBase, Fmi3Variability, Float64,
                        ModelExchange)


class Oscillator3(Fmi3SlaveBase, ModelExchange):
    """Damped oscillator x'' + 2 zeta w x' + w^2 x = 0 as FMI 3.0 Model Exchange."""

    def __init__(self, **kwargs):
        super().__init__(**kwargs)
        self.time, self.x, self.v, self.w, self.zeta = 0.0, 1.0, 0.0, 3.0, 0.1
        self.der_x, self.der_v = 0.0, 0.0
        continuous = Fmi3Variability.continuous
        self.register_variable(Float64("time", causality=Fmi3Causality.independent,
                                       variability=continuous))
        self.register_variable(Float64("x", causality=Fmi3Causality.output, start=1.0,
                                       variability=continuous, initial=Fmi3Initial.exact))
        self.register_variable(Float64("der_x", causality=Fmi3Causality.local,
                                       variability=continuous, derivative=1))
        self.register_variable(Float64("v", causality=Fmi3Causality.output, start=0.0,
                                       variability=continuous, initial=Fmi3Initial.exact))
        self.register_variable(Float64("der_v", causality=Fmi3Causality.local,
                                       variability=continuous, derivative=3))
        for name in ("w", "zeta"):
            self.register_variable(Float64(name, causality=Fmi3Causality.parameter,
                                           variability=Fmi3Variability.fixed))

    def get_continuous_state_derivatives(self):
        self.der_x = self.v
        self.der_v = -2.0 * self.zeta * self.w * self.v - self.w ** 2 * self.x
        return [self.der_x, self.der_v]
'''

BOUNCING_BALL3 = '''
from pythonfmu3 import (Fmi3Causality, Fmi3Initial, Fmi3SlaveBase, Fmi3Variability, Float64,
                        ModelExchange)
from pythonfmu3.modelexchange import Fmi3UpdateDiscreteStatesResult


class BouncingBall3(Fmi3SlaveBase, ModelExchange):
    """A ball dropped from h = 1 m (g = 9.81 m/s2) that bounces with restitution e = 0.8:
    a state event (indicator h) that resets v to -e v."""

    def __init__(self, **kwargs):
        super().__init__(**kwargs)
        self.time, self.h, self.v, self.g, self.e = 0.0, 1.0, 0.0, 9.81, 0.8
        self.der_h, self.der_v = 0.0, 0.0
        continuous = Fmi3Variability.continuous
        self.register_variable(Float64("time", causality=Fmi3Causality.independent,
                                       variability=continuous))
        self.register_variable(Float64("h", causality=Fmi3Causality.output, start=1.0,
                                       variability=continuous, initial=Fmi3Initial.exact),
                               has_event_indicator=True)
        self.register_variable(Float64("der_h", causality=Fmi3Causality.local,
                                       variability=continuous, derivative=1))
        self.register_variable(Float64("v", causality=Fmi3Causality.output, start=0.0,
                                       variability=continuous, initial=Fmi3Initial.exact))
        self.register_variable(Float64("der_v", causality=Fmi3Causality.local,
                                       variability=continuous, derivative=3))
        for name in ("g", "e"):
            self.register_variable(Float64(name, causality=Fmi3Causality.parameter,
                                           variability=Fmi3Variability.fixed))

    def get_continuous_state_derivatives(self):
        self.der_h, self.der_v = self.v, -self.g
        return [self.der_h, self.der_v]

    def get_event_indicators(self):
        return [self.h]

    def update_discrete_states(self):
        result = Fmi3UpdateDiscreteStatesResult()
        if self.h <= 0.0 and self.v < 0.0:
            self.h, self.v = 0.0, -self.e * self.v
            result.valuesOfContinuousStatesChanged = True
        return result
'''

DROP3 = '''
from pythonfmu3 import (Fmi3Causality, Fmi3Initial, Fmi3SlaveBase, Fmi3Variability, Float64,
                        ModelExchange)
from pythonfmu3.modelexchange import Fmi3UpdateDiscreteStatesResult


class Drop3(Fmi3SlaveBase, ModelExchange):
    """A ball dropped from h = 2 m (g = 9.81 m/s2) whose model ends the run when it reaches
    the ground: terminateSimulation at the event of the indicator h."""

    def __init__(self, **kwargs):
        super().__init__(**kwargs)
        self.time, self.h, self.v, self.g = 0.0, 2.0, 0.0, 9.81
        self.der_h, self.der_v = 0.0, 0.0
        continuous = Fmi3Variability.continuous
        self.register_variable(Float64("time", causality=Fmi3Causality.independent,
                                       variability=continuous))
        self.register_variable(Float64("h", causality=Fmi3Causality.output, start=2.0,
                                       variability=continuous, initial=Fmi3Initial.exact),
                               has_event_indicator=True)
        self.register_variable(Float64("der_h", causality=Fmi3Causality.local,
                                       variability=continuous, derivative=1))
        self.register_variable(Float64("v", causality=Fmi3Causality.output, start=0.0,
                                       variability=continuous, initial=Fmi3Initial.exact))
        self.register_variable(Float64("der_v", causality=Fmi3Causality.local,
                                       variability=continuous, derivative=3))
        self.register_variable(Float64("g", causality=Fmi3Causality.parameter,
                                       variability=Fmi3Variability.fixed))

    def get_continuous_state_derivatives(self):
        self.der_h, self.der_v = self.v, -self.g
        return [self.der_h, self.der_v]

    def get_event_indicators(self):
        return [self.h]

    def update_discrete_states(self):
        return Fmi3UpdateDiscreteStatesResult(terminateSimulation=self.h <= 0.0)
'''

ROBERTSON3 = '''
from pythonfmu3 import (Fmi3Causality, Fmi3Initial, Fmi3SlaveBase, Fmi3Variability, Float64,
                        ModelExchange)


class Robertson3(Fmi3SlaveBase, ModelExchange):
    """Robertson's stiff chemical kinetics (rate constants 0.04, 1e4, 3e7) from (1, 0, 0)."""

    def __init__(self, **kwargs):
        super().__init__(**kwargs)
        self.time, self.y1, self.y2, self.y3 = 0.0, 1.0, 0.0, 0.0
        self.der_y1, self.der_y2, self.der_y3 = 0.0, 0.0, 0.0
        continuous = Fmi3Variability.continuous
        self.register_variable(Float64("time", causality=Fmi3Causality.independent,
                                       variability=continuous))
        for k, (name, start) in enumerate((("y1", 1.0), ("y2", 0.0), ("y3", 0.0))):
            # y2 (at most 3.6e-5) is local: the suite compares outputs relative to their size
            causality = Fmi3Causality.local if name == "y2" else Fmi3Causality.output
            self.register_variable(Float64(name, causality=causality, start=start,
                                           variability=continuous, initial=Fmi3Initial.exact))
            self.register_variable(Float64(f"der_{name}", causality=Fmi3Causality.local,
                                           variability=continuous, derivative=1 + 2 * k))

    def get_continuous_state_derivatives(self):
        r1, r2, r3 = 0.04 * self.y1, 1e4 * self.y2 * self.y3, 3e7 * self.y2 ** 2
        self.der_y1, self.der_y2, self.der_y3 = -r1 + r2, r1 - r2 - r3, r3
        return [self.der_y1, self.der_y2, self.der_y3]
'''

PYTHONFMU3_SCRIPTS = {"Lag3": LAG3, "Oscillator3": OSCILLATOR3, "BouncingBall3": BOUNCING_BALL3,
                      "Drop3": DROP3, "Robertson3": ROBERTSON3}
PYTHONFMU3 = "pythonfmu3==0.3.4"


def pythonfmu3_fmu(name: str) -> Path:
    """`name` (a key of :data:`PYTHONFMU3_SCRIPTS`) built by pythonfmu3 (FMI 3.0)."""
    script = PYTHONFMU3_SCRIPTS[name]

    def make(work: Path):
        (work / f"{name}.py").write_text(script)
        _run_tool(PYTHONFMU3, ["-m", "pythonfmu3", "build", "-f", f"{name}.py", "-d", "."],
                  work, f"{name}.fmu")

    return _built(PYTHONFMU3.replace("==", ""), script, f"{name}.fmu", make)


# --- FMU Manipulation Toolbox: a container FMU (its own C runtime) around an embedded one ---
FMU_TOOLBOX = "fmu-manipulation-toolbox==2.0"
CONTAINER_SCRIPT = '''
import sys
from pathlib import Path
from fmu_manipulation_toolbox.assembly import AssemblyNode
node = AssemblyNode(sys.argv[1], step_size=float(sys.argv[3]), auto_parameter=True)
node.add_fmu(sys.argv[2])
node.make_fmu(Path("."), fmi_version=int(sys.argv[4]))
'''


def toolbox_container(inner: Path, fmi_version: int, step: float) -> Path:
    """A container FMU (FMI `fmi_version` CS, internal step `step`) holding `inner`, as
    fmu-manipulation-toolbox builds it: its inputs, outputs and parameters exposed."""
    name = f"Container{fmi_version}_{inner.stem}.fmu"
    key = f"{CONTAINER_SCRIPT}{_sha256(inner)} {fmi_version} {step!r}"

    def make(work: Path):
        (work / inner.name).write_bytes(inner.read_bytes())
        _run_tool(FMU_TOOLBOX, ["-c", CONTAINER_SCRIPT, name, inner.name, repr(step),
                                str(fmi_version)], work, name)

    return _built(FMU_TOOLBOX.replace("==", ""), key, name, make)


# --- fmpy's container FMU (FMI 3.0 CS; its own C runtime, fmpy/container_fmu/binaries) -----
def fmpy_container(inner: Path, step: float) -> Path:
    """A container FMU (FMI 3.0 CS, fixed internal step `step`) holding `inner` (a CS FMU),
    as ``fmpy.container_fmu`` builds it: the inner Float64 inputs, outputs and parameters
    exposed under their own names."""
    import uuid

    import fmpy
    from fmpy import read_model_description
    from fmpy.container_fmu import Configuration
    from fmpy.container_fmu.cli import create_container_fmu
    from fmpy.container_fmu.config import Component
    from fmpy.model_description import CoSimulation, ModelDescription, ModelVariable, Unknown

    name = f"FmpyContainer_{inner.stem}.fmu"

    def make(work: Path):
        imd = read_model_description(str(inner), validate=False)
        md = ModelDescription(fmiVersion="3.0", modelName=name[:-4],
                              instantiationToken="{%s}" % uuid.uuid5(uuid.NAMESPACE_URL, name),
                              generationTool=f"FMPy {fmpy.__version__} container_fmu")
        md.coSimulation = CoSimulation(modelIdentifier="container_fmu",
                                       fixedInternalStepSize=step)
        md.modelVariables.append(ModelVariable(name="time", type="Float64",
                                               causality="independent",
                                               variability="continuous"))
        component = Component(name=inner.stem, filename=inner, modelDescription=imd)
        mappings = {}
        for v in imd.modelVariables:
            if v.causality in ("input", "output", "parameter") and v.type in ("Real", "Float64"):
                exposed = ModelVariable(
                    name=v.name, type="Float64", causality=v.causality,
                    variability=v.variability,
                    initial=v.initial if v.causality == "parameter" else None,
                    start=None if v.causality == "output" else v.start)
                md.modelVariables.append(exposed)
                mappings[exposed] = [(component, v)]
        md.outputs = [Unknown(index=i + 1, variable=v) for i, v in enumerate(md.modelVariables)
                      if v.causality == "output"]
        md.initialUnknowns = list(md.outputs)
        (work / "unzipped").mkdir()  # create_container_fmu empties it first
        create_container_fmu(Configuration(parallelDoStep=False, modelDescription=md,
                                           components=[component], connections=[],
                                           variableMappings=mappings),
                             work / "unzipped", work / name)

    key = f"container {_sha256(inner)} {step!r}"
    return _built(f"fmpy{fmpy.__version__}", key, name, make)
