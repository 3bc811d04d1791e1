"""Friction against the housing with a tabulated characteristic (MSL SupportFriction, Brake).

MSL's SupportFriction and Brake are massless: connected rigidly to a Mass, the sticking
force is found from the mass's balance at acceleration level, inside one equation
system. Across an FMU boundary that is an algebraic loop with a set-valued law, so here
each carries the mass it acts on (``m``, MSL's Mass beside it): the same equations as
MSL's Mass + SupportFriction (or + Brake) connected rigidly, in one FMU, with exact
stick/slip modes (components.friction). Their flanges take forces in and give motion
out, like Mass.

The sliding characteristic is a table of ``rows`` rows (v >= 0, value), interpolated
linearly and extrapolated through the last two rows (MSL's LinearSegments and
LastTwoPoints); a one-row table is a constant. Backward sliding mirrors it.
"""
from __future__ import annotations

from ..component import Component
from ..friction import coulomb_modes
from ..interfaces import (FIXED, FORCE_IN, MOTION_IN, SIGNAL_IN, TRANSLATIONAL, ComponentError,
                          Constraint, Mode, Option, Parameter, Port, Profile, State, signal)
from ..lazy import lazy
from .elements import on_support

ca = lazy("casadi")  # loaded by the first equation written, not by an import
np = lazy("numpy")

MAX_ROWS = 64
_PORTS = (Port("flange_a", TRANSLATIONAL, "left side of the braked mass"),
          Port("flange_b", TRANSLATIONAL, "right side of the braked mass"),
          Port("support", TRANSLATIONAL, "housing the friction acts against"))
_STATES = (State("s", 0.0, "m", "position of the mass relative to the support"),
           State("v", 0.0, "m/s", "velocity of the mass relative to the support"))
_MODES = (Mode("mode", 0, "friction mode: -1 sliding backward, 0 stuck, +1 sliding forward"),)


def _profiles(extra: dict) -> tuple[Profile, ...]:
    return (Profile("grounded", "forces in, motion out; housing fixed (MSL useSupport=false)",
                    {"flange_a": FORCE_IN, "flange_b": FORCE_IN, "support": FIXED, **extra}),
            Profile("on_support", "forces in, motion out; housing moved by an input",
                    {"flange_a": FORCE_IN, "flange_b": FORCE_IN, "support": MOTION_IN, **extra}))


def interpolate(table, x):
    """Linear interpolation in rows (x_k, y_k), extrapolated through the last two rows at
    either end (MSL's LinearSegments, LastTwoPoints); one row is a constant."""
    xs, ys = [r[0] for r in table], [r[1] for r in table]
    if len(xs) == 1:
        return ys[0]

    def line(k):  # through rows k and k + 1
        dx = xs[k + 1] - xs[k]
        return ys[k] + (ys[k + 1] - ys[k]) / ca.if_else(dx > 0, dx, 1) * (x - xs[k])
    # the last segment also covers everything after it; each earlier one everything
    # before its right end that no earlier segment covers
    value = line(len(xs) - 2)
    for k in range(len(xs) - 3, -1, -1):
        value = ca.if_else(x < xs[k + 1], line(k), value)
    return value


def _shown(table) -> str:
    return f"an array of shape {table.shape}" if table.size else "that"


def _rows(table: str) -> Option:
    return Option("rows", 1, range(1, MAX_ROWS + 1),
                  f"rows of the table {table}: row k is {table}[k,1] the speed, {table}[k,2] "
                  "the value (default speeds 0, 1, 2, ... m/s)")


class _TableFriction(Component):
    """What SupportFriction and Brake share: the table, the mass, the mode machine."""
    table_name = ""
    table_default = ((0.0, 1.0),)
    table_unit = ""

    def __init__(self, name=None, profile=None, **values):
        table = values.pop(self.table_name, None)
        rows = values.pop("rows", None)
        if table is not None:
            try:
                table = np.array(table, dtype=float)
            except (TypeError, ValueError):
                table = np.zeros((0, 0))  # not numbers: said below, with the shape wanted
            if table.ndim != 2 or table.shape[1] != 2 or not 1 <= len(table) <= MAX_ROWS:
                raise ComponentError(f"{type(self).__name__} '{name or type(self).__name__}': "
                                     f"{self.table_name} must be 1 to {MAX_ROWS} "
                                     f"rows [v, value] of numbers, not {_shown(table)}")
            rows = len(table) if rows is None else rows
        rows = self._rows_option().parse(1 if rows is None else rows)
        if rows is None:
            raise ComponentError(f"{type(self).__name__} '{name or type(self).__name__}': "
                                 f"option rows must be {self._rows_option().allowed()}")
        self.parameters = self._parameters_for(rows)
        for k, row in enumerate(() if table is None else table, start=1):
            values.update({f"{self.table_name}[{k},{j}]": x for j, x in enumerate(row, 1)})
        super().__init__(name, profile, rows=rows, **values)

    def _parameters_for(self, rows: int) -> tuple[Parameter, ...]:
        # a default table of more rows than the default's one: speeds 0, 1, 2, ... m/s
        default = [(float(k), self.table_default[0][1]) for k in range(rows)]
        return (*self.own_parameters, *(
            Parameter(f"{self.table_name}[{k},{j}]", default[k - 1][j - 1], unit,
                      f"{what} of row {k} of {self.table_name}")
            for k in range(1, rows + 1)
            for j, unit, what in ((1, "m/s", "sliding speed"), (2, self.table_unit, "value"))))

    def set(self, key: str, value) -> None:
        super().set(key, value)
        if key == "rows":  # set after construction (--param brake.rows=2): the table grows
            self.resize_parameters(self._parameters_for(self.option("rows")))

    def _rows_option(self):
        return next(o for o in self.options if o.name == "rows")

    @property
    def constraints(self):
        rows, name = self.option("rows"), self.table_name

        def speed(k):
            return lambda p: getattr(p, f"{name}[{k},1]")
        first = Constraint(speed(1), f"{name}[1,1] >= 0 (the table starts at a speed >= 0)")
        return (first, *(Constraint(lambda p, k=k: speed(k + 1)(p) - speed(k)(p),
                                    f"{name} speeds increase: {name}[{k + 1},1] > {name}[{k},1]",
                                    strict=True) for k in range(1, rows)))

    def table(self, e):
        rows = self.option("rows")
        return [(getattr(e.p, f"{self.table_name}[{k},1]"),
                 getattr(e.p, f"{self.table_name}[{k},2]")) for k in range(1, rows + 1)]

    def friction_equations(self, e, kinetic, static_limit):
        """The mass on its support, its friction from `kinetic(|v|)` and `static_limit`."""
        v, support = e.x.v, e.port("support")
        friction, applied = on_support(e, e.p.m, "s")
        coulomb_modes(e, speed="v", acceleration=e.der.v, friction=friction, applied=applied,
                      static_limit=static_limit, kinetic_limit=kinetic(ca.fabs(v)))
        e.output("s_abs", support.s + e.x.s, "m", "absolute position of the mass")
        e.output("a", e.der.v, "m/s2", "acceleration of the mass relative to the support")
        e.output("f", -friction, "N", "friction force, positive when it opposes +v")
        e.output("lossPower", -friction * v, "W", "power dissipated by friction")


_MASS = Parameter("m", 1.0, "kg", "mass the friction acts on (MSL's Mass beside it)", min=0.0,
                  min_strict=True)
_PEAK = Parameter("peak", 1.0, "1", "peak of the friction at v = 0 over the sliding value",
                  min=1.0)


class SupportFriction(_TableFriction):
    """Mass with Coulomb friction in its support from a table f_pos(v) (MSL Translational.Components.SupportFriction).

    Sliding: ``f = sign(v) f_pos(|v|)``; stuck (v = 0 exactly) up to ``peak f_pos(0)``.
    Carries the mass it acts on (see the module). Parameters: ``m`` [kg], ``peak`` [1],
    ``f_pos[k,1]`` [m/s], ``f_pos[k,2]`` [N] (give ``f_pos=[[v, f], ...]``; option ``rows``).
    States: ``s``, ``v`` relative to the support. Mode: ``mode``.
    Connectors: ``flange_a``, ``flange_b`` force in, motion out; ``support`` fixed or motion in.
    Outputs: ``s_abs`` [m], ``a`` [m/s2], ``f`` [N], ``lossPower`` [W].
    """
    table_name, table_default, table_unit = "f_pos", ((0.0, 1.0),), "N"
    own_parameters = (_MASS, _PEAK)
    parameters = own_parameters  # what `mechfmu show` lists; an instance adds its table's
    options = (_rows("f_pos"),)
    states, modes, ports, profiles = _STATES, _MODES, _PORTS, _profiles({})

    def equations(self, e):
        table = self.table(e)
        self.friction_equations(e, lambda speed: interpolate(table, speed),
                                e.p.peak * interpolate(table, 0.0))


class Brake(_TableFriction):
    """Mass braked by friction against the housing, pressed by a signal (MSL Translational.Components.Brake).

    ``fn = fn_max f_normalized`` (free, no friction, while fn <= 0); sliding
    ``f = sign(v) cgeo mu_pos(|v|) fn``; stuck (v = 0 exactly) up to ``peak cgeo mu_pos(0) fn``.
    Carries the mass it brakes (see the module). Parameters: ``m`` [kg], ``fn_max`` [N],
    ``cgeo`` [1], ``peak`` [1], ``mu_pos[k,1]`` [m/s], ``mu_pos[k,2]`` [1] (give
    ``mu_pos=[[v, mu], ...]``, MSL's default [[0, 0.5]]; option ``rows``).
    Input: ``f_normalized`` [1]. States: ``s``, ``v`` relative to the support. Mode: ``mode``.
    Connectors: ``flange_a``, ``flange_b`` force in, motion out; ``support`` fixed or motion in.
    Outputs: ``s_abs`` [m], ``a`` [m/s2], ``f`` [N], ``fn`` [N], ``lossPower`` [W].
    """
    table_name, table_default, table_unit = "mu_pos", ((0.0, 0.5),), "1"
    own_parameters = (_MASS, _PEAK,
                      Parameter("cgeo", 1.0, "1", "geometry constant of the friction "
                                "distribution", min=0.0),
                      Parameter("fn_max", 1.0, "N", "maximum normal force", min=0.0))
    parameters = own_parameters  # what `mechfmu show` lists; an instance adds its table's
    options = (_rows("mu_pos"),)
    states, modes = _STATES, _MODES
    ports = (*_PORTS, Port("f_normalized", signal("1"), "normalised normal force (fn = "
                           "fn_max f_normalized; the brake acts while > 0)"))
    profiles = _profiles({"f_normalized": SIGNAL_IN})

    def equations(self, e):
        p, table = e.p, self.table(e)
        # MSL: free (no friction) while fn <= 0, the same as a zero normal force
        fn = ca.fmax(p.fn_max * e.port("f_normalized"), 0)
        self.friction_equations(e, lambda speed: p.cgeo * interpolate(table, speed) * fn,
                                p.peak * p.cgeo * interpolate(table, 0.0) * fn)
        e.output("fn", fn, "N", "normal force")
