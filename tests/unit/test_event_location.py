"""Event location (fmus/runtime/events.c) on indicators given in closed form.

The runtime's mf_locate_event is compiled alone and called through ctypes with a Python
indicator that counts its evaluations: the roots it must find are those of the closed
forms, and a step whose indicators cannot cross inside it is not sampled there.
"""
from __future__ import annotations

import ctypes
import math

import numpy as np
import pytest

from fmus.build import RUNTIME_DIR, compile_library

INDICATOR = ctypes.CFUNCTYPE(ctypes.c_int, ctypes.c_void_p, ctypes.c_double,
                             ctypes.POINTER(ctypes.c_double))
N_SUB = 4  # the runtime's EVENT_SUBSAMPLES


# the runtime is built with hidden symbols: one exported entry in front of it
ENTRY = """#include "events.h"
__attribute__((visibility("default"))) int test_locate(mf_indicator_fn z, void *ctx, int n,
    double ta, double *z_ref, double tb, const double *z_b, int n_sub, double *t_event,
    double *z_event, double *work)
{ return mf_locate_event(z, ctx, n, ta, z_ref, tb, z_b, n_sub, t_event, z_event, work); }
"""


@pytest.fixture(scope="module")
def locate(tmp_path_factory):
    folder = tmp_path_factory.mktemp("events")
    (folder / "entry.c").write_text(ENTRY)
    library = folder / "events.so"
    compile_library([folder / "entry.c", RUNTIME_DIR / "events.c", RUNTIME_DIR / "solver.c"],
                    library, [RUNTIME_DIR], "the event location test")
    fn = ctypes.CDLL(str(library)).test_locate
    dp = ctypes.POINTER(ctypes.c_double)
    fn.argtypes = [INDICATOR, ctypes.c_void_p, ctypes.c_int, ctypes.c_double, dp,
                   ctypes.c_double, dp, ctypes.c_int, dp, dp, dp]
    fn.restype = ctypes.c_int

    def run(funcs, ta, tb):
        """(found, t_event, evaluations inside the step) for indicators `funcs` of t."""
        calls = [0]

        def z(_, t, out):
            calls[0] += 1
            for i, f in enumerate(funcs):
                out[i] = f(t)
            return 0
        cb = INDICATOR(z)
        n = len(funcs)
        z_ref = (ctypes.c_double * n)(*(f(ta) for f in funcs))
        z_b = (ctypes.c_double * n)(*(f(tb) for f in funcs))
        t_event, z_event = ctypes.c_double(math.nan), (ctypes.c_double * n)()
        work = (ctypes.c_double * (n * (N_SUB + 4)))()
        found = fn(cb, None, n, ta, z_ref, tb, z_b, N_SUB, ctypes.byref(t_event), z_event, work)
        return found, t_event.value, calls[0]
    return run


def test_a_step_whose_indicators_move_away_from_zero_is_not_sampled_inside(locate):
    """A relative velocity growing from 1 to 3 and a static margin falling from 5 to 4 over
    the step cannot reach zero: two evaluations (their rates) instead of N_SUB - 1 samples."""
    found, _, calls = locate([lambda t: 1.0 + 2.0 * t, lambda t: 5.0 - t * t], 0.0, 1.0)
    assert found == 0
    assert calls == 2


def test_a_dip_through_zero_between_positive_ends_is_found(locate):
    """(t - 0.4)(t - 0.6) + 0.01 t is positive at both ends and crosses zero at its smaller
    root: the rate at the start points at zero, so the interior is sampled."""
    def f(t):
        return (t - 0.4) * (t - 0.6) + 0.01 * t
    root = (1.0 - 0.01 - math.sqrt((1.0 - 0.01) ** 2 - 4 * 0.24)) / 2
    found, t_event, _ = locate([f], 0.0, 1.0)
    assert found == 1
    assert t_event == pytest.approx(root, abs=1e-12)
    assert f(t_event) <= 0.0  # on the far side, as the model must see it


def test_a_monotone_crossing_is_located_from_the_ends_alone(locate):
    """cos(t) - 0.5 falls monotonically through zero at pi/3 over [0.9, 1.2], a step short
    against its curvature as a solver's are: one root, located by the bracket without
    interior samples; its neighbour, positive throughout, is not sampled either."""
    found, t_event, calls = locate([lambda t: math.cos(t) - 0.5, lambda t: 2.0 + t], 0.9, 1.2)
    assert found == 1
    assert t_event == pytest.approx(math.pi / 3, abs=1e-12)
    # the two rate evaluations, then the Illinois iteration only
    assert calls < 2 + N_SUB - 1 + 20


def test_a_crossing_that_turns_back_is_sampled(locate):
    """sin(3 t) on [0.1, 1.2] rises, turns and crosses zero at pi/3: not monotone, so the
    interior is sampled, and the one root is found."""
    found, t_event, _ = locate([lambda t: math.sin(3 * t)], 0.1, 1.2)
    assert found == 1
    assert t_event == pytest.approx(math.pi / 3, abs=1e-12)


@pytest.mark.parametrize("phase", np.linspace(0.15, 0.85, 7))
def test_a_narrow_excursion_inside_a_step_is_never_missed(locate, phase):
    """A velocity that passes through zero and back inside one step (a short slip): the
    ends and their rates point at zero, so the step is sampled and the first root found."""
    w = 0.08

    def f(t):
        return (t - phase) ** 2 - w * w
    first = phase - w
    found, t_event, _ = locate([f], 0.0, 1.0)
    assert found == 1
    assert t_event == pytest.approx(first, abs=1e-12)
