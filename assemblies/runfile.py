"""A run's JSON file as the record that repeats it: what it writes, and reading it back.

``out/SCENE.json`` holds, beside the figures and the master's settings, everything the
run was given and everything it used: the run's options as asked (``run``: the mode,
engine, times, step, tolerance, co-simulation scheme, adaptive and extrapolation, the
Jacobian, pruning, ``--param`` as given, and the inputs table: its file's path and
SHA-256, or its rows where it came from memory), and every instance's parameters,
options, start values and solver as the run used them (``instances``, after the
parameters were applied), with the FMI version of each instance's FMU and the mechfmu
version that ran it.

:func:`rerun` (and ``mechfmu run --from FILE.json``) builds the scene again, sets every
recorded value, and runs it with the recorded options; an option given to it overrides
the file's. The same mechfmu on the same machine gives the same table bit for bit: the
same FMUs (built from the same values, so fetched from the same cache entries) are run
by the same deterministic masters with the same doubles (JSON keeps a double exactly).

The file is foreign input: it is read only up to :data:`MAX_RUN_FILE_BYTES`, and a file
that is not such a record, was written by another version, or names a scene, instance
or value that does not exist here is refused in one line before anything runs.
"""
from __future__ import annotations

import hashlib
import json
import math
import numbers
from pathlib import Path

from .assembly import AssemblyError
from .version import mechfmu_version

#: the layout of the record; a file of another is refused (its fields mean other things)
FORMAT = 1
#: the largest run file read: a record with an inputs table held inline is at most about
#: the table's CSV (assemblies.inputs.MAX_CSV_BYTES, 16 MiB) again, as JSON numbers
MAX_RUN_FILE_BYTES = 32 * 2**20
#: the options of run_scene_full that a record holds, as it names them
RUN_OPTIONS = ("mode", "engine", "start_time", "stop_time", "step", "tolerance", "scheme",
               "adaptive", "extrapolation", "jacobian", "prune")
#: the fields of an instance's record, in the order they are set again (options first:
#: they decide which parameters and states exist)
VALUE_GROUPS = ("options", "parameters", "starts", "strings", "solver")


class RunFileError(AssemblyError):
    """A run file that cannot be repeated (a ValueError, one line)."""


_JSON_TYPES = frozenset((float, int, str, bool, type(None)))


def _plain(value):
    """A value as JSON holds it: numpy scalars as Python numbers."""
    if type(value) in _JSON_TYPES:  # nearly every value: no ABC checks (every run records)
        return value
    if isinstance(value, (str, bool)):
        return value
    if isinstance(value, numbers.Integral):
        return int(value)
    if isinstance(value, numbers.Real):
        return float(value)
    return str(value)


def instance_values(assembly, profiles: dict[str, str]) -> dict:
    """Every instance's values as the run uses them, with its causality profile (of
    `profiles`, the run's assembly resolved: an engine that reuses a prepared run leaves
    a fresh instance's own unresolved) and its FMU's FMI version."""
    from fmus.model_description import DEFAULT_FMI

    from .foreign import FMU
    out = {}
    for name, comp in assembly.components.items():
        rec = {"type": type(comp).__name__, "profile": profiles[name],
               "options": {k: _plain(v) for k, v in comp.option_values.items()},
               "parameters": {k: _plain(v) for k, v in comp.values.items()},
               "starts": {k: _plain(v) for k, v in comp.starts.items()},
               "strings": dict(getattr(comp, "_strings", {})),
               "solver": getattr(comp, "solver", None),
               "fmi": comp.fmi_version if isinstance(comp, FMU) else DEFAULT_FMI}
        if isinstance(comp, FMU):
            rec["fmu"] = str(comp.path)
        out[name] = rec
    return out


def set_instance_values(assembly, instances: dict) -> None:
    """Set what :func:`instance_values` recorded, each instance checked once all of its
    values are set (a value may need another: the beam's n_modes='auto' its coordinates)."""
    if not isinstance(instances, dict):
        raise RunFileError("run file: 'instances' must map each instance to its values")
    missing = set(assembly.components) - set(instances)
    if missing:
        raise RunFileError(f"run file: no values for instance(s) {', '.join(sorted(missing))} "
                           f"of scene '{assembly.name}'")
    for name, rec in instances.items():
        comp = assembly.component(name)  # an instance the scene lacks: one line
        if not isinstance(rec, dict) or rec.get("type") != type(comp).__name__:
            got = rec.get("type") if isinstance(rec, dict) else rec
            raise RunFileError(f"run file: instance '{name}' is a {type(comp).__name__} in "
                               f"scene '{assembly.name}', and the file's is {got!r}")
        for group in VALUE_GROUPS:
            values = rec.get(group)
            if group == "solver":
                if values is not None:
                    comp.set("solver", values)
                continue
            if not isinstance(values, dict):
                raise RunFileError(f"run file: instance '{name}': '{group}' must map names to "
                                   f"values, not {type(values).__name__}")
            for key, value in values.items():
                if not isinstance(value, (str, int, float)) or isinstance(value, bool):
                    raise RunFileError(f"run file: {name}.{key} = {value!r} is not a number "
                                       "or text")
                comp.set(key, value)
        comp.validate()


def _sha256(path: Path) -> str:
    from .inputs import MAX_CSV_BYTES
    with path.open("rb") as fh:  # bounded: the inputs reader refuses more before this
        return hashlib.sha256(fh.read(MAX_CSV_BYTES + 1)).hexdigest()


def inputs_record(inputs) -> dict | None:
    """The inputs table as the record keeps it: a file by its path and content hash, a
    table from memory by its columns (read and checked as the run reads it)."""
    if inputs is None:
        return None
    if isinstance(inputs, (str, Path)):
        path = Path(inputs).expanduser().resolve()
        return {"path": str(path), "sha256": _sha256(path)}
    from .inputs import TIME, read_table
    times, columns = read_table(inputs)
    return {"columns": {TIME: times.tolist(), **{k: v.tolist() for k, v in columns.items()}}}


def inputs_from_record(rec):
    """The run's inputs again: the same file, refused if its content changed since."""
    if rec is None:
        return None
    if not isinstance(rec, dict):
        raise RunFileError("run file: 'inputs' must be null or an object")
    if "path" in rec:
        path, sha = rec.get("path"), rec.get("sha256")
        if not isinstance(path, str) or not isinstance(sha, str):
            raise RunFileError("run file: inputs need a 'path' and its 'sha256'")
        try:
            now = _sha256(Path(path))
        except OSError as exc:
            raise RunFileError(f"run file: inputs {path}: cannot read it "
                               f"({exc.strerror or exc})") from None
        if now != sha:
            raise RunFileError(f"run file: inputs {path} changed since the run (SHA-256 "
                               f"{now[:12]}..., the run's {sha[:12]}...); give the table "
                               "again with --inputs to run with the new one")
        return path
    columns = rec.get("columns")
    if not isinstance(columns, dict) or not all(isinstance(v, list) for v in columns.values()):
        raise RunFileError("run file: inputs need a 'path' or 'columns' of numbers")
    import numpy as np
    try:
        data = {k: np.asarray(v, dtype=float) for k, v in columns.items()}
    except (TypeError, ValueError):
        raise RunFileError("run file: inputs 'columns' must hold numbers") from None
    lengths = {len(v) for v in data.values()}
    if len(lengths) != 1 or any(v.ndim != 1 for v in data.values()):
        raise RunFileError("run file: inputs 'columns' must be lists of one length")
    table = np.zeros(lengths.pop(), dtype=[(k, float) for k in data])
    for k, v in data.items():
        table[k] = v
    return table


def run_record(scene_name: str, options: dict, params: dict | None, inputs,
               assembly, profiles: dict[str, str]) -> dict:
    """The record of a run (see the module doc): `options` as run_scene_full took them,
    `profiles` the causality profile of each instance."""
    return {"format": FORMAT, "mechfmu": mechfmu_version(),
            "run": {"scene": scene_name, **{k: _plain(options[k]) for k in RUN_OPTIONS},
                    "params": {k: _plain(v) for k, v in (params or {}).items()},
                    "inputs": inputs_record(inputs)},
            "instances": instance_values(assembly, profiles)}


def read_run(path) -> dict:
    """The record in the run file at `path`, checked as far as it can be before a run."""
    path = Path(path)
    try:
        with path.open("rb") as fh:
            data = fh.read(MAX_RUN_FILE_BYTES + 1)
    except OSError as exc:
        raise RunFileError(f"run file {path}: cannot read it ({exc.strerror or exc})") from None
    if len(data) > MAX_RUN_FILE_BYTES:
        raise RunFileError(f"run file {path}: more than {MAX_RUN_FILE_BYTES:,} bytes "
                           "(assemblies.runfile.MAX_RUN_FILE_BYTES); a run's file is smaller")
    try:
        record = json.loads(data.decode("utf-8"))
    except (ValueError, RecursionError) as exc:  # UnicodeDecodeError is a ValueError
        raise RunFileError(f"run file {path}: not a JSON file "
                           f"({str(exc).splitlines()[0][:120]})") from None
    if not isinstance(record, dict) or not isinstance(record.get("run"), dict):
        raise RunFileError(f"run file {path}: no 'run' record; it is not the JSON a run of "
                           "mechfmu writes (out/SCENE.json)")
    if record.get("format") != FORMAT or record.get("mechfmu") != mechfmu_version():
        raise RunFileError(
            f"run file {path}: written by mechfmu {record.get('mechfmu')!r} (run file format "
            f"{record.get('format')!r}); this is mechfmu {mechfmu_version()!r} (format "
            f"{FORMAT}): a run is repeated by the version that made it")
    run = record["run"]
    unknown = set(run) - {"scene", "params", "inputs", *RUN_OPTIONS}
    if unknown or not isinstance(run.get("scene"), str):
        raise RunFileError(f"run file {path}: 'run' needs a scene name and takes "
                           f"{', '.join(RUN_OPTIONS)}, params, inputs"
                           + (f"; unknown: {', '.join(sorted(unknown))}" if unknown else ""))
    if not isinstance(record.get("instances"), dict):
        raise RunFileError(f"run file {path}: 'instances' must map each instance to its values")
    if not isinstance(run.get("prune", True), bool):
        raise RunFileError(f"run file {path}: prune must be true or false, not {run['prune']!r}")
    if not isinstance(run.get("params", {}), dict):
        raise RunFileError(f"run file {path}: 'params' must map INSTANCE.NAME to values")
    for key in ("stop_time", "step", "tolerance", "start_time"):
        if isinstance(run.get(key), float) and not math.isfinite(run[key]):
            raise RunFileError(f"run file {path}: {key} is {run[key]}")
    return record


# the overrides that make the file's settings of another mode or engine meaningless
_MODE_BOUND = {"mode": ("scheme", "adaptive", "extrapolation", "jacobian"),
               "engine": ("jacobian",)}


def run_arguments(record: dict, params: dict | None = None, **overrides) -> dict:
    """Keyword arguments of run_scene_full that repeat `record`, each of `overrides`
    (not None) replacing the file's and `params` set after its values. A new mode drops
    the file's co-simulation settings and Jacobian, a new engine its Jacobian: they
    belong to the run that was."""
    from .scenes import scene
    run = record["run"]
    sc = scene(run["scene"])  # an unknown scene: one line
    given = {k: v for k, v in overrides.items() if v is not None}
    unknown = set(given) - {*RUN_OPTIONS, "inputs", "out", "progress"}
    if unknown:
        raise RunFileError(f"rerun: unknown option(s) {', '.join(sorted(unknown))}")
    options = {k: run.get(k) for k in RUN_OPTIONS}
    for changed, bound in _MODE_BOUND.items():
        if changed in given and given[changed] != options[changed]:
            options.update({k: None for k in bound})
    options.update(given)
    options["prune"] = True if options["prune"] is None else options["prune"]
    options["engine"] = options["engine"] or "c"
    inputs = given["inputs"] if "inputs" in given else inputs_from_record(run.get("inputs"))
    return {"name": sc, **options, "inputs": inputs,
            "params": {**run.get("params", {}), **(params or {})},
            "values": record.get("instances")}


def rerun(path, params: dict | None = None, **overrides):
    """Repeat the run whose JSON file is `path` (``out/SCENE.json``) and return its
    :class:`~assemblies.run.SceneRun`; `overrides` (``stop_time=``, ``mode=``, ``out=``,
    any option of :func:`~assemblies.run.run_scene_full`) replace the file's, `params`
    are set after its values. See the module doc."""
    from .run import run_scene_full
    return run_scene_full(**run_arguments(read_run(path), params, **overrides))
