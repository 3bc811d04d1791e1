"""ctypes mirror of c/engine.h, and the plumbing every engine call shares: building
the C description of the instances, the progress callback with Ctrl-C, the stats.

Everything a C structure points to is kept alive in a `Keep` list until the call
returns (ctypes does not own the memory behind a pointer field).
"""
from __future__ import annotations

import _signal
import collections
import ctypes as C
import signal
import struct
import threading

import numpy as np

from components.errors import SimulationError

from ..value_types import STRING

_P = C.POINTER


class EngineError(SimulationError):
    """The compiled engine could not finish a run; the message carries the FMU's log."""


class Variable(C.Structure):  # eng_variable
    _fields_ = [("instance", C.c_int), ("vr", C.c_uint32), ("type", C.c_int),
                ("element", C.c_int), ("size", C.c_int)]


class InstanceSpec(C.Structure):  # eng_instance_spec
    _fields_ = [("unzip_dir", C.c_char_p), ("model_identifier", C.c_char_p),
                ("instantiation_token", C.c_char_p), ("instance_name", C.c_char_p),
                ("fmi_version", C.c_int), ("n_states", C.c_int), ("n_event_indicators", C.c_int),
                ("can_get_set_state", C.c_int), ("provides_directional_derivative", C.c_int),
                ("n_float_starts", C.c_int), ("float_start_vr", _P(C.c_uint32)),
                ("float_start_values", _P(C.c_double)),
                ("n_int_starts", C.c_int), ("int_start_vr", _P(C.c_uint32)),
                ("int_start_values", _P(C.c_int32)),
                ("n_event_outputs", C.c_int), ("event_outputs", _P(Variable)),
                ("state_vr", _P(C.c_uint32)), ("derivative_vr", _P(C.c_uint32)),
                ("completed_step_not_needed", C.c_int), ("foreign", C.c_int),
                ("n_typed_starts", C.c_int), ("typed_starts", _P(Variable)),
                ("typed_start_values", _P(C.c_double)),
                ("n_string_starts", C.c_int), ("string_start_vr", _P(C.c_uint32)),
                ("string_start_values", _P(C.c_char_p)),
                ("feedthrough_listed", C.c_int), ("n_feedthrough", C.c_int),
                ("feedthrough_unknown", _P(C.c_uint32)), ("feedthrough_known", _P(C.c_uint32))]


class EventGroup(C.Structure):  # eng_event_group
    _fields_ = [("instance", C.c_int), ("first_indicator", C.c_int), ("n_indicators", C.c_int),
                ("n_outputs", C.c_int), ("outputs", _P(Variable))]


class Coupling(C.Structure):  # eng_coupling
    _fields_ = [("source", Variable), ("target", Variable), ("gain", C.c_double)]


PROGRESS_FN = C.CFUNCTYPE(C.c_int, C.c_void_p, C.c_double)


class Stats(C.Structure):  # eng_stats
    _fields_ = [("status", C.c_int), ("n_rows", C.c_long), ("t_end", C.c_double),
                ("steps", C.c_long), ("rejected", C.c_long), ("rhs_calls", C.c_long),
                ("jacobians", C.c_long), ("events", C.c_long), ("method_switches", C.c_long),
                ("at_rest_from", C.c_double), ("terminated_by", C.c_int),
                ("exact_jacobian", C.c_int), ("message", C.c_char * 1024),
                ("jacobian_note", C.c_char * 512),
                ("jacobian_groups", C.c_long), ("jacobian_evaluations", C.c_long),
                ("jacobian_band", C.c_long), ("loop_iterations", C.c_long),
                ("loop_matrices", C.c_long), ("event_instances", C.c_long),
                ("explicit_order", C.c_int)]


def _numbers_layout(structure) -> tuple[struct.Struct, type]:
    """One struct.Struct that reads every int, long and double field of a ctypes
    Structure at its offset, and a named tuple of them in that order: a run's statistics
    in one call instead of a ctypes attribute read each (twenty of those cost a short run
    ~1.5 us; a dict of them, 2.5 us)."""
    codes = {C.c_int: "i", C.c_long: "q" if C.sizeof(C.c_long) == 8 else "i", C.c_double: "d"}
    fields = sorted((getattr(structure, name).offset, name, codes[kind])
                    for name, kind in structure._fields_ if kind in codes)
    fmt, at = "=", 0
    for offset, _, code in fields:
        fmt += (f"{offset - at}x" if offset > at else "") + code
        at = offset + struct.calcsize("=" + code)
    numbers = collections.namedtuple(f"{structure.__name__}Numbers",
                                     [name for _, name, _ in fields])
    return struct.Struct(fmt), numbers


_STATS_LAYOUT = _numbers_layout(Stats)


def stats_numbers(stats: Stats):
    """The numbers of an eng_stats (every field but the messages), a named tuple with
    the fields' names."""
    layout, numbers = _STATS_LAYOUT
    return numbers._make(layout.unpack_from(stats))


class MeSpec(C.Structure):  # eng_me_spec
    _fields_ = [("n_instances", C.c_int), ("instances", _P(InstanceSpec)),
                ("n_couplings", C.c_int), ("couplings", _P(Coupling)),
                ("n_columns", C.c_int), ("columns", _P(Variable)),
                ("n_event_groups", C.c_int), ("event_groups", _P(EventGroup)),
                ("n_times", C.c_long), ("times", _P(C.c_double)), ("out", _P(C.c_double)),
                ("stop_time", C.c_double), ("tolerance", C.c_double), ("method", C.c_int),
                ("event_subsamples", C.c_int), ("max_step", C.c_double),
                ("progress", PROGRESS_FN), ("progress_ctx", C.c_void_p),
                ("rest_group", _P(C.c_int)), ("asleep_since", _P(C.c_double)),
                ("continuous", _P(C.c_int)), ("column_state", _P(C.c_int)),
                ("row_coupling", _P(C.c_int)), ("jacobian", C.c_int),
                ("indicator_start", _P(C.c_int)), ("indicator_coupling", _P(C.c_int)),
                ("n_loops", C.c_int), ("loop_first", _P(C.c_int)), ("loop_count", _P(C.c_int)),
                ("loop_name", _P(C.c_char_p)),
                ("time_function", _P(C.c_int)), ("time_free", _P(C.c_int)),
                ("linear_map", _P(C.c_int)), ("taken_until", _P(C.c_double)),
                ("event_free", _P(C.c_int))]


DONE, STOPPED, TERMINATED, FAILED = 0, 1, 2, -1


class Keep(list):
    """Python objects that C pointers in a spec refer to, alive until the call returns."""

    def array(self, ctype, values):
        arr = (ctype * max(1, len(values)))(*values)
        self.append(arr)
        return C.cast(arr, _P(ctype))

    def numpy(self, arr: np.ndarray, ctype):
        self.append(arr)
        return arr.ctypes.data_as(_P(ctype))


def instance_spec(keep: Keep, name: str, fmu, model_exchange: bool, starts: dict,
                  event_outputs: list[str] = ()) -> InstanceSpec:
    """One instance through its Model Exchange or Co-Simulation interface: the extracted
    FMU, and its parameters and start values by name."""
    identifier = fmu.me_identifier if model_exchange else fmu.cs_identifier
    floats, ints, typed, strings = fmu.typed_starts(name, starts)
    s = InstanceSpec()
    s.unzip_dir, s.model_identifier = fmu.unzip_dir.encode(), identifier.encode()
    s.instantiation_token, s.instance_name = fmu.token.encode(), name.encode()
    s.fmi_version, s.n_states, s.n_event_indicators = fmu.fmi_version, fmu.n_states, \
        fmu.n_event_indicators
    s.can_get_set_state = int(fmu.can_get_set_state)
    s.provides_directional_derivative = int(fmu.me_directional_derivative if model_exchange
                                            else fmu.provides_directional_derivative)
    s.completed_step_not_needed = int(model_exchange and fmu.completed_step_not_needed)
    s.foreign = int(model_exchange and not fmu.ours)
    s.n_float_starts = len(floats)
    s.float_start_vr = keep.array(C.c_uint32, [vr for vr, _ in floats])
    s.float_start_values = keep.array(C.c_double, [v for _, v in floats])
    s.n_int_starts = len(ints)
    s.int_start_vr = keep.array(C.c_uint32, [vr for vr, _ in ints])
    s.int_start_values = keep.array(C.c_int32, [v for _, v in ints])
    s.n_typed_starts = len(typed)
    s.typed_starts = keep.array(Variable, [Variable(0, *v) for v, _ in typed])
    s.typed_start_values = keep.array(C.c_double, [x for _, x in typed])
    set_strings(keep, s, strings)
    s.n_event_outputs = len(event_outputs)
    s.event_outputs = keep.array(Variable, [variable(fmu, name, 0, v) for v in event_outputs])
    arrays = any(fmu.variables[v][3] > 1 for v in fmu.states)
    if fmu.n_states and len(fmu.states) == len(fmu.derivatives) == fmu.n_states and not arrays:
        s.state_vr = keep.array(C.c_uint32, [fmu.variables[v][0] for v in fmu.states])
        s.derivative_vr = keep.array(C.c_uint32, [fmu.variables[v][0] for v in fmu.derivatives])
    elif arrays:
        # an array state is one value reference for many states: the engine's Jacobian
        # from directional derivatives is per value reference, so it takes differences
        s.provides_directional_derivative = 0
    if model_exchange:
        set_feedthrough(keep, s, fmu)
    return s


def set_feedthrough(keep: Keep, spec: InstanceSpec, fmu) -> None:
    """Which inputs each scalar output and derivative of `fmu` depends on, by value
    reference (eng_instance_spec.feedthrough_listed): the ModelStructure as
    liveness.py reads it, every input where it lists nothing. An array input or output
    is one value reference for many values: then nothing is listed (every unknown
    depends on every input)."""
    from .liveness import inputs_behind
    scalar = [v for v in (*fmu.outputs, *fmu.derivatives, *fmu.inputs) if v in fmu.variables]
    if any(fmu.variables[v][3] > 1 for v in scalar):
        return
    pairs = sorted({(fmu.variables[u][0], fmu.variables[i][0])
                    for u in (*fmu.outputs, *fmu.derivatives) if u in fmu.variables
                    for i in inputs_behind(fmu, u) if i in fmu.variables})
    spec.feedthrough_listed, spec.n_feedthrough = 1, len(pairs)
    spec.feedthrough_unknown = keep.array(C.c_uint32, [u for u, _ in pairs])
    spec.feedthrough_known = keep.array(C.c_uint32, [i for _, i in pairs])


def set_strings(keep: Keep, spec: InstanceSpec, strings: list) -> None:
    """The String parameters and start values [(vr, text)] of an instance spec."""
    spec.n_string_starts = len(strings)
    spec.string_start_vr = keep.array(C.c_uint32, [vr for vr, _ in strings])
    spec.string_start_values = keep.array(C.c_char_p, [t.encode() for _, t in strings])


def variable(fmu, instance: str, index: int, name: str) -> Variable:
    """Variable `name` of `fmu`, instance `index` of the run (an array element too)."""
    return Variable(index, *fmu.variable(instance, name))


def needs_difference_jacobian(a: Variable, b: Variable) -> bool:
    """A coupling the engine's Jacobian from directional derivatives cannot carry (one
    of Float32 or array elements: c/jacobian.h); discrete ones carry nothing anyway."""
    continuous = {0, 2}
    plain = a.type == b.type == 0 and a.size <= 1 and b.size <= 1
    return not plain and a.type in continuous and b.type in continuous


def typed_column(lib, fmu, name: str | None, values: np.ndarray) -> np.ndarray:
    """A column of variable `name` (None: time) as its values: a String's string-table
    indices as text (an object array), every other type as the numbers they are."""
    if name is None or fmu.variables[name][1] != STRING:
        return values
    return np.array([(lib.eng_string(int(i)) or b"").decode("utf-8", "replace") if i == i
                     else None for i in values], dtype=object)


class Progress:
    """The C progress callback: calls the user's `progress(t)` and asks the engine to
    stop on Ctrl-C (a SIGINT handler sets a flag while the engine runs: the run then
    ends cleanly at its last completed step and keeps what it computed). An exception
    raised by `progress` also stops the run, and is raised again after it.

    The engine calls one C callback made once per process (making one per run costs as
    much as a short run); it reaches the Progress of the run in progress on its thread
    (:meth:`sigint` makes it current), since the engine calls back on the caller's."""

    def __init__(self, progress=None):
        self.user = progress
        self.interrupted = False
        self.error: BaseException | None = None
        self.callback = _dispatch

    def _call(self, t):
        if self.user is not None and self.error is None:
            try:
                self.user(float(t))
            except BaseException as exc:  # noqa: BLE001 - re-raised after the C call
                self.error = exc
        return int(self.interrupted or self.error is not None)

    def sigint(self) -> "_Sigint":
        """While the engine runs, this is the thread's current Progress and, on the main
        thread, Ctrl-C sets a flag instead of raising."""
        return _Sigint(self)

    def reraise(self):
        if self.error is not None:
            raise self.error


_current = threading.local()


class _Sigint:
    """Progress.sigint's context: a class, not a generator, since a short run's whole
    Python cost is a few of these microseconds (contextlib's generator costs ~2 us)."""
    __slots__ = ("progress", "outer", "previous", "installed")

    def __init__(self, progress: Progress):
        self.progress = progress
        self.installed = False

    def _handler(self, _signum, _frame):
        self.progress.interrupted = True

    def __enter__(self):
        self.outer = getattr(_current, "progress", None)
        _current.progress = self.progress
        try:
            # _signal: signal.signal's enum conversions cost more than a short run
            self.previous = _signal.signal(signal.SIGINT, self._handler)
            self.installed = True
        except ValueError:  # not the main thread (asking first costs a short run ~0.5 us)
            pass
        except BaseException:
            _current.progress = self.outer
            raise
        return self

    def __exit__(self, *exc):
        try:
            if self.installed:
                _signal.signal(signal.SIGINT, self.previous)
        finally:
            _current.progress = self.outer
        return False


@PROGRESS_FN
def _dispatch(_ctx, t):
    progress = getattr(_current, "progress", None)
    return 0 if progress is None else progress._call(t)


def run_events(lib, run, group: int) -> np.ndarray:
    """The event rows of one group as a (n_rows, width) array (copied out of C)."""
    rows, n, width = _P(C.c_double)(), C.c_long(), C.c_int()
    if lib.eng_run_events(run, group, C.byref(rows), C.byref(n), C.byref(width)) != 0:
        return np.zeros((0, 1))
    if n.value == 0:
        return np.zeros((0, width.value))
    # the bytes in one copy, into a writable buffer numpy takes as it is: cheaper than a
    # memmove into np.empty (whose address, by .ctypes or the array interface, costs
    # more than the copy) or np.ctypeslib.as_array (a ctypes array type per call)
    size = n.value * width.value * C.sizeof(C.c_double)
    return np.frombuffer(bytearray(C.string_at(rows, size))).reshape(n.value, width.value)


def declare(lib) -> None:
    """Argument and result types of the entry points this module calls."""
    lib.eng_simulate_me.argtypes = [_P(MeSpec), _P(Stats)]
    lib.eng_simulate_me.restype = C.c_void_p
    lib.eng_run_events.argtypes = [C.c_void_p, C.c_int, _P(_P(C.c_double)), _P(C.c_long),
                                   _P(C.c_int)]
    lib.eng_run_events.restype = C.c_int
    lib.eng_run_free.argtypes = [C.c_void_p]
    lib.eng_run_free.restype = None
    lib.eng_string.argtypes = [C.c_long]
    lib.eng_string.restype = C.c_char_p
    lib.eng_strings_clear.argtypes = []
    lib.eng_strings_clear.restype = None
