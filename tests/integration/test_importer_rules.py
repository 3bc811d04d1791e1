"""Our FMUs, components and assemblies, keep the rules an independent importer holds them
to (the Reference FMUs' fmusim, OMSimulator), checked here directly through the FMI calls:

* after every exit from Event Mode no event indicator is exactly 0: FMI 2.0 and 3.0,
  fmi2/fmi3GetEventIndicators (Model Exchange API, "Evaluation of Model Equations"):
  "The FMU must guarantee that at an event restart z_j != 0, for example, by shifting
  z_j with a small value". fmusim takes an exact 0 there for a root and stops
  ("root found at t = 8.000000000001");
* in FMI 3 Co-Simulation Step Mode fmi3Get{VariableType} reads every variable (FMI 3.0,
  Co-Simulation state machine, state Step Mode: fmi3Get{VariableType} is allowed with no
  list of variables, unlike Initialization Mode), event indicators included;
* a doStep past a stop time the importer defined is an Error (FMI 2.0 fmi2SetupExperiment,
  FMI 3.0 fmi3EnterInitializationMode: "if the environment tries to compute past stopTime
  the FMU has to return Error");
* an assembly FMU refuses a tolerance that is not in (0, 1] as a component FMU does;
* a component whose modelDescription says hasEventMode = false refuses eventModeUsed.
"""
import ctypes
import math

import pytest
from fmpy import extract, read_model_description, simulate_fmu
from fmpy.fmi1 import FMICallException
from fmpy.fmi2 import FMU2Model, FMU2Slave
from fmpy.fmi3 import FMU3Model, FMU3Slave

from assemblies import export_fmu
from assemblies.scenes import scene
from components import SpringBlock
from fmus import build_fmu

JOINED = ["two_block_belt", "beam_friction_damper", "conveyor", "moving_table", "axle_motor",
          "speed_control"]
# each scene's run long enough for its friction events (its first slips and re-sticks)
RUN = {"two_block_belt": 40.0, "beam_friction_damper": 2.0, "conveyor": 10.0,
       "moving_table": 10.0, "axle_motor": 5.0, "speed_control": 10.0}


def _open(path, kind, fmi, messages, **instantiate):
    """An instance through fmpy's low-level classes; kind: 'me' or 'cs'."""
    md = read_model_description(str(path))
    cls = {(2, "me"): FMU2Model, (2, "cs"): FMU2Slave, (3, "me"): FMU3Model,
           (3, "cs"): FMU3Slave}[fmi, kind]
    ident = (md.modelExchange if kind == "me" else md.coSimulation).modelIdentifier
    fmu = cls(guid=md.guid, unzipDirectory=extract(str(path)), modelIdentifier=ident,
              instanceName="importer")
    if fmi == 2:  # fmpy's FMI 2 logger is its own: messages are checked through FMI 3
        fmu.instantiate(**instantiate)
    else:
        fmu.instantiate(logMessage=lambda env, status, category, message:
                        messages.append(message.decode()), **instantiate)
    return md, fmu


def _checking(cls, n_z, restarts):
    """`cls` with every exit from Event Mode recorded: the indicators just after it.
    (fmpy finds the C functions by the class name's prefix: FMU2/FMU3 stays in front.)"""
    def enterContinuousTimeMode(self):
        status = cls.enterContinuousTimeMode(self)
        z = (ctypes.c_double * max(n_z, 1))()
        self.getEventIndicators(z, n_z)
        restarts.append(list(z)[:n_z])
        return status
    return type(cls.__name__ + "Checking", (cls,),
                {"enterContinuousTimeMode": enterContinuousTimeMode})


def _zeros(restarts):
    return [(k, z) for k, z in enumerate(restarts) if any(v == 0.0 for v in z)]


@pytest.fixture(scope="module")
def exported(tmp_path_factory):
    """Each joined scene's assembly FMU, by (scene, fmi, mode), exported once."""
    root = tmp_path_factory.mktemp("assemblies")
    cache = {}

    def get(name, fmi, mode):
        key = (name, fmi, mode)
        if key not in cache:
            sc = scene(name)
            cache[key] = export_fmu(sc.build(), root / f"{name}_{fmi}_{mode}.fmu", fmi=fmi,
                                    mode=mode, stop_time=sc.stop_time, step=sc.step,
                                    tolerance=sc.tolerance)
        return cache[key]
    return get


# --- no event indicator exactly 0 after Event Mode: Model Exchange -----------------

@pytest.mark.parametrize("fmi", [2, 3])
@pytest.mark.parametrize("name", JOINED)
def test_assembly_indicators_are_never_zero_after_event_mode(exported, name, fmi):
    """fmpy's CVode importer drives the assembly FMU (mode 'me') through its friction
    events; after every fmiEnterContinuousTimeMode (the initial event and each state
    event) no indicator is exactly 0."""
    path = exported(name, fmi, "me")
    md = read_model_description(str(path))
    n_z = md.numberOfEventIndicators
    assert n_z > 0
    restarts = []
    cls = _checking(FMU2Model if fmi == 2 else FMU3Model, n_z, restarts)
    fmu = cls(guid=md.guid, unzipDirectory=extract(str(path)),
              modelIdentifier=md.modelExchange.modelIdentifier, instanceName="asm")
    fmu.instantiate()
    try:
        sc = scene(name)
        simulate_fmu(str(path), fmi_type="ModelExchange", fmu_instance=fmu,
                     stop_time=RUN[name], output_interval=sc.step,
                     relative_tolerance=sc.tolerance, model_description=md)
    finally:
        fmu.freeInstance()
    # speed_control's block breaks free from rest at t = 0 and is then held sliding: its
    # one restart is the initial one, where its sliding indicator (mode * v) starts at 0
    least = 1 if name == "speed_control" else 3
    assert len(restarts) >= least, f"{name}: the run went through {len(restarts)} events only"
    zeros = _zeros(restarts)
    assert not zeros, f"{name}: indicators exactly 0 after Event Mode: {zeros[:3]}"


def _euler_run(path, fmi, stop, dt, drive):
    """fmusim's loop, in small: fixed Euler steps, an event where an indicator's domain
    (z > 0 or not) changed over the step, handled at the step's end; the indicators
    after each exit from Event Mode are returned with the event times."""
    messages = []
    md, fmu = _open(path, "me", fmi, messages)
    vr = {v.name: v.valueReference for v in md.modelVariables}
    n_x, n_z = md.numberOfContinuousStates, md.numberOfEventIndicators
    x, dx = (ctypes.c_double * n_x)(), (ctypes.c_double * n_x)()
    z = (ctypes.c_double * n_z)()
    set_real = fmu.setReal if fmi == 2 else fmu.setFloat64

    def inputs(t):
        values = drive(t)
        set_real([vr[n] for n in values], list(values.values()))

    def settle():
        while True:
            if fmi == 2:
                more = fmu.newDiscreteStates()[0]
            else:
                more = fmu.updateDiscreteStates()[0]
            if not more:
                break
        fmu.enterContinuousTimeMode()
        fmu.getEventIndicators(z, n_z)
        return list(z)

    if fmi == 2:
        fmu.setupExperiment(startTime=0.0)
        fmu.enterInitializationMode()
    else:
        fmu.enterInitializationMode(startTime=0.0)
    inputs(0.0)
    fmu.exitInitializationMode()
    restarts = [(0.0, settle())]
    z_before = restarts[0][1]
    t = 0.0
    for k in range(1, int(round(stop / dt)) + 1):
        fmu.getContinuousStates(x, n_x)
        (fmu.getDerivatives if fmi == 2 else fmu.getContinuousStateDerivatives)(dx, n_x)
        t = k * dt
        fmu.setTime(t)
        fmu.setContinuousStates((ctypes.c_double * n_x)(*[a + dt * b for a, b in zip(x, dx)]),
                                n_x)
        inputs(t)
        if fmi == 2:
            fmu.completedIntegratorStep()
        fmu.getEventIndicators(z, n_z)
        if any((a > 0) != (b > 0) for a, b in zip(z_before, z)):
            fmu.enterEventMode()
            restarts.append((t, settle()))
            z_before = restarts[-1][1]
        else:
            z_before = list(z)
    fmu.terminate()
    fmu.freeInstance()
    return restarts


@pytest.mark.parametrize("fmi", [2, 3])
def test_a_component_restarts_off_zero_where_a_slip_begins(fmi):
    """Seed 9.2's block (Coulomb friction) pulled at 0.05 m/s: it breaks free at t = 8,
    where its velocity is exactly 0, so the sliding indicator (mode * v) is exactly 0 at
    the restart unless the FMU shifts it; it re-sticks at t = 12.07."""
    path = build_fmu(SpringBlock(m=1, k=1, g=1, mu_k=0.3, mu_s=0.4), fmi_version=fmi)
    restarts = _euler_run(path, fmi, stop=13.0, dt=1e-3,
                          drive=lambda t: {"flange_a.s": 0.05 * t, "flange_a.v": 0.05,
                                           "flange_a.a": 0.0})
    times = [t for t, _ in restarts[1:]]
    assert any(abs(t - 8.0) < 2e-3 for t in times), times  # the slip is among them
    assert any(abs(t - 12.069) < 2e-2 for t in times), times  # and the re-stick
    zeros = [(t, z) for t, z in restarts if 0.0 in z]
    assert not zeros, f"indicators exactly 0 after Event Mode: {zeros}"
    # the shift is on the side the slide goes: the sliding indicator stays positive
    slip = next(z for t, z in restarts if abs(t - 8.0) < 2e-3)
    assert slip[0] > 0.0 and abs(slip[0]) < 1e-90


def test_a_component_returning_early_at_its_slip_reads_its_indicators_off_zero():
    """Co-Simulation, FMI 3 early return: the same block's doStep stops at each event;
    the indicators read there as variables (after the FMU's own event iteration) are
    not 0, the slip at t = 8 (mode * v = 0 exactly) included."""
    path = build_fmu(SpringBlock(m=1, k=1, g=1, mu_k=0.3, mu_s=0.4), fmi_version=3)
    messages = []
    md, fmu = _open(path, "cs", 3, messages, earlyReturnAllowed=True)
    vr = {v.name: v.valueReference for v in md.modelVariables}
    indicators = [vr[n] for n in vr if n.startswith("event_indicator")]
    assert len(indicators) == 2
    fmu.enterInitializationMode(startTime=0.0, stopTime=13.0)
    fmu.exitInitializationMode()
    t, events = 0.0, []
    while t < 13.0 - 1e-12:
        fmu.setFloat64([vr["flange_a.s"], vr["flange_a.v"], vr["flange_a.a"]],
                       [0.05 * t, 0.05, 0.0])
        # 0.7 s steps: the slip falls inside one (at a communication point it would be
        # an input event, handled before the step)
        _, _, early, reached = fmu.doStep(t, min(0.7, 13.0 - t))
        t = reached
        if early:
            events.append((t, fmu.getFloat64(indicators)))
    fmu.freeInstance()
    assert any(abs(t - 8.0) < 1e-9 for t, _ in events), events
    assert all(0.0 not in z for _, z in events), events


# --- FMI 3 Step Mode: every variable reads -------------------------------------------

def _read_all(fmu, md):
    """Every variable of the description through its getter: the values, or raises."""
    floats = [v.valueReference for v in md.modelVariables if v.type in ("Float64", "Real")]
    ints = [v.valueReference for v in md.modelVariables if v.type in ("Int32", "Integer")]
    out = {}
    if md.fmiVersion == "2.0":
        out.update(zip(floats, fmu.getReal(floats)))
        out.update(zip(ints, fmu.getInteger(ints)))
    else:
        out.update(zip(floats, fmu.getFloat64(floats)))
        out.update(zip(ints, fmu.getInt32(ints)))
    return out


@pytest.mark.parametrize("fmi", [2, 3])
@pytest.mark.parametrize("name, mode", [(n, m) for n in JOINED for m in ("cosim", "me")
                                        # its PI controller is a Model Exchange FMU only
                                        if (n, m) != ("speed_control", "cosim")])
def test_every_variable_reads_in_step_mode(exported, name, fmi, mode):
    """fmusim records every variable after each doStep: each getter returns OK, and the
    event indicators an FMI 3 assembly of Model Exchange members names are never 0."""
    path = exported(name, fmi, mode)
    sc = scene(name)
    messages = []
    md, fmu = _open(path, "cs", fmi, messages)
    indicators = [v.valueReference for v in md.modelVariables if "event_indicator" in v.name]
    assert bool(indicators) == (fmi == 3 and mode == "me")
    stop = min(RUN[name], 20 * sc.step)
    if fmi == 2:
        fmu.setupExperiment(startTime=0.0, stopTime=stop)
        fmu.enterInitializationMode()
    else:
        fmu.enterInitializationMode(startTime=0.0, stopTime=stop)
    fmu.exitInitializationMode()
    t, n = 0.0, int(round(stop / sc.step))
    for k in range(n):
        fmu.doStep(t, (k + 1) * sc.step - t if k < n - 1 else stop - t)
        t = (k + 1) * sc.step if k < n - 1 else stop
        values = _read_all(fmu, md)
        assert all(values[vr] != 0.0 for vr in indicators), (t, messages[-1:])
    fmu.terminate()
    fmu.freeInstance()


# --- a defined stop time ----------------------------------------------------------------

def _fails(messages, call, *words):
    with pytest.raises(FMICallException):
        call()
    assert messages and all(w in messages[-1] for w in words), messages[-1:]


@pytest.mark.parametrize("fmi", [2, 3])
def test_a_component_refuses_to_step_past_the_stop_time(fmi):
    path = build_fmu(SpringBlock(), fmi_version=fmi)
    messages = []
    md, fmu = _open(path, "cs", fmi, messages)
    if fmi == 2:
        fmu.setupExperiment(startTime=0.0, stopTime=1.0)
        fmu.enterInitializationMode()
    else:
        fmu.enterInitializationMode(startTime=0.0, stopTime=1.0)
    fmu.exitInitializationMode()
    fmu.doStep(0.0, 0.3)
    # 0.3 + 0.7 rounds to just about 1: still the stop time
    fmu.doStep(0.3, 1.0 - 0.3)
    if fmi == 3:  # FMI 2's logger is fmpy's own; FMI 3's comes back here
        _fails(messages, lambda: fmu.doStep(1.0, 0.1), "past the stop time")
    else:
        with pytest.raises(FMICallException):
            fmu.doStep(1.0, 0.1)
    fmu.freeInstance()


@pytest.mark.parametrize("fmi", [2, 3])
def test_a_stop_time_before_the_start_is_refused(fmi):
    path = build_fmu(SpringBlock(), fmi_version=fmi)
    md, fmu = _open(path, "cs", fmi, [])
    with pytest.raises(FMICallException):
        if fmi == 2:
            fmu.setupExperiment(startTime=1.0, stopTime=0.5)
        else:
            fmu.enterInitializationMode(startTime=1.0, stopTime=0.5)
    fmu.freeInstance()


@pytest.mark.parametrize("mode", ["cosim", "me"])
def test_an_assembly_refuses_to_step_past_the_stop_time(exported, mode):
    path = exported("two_block_belt", 3, mode)
    messages = []
    md, fmu = _open(path, "cs", 3, messages)
    fmu.enterInitializationMode(startTime=0.0, stopTime=0.5)
    fmu.exitInitializationMode()
    fmu.doStep(0.0, 0.5)
    _fails(messages, lambda: fmu.doStep(0.5, 0.1), "past the stop time", "0.5")
    fmu.freeInstance()


# --- the importer's tolerance at an assembly FMU ----------------------------------------

@pytest.mark.parametrize("tolerance", [0.0, -1e-6, math.nan, 2.0])
def test_an_assembly_refuses_a_tolerance_a_component_refuses(exported, tolerance):
    component = build_fmu(SpringBlock(), fmi_version=3)
    for path in (component, exported("two_block_belt", 3, "cosim")):
        messages = []
        md, fmu = _open(path, "cs", 3, messages)
        _fails(messages, lambda: fmu.enterInitializationMode(tolerance=tolerance),
               "tolerance", "outside the allowed range")
        fmu.freeInstance()


def test_an_assembly_accepts_a_valid_tolerance(exported):
    md, fmu = _open(exported("two_block_belt", 3, "cosim"), "cs", 3, [])
    fmu.enterInitializationMode(tolerance=1e-6)
    fmu.exitInitializationMode()
    fmu.doStep(0.0, 0.1)
    fmu.freeInstance()


# --- eventModeUsed where hasEventMode = false ---------------------------------------

def test_event_mode_used_is_refused_where_the_fmu_has_no_event_mode():
    path = build_fmu(SpringBlock(), fmi_version=3)
    md = read_model_description(str(path))
    assert not md.coSimulation.hasEventMode
    messages = []
    fmu = FMU3Slave(guid=md.guid, unzipDirectory=extract(str(path)),
                    modelIdentifier=md.coSimulation.modelIdentifier, instanceName="blk")
    with pytest.raises(Exception, match="Failed to instantiate"):
        fmu.instantiate(eventModeUsed=True,
                        logMessage=lambda env, status, cat, msg: messages.append(msg.decode()))
    assert messages and "eventModeUsed" in messages[-1] and "hasEventMode" in messages[-1]
    fmu.instantiate()  # without it the same FMU instantiates
    fmu.freeInstance()
