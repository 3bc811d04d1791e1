"""ModelStructure's dependency lists, computed for all outputs at once, against the
definition written per expression: a variable depends on exactly the states and inputs
in whose column its own Jacobian row has a structural nonzero (CasADi's sparsity of
that one expression), ascending, as the FMI writers list them."""
from __future__ import annotations

import casadi as ca
import pytest

import components as C
from assemblies.masters.monolithic import composite
from assemblies.scenes.burridge_knopoff import fault_chain
from components.dae import flatten
from fmus.codegen import computed_outputs, variable_table
from fmus.model_description import model_structure


def _one_by_one(expr, model, table):
    knowns = [r for r in table if r.kind in ("MF_STATE", "MF_INPUT")]
    symbols = ca.vertcat(model.x, model.u)
    if symbols.numel() == 0:
        return []
    return [knowns[c].vr for c in sorted(set(ca.jacobian_sparsity(expr, symbols).get_col()))]


def _models():
    yield "SpringBlock", flatten(C.SpringBlock())
    yield "FaultBlock", flatten(C.FaultBlock())
    yield "ConstantSpeed", flatten(C.ConstantSpeed())   # no states: every list empty
    yield "chain4", flatten(composite(fault_chain(4)))  # a composite: coupled blocks


@pytest.mark.parametrize("name,model", list(_models()), ids=lambda v: v if isinstance(v, str) else "")
def test_dependencies_match_the_per_expression_definition(name, model):
    table = variable_table(model)
    s = model_structure(model, table)
    y = computed_outputs(model)
    for r, deps in s.outputs:
        if r.kind == "MF_COMPUTED":
            assert deps == _one_by_one(y[r.index], model, table), r.name
    for r, deps in s.derivatives:
        assert deps == _one_by_one(model.xdot[r.index], model, table), r.name
    for r, deps in s.indicators:
        assert deps == _one_by_one(y[r.index], model, table), r.name
    if name == "chain4":
        # a middle block's acceleration sees its neighbours through the coupling springs
        # and not the far end: the lists are not all-or-nothing
        deriv = {r.name: d for r, d in s.derivatives}
        vr = {r.name: r.vr for r in table}
        a2 = next(d for n, d in deriv.items() if n.startswith("der(block2.v"))
        assert vr["block1.x"] in a2 and vr["block3.x"] in a2 and vr["block4.x"] not in a2
