"""Any FMU as an instance of an assembly: ``asm.add("ctrl", FMU("controller.fmu"))``.

An FMU from another tool (FMI 2.0 or 3.0, Model Exchange and/or Co-Simulation) joins
an assembly as a :class:`components.component.Block` (what an assembly needs of an
instance; our components are Blocks with CasADi equations), read from its model
description:

- its inputs and outputs of every FMI type the engine carries (Float64/Real, Float32,
  Int8...UInt64, Int32/Integer, Boolean, Enumeration, String:
  :mod:`assemblies.value_types`) are signal ports named after the variables
  (structured names such as ``a.b[1]`` kept), with the FMU's units, so
  ``Assembly.connect`` checks units and types as for our ports; an FMI 3 array is one
  port of its shape, connected whole and recorded element by element (``y[1]``,
  ``m[1,2]``: row-major); one profile (inputs in, outputs out), so the causality
  resolution needs no special case for it;
- its inputs are *optional* ports: one left unconnected keeps its start value, as FMI
  defines (ours must be connected);
- its parameters (causality ``parameter``, fixed or tunable), its inputs' start values
  and the start values of its continuous states that may be set (initial exact or
  approx) are settable by name, defaulting to the FMU's own start values and checked
  like ours (finite, within the declared min/max and the type's range; whole numbers
  for the integer types, True/False for Boolean, text for String); an array's elements
  by their names (``lam[2]``), its continuous states per element.

A Binary or Clock variable (or a clocked one, or a String array) that is an input, an
output or a parameter refuses the FMU at ``FMU(path)``, in one line naming it; a local
one is left alone.

It carries no CasADi equations (it is no ``Component``), so it cannot be joined
symbolically (mode ``monolithic``); the compiled engine runs it from its file
(``engine.prepare.prepared`` maps it to ``prepared_path``): Model Exchange FMUs in mode
``me``, Co-Simulation FMUs in mode ``cosim``. Of the fmpy reference masters, the
co-simulation one (``assemblies.masters.cosim``) runs it from its file too; the Model
Exchange one refuses it (:func:`check_own_only`). :func:`check_mode` says, before a run,
which instance a mode cannot run and which modes can.
"""
from __future__ import annotations

import math
import os
import zipfile
from pathlib import Path

from components.component import Block
from components.interfaces import (SIGNAL_IN, SIGNAL_OUT, ComponentError, Parameter, Port,
                                   Profile, State, signal)
from components.lazy import lazy

from .assembly import AssemblyError
from .value_types import MAX_ARRAY, RANGES, article, canonical, check_value, code, element_names, size

fmpy = lazy("fmpy")  # a foreign FMU's reader: loaded by the first one read (0.05-0.1 s)

# the assembly modes an FMU interface can take part in
INTERFACE_MODES = {"ModelExchange": "me", "CoSimulation": "cosim"}
MODES = ("cosim", "me", "monolithic")


class FmuError(AssemblyError):
    """A foreign FMU that cannot be used: the message names the file and what is wrong."""


class FMU(Block):
    """A foreign FMU (FMI 2.0/3.0, Model Exchange or Co-Simulation) as an assembly instance.

    ``FMU(path, name=None, units=None, **values)``: `units` declares the units of
    variables the FMU leaves without one (``units={"f": "N"}``), so that their
    connections are checked too (an undeclared unit connects to any unit); `values` set
    parameters and start values by name, as ``asm.set("inst.name", value)`` does.
    """

    def __init__(self, path: str | os.PathLike, name: str | None = None,
                 units: dict[str, str] | None = None, **values):
        if not isinstance(path, (str, os.PathLike)):
            raise FmuError(f"FMU: path must be the path of an .fmu file (str or Path), not "
                           f"{type(path).__name__} {path!r}")
        self.path = Path(path).expanduser().resolve()
        md = _read_model_description(self.path)
        self.model_description = md
        self.fmi_version = int(md.fmiVersion[0])
        # what identifies the binary: the engine's caches are keyed by it, so an FMU
        # rebuilt at the same path is read again
        stat = self.path.stat()
        self.stamp = (stat.st_mtime_ns, stat.st_size)
        self.interfaces = _interfaces_with_binaries(self.path, md)
        self._types: dict[str, str] = {}    # settable name -> its FMI type (value_types)
        self._strings: dict[str, str] = {}  # String parameters and start values
        self._state_names = {v.derivative.name for v in md.modelVariables
                             if v.derivative is not None}
        units = dict(units or {})
        self.ports, self.parameters, self.states = self._declare(md, units)
        if units:
            raise FmuError(f"{self._file()}: units= names variables that are not among its "
                           f"ports: {', '.join(units)}; ports: "
                           f"{', '.join(p.name for p in self.ports) or '(none)'}")
        self.profiles = (Profile("fmu", "inputs in, outputs out", {
            p.name: SIGNAL_IN if self._causality[p.name] == "input" else SIGNAL_OUT
            for p in self.ports}),)
        super().__init__(name=name or md.modelName, **values)

    # --- what the model description declares --------------------------------------
    def _declare(self, md, units: dict) -> tuple[tuple, tuple, tuple]:
        """(ports, parameters, states) from the model variables; `units` is consumed."""
        ports, parameters, states = [], [], []
        self._causality = {}
        derivative_of = {v.derivative.name for v in md.modelVariables if v.derivative is not None}
        for v in md.modelVariables:
            value_type = self._value_type(v)
            if value_type is None:
                continue  # a local Binary or Clock: nothing the user reaches
            shape = tuple(getattr(v, "shape", None) or ())
            unit = v.unit or (v.declaredType.unit if v.declaredType is not None else None) or ""
            if v.name in units:
                given = units.pop(v.name)
                if unit and unit != given:
                    raise FmuError(f"{self._file()}: units= gives {v.name} the unit '{given}', "
                                   f"but the FMU declares '{unit}'")
                unit = given
            description = v.description or f"{v.causality} {v.name} of {self.path.name}"
            has_start = v.start is not None
            if v.causality in ("input", "output"):
                self._causality[v.name] = v.causality
                # an input with a start value may stay unconnected: it keeps that value
                ports.append(Port(v.name, signal(unit, value_type), description,
                                  optional=v.causality == "input" and has_start, shape=shape))
            settable = v.causality in ("parameter", "input") and v.variability != "constant"
            state = v.name in derivative_of and v.initial in ("exact", "approx")
            if not has_start or not (settable or state):
                continue
            names = element_names(v.name, shape)
            starts = self._starts(v, value_type, len(names))
            if value_type == "String":
                self._strings.update(zip(names, starts))
                continue
            lo, hi = RANGES.get(value_type, (-math.inf, math.inf))
            for name, start in zip(names, starts):
                self._types[name] = value_type
                if settable:
                    parameters.append(Parameter(
                        name, start, unit, description,
                        min=max(lo, float(v.min)) if v.min is not None else lo,
                        max=min(hi, float(v.max)) if v.max is not None else hi))
                else:
                    states.append(State(name, start, unit, description))
        return tuple(ports), tuple(parameters), tuple(states)

    def _value_type(self, v) -> str | None:
        """The variable's type as value_types names it; None for a local one the engine
        need not carry. A Binary, Clock, clocked or oversized variable the user would reach
        (an input, an output, a parameter) refuses the FMU, naming it."""
        value_type = canonical(v.type)
        shape = tuple(getattr(v, "shape", None) or ())
        reached = v.causality in ("input", "output", "parameter", "structuralParameter")
        why = None
        if code(value_type) is None:
            why = f"is of type {v.type}, which the engine cannot carry (Binary and Clock " \
                  "variables are not supported)"
        elif getattr(v, "clocks", None):
            why = "is clocked (clocks=...); clocked variables are not supported"
        elif shape and value_type == "String":
            why = f"is a String array {list(shape)}; String arrays are not supported"
        elif size(shape) > MAX_ARRAY:
            why = f"is an array of {size(shape)} elements; at most {MAX_ARRAY} are supported"
        if why is None:
            return value_type
        if reached or v.name in self._state_names:
            raise FmuError(f"{self._file()}: {v.causality} variable '{v.name}' {why}")
        return None

    def _starts(self, v, value_type: str, n: int) -> list:
        """The start values of a variable, one per element (FMI 3 writes an array's start
        values space-separated, row-major; one value stands for all)."""
        if value_type == "String":
            return [str(v.start)] * n
        words = str(v.start).split() if n > 1 else [str(v.start)]
        if len(words) == 1:
            words = words * n
        if len(words) != n:
            raise FmuError(f"{self._file()}: variable '{v.name}' has {len(words)} start values "
                           f"for its {n} elements")
        if value_type == "Boolean":
            return [1.0 if w.strip() in ("true", "1") else 0.0 for w in words]
        try:
            return [float(w) for w in words]
        except ValueError:
            raise FmuError(f"{self._file()}: variable '{v.name}' has the start value "
                           f"'{v.start}', which is not a {value_type}") from None

    # --- Block's interface -------------------------------------------------------------
    def _file(self) -> str:
        return f"FMU '{self.path.name}'"

    def _where(self) -> str:
        return f"FMU '{self.name}' ({self.path.name})"

    def fmu_starts(self) -> dict:
        """Every value set on the FMU before it initialises, by name (Strings too)."""
        return {**self.values, **self.starts, **self._strings}

    def settable_names(self) -> list[str]:
        return super().settable_names() + list(self._strings)

    def set(self, key: str, value) -> None:
        """As for our components, each value checked against its FMI type: whole numbers
        within range for the integer types, True/False or 1/0 for Boolean, text for String."""
        value_type = "String" if key in self._strings else self._types.get(key)
        if value_type is not None:
            why = check_value(value_type, value)
            if why is not None:
                raise ComponentError(f"{self._where()}: {key} = {value!r} is not allowed; "
                                     f"{key} is {article(value_type)} variable: it {why}")
        if value_type == "String":
            self._strings[key] = value
            return
        if value_type == "Boolean":  # checked above; a Block takes no bools (a slip there)
            value = int(value)
        super().set(key, value)

    # --- which modes can run it -------------------------------------------------------
    def modes_supported(self) -> list[str]:
        """The assembly modes this FMU can take part in: 'me' for Model Exchange, 'cosim'
        for Co-Simulation (never 'monolithic': it has no equations to join)."""
        return [INTERFACE_MODES[i] for i in self.interfaces]

    def describe_interfaces(self) -> str:
        return " and ".join(self.interfaces) + (" only" if len(self.interfaces) == 1 else "")


def check_mode(assembly, mode: str) -> None:
    """Raise AssemblyError if `mode` cannot run `assembly`: it has no instance, or a
    foreign instance is not made for `mode` (the message names the instance, its file and
    interfaces, and the modes that apply). Every master calls it before any work."""
    if not assembly.components:
        # nothing to run is a mistake, not an empty result
        raise AssemblyError(f"assembly '{assembly.name}' has no instances: add components "
                            "with Assembly.add(name, component) first")
    foreign = {name: c for name, c in assembly.components.items() if isinstance(c, FMU)}
    if not foreign:
        return
    applicable = [m for m in MODES if all(m in c.modes_supported() for c in foreign.values())]
    if applicable:
        remedy = "run it with mode " + " or ".join(f"'{m}'" for m in applicable)
    else:
        remedy = "no mode runs all of " + ", ".join(
            f"{n} ({c.describe_interfaces()})" for n, c in foreign.items())
    for name, c in foreign.items():
        if mode == "monolithic":
            raise AssemblyError(
                f"assembly '{assembly.name}': mode 'monolithic' joins the CasADi equations of "
                f"our components into one FMU, but instance '{name}' is a compiled FMU "
                f"({c.path.name}) with no equations to join; {remedy}")
        if mode not in c.modes_supported():
            what = {"me": "integrates Model Exchange FMUs in one solver",
                    "cosim": "steps Co-Simulation FMUs"}[mode]
            raise AssemblyError(
                f"assembly '{assembly.name}': mode '{mode}' {what}, but instance '{name}' "
                f"({c.path.name}) is {c.describe_interfaces()}; {remedy}")


def check_own_only(assembly, master: str) -> None:
    """Raise AssemblyError if `assembly` has a foreign instance: the fmpy reference
    `master` (Model Exchange) rebuilds every FMU from its component and drives FMI 3
    only. The fmpy co-simulation master runs foreign FMUs (it uses :func:`check_mode`)."""
    for name, c in assembly.components.items():
        if isinstance(c, FMU):
            raise AssemblyError(
                f"assembly '{assembly.name}': the fmpy reference master {master} drives our "
                f"own components' FMUs only, but instance '{name}' is a foreign FMU "
                f"({c.path.name}); run it in the compiled engine (engine 'c': "
                "assemblies.cosimulate or assemblies.simulate_me)")


# --- reading the file, with one clear line for each way it can be unusable -----------------
def _read_model_description(path: Path):
    if not path.exists():
        raise FmuError(f"FMU file '{path}' does not exist")
    if path.is_dir() or not zipfile.is_zipfile(path):
        raise FmuError(f"'{path}' is not an FMU: an FMU is a zip archive with a "
                       "modelDescription.xml")
    with zipfile.ZipFile(path) as zf:
        names = zf.namelist()
    if "modelDescription.xml" not in names:
        raise FmuError(f"'{path}' is not an FMU: the archive has no modelDescription.xml")
    _check_entries(path, names)
    try:
        # not validated: many tools write descriptions fmpy's validation rejects (CasADi's
        # export lacks UnitDefinitions); what the engine needs is read all the same
        md = fmpy.read_model_description(str(path), validate=False)
    except Exception as exc:  # noqa: BLE001 - fmpy raises many kinds; one line names it
        reason = str(exc).strip().splitlines()[0] if str(exc).strip() else type(exc).__name__
        raise FmuError(f"cannot read the modelDescription.xml of '{path}': {reason}") from None
    if not md.fmiVersion.startswith(("2.", "3.")):
        raise FmuError(f"'{path}' is an FMI {md.fmiVersion} FMU; FMI 2.0 and 3.0 are supported")
    if md.modelExchange is None and md.coSimulation is None:
        raise FmuError(f"'{path}' has neither a Model Exchange nor a Co-Simulation interface "
                       "(FMI 3 Scheduled Execution is not supported)")
    _check_numbers(path, md)
    _check_states(path, md)
    return md


# the types whose start, min, max and nominal are numbers (one per element of an array)
_NUMERIC = {"Real", "Integer", "Enumeration", "Float64", "Float32", "Int8", "UInt8", "Int16",
            "UInt16", "Int32", "UInt32", "Int64", "UInt64"}


def _check_numbers(path: Path, md) -> None:
    """Every numeric attribute of a numeric variable reads as numbers: start="abc" is a
    mistake of the exporter, named in one line, not a ValueError of whoever reads it."""
    for v in md.modelVariables:
        if v.type not in _NUMERIC:
            continue
        for attribute in ("start", "min", "max", "nominal"):
            text = getattr(v, attribute, None)
            if text is not None and not _numbers(str(text)):
                raise FmuError(f"'{path}': variable {v.name} has {attribute}={str(text)!r}, "
                               f"which is not a number; a {v.type} {attribute} must be "
                               "one")


def _numbers(text: str) -> bool:
    """Is `text` one number, or several separated by spaces (an FMI 3 array's start)?"""
    words = text.split()
    try:
        for word in words:
            float(word)
    except ValueError:
        return False
    return bool(words)


def _check_entries(path: Path, names: list[str]) -> None:
    """Every file of the archive inside its folder: an absolute name or one that climbs
    out with '..' would be written anywhere when the FMU is extracted."""
    for name in names:
        parts = name.replace("\\", "/").split("/")
        if name.startswith(("/", "\\")) or (len(name) > 1 and name[1] == ":") or ".." in parts:
            raise FmuError(f"'{path}' is not a usable FMU: its archive entry '{name}' lies "
                           "outside the folder it is extracted to (an absolute path or '..'); "
                           "an FMU's files are relative paths inside it")


def _check_states(path: Path, md) -> None:
    """The continuous states the engine will integrate are the ones the file declares.

    The engine gives the FMU as many states as ModelStructure lists derivatives (an
    FMI 3 array counting per element). What a file can show is checked: every variable
    declared the derivative of a state is among those listed (FMI 2 and FMI 3 require
    it; an alias shares the listed one's value reference), and every one listed names
    its state. A binary with states its file names nowhere cannot be seen from outside:
    FMI has no call that reports the count, and asking for more states than declared is
    not allowed."""
    listed = [u.variable for u in md.derivatives]
    declared = [v for v in md.modelVariables if v.derivative is not None]
    # by value reference: an alias of a listed derivative (FMI 2 aliases share one) is
    # the same value, listed once
    refs = {(v.type, v.valueReference) for v in listed}
    missing = [v.name for v in declared if (v.type, v.valueReference) not in refs]
    if missing:
        raise FmuError(
            f"'{path}': ModelStructure lists {len(listed)} state derivative(s), but "
            f"{len(declared)} variables are declared derivatives of states; not listed: "
            f"{', '.join(missing)}; the engine would not integrate their states (the FMI "
            "standard lists every one)")
    for v in listed:
        if v.derivative is None:
            raise FmuError(f"'{path}': ModelStructure lists {v.name} as a state derivative, "
                           "but the variable names no state it is the derivative of (its "
                           "derivative attribute is missing)")


def _interfaces_with_binaries(path: Path, md) -> tuple[str, ...]:
    """The interfaces whose shared library for this platform is in the archive."""
    folder = fmpy.platform if md.fmiVersion.startswith("2") else fmpy.platform_tuple
    with zipfile.ZipFile(path) as zf:
        names = set(zf.namelist())
    found, expected = [], []
    for kind, interface in (("ModelExchange", md.modelExchange), ("CoSimulation", md.coSimulation)):
        if interface is None:
            continue
        library = f"binaries/{folder}/{interface.modelIdentifier}{fmpy.sharedLibraryExtension}"
        expected.append(library)
        if library in names:
            found.append(kind)
    if not found:
        present = sorted({n.split("/")[1] for n in names
                          if n.startswith("binaries/") and n.count("/") >= 2 and n.split("/")[1]})
        source = any(n.startswith("sources/") for n in names)
        raise FmuError(
            f"'{path}' has no binary for this platform ({folder}): expected "
            f"{' or '.join(dict.fromkeys(expected))}; it has binaries for "
            f"{', '.join(present) or 'no platform'}"
            + ("; it ships sources: compile them first (fmpy.util.compile_platform_binary)"
               if source else ""))
    return tuple(found)


__all__ = ["FMU", "FmuError", "check_mode", "check_own_only"]
