"""What the README shows is what happens: every fenced block in it is run here, or says
why not.

A block is classified by its language and by a marker comment on the line above it,
``<!-- readme-test: KIND -->``:

- ``sh`` block, no marker: each line is a ``mechfmu`` command, run from a scratch folder
  (shared by the whole README, in its order, so a later block can read what an earlier one
  wrote); each must exit 0, and each ``run`` must end with ``all N figures pass``;
- ``exit N`` above an ``sh`` block: the same, exit status N expected (and for ``run`` with
  N = 1, the ``FAILED:`` line);
- ``python`` block, no marker: executed in the scratch folder;
- ``output of the block above``: the printed output of the block before it, compared line by
  line (numbers to 1e-6 relative, the wall time left out);
- ``output of `mechfmu ...` ``: that command's output, compared the same way;
- ``synopsis``: every ``--option`` shown for a command is in that command's ``--help``;
- ``layout``: every file and folder named in the tree exists in the repository;
- ``skip: REASON``: not run, with the reason (counted; a skip without a reason fails).

Any other block fails `test_every_block_is_run_or_says_why_not`.
"""
from __future__ import annotations

import contextlib
import io
import math
import os
import re
import shlex
import subprocess
import sys
from dataclasses import dataclass
from pathlib import Path

import pytest

ROOT = Path(__file__).resolve().parents[2]
README = ROOT / "README.md"
SHELLS = {"sh", "bash", "console", "shell"}
MARKER = re.compile(r"^\s*<!--\s*readme-test:\s*(.*?)\s*-->\s*$")
FENCE = re.compile(r"^(\s*)```(\S*)\s*$")
# what a run prints that no two runs share: left out of the comparison
VOLATILE = [re.compile(r"wall time .*$")]


@dataclass
class Block:
    line: int  # of the opening fence, 1-based
    lang: str
    text: str
    marker: str | None
    output: "Block | None" = None  # the "output of the block above" that follows it

    @property
    def kind(self) -> str:
        m = self.marker or ""
        if m.startswith("skip:"):
            return "skip" if m[5:].strip() else "unmarked"
        if m.startswith("output of the block above"):
            return "output-above"
        if m.startswith("output of `"):
            return "output-of"
        if m.startswith("synopsis"):
            return "synopsis"
        if m.startswith("layout"):
            return "layout"
        if self.lang in SHELLS and (not m or re.fullmatch(r"exit \d+", m)):
            return "sh"
        if self.lang == "python" and not m:
            return "python"
        return "unmarked"

    @property
    def id(self) -> str:
        return f"L{self.line}-{self.kind}"


def readme_blocks(text: str) -> list[Block]:
    """Every fenced block of `text`, with the marker on the line above it, dedented to its
    fence; an ``output of the block above`` block is attached to the block before it."""
    lines = text.splitlines()
    blocks, i = [], 0
    while i < len(lines):
        fence = FENCE.match(lines[i])
        if not fence:
            i += 1
            continue
        indent, lang = len(fence.group(1)), fence.group(2)
        above = MARKER.match(lines[i - 1]) if i else None
        j = i + 1
        while j < len(lines) and not re.match(r"^\s*```\s*$", lines[j]):
            j += 1
        body = "\n".join(line[indent:] for line in lines[i + 1:j])
        blocks.append(Block(i + 1, lang, body + "\n", above.group(1) if above else None))
        i = j + 1
    for before, block in zip(blocks, blocks[1:]):
        if block.kind == "output-above":
            before.output = block
    return blocks


BLOCKS = readme_blocks(README.read_text())
RUN = [b for b in BLOCKS if b.kind in ("sh", "python", "output-of", "synopsis", "layout")]


def numbers_match(a: str, b: str) -> bool:
    try:
        x, y = float(a), float(b)
    except ValueError:
        return a == b
    if math.isnan(x) or math.isnan(y):
        return math.isnan(x) and math.isnan(y)
    # an error of 1e-10 against one of 3e-10: both rounding noise, neither a claim
    return abs(x - y) <= 1e-6 * max(abs(x), abs(y)) or max(abs(x), abs(y)) < 1e-9


def assert_output_matches(shown: str, printed: str, where: str) -> None:
    """The README's `shown` output against what was `printed`: the same lines, the same
    words, numbers within rounding (see `numbers_match`)."""
    def words(line):
        for pattern in VOLATILE:
            line = pattern.sub("", line)
        return line.split()
    expected = [words(line) for line in shown.strip().splitlines()]
    actual = [words(line) for line in printed.strip().splitlines()]
    assert len(expected) == len(actual), (
        f"{where}: the README shows {len(expected)} lines, the run printed {len(actual)}:\n"
        f"{printed}")
    for n, (e, a) in enumerate(zip(expected, actual), 1):
        assert len(e) == len(a) and all(map(numbers_match, e, a)), (
            f"{where}, line {n}: the README shows\n  {' '.join(e)}\nthe run printed\n  "
            f"{' '.join(a)}")


def commands(block_text: str) -> list[list[str]]:
    """The commands of a shell block: continuation lines joined, comments dropped."""
    joined = block_text.replace("\\\n", " ")
    return [shlex.split(line, comments=True) for line in joined.splitlines()
            if shlex.split(line, comments=True)]


def mechfmu(args: list[str], cwd: Path) -> subprocess.CompletedProcess:
    """`mechfmu ARGS` as the README's reader types it, from this checkout."""
    env = {**os.environ, "PYTHONPATH": str(ROOT)}
    return subprocess.run([sys.executable, "-m", "assemblies.cli", *args], cwd=cwd, env=env,
                          capture_output=True, text=True, timeout=300)


def check_command(argv: list[str], expected_rc: int, cwd: Path, where: str) -> str:
    assert argv[0] == "mechfmu", f"{where}: not a mechfmu command: {shlex.join(argv)}"
    done = mechfmu(argv[1:], cwd)
    assert done.returncode == expected_rc, (
        f"{where}: `{shlex.join(argv)}` exited {done.returncode}, the README says "
        f"{expected_rc}\n{done.stdout}\n{done.stderr}")
    if len(argv) > 1 and argv[1] == "run":
        last = done.stdout.strip().splitlines()[-1]
        if expected_rc == 0:
            assert re.fullmatch(r"all \d+ figures pass", last), f"{where}: {last}"
        elif expected_rc == 1:
            assert last.startswith("FAILED: "), f"{where}: {last}"
    if expected_rc not in (0, 1):
        assert "Traceback" not in done.stderr and len(done.stderr.strip().splitlines()) == 1
    return done.stdout


@pytest.fixture(scope="module")
def scratch(tmp_path_factory):
    """One folder for the whole README, as a reader's: a block reads what one above wrote."""
    return tmp_path_factory.mktemp("readme")


def test_every_block_is_run_or_says_why_not():
    kinds = [b.kind for b in BLOCKS]
    unmarked = [b.line for b in BLOCKS if b.kind == "unmarked"]
    assert not unmarked, (
        f"README blocks at lines {unmarked} are neither run nor marked: give each a "
        "`<!-- readme-test: ... -->` line (see tests/integration/test_readme.py)")
    skipped = [b for b in BLOCKS if b.kind == "skip"]
    orphans = [b.line for b in BLOCKS if b.kind == "output-above"
               and not any(o.output is b for o in BLOCKS)]
    assert not orphans
    print(f"README: {len(BLOCKS)} blocks, {len(RUN)} run, "
          f"{kinds.count('output-above')} outputs compared with the block above, "
          f"{len(skipped)} skipped: " + "; ".join(f"line {b.line}: {b.marker[5:].strip()}"
                                                   for b in skipped))
    # the ones that must never become skips: what a newcomer runs first
    assert kinds.count("python") >= 2 and kinds.count("sh") >= 2
    assert len(skipped) <= 4, "more README blocks skipped than run-worthy reasons allow"


@pytest.mark.parametrize("block", RUN, ids=[b.id for b in RUN])
def test_readme_block(block, scratch):
    where = f"README.md line {block.line}"
    if block.kind == "sh":
        expected = int(block.marker.split()[1]) if block.marker else 0
        printed = [check_command(argv, expected, scratch, where) for argv in commands(block.text)]
        if block.output:
            assert_output_matches(block.output.text, printed[-1], where)
    elif block.kind == "output-of":
        command = re.match(r"output of `([^`]+)`", block.marker).group(1)
        printed = check_command(shlex.split(command), 0, scratch, where)
        assert_output_matches(block.text, printed, where)
    elif block.kind == "python":
        run_python(block, scratch, where)
    elif block.kind == "synopsis":
        check_synopsis(block.text, scratch, where)
    elif block.kind == "layout":
        check_layout(block.text, where)


def run_python(block: Block, scratch: Path, where: str) -> None:
    printed = io.StringIO()
    before = os.getcwd()
    os.chdir(scratch)
    try:
        with contextlib.redirect_stdout(printed):
            exec(compile(block.text, where, "exec"), {"__name__": "__readme__"})
    finally:
        os.chdir(before)
    if block.output:
        assert_output_matches(block.output.text, printed.getvalue(), where)


def check_synopsis(text: str, scratch: Path, where: str) -> None:
    """Each `mechfmu COMMAND ...` line (with its indented continuation lines): COMMAND
    exists and every --option shown is in its --help."""
    entries: list[list[str]] = []
    for line in text.splitlines():
        if line.startswith("mechfmu"):
            entries.append([line.split("#")[0]])
        elif entries and line.startswith(" "):
            entries[-1].append(line.split("#")[0])
    assert entries, f"{where}: no mechfmu command in the synopsis"
    helps: dict[str, str] = {}
    for entry in entries:
        words = " ".join(entry).split()
        sub = words[1] if len(words) > 1 and not words[1].startswith("-") else ""
        if sub not in helps:
            done = mechfmu([sub, "--help"] if sub else ["--help"], scratch)
            assert done.returncode == 0, f"{where}: `mechfmu {sub} --help` failed:\n{done.stderr}"
            helps[sub] = done.stdout
        for option in re.findall(r"(?<![\w-])--[a-z][\w-]*", " ".join(entry)):
            assert re.search(rf"(?<![\w-]){re.escape(option)}(?![\w-])", helps[sub]), (
                f"{where}: the README shows `mechfmu {sub} {option}`, which "
                f"`mechfmu {sub} --help` does not list")


def check_layout(text: str, where: str) -> None:
    """Every path-like word of the tree (`name/`, `name.py`, `c/fmu.c`) names something in
    the repository."""
    present = {p.relative_to(ROOT).as_posix() + ("/" if p.is_dir() else "")
               for top in ("components", "fmus", "assemblies", "benchmarks", "tests", "docs")
               for p in [ROOT / top, *(ROOT / top).rglob("*")] if "__pycache__" not in p.parts}
    named = re.findall(r"(?<![\w./])((?:[\w]+/)*[\w]+(?:\.(?:py|c|h|md)|/))(?![\w])", text)
    assert len(named) > 20, f"{where}: the tree names only {named}"
    generated = {"docs/api/", "api/"}  # written by `make docs`, not committed
    missing = [n for n in named if n not in generated
               and not any(p == n or p.endswith("/" + n) for p in present)]
    assert not missing, f"{where}: the README's tree names what does not exist: {missing}"


def test_output_comparison_can_fail():
    """The comparison is not vacuous: a changed figure, a changed verdict, a line more."""
    shown = "t2   12.06888787  pass\nwall time 0.1 s\nall 3 figures pass\n"
    assert_output_matches(shown, "t2 12.068887871 pass\nwall time 9 s (more)\nall 3 figures pass", "x")
    for printed in ("t2 12.0689 pass\nwall time 1 s\nall 3 figures pass",
                    "t2 12.06888787 FAIL\nwall time 1 s\nall 3 figures pass",
                    "t2 12.06888787 pass\nwall time 1 s\nall 3 figures pass\nmore"):
        with pytest.raises(AssertionError):
            assert_output_matches(shown, printed, "x")


def test_blocks_are_classified_by_their_markers():
    text = ("<!-- readme-test: skip: too slow -->\n```sh\nmake test\n```\n"
            "```python\nprint(1)\n```\n<!-- readme-test: output of the block above -->\n"
            "```text\n1\n```\n  <!-- readme-test: exit 1 -->\n  ```sh\n  mechfmu run x\n  ```\n"
            "<!-- readme-test: skip: -->\n```sh\nls\n```\n```text\nloose\n```\n")
    blocks = readme_blocks(text)
    assert [b.kind for b in blocks] == ["skip", "python", "output-above", "sh", "unmarked",
                                        "unmarked"]
    assert blocks[1].output is blocks[2] and blocks[3].text == "mechfmu run x\n"
    assert commands("mechfmu a \\\n  --b c   # note\n\nmechfmu d\n") == [
        ["mechfmu", "a", "--b", "c"], ["mechfmu", "d"]]


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


def test_readme_links_stay_inside_the_repository():
    """Every relative link and image of the README names a file of this repository (the
    design notes once lived outside it); anchors name a heading."""
    text = README.read_text()
    headings = {re.sub(r"[^\w\- ]", "", h.strip().lower()).replace(" ", "-")
                for h in re.findall(r"^#+ (.*)$", text, re.M)}
    for target in re.findall(r"\]\(([^)\s]+)\)", text):
        if target.startswith(("http://", "https://")):
            continue
        if target.startswith("#"):
            assert target[1:] in headings, f"README links to a missing heading: {target}"
            continue
        path = (ROOT / target).resolve()
        assert path.is_relative_to(ROOT) and path.exists(), f"README links to {target}"
    assert "../" not in re.sub(r"https?://\S+", "", text)
