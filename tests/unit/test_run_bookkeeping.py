"""The per-run bookkeeping of the engine's Python side reads what the C wrote (issue 27):
a run's statistics unpacked in one call equal the ctypes fields one by one, a
composite's start values gathered per member land where their keys say, and a result's
settings are made once, when first read, and travel with it when it is pickled."""
import copy
import ctypes as C
import pickle

import numpy as np

from assemblies.engine import binding as B
from assemblies.result import Result
from assemblies.engine.me import _runs_by_member


def test_stats_numbers_are_the_fields_one_by_one():
    stats = B.Stats()
    numeric = [(name, kind) for name, kind in B.Stats._fields_
               if kind in (C.c_int, C.c_long, C.c_double)]
    for i, (name, kind) in enumerate(numeric):  # distinct values, signs and fractions
        setattr(stats, name, (-1) ** i * (i + 1) * (0.5 if kind is C.c_double else 1))
    stats.message = b"x" * 1023  # the text between the numbers is skipped, not read
    numbers = B.stats_numbers(stats)
    assert list(numbers._fields) == [name for name, _ in sorted(
        numeric, key=lambda f: getattr(B.Stats, f[0]).offset)]
    for name, _ in numeric:
        assert getattr(numbers, name) == getattr(stats, name), name
    assert B._STATS_LAYOUT[0].size <= C.sizeof(B.Stats)


def test_member_runs_fill_each_key_from_its_member():
    keys = [("a", "m"), ("a", "L"), ("b", "c"), ("a", "s")]  # a member may come back
    values = {"a": {"m": 1.0, "L": 2.0, "s": 4.0}, "b": {"c": 3.0}}
    runs = _runs_by_member(keys)
    assert [(name, first, end) for name, first, end, _ in runs] == [("a", 0, 2), ("b", 2, 3),
                                                                     ("a", 3, 4)]
    out = np.zeros(len(keys))
    for name, first, end, get in runs:
        out[first:end] = get(values[name])
    np.testing.assert_array_equal(out, [values[n][k] for n, k in keys])


def test_a_result_makes_its_settings_once_when_first_read_and_pickles_them():
    made = []

    def settings():
        made.append(1)
        return {"steps": 3}
    result = Result.of_columns({"time": np.zeros(2)}, {}, settings)
    assert made == []
    assert result.settings["steps"] == 3 and result.settings is result.settings
    assert made == [1]
    unread = Result.of_columns({"time": np.zeros(2)}, {}, settings)
    for back in (pickle.loads(pickle.dumps(unread)), copy.deepcopy(unread)):
        assert back.settings == {"steps": 3}
        assert list(back.columns) == ["time"]
    result.settings = {"steps": 4}  # a caller may still replace them
    assert result.settings == {"steps": 4}
