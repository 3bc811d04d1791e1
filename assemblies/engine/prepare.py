"""FMUs ready for the engine, prepared once per process.

Preparing an FMU means building it (``fmus.build_fmu`` of the class defaults under the
instance's profile and options: parameter studies reuse one binary, the instance's own
values are set as start values), reading its model description and extracting it.
Done naively that costs 0.02-0.3 s (flatten, codegen, hashing, unzip, XML) and would
dwarf a 1 ms run, so nothing of it is repeated:

- in one process, the result is memoised by what determines the binary
  (:func:`binary_key`): the component's class, profile, options and FMI version;
- across processes, the FMU is found by its recipe (:func:`fmus.build.fetch_fmu`, no
  flattening), and an FMU of the cache is extracted once, beside a JSON of what its
  model description says (:func:`prepared_path`), so a cached run reads one small file.

A foreign FMU (:class:`assemblies.foreign.FMU`) is not built: its file is prepared as
it is, memoised in the process by path and file stamp.
"""
from __future__ import annotations

import dataclasses
import functools
import json
import os
import shutil
import threading
from dataclasses import dataclass, field
from pathlib import Path

from fmus import build as fmu_build, integrity
from fmus.build import cache_dir, cached_fmu, fetch_fmu, fmu_recipe, recipes
from fmus.recipe import combine, files_digest

from ..assembly import AssemblyError
from ..foreign import FMU
from ..value_types import MAX_ARRAY, STRING, code, element_names, size

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
    me_directional_derivative: bool         # the Model Exchange interface's flag
    # name -> (value reference, type code (value_types.CODES), element, array size): a
    # scalar, or one element of an FMI 3 array (its name ``x[2]``: value_types)
    variables: dict = field(default_factory=dict)
    arrays: dict = field(default_factory=dict)     # array name -> its elements' names
    outputs: list = field(default_factory=list)
    inputs: list = field(default_factory=list)
    depends: dict = field(default_factory=dict)    # output -> the inputs it depends on
    # the inputs the state derivatives, and the event indicators, depend on (all inputs
    # where the model description does not say)
    derivatives_depend: set = field(default_factory=set)
    indicators_depend: set = field(default_factory=set)
    states: list = field(default_factory=list)
    derivatives: list = field(default_factory=list)  # of `states`, in their order
    chained: dict = field(default_factory=dict)    # input the FMU extrapolates -> its derivative input
    rate_inputs: tuple = ()  # inputs a co-simulation master sets from its extrapolation, none else
    autonomous: bool = False  # ours, with no explicit time (fmus.build.model_facts)
    # Model Exchange: the FMU needs no fmiCompletedIntegratorStep after each step
    completed_step_not_needed: bool = False
    # built here from a component: its outputs follow every set call, as FMI asks; a
    # foreign FMU may compute them in the set calls alone (me.c's write_row)
    ours: bool = False

    @property
    def model_identifier(self) -> str:
        """The Co-Simulation identifier (what the cosim master loads)."""
        return self.cs_identifier

    def variable(self, instance: str, name: str) -> tuple[int, int, int, int]:
        """(value reference, type code, element, size) of a variable or array element."""
        if name not in self.variables:
            raise AssemblyError(f"{instance} has no variable '{name}'")
        return self.variables[name]

    def start_list(self, instance: str, name: str) -> int:
        """Which of typed_starts' lists a value set before initialisation belongs in: 0
        a Float64 scalar, 1 an Int32 one, 2 another numeric type or an array element,
        3 a String (the engine sets each list its own way: eng_instance_spec)."""
        _, kind, _, n = self.variable(instance, name)
        return 3 if kind == STRING else 2 if n > 1 or kind not in (0, 1) else kind

    def typed_starts(self, instance: str, starts: dict) -> tuple[list, list, list, list]:
        """Parameters and start values by name as the engine sets them:
        ([(vr, float)] of Float64 scalars, [(vr, int)] of Int32 ones, [(variable, float)]
        of the other numeric types and array elements, [(vr, str)] of Strings)."""
        lists = ([], [], [], [])
        convert = (float, int, float, str)
        for name, value in starts.items():
            var = self.variable(instance, name)
            k = self.start_list(instance, name)
            lists[k].append((var if k == 2 else var[0], convert[k](value)))
        return lists


@functools.lru_cache(maxsize=None)
def prepared_path(path: str, stamp: tuple = ()) -> PreparedFmu:
    """An FMU file, ours or any tool's, read and extracted once (the same file is never
    extracted twice in a process); `stamp` (e.g. its mtime and size) makes a file
    rebuilt at the same path a different entry. An FMU of the cache (named by its
    content, so never rewritten) is extracted once for all processes."""
    path = str(path)
    if Path(path).parent == cache_dir() / "fmus":
        return _prepared_in_cache(Path(path))
    return _read(path, _extract_to_temp(path))


def _extract_to_temp(path: str) -> str:
    from fmpy import extract
    return str(Path(extract(path)))


def _read(path: str, unzip_dir: str) -> PreparedFmu:
    from fmpy import read_model_description
    # not validated: fmpy's validation rejects what many tools write (CasADi's export
    # lacks UnitDefinitions) though the engine needs none of it; ours are validated by
    # the tests
    md = read_model_description(path, validate=False)
    me, cs = md.modelExchange, md.coSimulation
    p = PreparedFmu(
        path=path, unzip_dir=unzip_dir, token=md.guid,
        fmi_version=int(md.fmiVersion[0]),
        me_identifier=me.modelIdentifier if me else None,
        cs_identifier=cs.modelIdentifier if cs else None,
        n_states=sum(_size(u.variable) for u in md.derivatives),
        n_event_indicators=_event_indicators(md),
        can_get_set_state=bool(cs and cs.canGetAndSetFMUstate),
        # fmpy reads FMI 2's completedIntegratorStepNotNeeded into this flag too
        completed_step_not_needed=bool(me and not me.needsCompletedIntegratorStep),
        **_directional_derivatives(md, unzip_dir))
    carried = [v for v in md.modelVariables
               if code(v.type) is not None and _size(v) <= MAX_ARRAY and _size(v) > 0]
    for v in carried:
        shape = _shape(v)
        names = element_names(v.name, shape)
        if shape:
            p.arrays[v.name] = names
        p.variables.update({name: (v.valueReference, code(v.type), i, size(shape) if shape else 1)
                            for i, name in enumerate(names)})
    p.outputs = [n for v in carried if v.causality == "output" for n in _elements(v)]
    p.inputs = [n for v in carried if v.causality == "input" for n in _elements(v)]
    p.depends = {n: _inputs_of([u], p.inputs) for u in md.outputs for n in _elements(u.variable)}
    p.derivatives_depend = _inputs_of(md.derivatives, p.inputs)
    # FMI 2 does not list the indicators' dependencies, and FMI 3 need not
    indicators = getattr(md, "eventIndicators", None) or []
    p.indicators_depend = (_inputs_of(indicators, p.inputs)
                           if sum(map(_size, (u.variable for u in indicators)))
                           == p.n_event_indicators else set(p.inputs))
    # an FMI 3 array state is as many states as it has elements, in row-major order
    p.states = [n for u in md.derivatives for n in _elements(u.variable.derivative)]
    p.derivatives = [n for u in md.derivatives for n in _elements(u.variable)]
    return p


def _shape(v) -> tuple:
    return tuple(getattr(v, "shape", None) or ())


def _size(v) -> int:
    return size(_shape(v))


def _elements(v) -> list[str]:
    """A variable's names as the engine knows them: itself, or its array's elements."""
    return element_names(v.name, _shape(v))


def _event_indicators(md) -> int:
    """FMI 3 lists its indicators (an array counts its elements); FMI 2 counts them."""
    indicators = getattr(md, "eventIndicators", None)
    if md.fmiVersion.startswith("3") and indicators:
        return sum(_size(u.variable) for u in indicators)
    return md.numberOfEventIndicators or 0


def _inputs_of(unknowns, inputs: list) -> set:
    """The inputs (array inputs by their elements) some of `unknowns` (ModelStructure
    entries) depend on; all of them where an entry does not list its dependencies."""
    depend = set()
    for u in unknowns:
        if u.dependencies is None:
            return set(inputs)
        depend |= {n for d in u.dependencies if d.causality == "input" for n in _elements(d)}
    return depend


def _directional_derivatives(md, unzip_dir: str) -> dict:
    """Whether each interface provides directional derivatives. fmpy reads FMI 2's
    providesDirectionalDerivative but not FMI 3's providesDirectionalDerivatives (plural),
    which it leaves False; FMI 3's is read from the model description here."""
    me, cs = md.modelExchange, md.coSimulation
    if md.fmiVersion.startswith("2"):
        return {"me_directional_derivative": bool(me and me.providesDirectionalDerivative),
                "provides_directional_derivative": bool(cs and cs.providesDirectionalDerivative)}
    from xml.etree import ElementTree
    root = ElementTree.parse(Path(unzip_dir) / "modelDescription.xml").getroot()

    def provides(interface: str) -> bool:
        return any(e.get("providesDirectionalDerivatives") in ("true", "1")
                   for e in root.findall(interface))
    return {"me_directional_derivative": provides("ModelExchange"),
            "provides_directional_derivative": provides("CoSimulation")}


#: what a summary JSON holds; one written with other fields is read again from its FMU
_SUMMARY_VERSION = 4


def _prepared_in_cache(path: Path) -> PreparedFmu:
    """cache/prepared/<fmu name>/ (the extracted FMU) and <fmu name>.json (its PreparedFmu):
    written once, atomically, read by every later process."""
    folder = cache_dir() / "prepared"
    unzip_dir, summary = folder / path.stem, folder / f"{path.stem}.json"
    if unzip_dir.is_dir() and not integrity.extracted_intact(path, unzip_dir):
        # the engine loads the binary from here: a damaged one would crash every run
        integrity.report(unzip_dir, "extracted FMU", fmu_build.announce, "extracting it again")
        shutil.rmtree(unzip_dir, ignore_errors=True)
    try:
        saved = json.loads(summary.read_text())
        if unzip_dir.is_dir():
            return _from_json(saved, str(path), str(unzip_dir))
    except (OSError, ValueError, TypeError, KeyError):
        pass
    import zipfile
    folder.mkdir(parents=True, exist_ok=True)
    if not unzip_dir.is_dir():
        partial = folder / f"{path.stem}.{os.getpid()}.partial"
        shutil.rmtree(partial, ignore_errors=True)
        with zipfile.ZipFile(path) as zf:
            zf.extractall(partial)
        try:
            partial.rename(unzip_dir)  # atomic; a parallel process may have won the race
        except OSError:
            shutil.rmtree(partial, ignore_errors=True)
    p = _read(str(path), str(unzip_dir))
    partial = summary.with_suffix(f".{os.getpid()}.partial")
    partial.write_text(json.dumps(_to_json(p)))
    partial.replace(summary)
    return p


def _to_json(p: PreparedFmu) -> dict:
    d = dataclasses.asdict(p)
    d["depends"] = {k: sorted(v) for k, v in p.depends.items()}
    d["derivatives_depend"] = sorted(p.derivatives_depend)
    d["indicators_depend"] = sorted(p.indicators_depend)
    d["chained"] = dict(p.chained)
    d["summary_version"] = _SUMMARY_VERSION
    del d["path"], d["unzip_dir"]  # where the reader finds them
    return d


def _from_json(d: dict, path: str, unzip_dir: str) -> PreparedFmu:
    if d.pop("summary_version", None) != _SUMMARY_VERSION:
        raise KeyError("summary_version")  # written by an older reader: read the FMU again
    d = dict(d, path=path, unzip_dir=unzip_dir)
    d["derivatives_depend"] = set(d["derivatives_depend"])
    d["indicators_depend"] = set(d["indicators_depend"])
    d["variables"] = {k: tuple(v) for k, v in d["variables"].items()}
    d["depends"] = {k: set(v) for k, v in d["depends"].items()}
    d["chained"] = dict(d["chained"])
    return PreparedFmu(**d)


def options_key(component) -> tuple:
    """The component's options as a hashable key (the options shape the binary)."""
    return tuple(sorted((k, repr(v)) for k, v in component.option_values.items()))


def binary_key(component) -> tuple:
    """What determines `component`'s FMU binary: for ours the class, profile and options
    (values are set per run); for a foreign FMU its file."""
    if isinstance(component, FMU):
        return ("fmu", str(component.path), component.stamp)
    return (type(component), component.profile.name, options_key(component))


def structure_key(assembly) -> tuple:
    """What an assembly's runs share whatever their values: its name, each instance's
    binary_key and the connections (a key to memoise what depends on structure only)."""
    return (assembly.name,
            tuple((n, *binary_key(c)) for n, c in assembly.components.items()),
            tuple((c.a, c.b) for c in assembly.connections))


def rest_groups(names: list[str], couplings, fmus: dict) -> list[int]:
    """Per instance, its group: the instances joined to it by couplings (either way);
    -1 for a group that can never be seen to rest (a member with explicit time, one we
    did not make, or one whose derivatives are not listed with its states)."""
    group = {n: n for n in names}

    def root(n):
        while group[n] != n:
            n = group[n]
        return n

    for c in couplings:
        group[root(c.source[0])] = root(c.target[0])
    able = {n: fmus[n].autonomous and len(fmus[n].derivatives) == len(fmus[n].states)
            for n in names}
    roots = [root(n) for n in names]
    restless = {r for r, n in zip(roots, names) if not able[n]}
    index = {r: i for i, r in enumerate(dict.fromkeys(roots))}
    return [-1 if r in restless else index[r] for r in roots]


def class_defaults(component):
    """A component of `component`'s class, profile and options with the class's default
    values: what its FMU is built from (values and starts are set per run)."""
    return type(component)(name=component.name, profile=component.profile.name,
                           **component.option_values)


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
    built = fetch_fmu(class_defaults(component), fmi_version=fmi_version)
    fmu = prepared_path(str(built.path))
    fmu.chained = dict(built.facts["chained_inputs"])
    fmu.rate_inputs = tuple(built.facts["rate_inputs"])
    fmu.autonomous = bool(built.facts.get("autonomous", False))  # unknown: it may move
    fmu.ours = True
    with _lock:
        _by_key[key] = fmu
    return fmu


@dataclass
class JoinedLayout:
    """What a run of a composite FMU needs of the joined model, kept in the recipe store
    so that a cached composite is used without joining anything."""
    outputs: dict                # instance -> names of its outputs, in FMU order
    owner_of_indicator: list     # instance owning each event indicator of the composite
    indicators_follow_time: bool
    terminate: list = field(default_factory=list)  # [instance, why]: members that can end a run


def member_termination(terminated: dict | None, members, composite: str) -> dict | None:
    """A composite run's ``settings["terminated"]`` in its member's terms. `members`:
    (instance, why) of each member that can end a run; `composite`: the composite's
    instance name. The composite's reason is the member's prefixed by the member's name,
    which says whose it is; the result then reads as the member's own run would (its
    instance, and the message the member's own FMU logs)."""
    if not terminated:
        return terminated
    message = terminated.get("message") or ""
    for instance, why in members:
        if f"{instance}: {why}" in message:
            message = message.replace(f"{instance}: {why}", why, 1)
            if message.startswith(f"{composite}: "):  # the importer's instance prefix
                message = f"{instance}: {message.removeprefix(f'{composite}: ')}"
            return dict(terminated, instance=instance, message=message)
    if len(members) == 1:  # an importer that kept no message: only one member can
        return dict(terminated, instance=members[0][0])
    return terminated


def assembly_recipe(assembly, *parts) -> str | None:
    """A recipe key of `assembly`'s structure: each member's class recipe (at its class
    defaults) under its resolved profile and options, the connections and `parts`; None
    where a member has no recipe (a foreign FMU, a class made at run time)."""
    assembly.resolve_causality()
    members = []
    for name, comp in assembly.components.items():
        if isinstance(comp, FMU):
            return None
        member = fmu_recipe(class_defaults(comp))
        if member is None:
            return None
        members.append((name, member))
    return combine("assembly", assembly.name, assembly.signals_from_outside, members,
                   [(c.a, c.b) for c in assembly.connections], files_digest(_JOINING_CODE),
                   *parts)


# what turns members into one model beyond the members' own recipes (which hold the
# builder and the components): the joining and the causality resolution. Named, not
# followed through imports: the closure of these modules is the whole package, and
# reading it would cost a cached run 15 ms
_ASSEMBLIES = Path(__file__).resolve().parent.parent
_JOINING_CODE = [_ASSEMBLIES / "masters" / "monolithic.py",
                 _ASSEMBLIES / "masters" / "composite_code.py", _ASSEMBLIES / "assembly.py",
                 _ASSEMBLIES / "causality.py"]


def defaults_assembly(assembly):
    """A copy of `assembly` whose members carry their class defaults under the profiles
    resolved for `assembly`: what a composite FMU is built from, so that parameter
    studies reuse one binary (values and starts are set per run)."""
    from ..assembly import Assembly
    assembly.resolve_causality()
    copy = Assembly(assembly.name)
    copy.signals_from_outside = assembly.signals_from_outside
    for name, comp in assembly.components.items():
        copy.add(name, class_defaults(comp))
    for c in assembly.connections:
        copy.connect(c.a, c.b)
    return copy


def prepared_composite(assembly, fmi_version: int = 3) -> tuple[JoinedLayout, PreparedFmu]:
    """(layout of the joined model, its PreparedFmu) of a joined assembly, memoised by
    the assembly's structure: names, classes, profiles, options and connections, in the
    process and (through :func:`assembly_recipe`) across processes. The composite's
    parameters and starts are set per run, so values are not in the key."""
    from ..masters.monolithic import composite
    assembly.resolve_causality()
    key = ("composite", assembly.name, fmi_version, tuple(
        (name, *binary_key(c)) for name, c in assembly.components.items()),
        tuple((c.a, c.b) for c in assembly.connections))
    with _lock:
        hit = _by_key.get(key)
    if hit is not None:
        return hit
    recipe = assembly_recipe(assembly, "composite", fmi_version)
    saved = recipes().get(recipe).get("layout")
    built = cached_fmu(recipe) if saved is not None else None
    if built is None:
        comp = composite(defaults_assembly(assembly))
        built = fetch_fmu(comp, fmi_version=fmi_version, key=recipe)
        saved = {"outputs": comp.joined.outputs,
                 "owner_of_indicator": list(comp.joined.owner_of_indicator),
                 "indicators_follow_time": built.facts["indicators_follow_time"],
                 "terminate": [[name, why] for _, name, why in comp.joined.terminate]}
        recipes().update(recipe, layout=saved)
    fmu = prepared_path(str(built.path))
    fmu.autonomous = bool(built.facts.get("autonomous", False))  # unknown: it may move
    fmu.ours = True
    result = (JoinedLayout(**saved), fmu)
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
        if var in fmus[instance].arrays:  # an array: a column per element
            columns += [(instance, element) for element in fmus[instance].arrays[var]]
            continue
        if var not in fmus[instance].variables:
            raise AssemblyError(f"cannot record '{ref}': {instance} has no variable '{var}'")
        columns.append((instance, var))
    return columns
