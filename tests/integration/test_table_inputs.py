"""Inputs from a table and a start time (issue 24, item 2), against closed forms and fmpy.

The plant is MSL's Speed source, a first-order lag ``v' = w (v_ref - v)`` with
``w = 2 pi f_crit``, its ``v_ref`` fed from a table with a ramp, a step (two rows at one
time) and a ramp down. Between breakpoints the input is linear, so the lag has a closed
form there, ``v = r(t) - b/w + (v_a - r_a + b/w) exp(-w (t - t_a))`` for
``r = r_a + b (t - t_a)``, chained across the breakpoints by hand: the reference. fmpy's
``simulate_fmu(input=...)`` on the same FMU is the second reference, for the
interpolation rules themselves (before the first row and after the last, where the step
falls, which side of it a row takes).
"""
import math

import numpy as np
import pytest

from assemblies import Assembly, AssemblyError
from assemblies import engine as C
from assemblies import masters as P
from components import PositionSensor, Speed
from components.sources.table import TimeTable

F_CRIT = 1.0
W = 2 * math.pi * F_CRIT
# (time, v_ref): held 0.2 before 0.5, ramp to 1, a step to 3 at t = 1, flat, ramp down
# to 0.5 at t = 3, held after
ROWS = [(0.5, 0.2), (1.0, 1.0), (1.0, 3.0), (2.0, 3.0), (3.0, 0.5)]
TOL = 1e-10


def table(rows=ROWS, shift=0.0, column="src.v_ref"):
    return np.array([(t + shift, y) for t, y in rows], dtype=[("time", float), (column, float)])


def lag() -> Assembly:
    asm = Assembly("lag")
    asm.add("src", Speed(f_crit=F_CRIT))
    asm.add("pos", PositionSensor())
    asm.connect("src.flange", "pos.flange")
    return asm


def closed_form(times, rows=ROWS, v0=0.0, w=W) -> np.ndarray:
    """The lag (rate `w`) from rest at t = 0 under the table, linear input piece by piece."""
    T = [t for t, _ in rows]
    # pieces (start, end, value at start, slope): held before the first and after the
    # last row, linear between two rows at different times (equal times: the step)
    pieces = [(-math.inf, T[0], rows[0][1], 0.0)]
    for (ta, ya), (tb, yb) in zip(rows, rows[1:]):
        if tb > ta:
            pieces.append((ta, tb, ya, (yb - ya) / (tb - ta)))
    pieces.append((T[-1], math.inf, rows[-1][1], 0.0))
    out = []
    for t in times:
        v, ts = v0, 0.0
        for start, end, ya, b in pieces:
            if end <= ts:
                continue
            te = min(end, t)
            if te <= ts:
                break
            ra = ya + b * (ts - start) if b else ya
            h = te - ts
            v = ra + b * h - b / w + (v - ra + b / w) * math.exp(-w * h)
            ts = te
        out.append(v)
    return np.array(out)


ADAPTIVE = dict(adaptive=True, extrapolation=1, tol=1e-8)
# the fmpy master takes the compiled one's steps in Python: 72,000 of them at 1e-8 took
# 20 s a run; at 1e-6 (9,700 steps, 2.5 s) it is 3.2e-8 off, and held to the 1e-6 the
# run at 1e-8 was (a misread row or breakpoint moves the response by tenths)
FMPY_ADAPTIVE = dict(ADAPTIVE, tol=1e-6)
RUNS = {  # (function, keywords, the accuracy it promises against the closed form)
    "c-me": (C.simulate_me, {}, 100 * TOL),
    "c-monolithic": (C.simulate_monolithic, {}, 100 * TOL),
    "c-cosim": (C.cosimulate, ADAPTIVE, 100 * ADAPTIVE["tol"]),
    "fmpy-me": (P.simulate_me, {}, 100 * TOL),
    "fmpy-monolithic": (P.simulate_monolithic, {}, 100 * TOL),
    "fmpy-cosim": (P.cosimulate, FMPY_ADAPTIVE, 100 * ADAPTIVE["tol"]),
}


@pytest.mark.parametrize("run", RUNS)
def test_tabulated_step_through_a_lag_matches_the_closed_form(run):
    """Every mode of both engines: the input ramps, steps at t = 1 and ramps down; the
    breakpoints are events, so the solvers meet the closed form to their tolerance
    (a kink or step inside a solver step would cost far more: the step alone is 2)."""
    fn, kw, accuracy = RUNS[run]
    res = fn(lag(), 4.0, 0.25, TOL, inputs=table(), **kw)
    assert res["time"][0] == 0.0 and res["time"][-1] == 4.0
    assert np.abs(res["src.v"] - closed_form(res["time"])).max() < accuracy
    if run == "c-me":  # the table's own output: fmpy's rule at every row (after the event)
        assert np.allclose(res["src_v_ref_table.y"][:5], [0.2, 0.2, 0.2, 0.6, 3.0],
                           rtol=0, atol=1e-12)
        assert res.settings["events"] >= 3  # t = 1 (the step), 2 and 3 (kinks)


@pytest.mark.parametrize("run", RUNS)
def test_start_time_shifts_the_closed_form(run):
    """A run from t0 = 1.5 with the table shifted by t0 is the run from 0 shifted: the
    FMUs are initialised at t0 (a table FMU still at 0 would be 1.5 s off), the rows start
    there, and the closed form from rest at t0 holds."""
    fn, kw, accuracy = RUNS[run]
    t0 = 1.5
    res = fn(lag(), t0 + 4.0, 0.25, TOL, inputs=table(shift=t0), start_time=t0, **kw)
    assert res["time"][0] == t0 and res["time"][-1] == t0 + 4.0
    assert np.allclose(np.diff(res["time"]), 0.25)
    assert res.settings["start_time"] == t0
    assert np.abs(res["src.v"] - closed_form(res["time"] - t0)).max() < accuracy


@pytest.mark.parametrize("fn", [C.cosimulate, P.cosimulate], ids=["c", "fmpy"])
def test_start_time_shifts_a_fixed_step_cosimulation(fn):
    """Fixed communication steps hold each input over a step (far from the closed form at
    h = 0.25); shifted by t0 the run must still be the same run: each row to rounding."""
    base = fn(lag(), 4.0, 0.25, TOL, inputs=table())
    moved = fn(lag(), 6.0, 0.25, TOL, inputs=table(shift=2.0), start_time=2.0)
    assert np.allclose(moved["time"] - 2.0, base["time"], rtol=0, atol=1e-12)
    assert np.abs(moved["src.v"] - base["src.v"]).max() < 1e-8


@pytest.mark.parametrize("fmi_type", ["ModelExchange", "CoSimulation"])
def test_interpolation_rules_match_fmpy_on_the_same_fmu(fmi_type):
    """fmpy's simulate_fmu(input=...) drives the Speed FMU itself (flange force 0, as the
    sensor gives it). fmpy applies continuous inputs at its communication points and holds
    them in between, an O(h) error at h = 1 ms; a rule of ours that differed (the step a
    row late or early, the first value not held before t = 0.5, the last not held after
    t = 3) would be off by 0.1 to 2."""
    import fmpy

    from fmus.build import build_fmu
    path = build_fmu(Speed(f_crit=F_CRIT), fmi_version=2)
    signals = np.array([(t, y, 0.0) for t, y in ROWS],
                       dtype=[("time", float), ("v_ref", float), ("flange.f", float)])
    ref = fmpy.simulate_fmu(str(path), fmi_type=fmi_type, input=signals, stop_time=4.0,
                            output_interval=1e-3, relative_tolerance=1e-8, output=["v"])
    ours = C.simulate_me(lag(), 4.0, 0.25, TOL, inputs=table())
    assert np.abs(np.interp(ours["time"], ref["time"], ref["v"]) - ours["src.v"]).max() < 5e-3


def test_time_table_follows_fmpys_interpolate():
    """The TimeTable alone, linear and held, against fmpy.simulation.Input.interpolate
    itself at times between rows, on rows and outside the table: continuous inputs
    linear, discrete ones the last row at or before the time (after_event: a run samples
    a row's time after its event)."""
    from fmpy.simulation import Input

    rows = [(0.5, 0.2), (1.0, 1.0), (1.0, 3.0), (2.0, 3.0), (2.5, -1.0), (3.0, 0.5)]
    t, y = np.array(rows).T
    for interpolation, discrete in (("linear", False), ("hold", True)):
        asm = Assembly("table_only")
        asm.add("tt", TimeTable(table=rows, interpolation=interpolation, offset=0.0))
        res = C.simulate_me(asm, 4.0, 0.125, TOL)
        expected = [Input.interpolate(s, t, y[None, :], discrete=discrete,
                                      after_event=True)[0][0] for s in res["time"]]
        assert np.abs(res["tt.y"] - expected).max() < 1e-12, interpolation


def test_time_table_offset_and_start_time():
    """MSL's TimeTable: y = offset + table(time - startTime)."""
    asm = Assembly("table_only")
    asm.add("tt", TimeTable(table=[(0.0, 0.0), (1.0, 2.0)], offset=0.5, startTime=1.0))
    res = C.simulate_me(asm, 3.0, 0.25, TOL)
    expected = 0.5 + np.clip(2.0 * (res["time"] - 1.0), 0.0, 2.0)
    assert np.abs(res["tt.y"] - expected).max() < 1e-12


def test_a_table_is_checked_as_input():
    """One line each: the column, the row or the bound, and what is allowed."""
    asm = lag()
    with pytest.raises(AssemblyError, match=r"column 'src\.v_rf' is not an open input of "
                                            r"assembly 'lag'; open inputs: src\.v_ref"):
        C.simulate_me(asm, 1.0, 0.1, inputs=table(column="src.v_rf"))
    bad = table()
    bad["time"][3] = 0.7
    with pytest.raises(AssemblyError, match=r"times must not decrease; row 4 \(time 0.7\) comes "
                                            r"after row 3 \(time 1\)"):
        C.simulate_me(asm, 1.0, 0.1, inputs=bad)
    bad = table()
    bad["src.v_ref"][2] = np.nan
    with pytest.raises(AssemblyError, match=r"column 'src\.v_ref' row 3 is nan, not a finite"):
        C.simulate_me(asm, 1.0, 0.1, inputs=bad)
    with pytest.raises(AssemblyError, match=r"no 'time' column; columns: t, src\.v_ref"):
        C.simulate_me(asm, 1.0, 0.1, inputs=np.zeros(2, dtype=[("t", float),
                                                                ("src.v_ref", float)]))
    from components.sources.table import MAX_ROWS
    many = np.zeros(MAX_ROWS + 1, dtype=[("time", float), ("src.v_ref", float)])
    many["time"] = np.arange(MAX_ROWS + 1)
    with pytest.raises(AssemblyError, match=rf"{MAX_ROWS + 1} rows; a table has 1 to {MAX_ROWS}"):
        P.simulate_me(asm, 1.0, 0.1, inputs=many)
    with pytest.raises(AssemblyError, match="inputs must be a numpy structured array, a pandas "
                                            "DataFrame or the path of a CSV file"):
        C.cosimulate(asm, 1.0, 0.1, inputs=[[0, 1]])
    assert list(asm.components) == ["src", "pos"]  # the user's assembly is left as it was


def test_start_time_is_checked():
    for start, words in ((math.inf, "start time must be finite, not inf"),
                         (2.0, "start time 2 s must be before the stop time 1 s"),
                         ("0", "start time must be a number, not '0'")):
        for fn in (C.simulate_me, C.cosimulate, C.simulate_monolithic, P.simulate_me,
                   P.cosimulate, P.simulate_monolithic):
            with pytest.raises(AssemblyError, match=words):
                fn(lag(), 1.0, 0.1, start_time=start)


def test_inputs_from_a_csv_file_and_a_dataframe(tmp_path):
    """A CSV file (fmpy's _in.csv shape) and a DataFrame give the run the array gives."""
    import pandas as pd

    csv = tmp_path / "lag_in.csv"
    csv.write_text("time,src.v_ref\n" + "".join(f"{t},{y}\n" for t, y in ROWS))
    frame = pd.DataFrame(ROWS, columns=["time", "src.v_ref"])
    runs = [C.simulate_me(lag(), 4.0, 0.25, TOL, inputs=i) for i in (table(), csv, str(csv), frame)]
    for res in runs[1:]:
        assert np.array_equal(res["src.v"], runs[0]["src.v"])
    csv.write_text("time,src.v_ref\n0,1\n1,x\n")
    with pytest.raises(AssemblyError, match=r"line 3 holds a field that is not a number"):
        C.simulate_me(lag(), 1.0, 0.1, inputs=csv)


def test_run_scene_takes_inputs_and_a_start_time():
    """run_scene_full with a Scene of the lag: tables attached before pruning, the start
    time reaches the master, and a single-instance scene names inputs without prefix."""
    from assemblies.run import run_scene_full
    from assemblies.scenes import Scene

    sc = Scene("lag", "a lag fed by a table", lag, 4.0, 0.25, TOL, ["src.v"],
               lambda res, asm: [], mode="me")
    run = run_scene_full(sc, inputs=table(shift=1.0), start_time=1.0, stop_time=5.0)
    res = run.result
    assert res["time"][0] == 1.0
    assert np.abs(res["src.v"] - closed_form(res["time"] - 1.0)).max() < 100 * TOL


# time, u (continuous: linear), d (discrete: held), k (Integer: held); rows on the
# 0.25 s output grid, so that fixed communication steps meet every change of d and k as
# fmpy's variable steps do
HOLD_ROWS = [(0.0, 0.0, 1.0, 1), (1.0, 2.0, 1.0, 1), (1.0, 2.0, -0.5, 4), (2.5, -1.0, 3.0, -3),
             (3.0, 0.0, 3.0, -3)]


def _hold_reference(t):
    """x = integral of d held at each row's value until the next row; y = u linear;
    k_out = k held."""
    x = np.where(t < 1.0, t, np.where(t < 2.5, 1.0 - 0.5 * (t - 1.0), 0.25 + 3.0 * (t - 2.5)))
    y = np.interp(t, [0.0, 1.0, 2.5, 3.0], [0.0, 2.0, -1.0, 0.0])
    k = np.where(t < 1.0, 1, np.where(t < 2.5, 4, -3))
    return x, y, k


def _hold_table(prefix=""):
    return np.array(HOLD_ROWS, dtype=[("time", float), (f"{prefix}u", float),
                                      (f"{prefix}d", float), (f"{prefix}k", np.int32)])


@pytest.mark.parametrize("how", ["c-me", "c-cosim", "fmpy-cosim", "fmpy.simulate_fmu-ME",
                                 "fmpy.simulate_fmu-CS"])
def test_a_discrete_input_is_held_and_a_continuous_one_interpolated(how):
    """A hand-written foreign FMU (tests/handmade/inputs_hold: x' = d for a discrete
    input d, y = u for a continuous one) fed one table by each master and by fmpy's
    simulate_fmu itself: d held from row to row (x piecewise linear, kinks at 1 and 2.5),
    u linear (y at the output points), the Integer k held (k_out), all to rounding. A single-instance assembly names
    its inputs without the instance."""
    import sys
    import warnings
    from pathlib import Path

    sys.path.insert(0, str(Path(__file__).parents[1]))
    from handmade_fmus import handmade_fmu

    from assemblies import FMU
    path = handmade_fmu("inputs_hold")
    if how.startswith("fmpy.simulate_fmu"):
        import fmpy
        res = fmpy.simulate_fmu(str(path), fmi_type="ModelExchange" if how.endswith("ME")
                                else "CoSimulation", input=_hold_table(), stop_time=4.0,
                                output_interval=0.25, output=["x", "y", "k_out"])
        keep = np.r_[np.diff(res["time"]) > 0, True]  # fmpy's rows before each event go
        t, x, y, k = res["time"][keep], res["x"][keep], res["y"][keep], res["k_out"][keep]
    else:
        asm = Assembly("held")
        asm.add("plant", FMU(path))
        fn, kw = {"c-me": (C.simulate_me, {}), "c-cosim": (C.cosimulate, {"adaptive": False}),
                  "fmpy-cosim": (P.cosimulate, {"adaptive": False})}[how]
        with warnings.catch_warnings():
            warnings.simplefilter("error")
            res = fn(asm, 4.0, 0.25, TOL, inputs=_hold_table(), **kw)
        t, x, y, k = res["time"], res["plant.x"], res["plant.y"], res["plant.k_out"]
        assert res["plant_d_table.y"][9] == -0.5  # t = 2.25: held, not 0.5 interpolated
    assert len(t) == 17
    x_ref, y_ref, k_ref = _hold_reference(t)
    assert np.abs(x - x_ref).max() < 1e-9
    if how != "fmpy.simulate_fmu-CS":
        assert np.array_equal(k, k_ref)
    if how != "fmpy.simulate_fmu-CS":  # fmpy's CS rows read y after a step, with the u
        assert np.abs(y - y_ref).max() < 1e-12  # set before it: a step behind


@pytest.mark.parametrize("t0", [0.0, 1.5])
@pytest.mark.parametrize("mode", ["me", "cosim"])
def test_a_time_table_inside_an_exported_assembly_fmu(mode, t0, tmp_path):
    """Every element is an FMU, so a TimeTable travels inside an assembly exported as one
    FMU: fmpy runs it with no input of its own, from its start time t0 (the table shifted
    alike), and the lag inside meets the closed form (fmpy's output points are the
    exported FMU's communication points)."""
    from fmpy import simulate_fmu
    from fmpy.validation import validate_fmu

    from assemblies import export_fmu
    asm = lag()
    asm.add("drive", TimeTable(table=[(t + t0, y) for t, y in ROWS]))
    asm.connect("drive.y", "src.v_ref")
    settings = {"adaptive": True, "extrapolation": 1, "tol": 1e-8} if mode == "cosim" else {}
    path = export_fmu(asm, tmp_path / f"lag_{mode}.fmu", outputs=["src.v", "drive.y"],
                      stop_time=4.0, step=0.25, tolerance=TOL, mode=mode, **settings)
    assert validate_fmu(str(path)) == []
    res = simulate_fmu(str(path), start_time=t0, stop_time=t0 + 4.0, output_interval=0.25)
    assert res["time"][0] == t0
    accuracy = 100 * (TOL if mode == "me" else settings["tol"])
    assert np.abs(res["src.v"] - closed_form(res["time"] - t0)).max() < accuracy
    assert res["drive.y"][4] == 3.0  # t0 + 1: the row after the step, as fmpy would set it


def _mechfmu(*args, cwd=None):
    import subprocess
    import sys
    return subprocess.run([sys.executable, "-m", "assemblies.cli", *args], capture_output=True,
                          text=True, cwd=cwd)


@pytest.mark.parametrize("args, words", [
    (["--start-time", "inf"], "start time must be finite, not inf (start_time=, --start-time)"),
    (["--start-time", "20", "--stop-time", "10"],
     "start time 20 s must be before the stop time 10 s (start_time=, --start-time)"),
    (["--inputs", "missing.csv"], "inputs: cannot read missing.csv: No such file or directory"),
    (["--inputs", "in.csv"], "inputs: column 'block.f' is not an open input of assembly "
                             "'stick_slip'; open inputs: (none)"),
])
def test_cli_start_time_and_inputs_errors_are_one_line(args, words, tmp_path):
    (tmp_path / "in.csv").write_text("time,block.f\n0,1\n")
    proc = _mechfmu("run", "stick_slip", *args, cwd=tmp_path)
    assert proc.returncode == 2
    assert proc.stderr.strip().splitlines() == [f"mechfmu: error: {words}"]


def test_cli_run_from_a_start_time(tmp_path):
    """The scene's rows start at --start-time, and its settings say so."""
    import json
    proc = _mechfmu("run", "stick_slip", "--start-time", "1", "--stop-time", "3", "--step",
                    "0.5", "--out", str(tmp_path))
    assert proc.returncode in (0, 1), proc.stderr  # its figures are measured from t = 0
    rows = (tmp_path / "stick_slip.csv").read_text().splitlines()
    assert [float(r.split(",")[0]) for r in rows[1:]] == [1.0, 1.5, 2.0, 2.5, 3.0]
    assert json.loads((tmp_path / "stick_slip.json").read_text())["settings"]["start_time"] == 1.0


def test_a_sweep_runs_from_a_start_time():
    """sweep(start_time=...) hands it to every run; a bad one is one line, before any run."""
    from assemblies.scenes import Scene
    from assemblies.sweep import sweep

    sc = Scene("lag", "a lag fed by a table", lambda: _fed_lag(1.0), 5.0, 0.25, TOL,
               ["src.v"], lambda res, asm: [], mode="me")
    table = sweep(sc, {"src.f_crit": [0.5, 1.0]}, outputs=["src.v@3.0"], workers=0,
                  progress=False, start_time=1.0)
    assert list(table["status"]) == ["ok", "ok"]
    for f_crit, v in zip(table["src.f_crit"], table["src.v@3.0"]):
        # from rest at t0 = 1 under the table shifted by 1: the closed form at 3 - 1
        assert abs(v - closed_form([2.0], w=2 * math.pi * f_crit)[0]) < 100 * TOL
    with pytest.raises(AssemblyError, match="start time 6 s must be before the stop time 5 s"):
        sweep(sc, {"src.f_crit": [1.0]}, workers=0, progress=False, start_time=6.0)


def _fed_lag(shift):
    asm = lag()
    asm.add("drive", TimeTable(table=[(t + shift, y) for t, y in ROWS]))
    asm.connect("drive.y", "src.v_ref")
    return asm


def test_an_integer_input_takes_whole_numbers_only():
    import sys
    from pathlib import Path

    sys.path.insert(0, str(Path(__file__).parents[1]))
    from handmade_fmus import handmade_fmu

    from assemblies import FMU
    asm = Assembly("held")
    asm.add("plant", FMU(handmade_fmu("inputs_hold")))
    bad = np.array([(0.0, 1.0), (1.0, 1.5)], dtype=[("time", float), ("k", float)])
    with pytest.raises(AssemblyError, match=r"column 'k' feeds an Int32 input, and row 2 holds "
                                            r"1.5, not a whole number within \+-2147483647"):
        C.simulate_me(asm, 4.0, 0.25, inputs=bad)
