"""Random call sequences through fmpy's low-level API: the FMU never takes its host down.

For each FMI version and interface, a seeded random walk of CALLS calls on the
SpringBlock FMU: life-cycle calls in any order, get/set of random (also unknown)
value references with NaN, infinite and huge values, doStep with bad times and step
sizes, mode changes, FMU state get/set/free/serialize (also corrupted bytes),
terminate, reset, free and instantiate again. Every answer must be a legal status
(OK, Warning, Discard or Error; never Fatal, never an undefined code) and the process
must survive. The walk runs in a child process, so that a crash fails this test
instead of killing pytest.

Every value read with status OK must be finite (a NaN or infinity read as OK exits the
child with code 4, naming the call), steps include huge (1e300 s) and tiny (down to
1e-300 s) ones, and the RollingCoin FMU is walked too. MECHFMU_FUZZ_CALLS raises the
number of calls per walk for a long run (benchmarks: `MECHFMU_FUZZ_CALLS=50000 python -m
pytest tests/integration/test_fuzz.py`).

Not fuzzed: calls that the standard makes undefined for the importer to make (a
freed instance or FMU state used again, arrays shorter than the count passed).
"""
import json
import math
import os
import random
import subprocess
import sys
from collections import Counter
from ctypes import c_double
from pathlib import Path

import pytest

CALLS = int(os.environ.get("MECHFMU_FUZZ_CALLS", "2000"))
LEGAL = {0, 1, 2, 3}  # OK, Warning, Discard, Error
CELLS = [(version, kind) for version in (2, 3) for kind in ("CoSimulation", "ModelExchange")]


def _values(rng, n):
    pool = [0.0, 1.0, -1.0, 0.1, 1e308, -1e308, 1e-320, math.nan, math.inf, -math.inf, 2.5e9]
    return [rng.choice(pool) if rng.random() < 0.7 else rng.uniform(-10, 10) for _ in range(n)]


def _ints(rng, n):
    return [rng.choice([0, 1, -1, 2, 2**31 - 1, -2**31, 7]) for _ in range(n)]


def _refs(rng, n_vars):
    pool = list(range(n_vars)) + [n_vars, n_vars + 1, 2**31, 2**32 - 1]
    return [rng.choice(pool) for _ in range(rng.randint(0, 4))]


def fuzz(path, version, kind, seed, calls):
    """The walk itself (runs in the child). Returns a Counter of statuses seen."""
    from fmpy import extract, read_model_description
    from fmpy.fmi1 import FMICallException

    md = read_model_description(path)
    unzipped = extract(path)
    model_id = (md.coSimulation if kind == "CoSimulation" else md.modelExchange).modelIdentifier
    if version == 2:
        from fmpy.fmi2 import FMU2Model as Model, FMU2Slave as Slave
    else:
        from fmpy.fmi3 import FMU3Model as Model, FMU3Slave as Slave
    cls = Slave if kind == "CoSimulation" else Model
    fmu = None
    rng = random.Random(seed)
    n_vars = len(md.modelVariables) + (1 if version == 3 else 0)  # FMI 2 lists no time
    n_x, n_z = md.numberOfContinuousStates, md.numberOfEventIndicators
    seen = Counter()
    alive, states, blobs, t = False, [], [], 0.0
    get_f = "getReal" if version == 2 else "getFloat64"
    set_f = "setReal" if version == 2 else "setFloat64"
    get_i = "getInteger" if version == 2 else "getInt32"
    set_i = "setInteger" if version == 2 else "setInt32"

    def instantiate():
        nonlocal fmu, alive, states, t
        # fmpy's freeInstance also unloads the library: every instance needs a new load
        fmu = cls(guid=md.guid, unzipDirectory=unzipped, modelIdentifier=model_id,
                  instanceName="fuzz")
        logging_on = rng.random() < 0.5
        options = ({} if version == 2 or kind == "ModelExchange"
                   else {"eventModeUsed": rng.random() < 0.3})
        fmu.component = None
        try:
            fmu.instantiate(loggingOn=logging_on, **options)
        except Exception:  # fmpy raises when an instantiation returns NULL
            # the only refusal expected: eventModeUsed where hasEventMode = false
            if not options.get("eventModeUsed"):
                raise
        alive, states, t = fmu.component is not None, [], 0.0

    def free_instance():
        nonlocal alive, states
        fmu.freeInstance()
        alive, states = False, []  # states of a freed instance are never touched again

    def init():
        tol = rng.choice([None, 1e-6, 0.0, -1.0, math.nan, math.inf])
        start = rng.choice([0.0, 0.0, -5.0, math.nan, 1e300])
        if version == 2:
            fmu.setupExperiment(tolerance=tol, startTime=start)
            fmu.enterInitializationMode()
        else:
            fmu.enterInitializationMode(tolerance=tol, startTime=start)

    def do_step():
        nonlocal t
        start = rng.choice([t, t, t, t + 1.0, -t - 1.0, math.nan])
        h = rng.choice([0.1, 1.0, 20.0, 1e-12, 0.0, -0.1, math.nan, math.inf, 1e300, 1e30,
                        1e-300, 1.1e-16, 5e-324])
        fmu.doStep(start, h)
        if math.isfinite(start) and math.isfinite(h):
            t = start + h

    def get_state():
        states.append(fmu.getFMUState())

    def set_state():
        if states:
            fmu.setFMUState(rng.choice(states))

    def free_state():
        if states:
            fmu.freeFMUState(states.pop(rng.randrange(len(states))))

    def serialize():
        if states:
            blobs.append(fmu.serializeFMUState(rng.choice(states)))

    def deserialize():
        if not blobs:
            return
        blob = bytearray(rng.choice(blobs))
        for _ in range(rng.choice([0, 0, 1, 8])):  # corrupt some bytes, sometimes
            blob[rng.randrange(len(blob))] = rng.randrange(256)
        if rng.random() < 0.1:
            blob = blob[:rng.randrange(len(blob))]
        states.append(fmu.deserializeFMUState(bytes(blob)))

    def finite(name, values):
        bad = [v for v in values if not math.isfinite(v)]
        if bad:
            print(f"{name} read {bad} with status OK", file=sys.stderr)
            sys.exit(4)

    def get_float():
        finite(get_f, getattr(fmu, get_f)(_refs(rng, n_vars)))

    def me(name):
        def call():
            # buffers always hold the count passed; the count itself may be wrong
            n_true = n_z if name == "getEventIndicators" else n_x
            n = rng.choice([n_true, n_true, n_true, 0, n_true + 1, n_true + 2])
            buffer = (c_double * (n_true + 2))(*_values(rng, n_true + 2))
            if name == "setTime":
                fmu.setTime(rng.choice([t, 0.5, -1.0, math.nan, math.inf]))
            elif name in ("setContinuousStates", "getContinuousStates", "getEventIndicators",
                          "getNominalsOfContinuousStates", "getDerivatives",
                          "getContinuousStateDerivatives"):
                getattr(fmu, name)(buffer, n)
                if name.startswith("get"):  # no exception: the call answered OK
                    finite(name, buffer[:n])
            else:
                getattr(fmu, name)()
        return call

    actions = {
        "get_float": get_float,
        "set_float": lambda: (lambda r: getattr(fmu, set_f)(r, _values(rng, len(r))))(_refs(rng, n_vars)),
        "get_int": lambda: getattr(fmu, get_i)(_refs(rng, n_vars)),
        "set_int": lambda: (lambda r: getattr(fmu, set_i)(r, _ints(rng, len(r))))(_refs(rng, n_vars)),
        "init": init,
        "exit_init": lambda: fmu.exitInitializationMode(),
        "terminate": lambda: fmu.terminate(),
        "reset": lambda: fmu.reset(),
        "get_state": get_state, "set_state": set_state, "free_state": free_state,
        "serialize": serialize, "deserialize": deserialize,
        "free_instance": free_instance,
    }
    if version == 3 or kind == "ModelExchange":  # FMI 2 Co-Simulation has no Event Mode
        actions["enter_event"] = lambda: fmu.enterEventMode()
    if kind == "CoSimulation":
        actions["do_step"] = do_step
        actions["do_step2"] = do_step  # stepping is what a master mostly does
        if version == 3:
            actions["enter_step"] = lambda: fmu.enterStepMode()
            actions["update"] = lambda: fmu.updateDiscreteStates()
    else:
        for name in ("setContinuousStates", "setTime", "getContinuousStates", "getEventIndicators",
                     "getNominalsOfContinuousStates", "enterContinuousTimeMode",
                     "completedIntegratorStep",
                     "getDerivatives" if version == 2 else "getContinuousStateDerivatives",
                     "newDiscreteStates" if version == 2 else "updateDiscreteStates"):
            actions[name] = me(name)
    names = sorted(actions)
    while sum(seen.values()) < calls:
        if not alive:
            name, action = "instantiate", instantiate
        else:
            name = rng.choice(names)
            action = actions[name]
            if name == "free_instance" and rng.random() < 0.8:
                continue  # a rarer call, so that walks get deep into a life cycle
        try:
            action()
            seen["0/1"] += 1
        except FMICallException as e:
            seen[e.status] += 1
            if e.status not in LEGAL:
                print(f"illegal status {e.status} from {e.function} ({name})", file=sys.stderr)
                sys.exit(3)
    if alive:
        fmu.freeInstance()
    return seen


# the coin (8 states, a terminate condition, no inputs) in one cell per FMI version
CELLS += [(3, "CoSimulation", "RollingCoin"), (2, "ModelExchange", "RollingCoin")]
CELLS = [cell if len(cell) == 3 else (*cell, "SpringBlock") for cell in CELLS]


@pytest.fixture(scope="module")
def fuzzed_fmus():
    from components import RollingCoin, SpringBlock
    from fmus import build_fmu
    return {(name, v): str(build_fmu(cls(), fmi_version=v))
            for name, cls in (("SpringBlock", SpringBlock), ("RollingCoin", RollingCoin))
            for v in (2, 3)}


@pytest.mark.parametrize("version, kind, model", CELLS,
                         ids=[f"{m}-fmi{v}-{k}" for v, k, m in CELLS])
def test_random_call_sequences_get_legal_answers(fuzzed_fmus, version, kind, model):
    child = subprocess.run(
        [sys.executable, __file__, fuzzed_fmus[model, version], str(version), kind, "12345",
         str(CALLS)], capture_output=True, text=True, timeout=60 + CALLS // 10,
        cwd=Path(__file__).resolve().parents[2])
    assert child.returncode == 0, (child.returncode, child.stderr[-2000:])
    seen = json.loads(child.stdout.strip().splitlines()[-1])
    assert sum(seen.values()) == CALLS
    # the walk reached both sides: calls that succeed and misuse answered with an error
    assert seen.get("0/1", 0) > CALLS // 10 and seen.get("3", 0) > CALLS // 10, seen


if __name__ == "__main__":
    path, version, kind, seed, calls = sys.argv[1:6]
    counts = fuzz(path, int(version), kind, int(seed), int(calls))
    print(json.dumps({str(k): n for k, n in counts.items()}))
