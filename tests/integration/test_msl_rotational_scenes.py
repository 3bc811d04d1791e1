"""MSL's Rotational examples rebuilt as scenes, against the event-driven reference."""
import pytest

from assemblies import AssemblyError, run_scene
from assemblies.scenes.msl_rotational_references import CoupledClutches, coupled_clutches


def test_coupled_clutches_meets_every_lock_and_break_away_of_the_reference():
    """Monolithic (the composite FMU in the engine) at MSL's parameters, tolerance 1e-6:
    the 6 lock/break-away times of the engaged clutches and the final speeds within
    100 x tolerance of the reference written from MSL's clutch law."""
    res = run_scene("coupled_clutches", mode="monolithic")
    figures = {f.name: f for f in res.figures}
    assert {"clutch1_4", "clutch2_1", "clutch3_1", "w4_end"} <= set(figures)
    assert all(f.passed for f in res.figures), [f for f in res.figures if not f.passed]


def test_the_reference_has_msl_documented_sequence():
    """MSL's documentation: clutch1 slips from the start (J1 at 10 rad/s, J2 at rest),
    clutch2 engages at T2 = 0.4 s and clutch3 at T3 = 0.9 s, each locking after; clutch1
    releases for good at 1.25 s (its normal force cos(2 pi 0.2 t) turns negative), after
    which J2..J4 turn together at constant speed (no torque reaches them)."""
    ref = coupled_clutches(CoupledClutches())
    firsts = {c: min(t for t, k, q in ref.events if k == c and q == 0) for c in (1, 2, 3)}
    assert 0.4 < firsts[2] < 0.9 < firsts[3] < 1.5
    late = ref.t > 1.26
    spread = ref.w[late][:, 1:].max(axis=0) - ref.w[late][:, 1:].min(axis=0)
    assert spread.max() < 1e-9
    assert abs(ref.w[late][:, 1] - ref.w[late][:, 3]).max() < 1e-9


def test_coupled_clutches_in_the_me_coupling_names_the_loop():
    with pytest.raises(AssemblyError, match=r"algebraic loop between direct-feedthrough outputs: "
                                            r"clutch1.flange_a.tau -> J1.flange_b.a"):
        run_scene("coupled_clutches", mode="me")


def test_coupled_clutches_in_cosim_is_refused_in_one_line_not_run_wrong():
    """Co-simulation engages clutch2 at 0.4 s sliding the wrong way (its slide direction
    kept from the free phase), so its figures cannot be met: the scene refuses the mode
    in one line naming the assembly and the mode that runs it, before any work."""
    with pytest.raises(AssemblyError) as err:
        run_scene("coupled_clutches", mode="cosim")
    message = str(err.value)
    assert "\n" not in message
    assert "assembly 'coupled_clutches'" in message and "mode 'cosim'" in message
    assert "'monolithic' runs it" in message
