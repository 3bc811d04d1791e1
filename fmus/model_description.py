"""modelDescription.xml for FMI 3.0 (Model Exchange and Co-Simulation in one FMU).

Dependencies in ModelStructure come from CasADi's structural sparsity, so they
are exact: an output lists exactly the states and inputs it depends on.
"""
from __future__ import annotations

from xml.sax.saxutils import quoteattr

import casadi as ca

from components.dae import FlatModel

from .codegen import ModelVariable, computed_outputs, variable_table
from .units import unit_exponents

GENERATION_TOOL = "mechfmu 0.1"


def _dependencies(expr: ca.SX, model: FlatModel, table: list[ModelVariable]) -> str:
    """Value references of the states and inputs that `expr` structurally depends on."""
    knowns = [r for r in table if r.kind in ("MF_STATE", "MF_INPUT")]
    symbols = ca.vertcat(model.x, model.u)
    if symbols.numel() == 0:
        return ""
    sp = ca.jacobian_sparsity(expr, symbols)
    cols = sorted(set(sp.get_col()))
    return " ".join(str(knowns[c].vr) for c in cols)


def _attrs(**kw) -> str:
    return " ".join(f"{k}={quoteattr(str(v))}" for k, v in kw.items() if v is not None)


def model_description(model: FlatModel, model_identifier: str, token: str,
                      stop_time: float, tolerance: float = 1e-8) -> str:
    table = variable_table(model)
    component = model.component
    y = computed_outputs(model)
    units = sorted({r.unit for r in table if r.unit})
    out = ['<?xml version="1.0" encoding="UTF-8"?>',
           "<fmiModelDescription " + _attrs(
               fmiVersion="3.0", modelName=model_identifier, instantiationToken=token,
               description=component.describe(), generationTool=GENERATION_TOOL,
               variableNamingConvention="structured") + ">",
           "  <ModelExchange " + _attrs(modelIdentifier=model_identifier,
                                        canGetAndSetFMUState="true",
                                        canSerializeFMUState="true") + "/>",
           "  <CoSimulation " + _attrs(modelIdentifier=model_identifier,
                                       canHandleVariableCommunicationStepSize="true",
                                       providesIntermediateUpdate="true",
                                       canGetAndSetFMUState="true",
                                       canSerializeFMUState="true") + "/>",
           "  <UnitDefinitions>"]
    for unit in units:
        exps = unit_exponents(unit)
        out.append(f"    <Unit {_attrs(name=unit)}><BaseUnit {_attrs(**exps)}/></Unit>")
    out += ["  </UnitDefinitions>",
            "  <LogCategories>",
            '    <Category name="logEvents" description="events: time, indicators, mode changes"/>',
            '    <Category name="logStatusWarning" description="warnings"/>',
            '    <Category name="logStatusError" description="errors, with what is allowed"/>',
            '    <Category name="logSolver" description="per step: internal steps, rejections, '
            'derivative evaluations, events"/>',
            "  </LogCategories>",
            "  " + "<DefaultExperiment " + _attrs(startTime=0.0, stopTime=stop_time,
                                                  tolerance=tolerance) + "/>",
            "  <ModelVariables>"]
    for r in table:
        tag = "Int32" if r.is_integer else "Float64"
        start = None
        if r.start is not None:
            start = int(r.start) if r.is_integer else repr(float(r.start))
        variability = r.variability if r.causality != "independent" else "continuous"
        attrs = _attrs(name=r.name, valueReference=r.vr, description=r.description or None,
                       causality=r.causality, variability=variability,
                       initial=r.initial if r.causality not in ("independent", "input") else None,
                       start=start, unit=(r.unit or None) if not r.is_integer else None,
                       derivative=r.derivative_of)
        out.append(f"    <{tag} {attrs}/>")
    out += ["  </ModelVariables>", "  <ModelStructure>"]
    for r in table:
        if r.causality != "output":
            continue
        if r.kind == "MF_STATE":
            deps = str(r.vr)
        elif r.kind == "MF_COMPUTED":
            deps = _dependencies(y[r.index], model, table)
        else:  # a mode changes at events only; it may depend on anything
            out.append(f"    <Output {_attrs(valueReference=r.vr)}/>")
            continue
        out.append(f"    <Output {_attrs(valueReference=r.vr, dependencies=deps)}/>")
    for r in table:
        if r.kind == "MF_DERIVATIVE":
            deps = _dependencies(model.xdot[r.index], model, table)
            out.append(f"    <ContinuousStateDerivative {_attrs(valueReference=r.vr, dependencies=deps)}/>")
    for r in table:
        if r.initial == "calculated" and (r.causality == "output" or r.kind == "MF_DERIVATIVE"):
            out.append(f"    <InitialUnknown {_attrs(valueReference=r.vr)}/>")
    for r in table:
        if r.is_indicator:
            deps = _dependencies(y[r.index], model, table)
            out.append(f"    <EventIndicator {_attrs(valueReference=r.vr, dependencies=deps)}/>")
    out += ["  </ModelStructure>", "</fmiModelDescription>", ""]
    return "\n".join(out)
