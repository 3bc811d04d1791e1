"""Absurd requests (issue 25): a number that sizes memory or work beyond its limit
(assemblies.limits) is one line naming the limit, from Python and from `mechfmu`, in well
under a second and before anything is allocated, started or written; settings a study
shares are checked once before its first run."""
from __future__ import annotations

import time

import pytest

from assemblies import cosimulate, run_scene, scene, simulate_me
from assemblies.limits import (MAX_OUTPUT_ROWS, MAX_SWEEP_RUNS, LimitError, check_output_rows,
                               check_output_values, max_workers)
from assemblies.sweep import sweep
from test_bad_input import one_line_error
from conftest import quick_refusal

STICK_SLIP = scene("stick_slip").build


ROWS = ["assemblies.limits.MAX_OUTPUT_ROWS", f"at most {MAX_OUTPUT_ROWS:,}"]


@pytest.mark.parametrize("call, argv", [
    (lambda: run_scene("stick_slip", stop_time=1e300), ["--stop-time", "1e300"]),
    (lambda: run_scene("stick_slip", step=1e-300), ["--step", "1e-300"]),
    (lambda: run_scene("stick_slip", stop_time=1e9), ["--stop-time", "1e9"]),
    (lambda: run_scene("stick_slip", mode="me", stop_time=1e9), ["--mode", "me",
                                                                  "--stop-time", "1e9"]),
    (lambda: run_scene("stick_slip", engine="fmpy", stop_time=1e9), ["--engine", "fmpy",
                                                                      "--stop-time", "1e9"]),
], ids=["stop 1e300", "step 1e-300", "stop 1e9", "me stop 1e9", "fmpy stop 1e9"])
def test_an_output_table_beyond_memory_is_refused_before_the_run(capsys, tmp_path, call, argv):
    message = quick_refusal(call, *ROWS, "output rows")
    assert one_line_error(capsys, ["run", "stick_slip", *argv, "--out", str(tmp_path)],
                          ROWS) == f"mechfmu: error: {message}"
    assert list(tmp_path.iterdir()) == []


# every absurd number of `mechfmu run` (issue 26): one line naming the option and what it
# may be, before anything is built or written, in every mode
ABSURD = [
    (["--step", "1e-300"], ["output rows", "--step", f"at most {MAX_OUTPUT_ROWS:,}"]),
    (["--step", "1e-300", "--start-time", "39.9"],
     ["a run of 0.1 s (start time 39.9 s)", "--step", "--start-time"]),
    (["--step", "0"], ["step must be a positive finite number", "--step"]),
    (["--step", "inf"], ["step must be a positive finite number", "--step"]),
    (["--stop-time", "-1"], ["stop time must be a positive finite number", "--stop-time"]),
    (["--stop-time", "1e300"], ["output rows", "--stop-time"]),
    (["--tolerance", "0"], ["tolerance must be in [1e-14, 1)", "--tolerance"]),
    (["--tolerance", "nan"], ["tolerance must be in [1e-14, 1)", "--tolerance"]),
    (["--start-time", "nan"], ["start time must be finite", "--start-time"]),
    (["--start-time", "50"], ["start time 50 s must be before the stop time 40 s",
                              "--start-time"]),
    # the output times would not differ by a step (before: hundreds of rows at one time)
    (["--start-time", "1e17", "--stop-time", "100000000000000040"],
     ["step 0.1 s is below what times near 1e+17 s resolve", "--step"]),
]


@pytest.mark.parametrize("mode", ["cosim", "me", "monolithic"])
@pytest.mark.parametrize("argv, words", ABSURD, ids=[" ".join(a) for a, _ in ABSURD])
def test_an_absurd_number_of_a_run_names_its_option(capsys, tmp_path, argv, words, mode):
    started = time.perf_counter()
    one_line_error(capsys, ["run", "stick_slip", "--mode", mode, *argv, "--out", str(tmp_path)],
                   words)
    assert time.perf_counter() - started < 1.0
    assert list(tmp_path.iterdir()) == []


def test_the_engine_front_ends_check_the_rows_too():
    quick_refusal(lambda: cosimulate(STICK_SLIP(), 1e9, 0.01), *ROWS)
    quick_refusal(lambda: simulate_me(STICK_SLIP(), 10.0, 1e-300), *ROWS)


def test_the_row_count_is_the_output_grid():
    """0, h, ..., T: T/h + 1 rows; the last interval may be shorter (one more row)."""
    assert check_output_rows(10.0, 0.1) == 101
    assert check_output_rows(10.0, 3.0) == 5
    assert check_output_rows(MAX_OUTPUT_ROWS - 1.0, 1.0) == MAX_OUTPUT_ROWS
    with pytest.raises(LimitError):
        check_output_rows(float(MAX_OUTPUT_ROWS), 1.0)
    # rows x columns: 10 million rows of 26 columns are within 2**28 numbers, of 27 not
    check_output_values(MAX_OUTPUT_ROWS, 26, "x")
    with pytest.raises(LimitError, match="assemblies.limits.MAX_OUTPUT_VALUES"):
        check_output_values(MAX_OUTPUT_ROWS, 27, "x")


RUNS = ["assemblies.limits.MAX_SWEEP_RUNS", f"at most {MAX_SWEEP_RUNS:,}"]


@pytest.mark.parametrize("kwargs, argv, runs", [
    (dict(params={"block.m": "1:2:1000000000"}), ["--param", "block.m=1:2:1000000000"], "1e+09"),
    (dict(params={"block.m": "1:2"}, random=1_000_000_000),
     ["--param", "block.m=1:2", "--random", "1000000000"], "1e+09"),
    (dict(params={"block.m": "1:2:1000", "block.k": "1:2:1000"}),
     ["--param", "block.m=1:2:1000", "--param", "block.k=1:2:1000"], "1e+06"),
], ids=["count", "random", "grid"])
def test_a_study_beyond_its_run_limit_is_refused_before_its_design_is_made(capsys, tmp_path,
                                                                          kwargs, argv, runs):
    """The count, the random design and the grid's product are checked before any value
    is made (the 1e9-count grid was killed by the OOM killer at 23.8 GB)."""
    message = quick_refusal(lambda: sweep("stick_slip", workers=0, progress=False, **kwargs),
                            *RUNS, f"makes {runs} runs")
    assert one_line_error(capsys, ["sweep", "stick_slip", *argv, "--workers", "0", "--out",
                                   str(tmp_path)], RUNS) == f"mechfmu: error: {message}"
    assert list(tmp_path.iterdir()) == []


@pytest.mark.parametrize("workers", [100_000, max_workers() + 1, -1, 2.5, True])
def test_workers_beyond_twice_the_cores_are_refused_before_a_cluster_starts(capsys, workers):
    words = ["workers must be a whole number from 1 to", "assemblies.limits.WORKERS_PER_CORE"]
    message = quick_refusal(lambda: sweep("stick_slip", {"block.m": "1,2"}, workers=workers,
                                          progress=False), *words)
    if isinstance(workers, int) and not isinstance(workers, bool):
        assert one_line_error(capsys, ["sweep", "stick_slip", "--param", "block.m=1,2",
                                       "--workers", str(workers)], words) == \
            f"mechfmu: error: {message}"


@pytest.mark.parametrize("argv, words", [
    (["--stop-time", "0"], ["stop time must be a positive finite number", "0.0"]),
    (["--stop-time", "nan"], ["stop time must be a positive finite number", "nan"]),
    (["--stop-time", "1e300"], ROWS),
    (["--output", "block.x@1e300"], ["output 'block.x@1e300'", "1e300 s is not in the run",
                                     "stop time 40 s"]),
    (["--output", "block.x@-1"], ["output 'block.x@-1'", "-1 s is not in the run"]),
], ids=["stop 0", "stop nan", "stop 1e300", "output time 1e300", "output time -1"])
def test_the_settings_of_a_study_are_checked_once_before_its_first_run(capsys, tmp_path,
                                                                      argv, words):
    """Before: exit 0 with every run failed, or a NaN column."""
    started = time.perf_counter()
    one_line_error(capsys, ["sweep", "stick_slip", "--param", "block.m=1,2", "--workers", "0",
                            "--out", str(tmp_path), *argv], words)
    assert time.perf_counter() - started < 1.0
    assert list(tmp_path.iterdir()) == []


def test_a_study_whose_folder_cannot_be_written_stops_before_it_runs(capsys):
    """Before: the runs went through, then a traceback (FileNotFoundError)."""
    one_line_error(capsys, ["sweep", "stick_slip", "--param", "block.m=1,2", "--workers", "0",
                            "--out", "/proc/x"], ["--out /proc/x: cannot write there"])
    quick_refusal(lambda: sweep("stick_slip", {"block.m": "1,2"}, workers=0, progress=False,
                                out="/proc/x"), "out /proc/x: cannot write there")


def test_a_plot_of_no_such_column_leaves_no_files_behind(capsys, tmp_path):
    """Before: exit 2, with the CSV and the JSON of the study left in --out."""
    one_line_error(capsys, ["sweep", "stick_slip", "--param", "block.m=1,2", "--workers", "0",
                            "--plot", "nosuch", "--out", str(tmp_path)],
                   ["cannot plot 'nosuch'", "columns: run, block.m"])
    assert list(tmp_path.iterdir()) == []


@pytest.mark.parametrize("kwargs, words", [
    (dict(chunk=-1), ["chunk must be a whole number of runs per task >= 1", "-1"]),
    (dict(chunk=0), ["chunk must be", "0"]),
    (dict(random=True), ["--random must be a whole number of runs >= 1", "True"]),
], ids=["chunk -1", "chunk 0", "random True"])
def test_a_study_with_a_chunk_or_design_size_that_is_no_count_is_refused(kwargs, words):
    """Before: chunk=-1 made no tasks (a study of no rows), chunk=0 was read as 'guided'
    and random=True as one run."""
    quick_refusal(lambda: sweep("stick_slip", {"block.m": "1:2"}, workers=0, progress=False,
                                **kwargs), *words)


def test_an_exported_fmu_may_default_to_a_long_experiment(tmp_path):
    """The row limit is the run's table: an exported FMU's default experiment keeps none."""
    from assemblies import export_fmu
    path = export_fmu(STICK_SLIP(), tmp_path / "long.fmu", stop_time=1e9, step=1e-3)
    assert 'stopTime="1000000000' in __import__("zipfile").ZipFile(path).read(
        "modelDescription.xml").decode()


@pytest.mark.parametrize("kwargs, words", [
    (dict(mode="cosmic"), ["mode must be one of cosim, me, monolithic", "'cosmic'"]),
    (dict(engine="x"), ["engine must be one of c, fmpy", "'x'"]),
    (dict(stop_time=float("nan")), ["stop time must be a positive finite number", "nan"]),
], ids=["mode", "engine", "stop nan"])
def test_a_study_from_python_checks_its_settings_before_its_runs(kwargs, words):
    """Before: a table of failed rows, the same error on each."""
    quick_refusal(lambda: sweep("stick_slip", {"block.m": "1,2"}, workers=0, progress=False,
                                **kwargs), *words)
