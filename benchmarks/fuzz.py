"""Random FMI call sequences against our FMUs: components and assembly FMUs.

    python -m benchmarks.fuzz --calls 100000 [--seed 1] [--chunk 5000]

Each cell is one FMU, FMI version and interface: SpringBlock and RollingCoin
(components), and an assembly (a friction block pushed by the FMU's input force)
exported in mode 'cosim' (Co-Simulation) and in mode 'me' (Co-Simulation running the
engine's integrator, and Model Exchange), each in FMI 2 and 3. The calls are spread
over the cells in walks of --chunk calls, each walk a child process with its own seed,
so that whatever happens to one walk is counted and the next one starts clean.

A walk (`walk`, run in the child) makes random calls through fmpy's low-level API:
life-cycle calls in any order, get/set of random (also unknown) value references with
NaN, infinite and huge values, doStep with bad times and step sizes (1e300 s down to
5e-324 s), mode changes, FMU state get/set/free/serialize (also corrupted bytes),
terminate, reset, free and instantiate again. What is counted, per walk:

- crash: the child died (a signal, a sanitizer abort, a Python exception);
- hang: one call took longer than --call-timeout seconds (10; a watchdog thread ends
  the child, so a loop inside C is caught too);
- illegal status: an answer other than OK, Warning, Discard or Error;
- non-finite: a value read with status OK that is NaN or infinite;
- corruption: a fresh instance, made beside the walked one after each free and at the
  end, does not give bit for bit what a fresh instance gave before the walk began (a
  short standard run: initialize, two steps, read every variable), so misuse of one
  instance cannot leak into another through shared state.

Not fuzzed: calls the standard makes undefined for the importer to make (a freed
instance or FMU state used again, arrays shorter than the count passed).
Exit code 0 only if every count is 0. tests/integration/test_fuzz.py runs short walks.
"""
from __future__ import annotations

import argparse
import faulthandler
import json
import math
import random
import subprocess
import sys
import tempfile
import time
from collections import Counter
from ctypes import c_double
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]
LEGAL = {0, 1, 2, 3}  # OK, Warning, Discard, Error
# exit codes of a walk that found something (a crash has its own: a signal, 1)
ILLEGAL_STATUS, NON_FINITE, CORRUPTION = 3, 4, 5
HANG_MARK = "Timeout ("  # what faulthandler writes before it ends a stuck child
CALL_TIMEOUT = 10.0


def _values(rng, n):
    pool = [0.0, 1.0, -1.0, 0.1, 1e308, -1e308, 1e-320, math.nan, math.inf, -math.inf, 2.5e9]
    return [rng.choice(pool) if rng.random() < 0.7 else rng.uniform(-10, 10) for _ in range(n)]


def _ints(rng, n):
    return [rng.choice([0, 1, -1, 2, 2**31 - 1, -2**31, 7]) for _ in range(n)]


def _refs(rng, n_vars):
    pool = list(range(n_vars)) + [n_vars, n_vars + 1, 2**31, 2**32 - 1]
    return [rng.choice(pool) for _ in range(rng.randint(0, 4))]


class _Fmu:
    """What a walk needs to know of one FMU: its description, classes and getters."""

    def __init__(self, path, version, kind):
        from fmpy import extract, read_model_description
        self.md = read_model_description(path)
        self.unzipped = extract(path)
        self.version, self.kind = version, kind
        self.model_id = (self.md.coSimulation if kind == "CoSimulation"
                         else self.md.modelExchange).modelIdentifier
        if version == 2:
            from fmpy.fmi2 import FMU2Model as Model, FMU2Slave as Slave
        else:
            from fmpy.fmi3 import FMU3Model as Model, FMU3Slave as Slave
        self.cls = Slave if kind == "CoSimulation" else Model
        self.get_f = "getReal" if version == 2 else "getFloat64"
        self.set_f = "setReal" if version == 2 else "setFloat64"
        self.get_i = "getInteger" if version == 2 else "getInt32"
        self.set_i = "setInteger" if version == 2 else "setInt32"

    def new(self, name):
        return self.cls(guid=self.md.guid, unzipDirectory=self.unzipped,
                        modelIdentifier=self.model_id, instanceName=name)

    def initialize(self, fmu, start=0.0, tolerance=None):
        if self.version == 2:
            fmu.setupExperiment(tolerance=tolerance, startTime=start)
            fmu.enterInitializationMode()
        else:
            fmu.enterInitializationMode(tolerance=tolerance, startTime=start)

    def standard_run(self):
        """A fresh instance's answers to a short run of proper calls, as text (bit exact,
        NaN-aware): initialize at 0, two steps of 0.1 s (Co-Simulation) or the states,
        derivatives and indicators at 0 (Model Exchange), every variable read."""
        from fmpy.fmi1 import FMICallException
        fmu = self.new("fresh")
        fmu.instantiate()
        out = []
        try:
            self.initialize(fmu)
            fmu.exitInitializationMode()
            if self.kind == "CoSimulation":
                fmu.doStep(0.0, 0.1)
                fmu.doStep(0.1, 0.1)
            else:
                if self.version == 2:
                    fmu.newDiscreteStates()
                else:
                    fmu.updateDiscreteStates()
                fmu.enterContinuousTimeMode()
                n_x, n_z = self.md.numberOfContinuousStates, self.md.numberOfEventIndicators
                x, dx, z = (c_double * max(n_x, 1))(), (c_double * max(n_x, 1))(), (c_double * max(n_z, 1))()
                fmu.getContinuousStates(x, n_x)
                (fmu.getDerivatives if self.version == 2
                 else fmu.getContinuousStateDerivatives)(dx, n_x)
                fmu.getEventIndicators(z, n_z)
                out += [x[:n_x], dx[:n_x], z[:n_z]]
            for v in self.md.modelVariables:
                getter = {"Real": self.get_f, "Float64": self.get_f, "Integer": self.get_i,
                          "Int32": self.get_i}.get(v.type)
                if getter:
                    try:
                        out.append((v.name, getattr(fmu, getter)([v.valueReference])))
                    except FMICallException as e:
                        out.append((v.name, "status", e.status))
        finally:
            fmu.terminate()
            fmu.freeInstance()
        return repr(out)


def walk(path, version, kind, seed, calls, call_timeout=CALL_TIMEOUT):
    """The walk itself (runs in the child). Returns a Counter of statuses seen; exits
    with ILLEGAL_STATUS, NON_FINITE or CORRUPTION when it finds one."""
    from fmpy.fmi1 import FMICallException

    F = _Fmu(path, version, kind)
    md = F.md
    fmu = None
    rng = random.Random(seed)
    n_vars = len(md.modelVariables) + (1 if version == 3 else 0)  # FMI 2 lists no time
    n_x, n_z = md.numberOfContinuousStates, md.numberOfEventIndicators
    seen = Counter()
    alive, states, blobs, t = False, [], [], 0.0
    get_f, set_f, get_i, set_i = F.get_f, F.set_f, F.get_i, F.set_i
    reference = F.standard_run()

    def fresh_instance_check(when):
        answer = F.standard_run()
        if answer != reference:
            print(f"corruption: a fresh instance {when} answered\n{answer}\nnot\n{reference}",
                  file=sys.stderr)
            sys.exit(CORRUPTION)

    def instantiate():
        nonlocal fmu, alive, states, t
        # fmpy's freeInstance also unloads the library: every instance needs a new load
        fmu = F.new("fuzz")
        try:
            fmu.instantiate(loggingOn=rng.random() < 0.5,
                            **({} if version == 2 or kind == "ModelExchange"
                               else {"eventModeUsed": rng.random() < 0.3}))
        except FMICallException:
            raise
        except Exception:  # fmpy's answer to a NULL instance: a refused instantiation
            fmu.freeLibrary()
            raise FMICallException("instantiate", 3) from None
        alive, states, t = fmu.component is not None, [], 0.0

    def free_instance():
        nonlocal alive, states
        fmu.freeInstance()
        alive, states = False, []  # states of a freed instance are never touched again
        fresh_instance_check("after an instance was freed")

    def init():
        tol = rng.choice([None, 1e-6, 0.0, -1.0, math.nan, math.inf])
        start = rng.choice([0.0, 0.0, -5.0, math.nan, 1e300])
        F.initialize(fmu, start, tol)

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
            print(f"non-finite: {name} read {bad} with status OK", file=sys.stderr)
            sys.exit(NON_FINITE)

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
        # a watchdog thread: a call stuck in C (where Python's signals wait) still ends
        faulthandler.dump_traceback_later(call_timeout, exit=True)
        try:
            action()
            seen["0/1"] += 1
        except FMICallException as e:
            seen[e.status] += 1
            if e.status not in LEGAL:
                print(f"illegal status {e.status} from {e.function} ({name})", file=sys.stderr)
                sys.exit(ILLEGAL_STATUS)
        finally:
            faulthandler.cancel_dump_traceback_later()
    if alive:
        fmu.freeInstance()
    faulthandler.dump_traceback_later(call_timeout, exit=True)
    fresh_instance_check("at the end of the walk")
    faulthandler.cancel_dump_traceback_later()
    return seen


def run_walk(path, version, kind, seed, calls, call_timeout=CALL_TIMEOUT, env=None):
    """One walk in a child process: (outcome, statuses, stderr tail). outcome is "ok",
    "crash", "hang", "illegal status", "non-finite" or "corruption"."""
    cmd = [sys.executable, "-m", "benchmarks.fuzz", "--child", str(path), str(version), kind,
           str(seed), str(calls), str(call_timeout)]
    # the child's whole life is bounded too: every call by the watchdog, plus the loads
    child = subprocess.run(cmd, capture_output=True, text=True, cwd=ROOT, env=env,
                           timeout=120 + calls * 0.1 + 2 * call_timeout)
    tail = child.stderr[-3000:]
    if child.returncode == 0:
        return "ok", json.loads(child.stdout.strip().splitlines()[-1]), tail
    outcome = {ILLEGAL_STATUS: "illegal status", NON_FINITE: "non-finite",
               CORRUPTION: "corruption"}.get(child.returncode, "crash")
    if HANG_MARK in child.stderr:
        outcome = "hang"
    return outcome, {}, tail


def pushed_block():
    """The assembly of the assembly-FMU cells: a friction block pushed through the FMU's
    input force (events, an input, both modes)."""
    from assemblies import Assembly
    from components import Force, MassWithFriction
    asm = Assembly("pushed_block")
    asm.add("force", Force())
    asm.add("block", MassWithFriction(m=2.0, g=9.81, mu_k=0.3, mu_s=0.4))
    asm.connect("force.flange", "block.flange_a")
    return asm


def cells(folder: Path, components=True, assemblies=True) -> list[tuple[str, str, int, str]]:
    """(name, FMU path, FMI version, interface) of every cell, the FMUs built (or taken
    from the cache) now; assembly FMUs are exported into `folder`."""
    out = []
    if components:
        from components import RollingCoin, SpringBlock
        from fmus import build_fmu
        for cls in (SpringBlock, RollingCoin):
            for v in (2, 3):
                path = str(build_fmu(cls(), fmi_version=v))
                for kind in ("CoSimulation", "ModelExchange"):
                    out.append((f"{cls.__name__}-fmi{v}-{kind}", path, v, kind))
    if assemblies:
        from assemblies import export_fmu
        for mode in ("cosim", "me"):
            for v in (2, 3):
                path = str(export_fmu(pushed_block(), folder / f"pushed_{mode}{v}.fmu", fmi=v,
                                      mode=mode, outputs=["block.s", "block.v", "block.mode"],
                                      stop_time=10.0, step=0.1))
                kinds = ("CoSimulation",) if mode == "cosim" else ("CoSimulation", "ModelExchange")
                out += [(f"assembly_{mode}-fmi{v}-{kind}", path, v, kind) for kind in kinds]
    return out


def main(argv=None) -> int:
    parser = argparse.ArgumentParser(prog="python -m benchmarks.fuzz", description=__doc__.split("\n\n")[0])
    parser.add_argument("--calls", type=int, default=100_000, help="calls in all (default 100000)")
    parser.add_argument("--seed", type=int, default=1)
    parser.add_argument("--chunk", type=int, default=5000, help="calls per walk (child process)")
    parser.add_argument("--call-timeout", type=float, default=CALL_TIMEOUT,
                        help="seconds a single call may take before it counts as a hang")
    parser.add_argument("--child", nargs=6, help=argparse.SUPPRESS)
    args = parser.parse_args(argv)
    if args.child:
        path, version, kind, seed, calls, timeout = args.child
        counts = walk(path, int(version), kind, int(seed), int(calls), float(timeout))
        print(json.dumps({str(k): n for k, n in counts.items()}))
        return 0
    if args.calls < 1 or args.chunk < 1:
        parser.error("--calls and --chunk must be positive")
    started = time.perf_counter()
    with tempfile.TemporaryDirectory(prefix="mechfmu-fuzz-") as tmp:
        table = cells(Path(tmp))
        totals = {name: Counter() for name, *_ in table}
        findings = []
        per_cell = -(-args.calls // len(table))
        for i, (name, path, version, kind) in enumerate(table):
            done, walk_no = 0, 0
            while done < per_cell:
                n = min(args.chunk, per_cell - done)
                seed = args.seed * 1_000_003 + i * 10_007 + walk_no
                outcome, statuses, tail = run_walk(path, version, kind, seed, n, args.call_timeout)
                totals[name][outcome] += 1
                totals[name]["calls"] += n
                totals[name].update({f"status {k}": v for k, v in statuses.items()})
                if outcome != "ok":
                    findings.append((name, seed, outcome, tail))
                done += n
                walk_no += 1
            print(f"{name:42s} {totals[name]['calls']:7d} calls, walks: "
                  + ", ".join(f"{k} {v}" for k, v in sorted(totals[name].items())
                              if not k.startswith(("calls", "status"))), flush=True)
    for name, seed, outcome, tail in findings:
        print(f"\n{outcome} in {name} (seed {seed}):\n{tail}")
    kinds = ("crash", "hang", "illegal status", "non-finite", "corruption")
    summed = Counter()
    for c in totals.values():
        summed.update(c)
    print(f"\n{summed['calls']} calls over {len(table)} cells in "
          f"{time.perf_counter() - started:.0f} s: "
          + ", ".join(f"{summed[k]} {k}" for k in kinds)
          + f" (statuses: OK/Warning {summed['status 0/1']}, Discard {summed['status 2']}, "
            f"Error {summed['status 3']})")
    return 0 if not any(summed[k] for k in kinds) else 1


if __name__ == "__main__":
    sys.exit(main())
