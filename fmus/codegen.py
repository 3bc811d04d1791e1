"""C for one model: CasADi-generated functions plus the ``MF_MODEL`` table of model.h.

The variable table fixes the value references: vr 0 is time, then parameters,
states, state derivatives, inputs, computed variables (outputs, then event
indicators) and modes, in that order. :mod:`fmus.model_description` reads the
same table, so the C and the XML cannot disagree.
"""
from __future__ import annotations

import json
from dataclasses import dataclass

from components.dae import FlatModel
from components.lazy import lazy

ca = lazy("casadi")  # loaded by the first equation written, not by an import

FUNCTION_ORDER = ("ode", "out", "zc", "jump", "check", "jac")


@dataclass
class ModelVariable:
    """One row of the variable table: what the C runtime and the XML both need."""
    vr: int
    name: str
    kind: str          # MF_TIME, MF_PARAMETER, MF_STATE, MF_DERIVATIVE, MF_INPUT, MF_COMPUTED, MF_DISCRETE, MF_RUNTIME
    index: int
    unit: str
    description: str
    start: float | None
    is_integer: bool = False
    causality: str = "local"
    variability: str = "continuous"
    initial: str | None = None
    derivative_of: int | None = None   # vr of the state this variable is the derivative of
    input_derivative: int | None = None  # for inputs: index (in u) of its derivative input
    is_indicator: bool = False
    nominal: float = 1.0  # declared for states; FMI's default elsewhere
    #: the value the runtime starts from where the XML may state none (a mode: a
    #: calculated output, set by the model's own start before the initial event iteration)
    runtime_start: float | None = None


def variable_table(model: FlatModel) -> list[ModelVariable]:
    """Every variable of the FMU, in value-reference order."""
    rows: list[ModelVariable] = []

    def add(**kw):
        rows.append(ModelVariable(vr=len(rows), **kw))
        return rows[-1]

    add(name="time", kind="MF_TIME", index=0, unit="s", description="simulation time",
        start=None, causality="independent")
    for i, v in enumerate(model.parameters):
        add(name=v.name, kind="MF_PARAMETER", index=i, unit=v.unit, description=v.description,
            start=v.start, causality="parameter", variability="fixed", initial="exact")
    state_rows = []
    for i, (v, is_output) in enumerate(zip(model.states, model.state_outputs)):
        state_rows.append(add(name=v.name, kind="MF_STATE", index=i, unit=v.unit,
                              description=v.description, start=v.start, nominal=v.nominal,
                              causality="output" if is_output else "local", initial="exact"))
    for i, state in enumerate(state_rows):
        add(name=f"der({state.name})", kind="MF_DERIVATIVE", index=i,
            unit=_derivative_unit(state.unit), description=f"time derivative of {state.name}",
            start=None, initial="calculated", derivative_of=state.vr)
    for i, v in enumerate(model.inputs):
        add(name=v.name, kind="MF_INPUT", index=i, unit=v.unit, description=v.description,
            start=v.start, causality="input", input_derivative=v.derivative_input)
    for i, v in enumerate(model.outputs):
        add(name=v.name, kind="MF_COMPUTED", index=i, unit=v.unit, description=v.description,
            start=None, causality="output", initial="calculated")
    for i, v in enumerate(model.indicators):
        add(name=v.name, kind="MF_COMPUTED", index=len(model.outputs) + i, unit="",
            description=v.description, start=None, initial="calculated", is_indicator=True)
    for i, v in enumerate(model.modes):
        add(name=v.name, kind="MF_DISCRETE", index=i, unit="", description=v.description,
            start=None, is_integer=True, causality="output", variability="discrete",
            initial="calculated", runtime_start=v.start)
    # settings of the runtime itself, the same in every FMU, after the model's own
    # variables so that adding one never renumbers a model's value references
    add(name="solver", kind="MF_RUNTIME", index=0, unit="",
        description="Co-Simulation solver: 0 = DOPRI5 (explicit, non-stiff), "
                    "1 = RODAS3 (Rosenbrock, implicit, for stiff models), 2 = automatic (DOPRI5 "
                    "until stiffness shows, RODAS3 until it is gone); unused by Model Exchange",
        start=2, is_integer=True, causality="parameter", variability="fixed", initial="exact")
    return rows


def _derivative_unit(unit: str) -> str:
    return {"m": "m/s", "m/s": "m/s2", "rad": "rad/s", "rad/s": "rad/s2", "": "1/s"}.get(unit, f"{unit}/s")


def computed_outputs(model: FlatModel) -> ca.SX:
    """The `out` function's result: outputs, then event indicators (exposed as locals)."""
    return ca.vertcat(model.y, model.z)


def time_invariant(model: FlatModel) -> bool:
    """Time appears in none of the derivatives, outputs and event indicators: with its
    inputs held, the model stands still wherever its derivatives are zero, and setting
    the time alone changes nothing it computes."""
    return not ca.depends_on(ca.vertcat(model.xdot, computed_outputs(model)), model.t)


def constant_derivatives(model: FlatModel) -> bool:
    """Every state derivative is a constant of the parameters (ConstantSpeed's
    travel' = v) and no event indicator can fire: a step adds h xdot exactly, so the
    runtime takes it without its solver."""
    moving = ca.vertcat(model.t, model.x, model.q, model.u)
    return (model.x.numel() > 0 and model.z.numel() == 0
            and not ca.depends_on(model.xdot, moving))


def inputs_read(model: FlatModel) -> list[bool]:
    """For each input, whether any model function reads it. Rate inputs (components/dae.py
    rate_of) are read by no equation: they only carry their input along its Taylor chain,
    and Co-Simulation's inputs_at need not extrapolate them for their own sake."""
    read_by = ca.vertcat(model.xdot, model.y, model.z, model.jump_x, model.jump_q, model.g)
    if model.u.numel() == 0:
        return []
    # structural: a comparison (if_else, sign) counts as reading its operand
    columns = ca.jacobian_sparsity(read_by, model.u).colind()
    return [columns[i + 1] > columns[i] for i in range(model.u.numel())]


def directional_jacobian(model: FlatModel) -> ca.Function:
    """``mf_dd``: the Jacobian of [xdot; computed outputs] w.r.t. [x; u], its structural
    nonzeros only (the runtime scatters them by ``mf_dd_sparsity_out`` into a dense
    matrix whose zeros it never writes).

    One matrix rather than forward/reverse seeds: n is small for every component, and
    the runtime then serves directional (J s) and adjoint (s^T J) products for any
    subset of value references from one evaluation.
    """
    unknowns = ca.vertcat(model.xdot, computed_outputs(model))
    knowns = ca.vertcat(model.x, model.u)
    jac = ca.jacobian(unknowns, knowns) if knowns.numel() else ca.SX(unknowns.numel(), 0)
    return ca.Function("mf_dd", model.args, [jac], ["t", "x", "q", "u", "p"], ["dd"])


def _c_string(text: str) -> str:
    return json.dumps(text)  # a JSON string literal is a valid C string literal for our text


def _c_double(value: float) -> str:
    return repr(float(value)) if value is not None else "0.0"


def generate_c(model: FlatModel, model_name: str, token: str) -> str:
    """The whole model.c: CasADi's functions and the MF_MODEL table."""
    functions = model.functions()
    functions["out"] = ca.Function("mf_out", model.args, [ca.densify(computed_outputs(model))],
                                   ["t", "x", "q", "u", "p"], ["y"])
    functions["dd"] = directional_jacobian(model)
    functions.update(model.component.vectorised_functions(model))  # loops instead of unrolled SX
    # C written by the component itself for some functions (a composite's member loops):
    # CasADi writes the functions that C calls, and the rest
    own = functions.pop("c", None)
    gen = ca.CodeGenerator("model.c", {"with_header": False, "with_export": False,
                                        "casadi_real": "double", "casadi_int": "long long"})
    for key in FUNCTION_ORDER + ("dd",):
        if own is None or key not in own.FUNCTIONS:
            gen.add(functions[key])
    for kernel in own.kernels if own is not None else ():
        gen.add(kernel)
    table = variable_table(model)
    n_y = len(model.outputs) + len(model.indicators)
    lines = [gen.dump(), own.text() if own is not None else "", '#include "model.h"', ""]
    lines.append("static const mf_variable variables[] = {")
    for row in table:
        lines.append(f"    {{{_c_string(row.name)}, {row.kind}, {row.index}, {int(row.is_integer)}, "
                     f"{_c_double(row.start if row.runtime_start is None else row.runtime_start)}, "
                     f"{_c_double(row.nominal)}}},")
    lines.append("};")
    derivs = [(-1 if v.derivative_input is None else v.derivative_input) for v in model.inputs]
    lines.append(f"static const int input_derivative[] = {{{', '.join(map(str, derivs)) or '-1'}}};")
    read = ", ".join(str(int(r)) for r in inputs_read(model)) or "0"
    lines.append(f"static const int input_read[] = {{{read}}};")
    lines.append("static const mf_constraint constraints[] = {")
    for c in model.constraints:
        lines.append(f"    {{{_c_string(c.message)}, {int(c.strict)}}},")
    if not model.constraints:
        lines.append('    {"", 0},')
    lines.append("};")
    # C has no empty arrays: a model that never ends a run gets a -1 nobody reads
    lines.append("static const int terminate_q[] = {"
                 f"{', '.join(str(q) for q, _ in model.terminate) or '-1'}}};")
    lines.append("static const char *const terminate_message[] = {"
                 f"{', '.join(_c_string(why) for _, why in model.terminate) or '0'}}};")
    fn = ", ".join(f"{{mf_{k}, mf_{k}_work}}" for k in FUNCTION_ORDER)
    lines.append(f"""
const mf_model MF_MODEL = {{
    {_c_string(model_name)}, {_c_string(token)},
    {model.x.numel()}, {model.q.numel()}, {model.u.numel()}, {model.p.numel()}, {n_y},
    {model.z.numel()}, {len(model.constraints)},
    {len(table)}, variables, input_derivative, constraints,
    {fn},
    {len(model.terminate)}, terminate_q, terminate_message,
    {{mf_dd, mf_dd_work}},
    {int(time_invariant(model))},
    mf_dd_sparsity_out,
    {int(constant_derivatives(model))},
    input_read
}};
""")
    return "\n".join(lines)
