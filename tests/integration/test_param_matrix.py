"""Every scene x every settable name x every mode runs or is refused in one line (issue 26).

The cases are benchmarks.param_matrix's --quick ones: per scene, every numeric parameter
and start value nudged at once in each mode, the start-value aliases at once, and every
option value (on every instance of a kind at once) and FMU solver setting in the
scene's own mode (option values of a joined, monolithic scene in me), over five output
intervals.
`python -m benchmarks.param_matrix` runs every option value in every mode too.
"""
import pytest

from assemblies.scenes import SCENES
from benchmarks import param_matrix
from benchmarks.param_matrix import Case, cases, run_case, run_matrix


@pytest.mark.parametrize("name", list(SCENES))
def test_every_settable_name_runs_or_is_refused_in_one_line(name):
    outcomes = run_matrix([name], quick=True)
    failed = [o for o in outcomes if not o.ok]
    assert not failed, "\n\n".join(f"{o.mode} {o.case}:\n{o.message}" for o in failed)
    # the nudged values are valid ones: only a mode may refuse them (a foreign FMU the
    # mode cannot run, members one FMU cannot join yet), never an instance
    refused = [o for o in outcomes if o.case == "nudged" and o.verdict == "refused"]
    assert all(o.error == "AssemblyError" and "assembly" in o.message for o in refused), refused


@pytest.mark.parametrize("name", list(SCENES))
def test_the_cases_cover_every_name_show_lists(name):
    """No settable name is left out (a name the nudge could not move would be)."""
    covered = set()
    for case in cases(SCENES[name], quick=True):
        covered.update(case.params)
    asm = SCENES[name].build()
    wanted = {f"{inst_name}.{key}" for inst_name, inst in asm.components.items()
              for key in inst.settable_names()}
    assert wanted <= covered, sorted(wanted - covered)
    every_mode = [c for c in cases(SCENES[name], quick=True) if c.label == "nudged"]
    assert every_mode and every_mode[0].modes == param_matrix.MODES


def test_a_traceback_or_a_message_over_lines_fails(monkeypatch):
    """The verdicts themselves: what the matrix is there to catch is caught."""
    import assemblies.run
    from assemblies.assembly import AssemblyError

    case = Case("x", {})
    for raised, verdict in ((KeyError("no column 'beam.a0'"), "failed"),
                            (AssemblyError("first line\nsecond line"), "failed"),
                            (AssemblyError("instance 'a': b = 1 is not allowed"), "refused")):
        def boom(*args, raised=raised, **kwargs):
            raise raised
        monkeypatch.setattr(assemblies.run, "run_scene_full", boom)
        outcome = run_case("stick_slip", "cosim", case)
        assert outcome.verdict == verdict, outcome
