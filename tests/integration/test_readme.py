"""The README's Python example runs as printed."""
import re
from pathlib import Path

README = Path(__file__).resolve().parents[2] / "README.md"


def test_python_example_runs(tmp_path, monkeypatch):
    block = re.search(r"```python\n(.*?)```", README.read_text(), re.S).group(1)
    code_lines = [line for line in block.splitlines() if line.strip()]
    assert len(code_lines) <= 11  # "a ten-line example", imports included
    monkeypatch.chdir(tmp_path)
    namespace = {}
    exec(compile(block, "README.md", "exec"), namespace)
    assert (tmp_path / "block.fmu").exists()
    res = namespace["res"]
    assert "block.x" in res.columns and len(res["time"]) > 10
