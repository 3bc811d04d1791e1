"""A run's files reproduce it (issue 26): the JSON a run writes records every option and
every instance's values as used, and `mechfmu run --from FILE.json` / `assemblies.rerun`
repeats the run from it alone, in another folder, bit for bit: the same mechfmu runs the
same FMUs (fetched by the same values) through the same deterministic masters with the
same doubles (JSON keeps each double exactly), so nothing is left to round. A file that
is not such a record, or names what does not exist here, is one line before any run."""
from __future__ import annotations

import json

import numpy as np
import pytest

from assemblies import rerun, run_scene_full
from assemblies.cli import main
from assemblies.runfile import MAX_RUN_FILE_BYTES
from assemblies.scenes import SCENES, Scene
from assemblies.version import mechfmu_version
from conftest import quick_refusal
from conftest import one_line_error

# settings that are not the run's but the machine's time
TIMING = ("wall_s", "setup_s")


def _mechfmu(capsys, *argv) -> int:
    """Run `mechfmu argv`, which must go through (exit 1: a figure missed; the run
    is still written)."""
    code = main(list(argv))
    err = capsys.readouterr().err
    assert code in (0, 1), err
    return code


def _files(folder, name):
    record = json.loads((folder / f"{name}.json").read_text())
    for key in TIMING:
        record["settings"].pop(key, None)
    return (folder / f"{name}.csv").read_bytes(), record


# a friction law, a mass and a start value that are not the scene's, in a mode, sweep,
# extrapolation, step, tolerance and times that are not its defaults either
ARGV = ["--param", "block.friction=tanh", "--param", "block.m=1.5", "--param", "block.x=0.2",
        "--mode", "cosim", "--fixed-step", "--scheme", "gauss-seidel", "--extrapolation", "1",
        "--step", "0.02", "--tolerance", "1e-9", "--start-time", "0.5", "--stop-time", "12"]


def test_a_run_repeats_from_its_json_file_in_another_folder(capsys, tmp_path, monkeypatch):
    first, second, plain = tmp_path / "first", tmp_path / "elsewhere", tmp_path / "plain"
    _mechfmu(capsys, "run", "stick_slip", *ARGV, "--out", str(first))
    csv, record = _files(first, "stick_slip")
    # the file says what was asked and what the instances held, as given above
    run = record["run"]
    assert (run["scene"], run["mode"], run["scheme"], run["adaptive"], run["extrapolation"],
            run["step"], run["tolerance"], run["start_time"], run["stop_time"]) == \
        ("stick_slip", "cosim", "gauss-seidel", False, 1, 0.02, 1e-9, 0.5, 12.0)
    block = record["instances"]["block"]
    assert block["options"]["friction"] == "tanh" and block["parameters"]["m"] == 1.5
    assert block["starts"]["x"] == 0.2 and block["fmi"] == 3
    assert record["mechfmu"] == mechfmu_version()

    monkeypatch.chdir(tmp_path)  # another folder, and the file named relative to it
    _mechfmu(capsys, "run", "--from", "first/stick_slip.json", "--out", "elsewhere")
    assert _files(second, "stick_slip") == (csv, record)  # bitwise, settings and all
    # and the file, not the defaults, made it: the scene's own run is another table
    _mechfmu(capsys, "run", "stick_slip", "--out", str(plain))
    assert _files(plain, "stick_slip")[0] != csv


def test_the_values_come_from_the_instances_and_options_given_override(tmp_path, capsys):
    """The instances' values are what the repeat sets (a file edited there runs edited),
    and each option on the command line replaces the file's."""
    a, b, c = tmp_path / "a", tmp_path / "b", tmp_path / "c"
    _mechfmu(capsys, "run", "stick_slip", "--stop-time", "8", "--out", str(a))
    record = json.loads((a / "stick_slip.json").read_text())
    record["instances"]["block"]["parameters"]["m"] = 2.0
    edited = tmp_path / "edited.json"
    edited.write_text(json.dumps(record))
    _mechfmu(capsys, "run", "--from", str(edited), "--out", str(b))
    _mechfmu(capsys, "run", "stick_slip", "--stop-time", "8", "--param", "block.m=2",
             "--out", str(c))
    assert _files(b, "stick_slip")[0] == _files(c, "stick_slip")[0]
    # an override: --stop-time and --mode replace the file's, the rest is kept
    _mechfmu(capsys, "run", "--from", str(a / "stick_slip.json"), "--stop-time", "5",
             "--mode", "me", "--out", str(b))
    run = _files(b, "stick_slip")[1]["run"]
    assert (run["stop_time"], run["mode"], run["tolerance"]) == \
        (5.0, "me", record["run"]["tolerance"])
    assert float((b / "stick_slip.csv").read_text().splitlines()[-1].split(",")[0]) == 5.0


def test_the_help_says_how_options_meet_the_file(capsys):
    with pytest.raises(SystemExit):
        main(["run", "--help"])
    text = " ".join(capsys.readouterr().out.split())
    assert "--from FILE.json" in text and "each option given here overrides the file's" in text


def _lag_scene(monkeypatch):
    """A scene with an open input (the registry's have none): a speed source lagging
    behind the table (tests/integration/test_table_inputs.py's assembly)."""
    from test_table_inputs import lag
    sc = Scene("rf_lag", "lag behind a table", lag, 4.0, 0.25, 1e-10,
               ["src.v", "pos.s"], lambda res, asm: [], plot=["src.v"], mode="me")
    monkeypatch.setitem(SCENES, "rf_lag", sc)
    return sc


def test_an_inputs_file_is_recorded_by_its_content(tmp_path, monkeypatch):
    from test_table_inputs import ROWS
    sc = _lag_scene(monkeypatch)
    inputs = tmp_path / "in.csv"
    inputs.write_text("time,src.v_ref\n" + "".join(f"{t},{y}\n" for t, y in ROWS))
    first = run_scene_full(sc, inputs=str(inputs), out=tmp_path / "a")
    again = rerun(tmp_path / "a" / "rf_lag.json", out=tmp_path / "b")
    assert (tmp_path / "a" / "rf_lag.csv").read_bytes() == (tmp_path / "b" / "rf_lag.csv").read_bytes()
    assert np.array_equal(first.result["src.v"], again.result["src.v"])
    assert again.record["run"]["inputs"]["path"] == str(inputs.resolve())
    # the same table from memory is kept in the file itself, and repeats the same
    table = np.array(ROWS, dtype=[("time", float), ("src.v_ref", float)])
    run_scene_full(sc, inputs=table, out=tmp_path / "c")
    rerun(tmp_path / "c" / "rf_lag.json", out=tmp_path / "d")
    assert (tmp_path / "c" / "rf_lag.csv").read_bytes() == \
        (tmp_path / "d" / "rf_lag.csv").read_bytes() == (tmp_path / "a" / "rf_lag.csv").read_bytes()
    # a table changed since the run is not the run's
    inputs.write_text(inputs.read_text().replace("3.0", "4.0"))
    quick_refusal(lambda: rerun(tmp_path / "a" / "rf_lag.json", out=tmp_path / "e"),
                  f"inputs {inputs.resolve()} changed since the run", "--inputs")


def _bad(tmp_path, name: str, text: str | bytes):
    path = tmp_path / name
    (path.write_bytes if isinstance(text, bytes) else path.write_text)(text)
    return path


@pytest.fixture(scope="module")
def good(tmp_path_factory) -> str:
    """The text of a short run's JSON file, made once for the cases that spoil it."""
    folder = tmp_path_factory.mktemp("good")
    run_scene_full("stick_slip", stop_time=1.0, out=folder)
    return (folder / "stick_slip.json").read_text()


def _edited(good: str, edit) -> str:
    record = json.loads(good)
    edit(record)
    return json.dumps(record)


def _set(path, value):
    def edit(record):
        *keys, last = path
        for key in keys:
            record = record[key]
        record[last] = value
    return edit


BAD = {  # name -> (the file's text, or an edit of a good file; the words of its one line)
    "corrupt": (b"\x89PNG\r\n\x1a\n\x00\x00", ["not a JSON file"]),
    "truncated": ('{"scene": "stick_slip", "run": {', ["not a JSON file"]),
    "nested": ("[" * 100_000 + "]" * 100_000, ["not a JSON file"]),
    "not a run": ('{"scene": "stick_slip", "figures": []}', ["no 'run' record"]),
    "other version": (_set(["mechfmu"], "0.0.1"),
                      ["written by mechfmu '0.0.1'", "repeated by the version that made it"]),
    "other format": (_set(["format"], 99), ["run file format 99"]),
    "unknown scene": (_set(["run", "scene"], "no_such_scene"),
                      ["unknown scene 'no_such_scene'", "stick_slip"]),
    "unknown instance": (_set(["instances", "ghost"], {"type": "SpringBlock"}),
                         ["no instance 'ghost'", "instances: driver, block"]),
    "unknown parameter": (_set(["instances", "block", "parameters", "mass"], 1.0),
                          ["unknown name 'mass'", "settable names: m, k"]),
    "value out of range": (_set(["instances", "block", "parameters", "m"], -1.0),
                           ["parameter m = -1 is not allowed"]),
    "value not a number": (_set(["instances", "block", "parameters", "m"], [1]),
                           ["block.m = [1] is not a number or text"]),
    "unknown option": (_set(["run", "speed"], 2), ["unknown: speed"]),
    "absurd step": (_set(["run", "step"], 1e-300), ["output rows", "--step"]),
    # before: a ValueError traceback from float('x'), from the API as from the file
    "adaptive text": (_set(["run", "adaptive"], "x"),
                      ["adaptive (--adaptive/--fixed-step) must be True, False or a tolerance"]),
    "prune text": (_set(["run", "prune"], "no"), ["prune must be true or false"]),
    "instance of another type": (_set(["instances", "block", "type"], "Beam"),
                                 ["instance 'block' is a SpringBlock", "the file's is 'Beam'"]),
    "no instances": (_set(["instances"], None), ["'instances' must map each instance"]),
}


@pytest.mark.parametrize("case", BAD)
def test_a_bad_run_file_is_refused_in_one_line(case, tmp_path, capsys, good):
    text, words = BAD[case]
    if callable(text):
        text = _edited(good, text)
    path = _bad(tmp_path, "run.json", text)
    out = tmp_path / "out"
    one_line_error(capsys, ["run", "--from", str(path), "--out", str(out)], words)
    assert not out.exists() or not list(out.iterdir())
    quick_refusal(lambda: rerun(path, out=out), *words)


def test_a_run_file_is_read_only_up_to_its_bound(tmp_path, capsys):
    big = tmp_path / "big.json"
    with big.open("wb") as fh:  # sparse: its size, not its reading, is the point
        fh.truncate(MAX_RUN_FILE_BYTES + 1)
    one_line_error(capsys, ["run", "--from", str(big)], ["assemblies.runfile.MAX_RUN_FILE_BYTES"])
    one_line_error(capsys, ["run", "--from", str(tmp_path / "none.json")], ["cannot read it"])


def test_a_scene_named_beside_the_file_must_be_the_files(tmp_path, capsys, good):
    path = _bad(tmp_path, "run.json", good)
    one_line_error(capsys, ["run", "friction_damping", "--from", str(path)],
                   ["is a run of scene 'stick_slip', not 'friction_damping'"])
    one_line_error(capsys, ["run"], ["required: scene", "--from FILE.json"])
