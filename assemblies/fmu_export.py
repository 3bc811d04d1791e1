"""An assembly as one FMU: any importer runs it as a single FMU.

The exported FMU carries its member FMUs (ours and foreign, extracted) in
``resources/<instance>/`` and, in ``resources/assembly.txt``, the same description of
the coupling that a run hands the compiled engine (:func:`assemblies.engine.cosim.
coupling_plan`): its ``doStep`` runs one of the engine's masters over the members for
one communication step, so the FMU computes what ``cosimulate`` (mode 'cosim') or
``simulate_me`` (mode 'me') computes with the same settings. In mode 'cosim' only events
whose coupled crossing falls in the last internal step before a communication point are
located by a probe at that point rather than by the next step (the importer has already
read the outputs there). In mode 'me' the FMU is a Model Exchange FMU too: the members'
stacked states and indicators are its own.

Its interface is the members' unconnected inputs (start values as the assembly has
them) and the outputs chosen at export, named ``<instance>.<variable>`` with the members'
units; value reference 0 is time. The binary is one generic library, compiled once per
FMI version and machine from the engine's sources and the shared FMI adapters
(``fmus/runtime/fmi2.c``, ``fmi3.c``) over ``assemblies/engine/fmu/assembly_runtime.c``.
"""
from __future__ import annotations

import hashlib
import os
import re
import warnings
import zipfile
from pathlib import Path

from fmpy import read_model_description

from components.errors import writable_file
from fmus.build import FMI_HEADERS, RUNTIME_DIR, cached_library, platform_folder, token_from_digest
from fmus.model_description import (DEFAULT_FMI, FMI_VERSIONS, GENERATION_TOOL, shared_head,
                                    xml_attributes)

from .assembly import Assembly, AssemblyError
from .engine.build import C_DIR, SHARED_RUNTIME
from .engine.cosim import DEFAULT_SCHEME, EVENT_TOL, coupling_plan
from .engine.me import EVENT_SUBSAMPLES, METHODS, integrator, step_limit_needed
from .engine.prepare import prepared, record_columns
from .engine.restore import inexact_restores
from .experiment import (FixedStepFallback, check_cosim_settings, check_experiment,
                         fixed_step_fallback)
from .foreign import FMU, check_mode
from .masters.loops import loop_order

FMU_C_DIR = Path(__file__).parent / "engine" / "fmu"
# the engine's files the FMU links: its two masters and what they stand on
ENGINE_FILES = ("arena", "cosim", "dop853", "me", "jacobian", "loop", "linear_map", "fmu", "instances",
                "output")
# the members' variable types the interface passes on (the engine reads Float64/Int32)
_TYPES = {"Real": "Real", "Float64": "Real", "Integer": "Integer", "Int32": "Integer"}


def export_fmu(assembly: Assembly, path: str | os.PathLike, fmi: int = DEFAULT_FMI,
               outputs: list[str] | None = None, stop_time: float = 10.0, step: float = 0.01,
               tolerance: float = 1e-8, mode: str | None = None, scheme: str = "jacobi",
               method: str | None = None, **settings) -> Path:
    """Write `assembly` as one Co-Simulation FMU (FMI `fmi` = 2 or 3, by default 3) to `path`.

    `outputs`: the members' variables the FMU exposes (``"block.x"``; default every
    output of every member). `stop_time` and `step` become its default experiment.
    `mode` is the master its doStep runs, as a run from Python would:

    - ``"cosim"`` (the default, unless a member is Model Exchange only): the members'
      Co-Simulation interfaces, `tolerance` for their own solvers, `scheme` and
      ``**settings`` (extrapolation, adaptive, tol, event_sync, loop_tolerance,
      max_loop_iterations, newton) as in ``cosimulate``, by default
      :data:`DEFAULT_SCHEME` (what a friction assembly needs to be right). A member that
      cannot roll back, or a foreign member whose state restore proves inexact
      (:mod:`assemblies.engine.restore`), makes it fixed steps of `step`, with a
      :class:`FixedStepFallback` warning, as a run does.
    - ``"me"``: the members' Model Exchange interfaces in the engine's one integrator
      (`method`, `tolerance`), as ``simulate_me``; an input set from outside starts the
      next step with an event.

    Returns the path written.
    """
    if fmi not in FMI_VERSIONS:
        raise AssemblyError(f"export_fmu: fmi must be 2 or 3, not {fmi!r}")
    # before the members are built and the engine compiled (seconds), not after
    path = writable_file(path, "export_fmu: path", ".fmu", AssemblyError)
    foreign = {n: c for n, c in assembly.components.items() if isinstance(c, FMU)}
    if mode is None:
        me_only = any("cosim" not in c.modes_supported() for c in foreign.values())
        mode = "me" if me_only else "cosim"
    if mode not in ("cosim", "me"):
        raise AssemblyError(f"export_fmu: mode must be 'cosim' or 'me', not {mode!r}")
    try:
        check_mode(assembly, mode)
    except AssemblyError as exc:
        raise AssemblyError(f"export_fmu: {exc}") from None
    unknown = set(settings) - {"extrapolation", "adaptive", "tol", "event_sync",
                               "loop_tolerance", "max_loop_iterations", "newton"}
    if unknown:
        raise AssemblyError(f"export_fmu: unknown setting(s) {', '.join(sorted(unknown))}")
    if mode == "me" and settings:
        raise AssemblyError(f"export_fmu: {', '.join(sorted(settings))} set(s) the co-simulation "
                            "master; mode 'me' integrates and takes `method` and `tolerance`")
    if method is not None and method not in METHODS:
        raise AssemblyError(f"export_fmu: method must be one of {', '.join(METHODS)}, "
                            f"not {method!r}")
    s = {**DEFAULT_SCHEME, "loop_tolerance": 1e-10, "max_loop_iterations": 20, "newton": True,
         **settings}
    s.setdefault("event_sync", bool(s["adaptive"]))
    check_experiment(stop_time, step, tolerance, rows=False)  # the importer keeps the rows
    check_cosim_settings(scheme, s["extrapolation"], s["adaptive"], s["tol"])

    assembly.signals_from_outside = True  # open signal inputs become the FMU's inputs
    try:
        couplings = assembly.couplings()  # resolves the profiles: which FMU each component is
        names = list(assembly.components)
        fmus = {n: prepared(assembly.components[n]) for n in names}
        stateless = [n for n in names if not fmus[n].can_get_set_state]
        rolls_back = mode == "cosim" and (s["adaptive"] or s["event_sync"])
        # a foreign member's restore is checked once here, as before a run
        inexact = inexact_restores(assembly, fmus, step, tolerance) if rolls_back else {}
        if rolls_back and (stateless or inexact):
            warnings.warn(fixed_step_fallback(s["adaptive"], stateless, step, inexact),
                          FixedStepFallback, stacklevel=2)
            s["adaptive"] = s["event_sync"] = False
        for n in names:
            if re.search(r"\s", fmus[n].token) or re.search(r"[\s/\\]", n):
                raise AssemblyError(f"export_fmu: instance '{n}' has a name or instantiation "
                                    "token with whitespace or a path separator")
        plan = coupling_plan(assembly, fmus)
        if mode == "me":  # the integrator evaluates the couplings by dependency level
            # (the co-simulation's groups and sweep travel along unused)
            ordered, loops = loop_order(couplings, fmus)
            plan.pairs = [(plan.variable(*c.source), plan.variable(*c.target), c.gain)
                          for c in ordered]
            # the groups section carries the algebraic loops, each consecutive in this
            # order, which the engine's me solves by Newton (assembly_config.c)
            plan.groups = [list(range(first, first + count)) for first, count, _ in loops]
            plan.loops = list(plan.groups)
            for (first, count, name), group in zip(loops, plan.groups):
                if any(plan.pairs[k][i][2] != 0 for k in group for i in (0, 1)):
                    raise AssemblyError(f"export_fmu: assembly '{assembly.name}': algebraic "
                                        f"loop {name}: a coupling of it is not a Float64 "
                                        "scalar, and the engine's me solves loops of Float64 "
                                        "scalars only")
            plan.held = [0] * len(plan.pairs)
            plan.derivative = [-1] * len(plan.pairs)
            plan.rates = [[] for _ in plan.pairs]
            # an input set from outside moves indicators while the states stand still,
            # as a time-dependent one does (and the joined model has no open inputs)
            fed = {c.target for c in couplings}
            open_inputs = any((n, i) not in fed for n in names for i in fmus[n].inputs
                              if i not in fmus[n].rate_inputs)
            s["max_step"] = step if open_inputs or step_limit_needed(assembly) else 0.0
    finally:
        assembly.signals_from_outside = False
    s.update(mode=mode, method=METHODS[integrator(assembly, method)])
    ports = _interface(assembly, fmus, plan, outputs, mode, fmi)
    config = _config(assembly, fmus, plan, ports, stop_time, step, tolerance, scheme, s)
    token = token_from_digest(hashlib.sha256(config.encode()).hexdigest())
    identifier = re.sub(r"\W", "_", assembly.name) or "assembly"
    if identifier[0].isdigit():
        identifier = "_" + identifier
    xml = _model_description(assembly, identifier, token, ports, fmi, stop_time, step, mode,
                             sum(f.n_event_indicators for f in fmus.values()))

    partial = path.with_name(path.name + f".{os.getpid()}.partial")
    try:
        with zipfile.ZipFile(partial, "w", zipfile.ZIP_DEFLATED) as zf:
            zf.writestr("modelDescription.xml", xml)
            zf.write(library(fmi), f"binaries/{platform_folder(fmi)}/{identifier}.so")
            zf.writestr("resources/assembly.txt", config.replace("@TOKEN@", token))
            for n in names:
                root = Path(fmus[n].unzip_dir)
                for file in sorted(root.rglob("*")):
                    if file.is_file():
                        zf.write(file, f"resources/{n}/{file.relative_to(root).as_posix()}")
        partial.replace(path)
    finally:
        partial.unlink(missing_ok=True)  # what failed half-way leaves nothing behind
    return path


def _interface(assembly, fmus, plan, outputs, mode, fmi) -> list[dict]:
    """The FMU's variables: unconnected member inputs, the chosen outputs and, for a Model
    Exchange interface (mode 'me'), the members' continuous states with their derivatives
    (in the order the engine stacks them) and, in FMI 3, the event indicators."""
    coupled = {(target[0], target[1]) for _, target, _ in plan.pairs}
    described = {n: read_model_description(fmus[n].path, validate=False) for n in fmus}
    variables = {n: {v.name: v for v in md.modelVariables} for n, md in described.items()}
    ports, by_name = [], {}

    def add(instance, name, causality, derivative_of=None):
        full = f"{instance}.{name}" if derivative_of is None else f"der({derivative_of})"
        if full in by_name:  # a state that is also a chosen output is one variable
            return by_name[full]
        if name not in variables[instance]:  # an element of an FMI 3 array
            raise AssemblyError(f"export_fmu: {instance}.{name} is an element of an FMI 3 "
                                "array; the assembly FMU passes on scalars only")
        v = variables[instance][name]
        kind = _TYPES.get(v.type)
        if kind is None:
            raise AssemblyError(f"export_fmu: {instance}.{name} is of type {v.type}; the "
                                "assembly FMU passes on Float64/Real and Int32/Integer only")
        inst, vr, is_int = plan.variable(instance, name)[:3]
        start = None
        if causality == "input":
            own = {**assembly.components[instance].values, **assembly.components[instance].starts}
            start = own.get(name, v.start)
            if start is None:
                start = 0
        port = dict(name=full, causality=causality, kind=kind,
                    unit=v.unit or (v.declaredType.unit if v.declaredType else None),
                    description=v.description, start=start, member=(inst, vr, is_int),
                    derivative_of=derivative_of)
        ports.append(port)
        by_name[full] = port
        return port

    for instance in fmus:
        for name in fmus[instance].inputs:
            # (a rate input is the master's to set within its doStep, held at 0 otherwise)
            if (plan.index[instance], plan.variable(instance, name)[1]) not in coupled \
                    and name not in fmus[instance].rate_inputs:
                add(instance, name, "input")
    for instance, name in record_columns(fmus, outputs):
        add(instance, name, "output")
    if mode == "me":
        for instance, md in described.items():
            for u in md.derivatives:
                state = add(instance, u.variable.derivative.name, "local")
                state["state"] = True
                add(instance, u.variable.name, "local", derivative_of=state["name"])
        if fmi == 3:  # FMI 3 names each event indicator as a variable
            k = 0
            for instance, fmu in fmus.items():
                for j in range(fmu.n_event_indicators):
                    port = dict(name=f"{instance}.event_indicator[{j + 1}]", causality="indicator",
                                kind="Real", unit=None, start=None, member=(0, k, 0),
                                description=f"event indicator {j + 1} of {instance}",
                                derivative_of=None)
                    ports.append(port)
                    k += 1
    for vr, port in enumerate(ports, start=1):
        port["vr"] = vr
    return ports


def _config(assembly, fmus, plan, ports, stop_time, step, tolerance, scheme, s) -> str:
    """resources/assembly.txt (its format: assemblies/engine/fmu/assembly_config.c)."""
    def line(*words):
        # floats by repr: the C side reads back exactly the numbers written
        return " ".join(repr(w) if isinstance(w, float) else str(w) for w in words)

    def var(v):
        # (instance, vr, type): the assembly FMU carries Float64 and Int32 scalars only
        instance, vr, kind = v[:3]
        if kind not in (0, 1) or (len(v) > 4 and v[4] > 1):
            raise AssemblyError("export_fmu: the assembly FMU couples and passes on Float64 "
                                "and Int32 scalars only; a member's coupling or state is of "
                                "another type or an array element")
        return line(instance, vr, kind)

    settings = (float(stop_time), float(tolerance), float(step), 0 if scheme == "jacobi" else 1,
                int(s["extrapolation"]), int(bool(s["adaptive"])), float(s["tol"]),
                float(s["loop_tolerance"]), int(s["max_loop_iterations"]),
                int(bool(s["newton"])), int(bool(s["event_sync"])), EVENT_TOL, s["method"],
                EVENT_SUBSAMPLES, float(s.get("max_step", 0.0)))
    lines = ["mechfmu-assembly 1", "token @TOKEN@", f"mode {s['mode']}",
             line("settings", *settings), f"instances {len(fmus)}"]
    for n, fmu in fmus.items():
        floats, ints, typed, strings = fmu.typed_starts(n, assembly.components[n].fmu_starts())
        if typed or strings:
            raise AssemblyError(f"export_fmu: member '{n}' has parameters or start values of "
                                "other types than Float64 and Int32 scalars, which the "
                                "assembly FMU does not carry")
        identifier = fmu.me_identifier if s["mode"] == "me" else fmu.cs_identifier
        lines.append(line("instance", n, identifier, fmu.token, fmu.fmi_version, fmu.n_states,
                          fmu.n_event_indicators, int(fmu.can_get_set_state),
                          int(fmu.provides_directional_derivative),
                          len(floats), *(w for pair in floats for w in pair),
                          len(ints), *(w for pair in ints for w in pair)))
    lines.append(f"couplings {len(plan.pairs)}")
    lines += [line("coupling", var(src), var(tgt), float(gain), held, derivative, len(rates),
                   *(var(r) for r in rates))
              for (src, tgt, gain), held, derivative, rates
              in zip(plan.pairs, plan.held, plan.derivative, plan.rates)]
    lines.append(f"groups {len(plan.groups)}")
    lines += [line("group", int(g in plan.loops), len(g), *g) for g in plan.groups]
    lines.append(line("sweep", *plan.sweep_order))
    lines.append(line("states", len(plan.states), *(var(v) for v in plan.states)))
    lines.append(f"ports {len(ports)}")
    # kinds: input, output, local (a state or its derivative), indicator
    lines += [line("port", p["vr"], p["causality"], var(p["member"])) for p in ports]
    lines.append("end")
    return "\n".join(lines) + "\n"


def _element(depth: int, tag: str, inner: str = "", **attributes) -> str:
    """One XML element on its own line: self-closing, or around `inner`."""
    opening = f"{'  ' * depth}<{tag} {xml_attributes(**attributes)}"
    return f"{opening}/>" if not inner else f"{opening}>{inner}</{tag}>"


def _model_description(assembly, identifier, token, ports, fmi, stop_time, step, mode,
                       n_indicators) -> str:
    """modelDescription.xml: Co-Simulation always; Model Exchange too in mode 'me'."""
    units = {p["unit"] for p in ports if p["unit"]} | {"s"}
    head = shared_head(units, stop_time, step=step, foreign_units=True)
    description = (f"mechfmu assembly '{assembly.name}': {len(assembly.components)} member FMUs "
                   f"({', '.join(assembly.components)}) run by the engine's "
                   f"{'one integrator' if mode == 'me' else 'co-simulation master'}")
    outputs = [p for p in ports if p["causality"] == "output"]
    derivatives = [p for p in ports if p["derivative_of"]]
    states = [p for p in ports if p.get("state")]
    indicators = [p for p in ports if p["causality"] == "indicator"]
    # a state that is also an output is one variable, listed once
    unknowns = sorted({p["vr"]: p for p in outputs + states + derivatives}.values(),
                      key=lambda p: p["vr"])
    me = mode == "me"
    by_name = {p["name"]: p for p in ports}
    time = dict(name="time", valueReference=0, causality="independent", variability="continuous",
                description="simulation time")
    cs = dict(modelIdentifier=identifier, canHandleVariableCommunicationStepSize="true")

    def declared(p):
        """causality, variability, initial as FMI names them: states, derivatives and
        indicators are local and calculated (outputs are calculated by default)."""
        causality = "local" if p["causality"] == "indicator" else p["causality"]
        return (causality, "continuous" if p["kind"] == "Real" else "discrete",
                "calculated" if causality == "local" else None)

    out = ['<?xml version="1.0" encoding="UTF-8"?>']
    if fmi == 2:
        out.append("<fmiModelDescription " + xml_attributes(
            fmiVersion="2.0", modelName=assembly.name, guid=token, description=description,
            generationTool=GENERATION_TOOL, variableNamingConvention="structured",
            numberOfEventIndicators=n_indicators if me else 0) + ">")
        if me:
            out.append(_element(1, "ModelExchange", modelIdentifier=identifier,
                                canNotUseMemoryManagementFunctions="true"))
        out += [_element(1, "CoSimulation", **cs, canNotUseMemoryManagementFunctions="true"),
                *head, "  <ModelVariables>",
                _element(2, "ScalarVariable", '<Real unit="s"/>', **time)]
        index = {p["vr"]: i + 2 for i, p in enumerate(ports)}  # 1-based, time first
        for p in ports:
            causality, variability, initial = declared(p)
            derivative = index[by_name[p["derivative_of"]]["vr"]] if p["derivative_of"] else None
            typed = _element(0, p["kind"], start=p["start"], derivative=derivative,
                             unit=p["unit"] if p["kind"] == "Real" else None)
            out.append(_element(2, "ScalarVariable", typed, name=p["name"], valueReference=p["vr"],
                                causality=causality, variability=variability, initial=initial,
                                description=p["description"]))
        out += ["  </ModelVariables>", "  <ModelStructure>"]
        for element, rows in (("Outputs", outputs), ("Derivatives", derivatives),
                              ("InitialUnknowns", unknowns)):
            if rows:
                out += [f"    <{element}>", *(_element(3, "Unknown", index=index[p["vr"]])
                                              for p in rows), f"    </{element}>"]
        out += ["  </ModelStructure>", "</fmiModelDescription>"]
        return "\n".join(out) + "\n"
    out.append("<fmiModelDescription " + xml_attributes(
        fmiVersion="3.0", modelName=assembly.name, instantiationToken=token,
        description=description, generationTool=GENERATION_TOOL,
        variableNamingConvention="structured") + ">")
    no_state = dict(canGetAndSetFMUState="false", canSerializeFMUState="false")
    if me:
        out.append(_element(1, "ModelExchange", modelIdentifier=identifier, **no_state))
    out += [_element(1, "CoSimulation", **cs, **no_state, providesDirectionalDerivative="false",
                     hasEventMode="false"),
            *head, "  <ModelVariables>", _element(2, "Float64", **time, unit="s")]
    for p in ports:
        tag = "Float64" if p["kind"] == "Real" else "Int32"
        causality, variability, initial = declared(p)
        derivative = by_name[p["derivative_of"]]["vr"] if p["derivative_of"] else None
        out.append(_element(2, tag, name=p["name"], valueReference=p["vr"], causality=causality,
                            variability=variability, initial=initial,
                            description=p["description"], start=p["start"],
                            unit=p["unit"] if tag == "Float64" else None, derivative=derivative))
    out += ["  </ModelVariables>", "  <ModelStructure>",
            *(_element(2, "Output", valueReference=p["vr"]) for p in outputs),
            *(_element(2, "ContinuousStateDerivative", valueReference=p["vr"])
              for p in derivatives),
            *(_element(2, "InitialUnknown", valueReference=p["vr"]) for p in unknowns),
            *(_element(2, "EventIndicator", valueReference=p["vr"]) for p in indicators),
            "  </ModelStructure>", "</fmiModelDescription>"]
    return "\n".join(out) + "\n"


def _sources(fmi: int) -> list[Path]:
    engine = [C_DIR / f"{name}.{ext}" for name in ENGINE_FILES for ext in ("c", "h")]
    engine.append(C_DIR / "engine.h")
    runtime = [RUNTIME_DIR / f"fmi{fmi}.c", RUNTIME_DIR / "runtime.h", RUNTIME_DIR / "model.h"]
    runtime += [RUNTIME_DIR / f"{name}.{ext}" for name in SHARED_RUNTIME for ext in ("c", "h")]
    return sorted(FMU_C_DIR.glob("*.[ch]")) + engine + runtime


def library(fmi: int) -> Path:
    """The assembly FMU's binary for FMI `fmi`, built now if these sources never were
    here: the same library serves every assembly (what differs is in resources/)."""
    return cached_library("assembly", f"assembly-fmi{fmi}", _sources(fmi),
                          [FMU_C_DIR, C_DIR, RUNTIME_DIR, FMI_HEADERS], "the assembly FMU",
                          defines=["ENG_API="])


__all__ = ["export_fmu"]
