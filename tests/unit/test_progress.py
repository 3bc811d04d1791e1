"""The progress report of a long run, driven by a fake clock: a log gets plain lines
(simulated time, wall time, time left) at a bounded rate, a terminal a bar redrawn in place."""
import io

from assemblies.progress import ProgressReport


class FakeClock:
    def __init__(self):
        self.now = 100.0

    def __call__(self):
        return self.now


class Terminal(io.StringIO):
    def isatty(self):
        return True


def test_a_log_gets_a_line_after_two_seconds_then_one_every_interval():
    clock, log = FakeClock(), io.StringIO()
    report = ProgressReport(50.0, stream=log, log_interval=5.0, clock=clock)
    for wall, t in ((1.0, 1.0), (1.9, 2.0), (2.0, 2.5), (4.0, 5.0), (7.0, 10.0), (63.0, 40.0),
                    (63.5, 50.0)):
        clock.now = 100.0 + wall
        report(t)
    report.close()
    # quiet for the first 2 s; then at 2 s, not at 4 s (< 5 s after), at 7 s and at 63 s;
    # time left = elapsed (1 - f) / f: 2 (1 - 0.05) / 0.05 = 38 s, 7 * 0.8 / 0.2 = 28 s,
    # 63 * 0.2 / 0.8 = 15.75 s
    assert log.getvalue().splitlines() == [
        "  t = 2.5 / 50 s (5.0 %), 2 s elapsed, about 38 s left",
        "  t = 10 / 50 s (20.0 %), 7 s elapsed, about 28 s left",
        "  t = 40 / 50 s (80.0 %), 1 min 03 s elapsed, about 16 s left",
    ]


def test_a_run_shorter_than_two_seconds_prints_nothing():
    clock, log = FakeClock(), io.StringIO()
    report = ProgressReport(10.0, stream=log, clock=clock)
    for wall in (0.5, 1.0, 1.99):
        clock.now = 100.0 + wall
        report(wall * 5)
    report.close()
    assert log.getvalue() == ""


def test_a_terminal_gets_a_bar_redrawn_in_place_and_a_newline_at_the_end():
    clock, tty = FakeClock(), Terminal()
    report = ProgressReport(3600.0, stream=tty, width=10, clock=clock)
    clock.now = 100.0 + 300.0
    report(0.0)
    clock.now = 100.0 + 600.0
    report(900.0)  # a quarter in 10 min: 30 min left
    report.close()
    text = tty.getvalue()
    assert "\n" not in text[:-1] and text.endswith("\n")
    frames = text[:-1].split("\r")[1:]
    assert frames == [
        "  [----------] t = 0 / 3600 s (0.0 %), 5 min 00 s elapsed, time left not known yet\x1b[K",
        "  [##--------] t = 900 / 3600 s (25.0 %), 10 min 00 s elapsed, about 30 min 00 s left"
        "\x1b[K"]


def test_the_command_says_when_it_builds_an_fmu(monkeypatch, tmp_path, capsys):
    """A build takes seconds (a 64-mode beam, more), so a command that builds is never
    silent: one line on stderr per FMU compiled, none when the cache has it."""
    import fmus.build
    import fmus.integrity
    from assemblies.cli import _say_when_building
    from components import SpringBlock

    compiled = []

    def compile_stand_in(identifier, c_source, xml, target, fmi_version, html=""):
        compiled.append(identifier)  # gcc is not what this test is about
        target.parent.mkdir(parents=True, exist_ok=True)
        target.write_bytes(b"")
        fmus.integrity.record(target)  # as a build does: the cache trusts what it recorded

    monkeypatch.setenv("MECHFMU_CACHE", str(tmp_path))
    monkeypatch.setattr(fmus.build, "_compile", compile_stand_in)
    monkeypatch.setattr(fmus.build, "announce", None)
    _say_when_building()
    fmus.build.build_fmu(SpringBlock(), fmi_version=3)
    fmus.build.build_fmu(SpringBlock(), fmi_version=3)  # cached: nothing to say
    assert compiled == ["SpringBlock"]
    assert capsys.readouterr().err == ("building the FMU of SpringBlock (FMI 3, once per "
                                       "machine)\n")
