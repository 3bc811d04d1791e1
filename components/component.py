"""The base classes of what an assembly holds.

:class:`Block` is what an assembly needs of an instance: ports, causality profiles,
and parameters and start values settable by name, checked when set, so a bad value
never reaches C. A foreign FMU (:class:`assemblies.foreign.FMU`) is a Block.

:class:`Component`, the base of every mechanical component, is a Block plus modes and
one method, ``equations(e)``, that states its physics as residuals in the symbols of an
:class:`components.dae.EquationBuilder`: what can be flattened, built into our FMU or
joined with others (``isinstance(x, Component)`` asks exactly that).
"""
from __future__ import annotations

import math
from types import SimpleNamespace

from .interfaces import (ComponentError, Constraint, Mode, Option, Parameter, Port,
                         Profile, State)
from .lazy import lazy

np = lazy("numpy")  # loaded by the first array: listing the components needs none


class Block:
    """An assembly instance: ports, profiles, and checked values settable by name."""
    parameters: tuple[Parameter, ...] = ()
    options: tuple[Option, ...] = ()
    states: tuple[State, ...] = ()
    ports: tuple[Port, ...] = ()
    profiles: tuple[Profile, ...] = ()
    constraints: tuple[Constraint, ...] = ()
    #: relations the start values must satisfy with the parameters (``g(ns)``, ``ns`` holding
    #: both): where the equations hold only for some states (a coin lying flat has no
    #: contact point). Checked here and, in the FMU, when initialisation ends.
    start_constraints: tuple[Constraint, ...] = ()

    def __init__(self, name: str | None = None, profile: str | None = None, **values):
        self.name = name or type(self).__name__
        self.profile = self._pick_profile(profile)
        self.profile_explicit = profile is not None  # an assembly may re-choose only implicit ones
        self.values = {p.name: float(p.default) for p in self.parameters}
        self.option_values = {o.name: o.default for o in self.options}
        self.starts = {s.name: float(s.start) for s in self.states}
        for key, value in values.items():
            self.set(key, value)
        self.validate()

    # --- naming and lookup ---------------------------------------------------
    def _where(self) -> str:
        return f"{type(self).__name__} '{self.name}'"

    def _pick_profile(self, name):
        if not self.profiles:
            raise ComponentError(f"{self._where()}: declares no causality profile")
        if name is None:
            return self.profiles[0]
        for profile in self.profiles:
            if profile.name == name:
                return profile
        known = ", ".join(p.name for p in self.profiles)
        raise ComponentError(f"{self._where()}: unknown profile '{name}'; known profiles: {known}")

    def resize_parameters(self, parameters) -> None:
        """Take `parameters` as this instance's (an option that sizes a table changed):
        the values of names kept stay, new names start at their defaults."""
        self.parameters = tuple(parameters)
        self.values = {p.name: self.values.get(p.name, float(p.default)) for p in self.parameters}

    def fmu_starts(self) -> dict:
        """Every value set on this instance's FMU before it initialises, by name."""
        return {**self.values, **self.starts}

    def settable_names(self) -> list[str]:
        return ([p.name for p in self.parameters] + [o.name for o in self.options]
                + [s.name for s in self.states] + [s.start_name for s in self.states if s.start_name])

    def set(self, key: str, value) -> None:
        """Set a parameter, an option or a state's start value, with checks."""
        options = {o.name: o for o in self.options}
        if key in options:
            parsed = options[key].parse(value)
            if parsed is None:
                raise ComponentError(f"{self._where()}: option {key} = {value!r} is not allowed; "
                                     f"{key} ({options[key].description}) must be "
                                     f"{options[key].allowed()}")
            self.option_values[key] = parsed
            return
        name = key  # as the user wrote it, for messages; a start alias maps to its state
        key = next((s.name for s in self.states if s.start_name == key), key)
        if key not in self.values and key not in self.starts:
            raise ComponentError(
                f"{self._where()}: unknown name '{name}'; settable names: "
                f"{', '.join(self.settable_names())}")
        if isinstance(value, (bool, np.bool_)):  # float(True) is 1.0: a slip, never a mass
            raise ComponentError(f"{self._where()}: {name} = {value!r} is not a number "
                                 f"(a bool); {name} takes a number")
        try:
            number = float(value)
        except (TypeError, ValueError):
            raise ComponentError(f"{self._where()}: {name} = {value!r} is not a number") from None
        if not math.isfinite(number):
            if key in self.values:
                p = next(p for p in self.parameters if p.name == key)
                raise ComponentError(f"{self._where()}: parameter {name} = {value} is not allowed; "
                                     f"{name} ({p.label()}) must be a finite number "
                                     f"{p.allowed()}")
            raise ComponentError(f"{self._where()}: start value {name} = {value} must be finite")
        (self.values if key in self.values else self.starts)[key] = number

    def validate(self) -> None:
        for p in self.parameters:
            value = self.values[p.name]
            if p.violates(value):
                raise ComponentError(
                    f"{self._where()}: parameter {p.name} = {value:g} is not allowed; "
                    f"{p.name} ({p.label()}) must be {p.allowed()}")
        for s in self.states:
            if not math.isfinite(self.starts[s.name]):
                raise ComponentError(f"{self._where()}: start value of {s.name} must be finite")
        namespace = SimpleNamespace(**self.values)
        for c in self.constraints:
            g = float(c.g(namespace))
            if not (g > 0 if c.strict else g >= 0):
                shown = ", ".join(f"{k} = {v:g}" for k, v in self.values.items())
                raise ComponentError(f"{self._where()}: parameters violate {c.message} ({shown})")
        both = SimpleNamespace(**self.values, **self.starts)
        for c in self.start_constraints:
            g = float(c.g(both))
            if not (g > 0 if c.strict else g >= 0):
                shown = ", ".join(f"{k} = {v:g}" for k, v in self.starts.items())
                raise ComponentError(f"{self._where()}: start values violate {c.message} "
                                     f"({shown})")

    def option(self, name: str) -> str:
        return self.option_values[name]

    @classmethod
    def describe(cls) -> str:
        """The first line of the docstring: what `mechfmu components` prints."""
        return (cls.__doc__ or cls.__name__).strip().splitlines()[0]

    def __repr__(self) -> str:
        vals = ", ".join(f"{k}={v:g}" for k, v in self.values.items())
        return f"{type(self).__name__}(name={self.name!r}, profile={self.profile.name!r}, {vals})"


#: the values of every FMU's runtime setting ``solver``, by the names a user may write
SOLVERS = {"0": 0, "explicit": 0, "dopri5": 0, "1": 1, "implicit": 1, "rodas3": 1,
           "2": 2, "auto": 2}
#: each value's method, as the engine names it
SOLVER_METHODS = {0: "DOPRI5", 1: "RODAS3", 2: "auto"}
SOLVER_CHOICES = ("0 (DOPRI5, explicit), 1 (RODAS3, implicit) or 2 (auto: switches between "
                  "them on stiffness, the default)")


class Component(Block):
    """A mechanical component: a Block whose physics are CasADi equations."""
    modes: tuple[Mode, ...] = ()
    #: the experiment written into the FMU's DefaultExperiment
    default_stop_time: float = 10.0

    def __init__(self, name: str | None = None, profile: str | None = None, **values):
        #: the FMU's own solver as set by the user (None: the FMU's default, auto); not a
        #: parameter of the physics, so it is neither joined nor part of the FMU's build
        self.solver: int | None = None
        super().__init__(name, profile, **values)

    def settable_names(self) -> list[str]:
        return super().settable_names() + ["solver"]

    def set(self, key: str, value) -> None:
        if key != "solver":
            return super().set(key, value)
        text = str(value).strip().lower()
        if text.endswith(".0"):
            text = text[:-2]
        if text not in SOLVERS:
            raise ComponentError(f"{self._where()}: solver = {value!r} is not allowed; solver "
                                 f"must be {SOLVER_CHOICES}")
        self.solver = SOLVERS[text]

    def fmu_starts(self) -> dict:
        """Parameters, start values and the runtime settings the user chose (`solver`)."""
        return {**super().fmu_starts(), **({} if self.solver is None else {"solver": self.solver})}

    def parameter_constraints(self) -> list[Constraint]:
        """Every check on the parameters (ranges included) and on the start values, in one
        list for the FMU's C check; each ``g`` takes a namespace of parameters and states."""
        out = []
        for p in self.parameters:
            msg = f"{type(self).__name__}: {p.name} ({p.label()}) must be {p.allowed()}"
            if p.min != -math.inf:
                out.append(Constraint(lambda ns, p=p: getattr(ns, p.name) - p.min, msg, p.min_strict))
            if p.max != math.inf:
                out.append(Constraint(lambda ns, p=p: p.max - getattr(ns, p.name), msg))
        out += [Constraint(c.g, f"{type(self).__name__}: parameters must satisfy {c.message}", c.strict)
                for c in self.constraints]
        out += [Constraint(c.g, f"{type(self).__name__}: start values must satisfy {c.message}",
                           c.strict) for c in self.start_constraints]
        return out

    def equations(self, e) -> None:  # pragma: no cover - every component overrides it
        raise NotImplementedError

    def vectorised_functions(self, model) -> dict:
        """Model functions this component writes itself for the C code, by key of
        ``FlatModel.functions()`` (plus ``dd``, see fmus.codegen.directional_jacobian).

        CasADi's SX, which flatten() works in, unrolls every scalar operation into a
        line of C; an MX function of whole vectors compiles to loops over constant data.
        A component with many similar states (a beam's modes) returns MX functions with
        the same arguments (t, x, q, u, p) and results as the flattened ones, which stay
        the reference they are tested against. None here: everything from flatten().
        """
        return {}
