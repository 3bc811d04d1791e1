"""modelDescription.xml for FMI 2.0 and 3.0 (Model Exchange and Co-Simulation in one FMU).

Both versions describe the same FMU: the variable table of :mod:`fmus.codegen`
(so value references are identical in both) and one :class:`Structure`, computed
once here. Dependencies in it come from CasADi's structural sparsity, so they are
exact: an output lists exactly the states and inputs it depends on. The two
writers below only spell that in their version's syntax:

- FMI 3 has typed elements (``<Float64 .../>``), ``time`` as the independent
  variable, and refers to variables by value reference.
- FMI 2 has ``<ScalarVariable>`` with a ``<Real>``/``<Integer>`` child, no time
  variable (time is implicit), and refers to variables by their 1-based index
  in ModelVariables. Event indicators are not variables in FMI 2 (their number is
  an attribute), but we keep them as ``local`` variables, which is legal: the
  value references stay those of FMI 3, and a user can still plot them.
"""
from __future__ import annotations

import math
from dataclasses import dataclass

from components.dae import FlatModel
from components.lazy import lazy

from .codegen import ModelVariable, computed_outputs, variable_table
from .units import DEFAULT_DISPLAY_UNIT, DISPLAY_UNITS, UNITS, unit_exponents

ca = lazy("casadi")  # loaded by the first equation written, not by an import

GENERATION_TOOL = "mechfmu 0.1"
FMI_VERSIONS = (2, 3)
#: the FMI version of every FMU we write unless asked for another: build_fmu, export_fmu,
#: the composite and `mechfmu build`/`export` alike (SSP archives excepted: their members
#: are FMI 2, what fmpy's SSP runner instantiates)
DEFAULT_FMI = 3

LOG_CATEGORIES = (
    ("logEvents", "events: time, indicators, mode changes"),
    ("logStatusWarning", "warnings"),
    ("logStatusError", "errors, with what is allowed"),
    ("logSolver", "per step: internal steps, rejections, derivative evaluations, events"),
)


@dataclass
class Structure:
    """ModelStructure, version-free: variables and the value references they depend on.

    A dependency list of None means "may depend on anything" (a mode, which
    changes only at events): the writers then leave the attribute out.
    """
    outputs: list[tuple[ModelVariable, list[int] | None]]
    derivatives: list[tuple[ModelVariable, list[int]]]
    initial_unknowns: list[ModelVariable]
    indicators: list[tuple[ModelVariable, list[int]]]


def _dependencies(exprs: ca.SX, model: FlatModel, table: list[ModelVariable]) -> list[list[int]]:
    """For each entry of `exprs`, the value references of the states and inputs it
    structurally depends on (ascending column order, as listed before).

    One sparsity pattern for the whole vector: one pattern per entry cost the whole
    expression graph and the whole table each time, quadratic in a chain's blocks."""
    n = exprs.numel()
    knowns = [r.vr for r in table if r.kind in ("MF_STATE", "MF_INPUT")]
    symbols = ca.vertcat(model.x, model.u)
    if symbols.numel() == 0 or n == 0:
        return [[] for _ in range(n)]
    rows, cols = ca.jacobian_sparsity(exprs, symbols).get_triplet()
    found: list[set[int]] = [set() for _ in range(n)]
    for i, j in zip(rows, cols):
        found[i].add(j)
    return [[knowns[j] for j in sorted(cols_i)] for cols_i in found]


def model_structure(model: FlatModel, table: list[ModelVariable]) -> Structure:
    y_deps = _dependencies(computed_outputs(model), model, table)
    xdot_deps = _dependencies(model.xdot, model, table)
    outputs = []
    for r in table:
        if r.causality != "output":
            continue
        if r.kind == "MF_STATE":
            outputs.append((r, [r.vr]))
        elif r.kind == "MF_COMPUTED":
            outputs.append((r, y_deps[r.index]))
        else:  # a mode changes at events only; it may depend on anything
            outputs.append((r, None))
    derivatives = [(r, xdot_deps[r.index]) for r in table if r.kind == "MF_DERIVATIVE"]
    initial = [r for r in table
               if r.initial == "calculated" and (r.causality == "output" or r.kind == "MF_DERIVATIVE")]
    indicators = [(r, y_deps[r.index]) for r in table if r.is_indicator]
    return Structure(outputs, derivatives, initial, indicators)


def xml_attributes(**kw) -> str:
    """name="value" pairs, quoted for XML; None leaves the attribute out."""
    from xml.sax.saxutils import quoteattr  # here: it loads urllib (0.03 s), a cached run none
    return " ".join(f"{k}={quoteattr(str(v))}" for k, v in kw.items() if v is not None)


def _nominal(r: ModelVariable):
    """A state's declared nominal value (the one GetNominalsOfContinuousStates returns)."""
    return repr(float(r.nominal)) if r.kind == "MF_STATE" else None


def _start(r: ModelVariable):
    if r.start is None:
        return None
    return int(r.start) if r.is_integer else repr(float(r.start))


def _initial(r: ModelVariable) -> str | None:
    # the standards forbid `initial` on the independent variable and on inputs
    return r.initial if r.causality not in ("independent", "input") else None


def _declared_parameters(model: FlatModel) -> dict:
    """The component's parameter declarations by name, built once per description (one
    lookup per variable, not one dict per variable: quadratic in a chain's blocks)."""
    return {p.name: p for p in model.component.parameters}


def _range(declarations: dict, r: ModelVariable) -> tuple[str | None, str | None, str]:
    """min, max (finite bounds only) and description of a parameter from its declaration.

    FMI's min is inclusive, so a strict bound (m > 0) is declared as min="0" and the
    description says that 0 itself is excluded: an importer still learns the sign
    (omitting min would lose it), and the FMU refuses 0 at initialisation with the
    component's own message.
    """
    declared = declarations.get(r.name)
    if r.kind != "MF_PARAMETER" or declared is None:
        return None, None, r.description
    lo = repr(float(declared.min)) if math.isfinite(declared.min) else None
    hi = repr(float(declared.max)) if math.isfinite(declared.max) else None
    description = r.description
    if declared.min_strict and lo is not None:
        description += f" (must be > {declared.min:g}; min is inclusive in FMI, {declared.min:g} is excluded)"
    return lo, hi, description


def _display_unit(r: ModelVariable) -> str | None:
    return None if r.is_integer else DEFAULT_DISPLAY_UNIT.get(r.unit)


def _shared_head(model: FlatModel, table: list[ModelVariable], stop_time: float,
                 tolerance: float) -> list[str]:
    return shared_head({r.unit for r in table if r.unit}, stop_time, tolerance)


def shared_head(units: set[str], stop_time: float, tolerance: float | None = None,
                step: float | None = None, foreign_units: bool = False) -> list[str]:
    """UnitDefinitions, LogCategories, DefaultExperiment: the same shape in FMI 2 and 3.

    Our units must be in fmus/units.py (a typo fails the build); with `foreign_units`
    (an assembly FMU passing on other tools' variables) a unit we do not know is
    declared by name alone, which both standards allow."""
    out = ["  <UnitDefinitions>"]
    for unit in sorted(units):
        if foreign_units and unit not in UNITS:
            out.append(f"    <Unit {xml_attributes(name=unit)}/>")
            continue
        display = "".join(f"<DisplayUnit {xml_attributes(name=n, factor=repr(f))}/>"
                          for n, f in DISPLAY_UNITS.get(unit, ()))
        out.append(f"    <Unit {xml_attributes(name=unit)}><BaseUnit {xml_attributes(**unit_exponents(unit))}/>"
                   f"{display}</Unit>")
    out += ["  </UnitDefinitions>", "  <LogCategories>"]
    out += [f"    <Category {xml_attributes(name=n, description=d)}/>" for n, d in LOG_CATEGORIES]
    out += ["  </LogCategories>",
            "  <DefaultExperiment " + xml_attributes(startTime=0.0, stopTime=stop_time,
                                             tolerance=tolerance, stepSize=step) + "/>"]
    return out


def _fmi3(model, identifier, token, table, structure, head) -> list[str]:
    out = ["<fmiModelDescription " + xml_attributes(
               fmiVersion="3.0", modelName=identifier, instantiationToken=token,
               description=model.component.describe(), generationTool=GENERATION_TOOL,
               variableNamingConvention="structured") + ">",
           "  <ModelExchange " + xml_attributes(modelIdentifier=identifier, canGetAndSetFMUState="true",
                                        canSerializeFMUState="true",
                                        providesDirectionalDerivatives="true",
                                        providesAdjointDerivatives="true") + "/>",
           "  <CoSimulation " + xml_attributes(modelIdentifier=identifier,
                                       canHandleVariableCommunicationStepSize="true",
                                       providesIntermediateUpdate="true",
                                       mightReturnEarlyFromDoStep="true",
                                       canGetAndSetFMUState="true",
                                       canSerializeFMUState="true",
                                       providesDirectionalDerivatives="true",
                                       providesAdjointDerivatives="true") + "/>",
           *head, "  <ModelVariables>"]
    declarations = _declared_parameters(model)
    for r in table:
        tag = "Int32" if r.is_integer else "Float64"
        variability = r.variability if r.causality != "independent" else "continuous"
        lo, hi, description = _range(declarations, r)
        attrs = xml_attributes(name=r.name, valueReference=r.vr, description=description or None,
                       causality=r.causality, variability=variability, initial=_initial(r),
                       start=_start(r), unit=(r.unit or None) if not r.is_integer else None,
                       displayUnit=_display_unit(r), min=lo, max=hi, nominal=_nominal(r),
                       derivative=r.derivative_of)
        out.append(f"    <{tag} {attrs}/>")
    out += ["  </ModelVariables>", "  <ModelStructure>"]

    def deps(vrs):
        return None if vrs is None else " ".join(map(str, vrs))

    out += [f"    <Output {xml_attributes(valueReference=r.vr, dependencies=deps(d))}/>"
            for r, d in structure.outputs]
    out += [f"    <ContinuousStateDerivative {xml_attributes(valueReference=r.vr, dependencies=deps(d))}/>"
            for r, d in structure.derivatives]
    out += [f"    <InitialUnknown {xml_attributes(valueReference=r.vr)}/>" for r in structure.initial_unknowns]
    out += [f"    <EventIndicator {xml_attributes(valueReference=r.vr, dependencies=deps(d))}/>"
            for r, d in structure.indicators]
    return out + ["  </ModelStructure>"]


def _fmi2(model, identifier, token, table, structure, head, source_files=()) -> list[str]:
    listed = [r for r in table if r.kind != "MF_TIME"]  # time is implicit in FMI 2
    index = {r.vr: i + 1 for i, r in enumerate(listed)}  # FMI 2 refers by 1-based position
    common = dict(modelIdentifier=identifier, canGetAndSetFMUstate="true",
                  canSerializeFMUstate="true", canNotUseMemoryManagementFunctions="true",
                  providesDirectionalDerivative="true")
    # the C files under sources/, listed per interface as FMI 2 wants (no buildDescription.xml)
    files = "".join(f"<File {xml_attributes(name=f)}/>" for f in source_files)
    sources = f"<SourceFiles>{files}</SourceFiles></" if source_files else None
    out = ["<fmiModelDescription " + xml_attributes(
               fmiVersion="2.0", modelName=identifier, guid=token,
               description=model.component.describe(), generationTool=GENERATION_TOOL,
               variableNamingConvention="structured",
               numberOfEventIndicators=len(structure.indicators)) + ">",
           # fmi2CompletedIntegratorStep does nothing here: events come from the indicators
           "  <ModelExchange " + xml_attributes(**common, completedIntegratorStepNotNeeded="true")
           + (f">{sources}ModelExchange>" if sources else "/>"),
           # inputs are extrapolated inside the step from the flange's own velocity,
           # acceleration and rate inputs (components.dae), not from
           # fmi2SetRealInputDerivatives
           "  <CoSimulation " + xml_attributes(**common, canHandleVariableCommunicationStepSize="true",
                                       canInterpolateInputs="false")
           + (f">{sources}CoSimulation>" if sources else "/>"),
           *head, "  <ModelVariables>"]
    declarations = _declared_parameters(model)
    for r in listed:
        lo, hi, description = _range(declarations, r)
        out.append("    <ScalarVariable " + xml_attributes(
            name=r.name, valueReference=r.vr, description=description or None,
            causality=r.causality, variability=r.variability, initial=_initial(r)) + ">")
        if r.is_integer:
            typed = xml_attributes(start=_start(r))
        else:
            derivative = index[r.derivative_of] if r.derivative_of is not None else None
            typed = xml_attributes(start=_start(r), unit=r.unit or None, displayUnit=_display_unit(r),
                           min=lo, max=hi, nominal=_nominal(r), derivative=derivative)
        tag = "Integer" if r.is_integer else "Real"
        out.append(f"      <{tag}{' ' + typed if typed else ''}/>")
        out.append("    </ScalarVariable>")
    out += ["  </ModelVariables>", "  <ModelStructure>"]

    def unknowns(element, rows):
        if not rows:
            return []
        lines = [f"    <{element}>"]
        for r, d in rows:
            deps = None if d is None else " ".join(str(index[vr]) for vr in d)
            lines.append(f"      <Unknown {xml_attributes(index=index[r.vr], dependencies=deps)}/>")
        return lines + [f"    </{element}>"]

    out += unknowns("Outputs", structure.outputs)
    out += unknowns("Derivatives", structure.derivatives)
    out += unknowns("InitialUnknowns", [(r, None) for r in structure.initial_unknowns])
    return out + ["  </ModelStructure>"]


def model_description(model: FlatModel, model_identifier: str, token: str,
                      stop_time: float, tolerance: float = 1e-8, fmi_version: int = 3,
                      source_files: tuple[str, ...] = ()) -> str:
    """The whole modelDescription.xml; `token` is FMI 3's instantiationToken / FMI 2's guid.

    `source_files` (paths relative to sources/) are listed in FMI 2's <SourceFiles>;
    FMI 3 lists them in sources/buildDescription.xml instead (fmus.sources).
    """
    if fmi_version not in FMI_VERSIONS:
        raise ValueError(f"fmi_version must be one of {FMI_VERSIONS}, not {fmi_version!r}")
    table = variable_table(model)
    structure = model_structure(model, table)
    head = _shared_head(model, table, stop_time, tolerance)
    if fmi_version == 2:
        body = _fmi2(model, model_identifier, token, table, structure, head, source_files)
    else:
        body = _fmi3(model, model_identifier, token, table, structure, head)
    return "\n".join(['<?xml version="1.0" encoding="UTF-8"?>', *body, "</fmiModelDescription>", ""])
