"""FMUs ready for the engine, prepared once per process.

Preparing an FMU means building it (``fmus.build_fmu`` of the class defaults under the
instance's profile and options: parameter studies reuse one binary, the instance's own
values are set as start values), reading its model description and extracting it.
That costs 0.02-0.3 s (flatten, codegen, hashing, unzip) and would dwarf a 1 ms run,
so the result is memoised by what determines the binary (:func:`binary_key`): the
component's class, profile, options and FMI version. A second run in one process
does none of it. A foreign FMU (:class:`assemblies.foreign.FMU`) is not built: its
file is prepared as it is (:func:`prepared_path`), memoised by path and file stamp.
"""
from __future__ import annotations

import functools
import threading
from dataclasses import dataclass, field
from pathlib import Path

from fmpy import extract, read_model_description

from fmus import build_fmu

from ..assembly import AssemblyError
from ..foreign import FMU
from ..masters.extrapolation import derivative_inputs

_lock = threading.Lock()
_by_key: dict = {}


@dataclass
class PreparedFmu:
    """What a master needs of one FMU, read once from its model description."""
    path: str
    unzip_dir: str
    token: str
    fmi_version: int
    me_identifier: str | None
    cs_identifier: str | None
    n_states: int
    n_event_indicators: int
    can_get_set_state: bool                 # Co-Simulation capability flags
    provides_directional_derivative: bool
    variables: dict = field(default_factory=dict)  # name -> (value reference, is Int32)
    outputs: list = field(default_factory=list)
    inputs: list = field(default_factory=list)
    depends: dict = field(default_factory=dict)    # output -> the inputs it depends on
    states: list = field(default_factory=list)
    chained: dict = field(default_factory=dict)    # input the FMU extrapolates -> its derivative input

    @property
    def model_identifier(self) -> str:
        """The Co-Simulation identifier (what the cosim master loads)."""
        return self.cs_identifier

    def variable(self, instance: str, name: str) -> tuple[int, bool]:
        if name not in self.variables:
            raise AssemblyError(f"{instance} has no variable '{name}'")
        return self.variables[name]

    def typed_starts(self, instance: str, starts: dict) -> tuple[list, list]:
        """Parameters and start values by name as ([(vr, float)], [(vr, int)]): the two
        value types the FMI calls set separately."""
        floats, ints = [], []
        for name, value in starts.items():
            vr, is_int = self.variable(instance, name)
            (ints if is_int else floats).append((vr, int(value) if is_int else float(value)))
        return floats, ints


@functools.lru_cache(maxsize=None)
def prepared_path(path: str, stamp: tuple = ()) -> PreparedFmu:
    """An FMU file, ours or any tool's, read and extracted once (the same file is never
    extracted twice); `stamp` (e.g. its mtime and size) makes a file rebuilt at the
    same path a different entry."""
    # not validated: fmpy's validation rejects what many tools write (CasADi's export
    # lacks UnitDefinitions) though the engine needs none of it; ours are validated by
    # the tests
    md = read_model_description(path, validate=False)
    me, cs = md.modelExchange, md.coSimulation
    p = PreparedFmu(
        path=path, unzip_dir=str(Path(extract(path))), token=md.guid,
        fmi_version=int(md.fmiVersion[0]),
        me_identifier=me.modelIdentifier if me else None,
        cs_identifier=cs.modelIdentifier if cs else None,
        n_states=len(md.derivatives), n_event_indicators=md.numberOfEventIndicators or 0,
        can_get_set_state=bool(cs and cs.canGetAndSetFMUstate),
        provides_directional_derivative=bool(cs and cs.providesDirectionalDerivative))
    p.variables = {v.name: (v.valueReference, v.type in ("Int32", "Integer"))
                   for v in md.modelVariables}
    p.outputs = [v.name for v in md.modelVariables if v.causality == "output"]
    p.inputs = [v.name for v in md.modelVariables if v.causality == "input"]
    p.depends = {u.variable.name: (set(p.inputs) if u.dependencies is None else
                                   {d.name for d in u.dependencies if d.causality == "input"})
                 for u in md.outputs}
    p.states = [u.variable.derivative.name for u in md.derivatives]
    return p


def options_key(component) -> tuple:
    """The component's options as a hashable key (the options shape the binary)."""
    return tuple(sorted((k, repr(v)) for k, v in component.option_values.items()))


def binary_key(component) -> tuple:
    """What determines `component`'s FMU binary: for ours the class, profile and options
    (values are set per run); for a foreign FMU its file."""
    if isinstance(component, FMU):
        return ("fmu", str(component.path), component.stamp)
    return (type(component), component.profile.name, options_key(component))


def prepared(component, fmi_version: int = 3) -> PreparedFmu:
    """The FMU of `component`'s class under its profile and options (see the module doc);
    a foreign FMU's own file (`fmi_version` is then the file's, not a choice)."""
    if isinstance(component, FMU):
        return prepared_path(str(component.path), component.stamp)
    key = (*binary_key(component), fmi_version)
    with _lock:
        hit = _by_key.get(key)
    if hit is not None:
        return hit
    defaults = type(component)(name=component.name, profile=component.profile.name,
                               **component.option_values)
    fmu = prepared_path(str(build_fmu(defaults, fmi_version=fmi_version)))
    fmu.chained = derivative_inputs(component)
    with _lock:
        _by_key[key] = fmu
    return fmu


def prepared_composite(assembly, fmi_version: int = 3):
    """(composite component, its PreparedFmu) of a joined assembly, memoised by the
    assembly's structure: names, classes, profiles, options and connections. The
    composite's parameters and starts are set per run, so values are not in the key."""
    from ..masters.monolithic import composite
    assembly.resolve_causality()
    key = ("composite", assembly.name, fmi_version, tuple(
        (name, *binary_key(c)) for name, c in assembly.components.items()),
        tuple((c.a, c.b) for c in assembly.connections))
    with _lock:
        hit = _by_key.get(key)
    if hit is not None:
        return hit
    comp = composite(assembly)
    result = (comp, prepared_path(str(build_fmu(comp, fmi_version=fmi_version))))
    with _lock:
        _by_key[key] = result
    return result


def record_columns(fmus: dict, record: list[str] | None) -> list[tuple[str, str]]:
    """(instance, variable) of each recorded column: `record`'s names checked against the
    FMUs (every output of every instance when None)."""
    if record is None:
        return [(name, v) for name, fmu in fmus.items() for v in fmu.outputs]
    columns = []
    for ref in record:
        instance, _, var = ref.partition(".")
        if instance not in fmus:
            raise AssemblyError(f"cannot record '{ref}': no instance '{instance}'; "
                                f"instances: {', '.join(fmus)}")
        if var not in fmus[instance].variables:
            raise AssemblyError(f"cannot record '{ref}': {instance} has no variable '{var}'")
        columns.append((instance, var))
    return columns
