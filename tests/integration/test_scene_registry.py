"""Every scene in the registry says what it reproduces and holds each figure to a stated,
finite accuracy, and at its own settings every figure passes: a scene added to any family
is held to this without a test of its own."""
import math

import pytest

from assemblies.run import run_scene_full
from assemblies.scenes import SCENES


@pytest.mark.parametrize("name", list(SCENES))
def test_scene_states_its_seed_and_references(name):
    sc = SCENES[name]
    # README's table is built from these (assemblies/scenes/listing.py); "—" where no
    # section of the seed is reproduced
    assert sc.seed.strip() and sc.reference.strip(), f"{name}: seed= and reference= are required"
    assert sc.name == name


def test_the_command_lines_scene_names_are_the_registrys():
    """mechfmu checks and lists scene names before it loads the scenes (and CasADi)."""
    from assemblies.scene_names import SCENE_NAMES
    assert list(SCENE_NAMES) == list(SCENES)


def test_the_scene_index_is_the_registrys():
    """`mechfmu scenes` prints, and scene() imports the family module, from the index:
    its names, families and descriptions are those of the registry, word for word."""
    from assemblies.scene_names import SCENE_INDEX
    from assemblies.scenes import FAMILIES, family
    from assemblies.scenes.listing import INDEX_PATH, index_source
    assert INDEX_PATH.read_text() == index_source(), \
        "assemblies/scene_names.py is stale: python -m assemblies.scenes.listing --index"
    assert {name: (module, sc.description) for module in FAMILIES
            for name, sc in family(module).items()} == SCENE_INDEX


@pytest.mark.parametrize("name", list(SCENES))
def test_every_figure_states_a_finite_accuracy_and_passes(name):
    run = run_scene_full(name)
    assert run.figures, f"{name}: no figures"
    for f in run.figures:
        # 0 is a finite accuracy too: a count (output points off the closed form's
        # premise) is exact
        assert math.isfinite(f.accuracy) and math.isfinite(f.bound), f"{name}: {f.name} {f}"
    assert run.passed, run.table()


def test_the_listing_tool_answers_a_flag_or_a_missing_file_in_one_line(capsys, tmp_path):
    """`python -m assemblies.scenes.listing --help` printed a traceback (the flag was read
    as a file name): a flag gets the usage, a missing file one line and exit status 2."""
    from assemblies.scenes import listing
    assert listing.main(["--help"]) == 0
    assert "usage:" in capsys.readouterr().out
    assert listing.main(["--bogus"]) == 2
    assert listing.main([str(tmp_path / "missing.md")]) == 2
    err = capsys.readouterr().err
    assert "missing.md: no such file" in err and "Traceback" not in err
