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


def test_scene_table_is_the_registrys():
    """README's scene table is generated (`mechfmu scenes --markdown`): a scene added,
    renamed or re-described without regenerating it fails here. Regenerate with
    `python -m assemblies.scenes.listing README.md`."""
    from assemblies.scenes import SCENES
    from assemblies.scenes.listing import markdown_table, readme_table
    table = readme_table(README.read_text())
    assert table, "README.md has lost the marker line of the generated scene table"
    assert table == markdown_table(), (
        "README's scene table is out of date: run `python -m assemblies.scenes.listing README.md`")
    assert len(table.splitlines()) == 2 + len(SCENES)


def test_scene_table_rewrites_a_stale_copy(tmp_path):
    from assemblies.scenes.listing import MARKER, markdown_table, readme_table, rewrite
    stale = tmp_path / "README.md"
    stale.write_text(f"# x\n\n{MARKER}\n| scene | seed | reference |\n| --- | --- | --- |\n"
                     "| `gone` | 1.1 | nothing |\n\nafter\n")
    only_scenes = [(MARKER, markdown_table())]
    assert rewrite(stale, only_scenes) and not rewrite(stale, only_scenes)
    text = stale.read_text()
    assert readme_table(text) == markdown_table() and text.endswith("\n\nafter\n")
    bare = tmp_path / "BARE.md"
    bare.write_text(f"{MARKER}\nafter\n")
    assert rewrite(bare, only_scenes) and bare.read_text() == f"{MARKER}\n{markdown_table()}\nafter\n"


def test_component_table_is_the_registrys():
    """README lists every component `mechfmu build` takes, generated from the registry with
    its ports and profiles: one added without regenerating the table fails here."""
    from components import COMPONENTS
    from components.listing import MARKER, markdown_table
    from assemblies.scenes.listing import readme_table
    table = readme_table(README.read_text(), MARKER)
    assert table == markdown_table(), (
        "README's component table is out of date: run "
        "`python -m assemblies.scenes.listing README.md`")
    names = [row.split("|")[1].strip().strip("`") for row in table.splitlines()[2:]]
    assert names == list(COMPONENTS)
    assert "| `SpringBlock` |" in table and "driven, driven_on_moving_support |" in table
