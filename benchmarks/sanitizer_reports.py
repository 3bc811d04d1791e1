"""Counts what AddressSanitizer, UBSan and LeakSanitizer wrote during `make asan`.

usage: python -m benchmarks.sanitizer_reports LOG_FOLDER

The sanitized runs write one log per process into LOG_FOLDER (ASAN_OPTIONS and
UBSAN_OPTIONS log_path). Every AddressSanitizer error (also a failed internal CHECK,
which ends the process as an error does) and every UBSan "runtime error" counts. Leaks are checked at each process's exit, and Python's interpreter, numpy and
lxml keep memory until the process dies by design: a leak counts only when the caller of
the allocator (frame #1) is mechfmu's C code (the runtime, the engine, the assembly FMU
or a generated model: compiled with -g from fmus/runtime, assemblies/engine or a
mechfmu-build- folder) or a library already unloaded (fmpy unloads an FMU's binary when
the instance is freed, so its frames lose their names; Python's own allocations come
through its allocator, frame #1 in Objects/ or Python/).
Prints one line per kind and each counted report; exit code 0 only if all are 0.
"""
from __future__ import annotations

import re
import sys
from pathlib import Path

OURS = re.compile(r"fmus/runtime/|assemblies/engine/|mechfmu-build-|<unknown module>")


def classify(text: str) -> dict[str, list[str]]:
    """{"asan": reports, "ubsan": reports, "leaks": our leak records} of one log."""
    found = {"asan": [], "ubsan": [], "leaks": []}
    for block in re.split(r"\n(?==+\n==\d+==ERROR)", text):
        if "ERROR: AddressSanitizer" in block or "AddressSanitizer: CHECK failed" in block:
            found["asan"].append(block.strip())
    found["ubsan"] += [line for line in text.splitlines() if "runtime error:" in line]
    for record in re.split(r"\n(?=(?:Direct|Indirect) leak of )", text):
        caller = re.search(r"^\s*#1 .*$", record, flags=re.M)
        if re.match(r"(Direct|Indirect) leak of ", record) and caller and OURS.search(caller[0]):
            found["leaks"].append(record.split("\n\n")[0].strip())
    return found


def main(argv: list[str]) -> int:
    if len(argv) != 1 or not Path(argv[0]).is_dir():
        print("usage: python -m benchmarks.sanitizer_reports LOG_FOLDER", file=sys.stderr)
        return 2
    logs = sorted(p for p in Path(argv[0]).iterdir() if p.is_file())
    totals = {"asan": [], "ubsan": [], "leaks": []}
    for log in logs:
        for kind, reports in classify(log.read_text(errors="replace")).items():
            totals[kind] += [f"{log.name}: {r}" for r in reports]
    for kind, reports in totals.items():
        for report in reports:
            print(report[:3000], end="\n\n")
    print(f"{len(logs)} sanitizer logs: {len(totals['asan'])} AddressSanitizer errors, "
          f"{len(totals['ubsan'])} UBSan runtime errors, {len(totals['leaks'])} leaks in "
          "mechfmu's code")
    return 0 if not any(totals.values()) else 1


if __name__ == "__main__":
    sys.exit(main(sys.argv[1:]))
