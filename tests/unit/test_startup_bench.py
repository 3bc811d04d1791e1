"""`python -m benchmarks.startup` times whole processes and says which it could not run;
nothing here depends on how fast they were."""
import json
import sys

from benchmarks import startup


def test_a_row_per_command_with_its_spread_and_a_failed_command_said(tmp_path):
    cases = [("pass", [sys.executable, "-c", "pass"], 1e9),
             ("fails", [sys.executable, "-c", "raise SystemExit(3)"], None)]
    rows = startup.measure(runs=3, cases=cases)
    ran, failed = rows
    assert ran["runs"] == 3 and 0 < ran["min_s"] <= ran["median_s"] <= ran["max_s"]
    assert ran["met"] is True  # a target no process can miss
    assert "exited 3" in failed["error"] and failed["met"] is None
    text = startup.table(rows)
    assert "met" in text and "failed: " in text
    section = startup.results_section({"runs": 3, "when": "now", "machine": "here",
                                       "load_average": [0.5, 0.7], "rows": rows})
    assert section[0] == "## Startup of a command (issue 26)"
    assert any(line.startswith("| `fails` | failed") for line in section)
    json.dumps(rows)  # what --json writes

