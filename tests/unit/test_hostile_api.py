"""Hostile values through the Python API and hostile model descriptions (issue 25): one
of our ValueErrors, one line naming the value and what is allowed, and nothing left
behind; a foreign FMU's file is checked before anything of it is loaded."""
from __future__ import annotations

import zipfile

import numpy as np
import pytest

from assemblies import FMU, export_fmu, run_scene, scene
from components import AssumedModesBeam, SpringBlock
from conftest import quick_refusal


def test_a_bool_is_no_parameter_value_and_a_float_no_count_of_modes():
    """float(True) is 1.0 and float(2.0).is_integer(): both were taken before."""
    quick_refusal(lambda: SpringBlock(m=True), "SpringBlock", "m = True is not a number (a bool)")
    quick_refusal(lambda: SpringBlock(k=np.True_), "k = np.True_ is not a number")
    quick_refusal(lambda: AssumedModesBeam(n_modes=2.0), "option n_modes = 2.0 is not allowed",
            "an integer from 1 to 128")
    quick_refusal(lambda: AssumedModesBeam(n_modes=True), "option n_modes = True is not allowed")
    quick_refusal(lambda: AssumedModesBeam(n_modes="2.5"), "n_modes = '2.5' is not allowed")
    # what stays allowed: numbers, their text (the command line), and ints of any kind
    assert SpringBlock(m="2").values["m"] == 2.0 and SpringBlock(m=np.float64(3)).values["m"] == 3
    for given in (8, "8", " 8 ", np.int64(8)):
        assert AssumedModesBeam(n_modes=given).option("n_modes") == 8


def test_an_fmu_path_that_is_no_path_is_one_line():
    quick_refusal(lambda: FMU(123), "FMU: path must be the path of an .fmu file", "int 123")


def test_a_run_into_an_unwritable_folder_stops_before_it_runs():
    """Before: the run went through, then FileNotFoundError from mkdir."""
    quick_refusal(lambda: run_scene("stick_slip", out="/proc/x"), "out /proc/x: cannot write there")


def test_an_export_onto_a_folder_is_refused_first_and_leaves_nothing(tmp_path):
    """Before: the members built, then IsADirectoryError, and a .partial file left beside
    the folder on every try."""
    target = tmp_path / "here"
    target.mkdir()
    for _ in range(2):
        quick_refusal(lambda: export_fmu(scene("stick_slip").build(), target),
                f"export_fmu: path {target} is a folder")
    assert [p.name for p in tmp_path.iterdir()] == ["here"] and not list(target.iterdir())


def test_an_export_that_fails_half_way_leaves_no_partial_file(tmp_path, monkeypatch):
    import assemblies.fmu_export as fx

    def broken(fmi):
        raise OSError(28, "No space left on device")
    monkeypatch.setattr(fx, "library", broken)
    with pytest.raises(OSError, match="No space left"):
        export_fmu(scene("stick_slip").build(), tmp_path / "a.fmu")
    assert list(tmp_path.iterdir()) == []


# --- model descriptions no exporter should write ------------------------------------------
FMI2 = """<?xml version="1.0" encoding="UTF-8"?>
<fmiModelDescription fmiVersion="2.0" modelName="hpy" guid="{{00000000-0000-4000-8000-000000000001}}"
  numberOfEventIndicators="0">
  <ModelExchange modelIdentifier="hpy"/>
  <ModelVariables>
    <ScalarVariable name="x" valueReference="1" causality="local" variability="continuous" initial="exact">
      <Real start="{x_start}"/>
    </ScalarVariable>
    <ScalarVariable name="der(x)" valueReference="2" causality="local" variability="continuous">
      <Real derivative="1"/>
    </ScalarVariable>
    <ScalarVariable name="v" valueReference="3" causality="local" variability="continuous" initial="exact">
      <Real start="0"/>
    </ScalarVariable>
    <ScalarVariable name="der(v)" valueReference="4" causality="local" variability="continuous">
      <Real derivative="3"/>
    </ScalarVariable>
    <ScalarVariable name="k" valueReference="5" causality="parameter" variability="fixed" initial="exact">
      <Real start="{k_start}"/>
    </ScalarVariable>
  </ModelVariables>
  <ModelStructure>
    <Derivatives>
{derivatives}
    </Derivatives>
  </ModelStructure>
</fmiModelDescription>
"""
BOTH = '      <Unknown index="2"/>\n      <Unknown index="4"/>'


def fmu_file(tmp_path, xml, extra=(), name="hpy.fmu"):
    """An FMU archive with `xml` and a binary entry (never loaded: the file is refused
    first), plus `extra` entries."""
    path = tmp_path / name
    with zipfile.ZipFile(path, "w") as zf:
        zf.writestr("modelDescription.xml", xml)
        zf.writestr("binaries/linux64/hpy.so", b"\x7fELF not loaded")
        for entry in extra:
            zf.writestr(entry, b"x")
    return path


def test_a_start_that_is_no_number_is_one_line(tmp_path):
    """Before: ValueError: could not convert string to float: 'abc' (a traceback)."""
    path = fmu_file(tmp_path, FMI2.format(x_start="0", k_start="abc", derivatives=BOTH))
    quick_refusal(lambda: FMU(path), "hpy.fmu': variable k has start='abc'", "not a number")
    assert isinstance(FMU(fmu_file(tmp_path, FMI2.format(x_start="1", k_start="2",
                                                        derivatives=BOTH), name="ok.fmu")), FMU)


@pytest.mark.parametrize("entry", ["/etc/hpy_evil", "../hpy_evil", "resources/../../hpy_evil"])
def test_an_entry_outside_the_archive_folder_is_refused_before_extraction(tmp_path, entry):
    """Before: fmpy's own exception (extract refuses it) surfaced from the run."""
    path = fmu_file(tmp_path, FMI2.format(x_start="0", k_start="1", derivatives=BOTH), [entry])
    quick_refusal(lambda: FMU(path), f"archive entry '{entry}'", "outside the folder")


def test_a_state_whose_derivative_the_structure_leaves_out_is_refused(tmp_path):
    """x and v are states (der(x), der(v) declare derivative=), but ModelStructure lists
    der(x) only: the engine would give the FMU one state, and v would never move (the
    standard lists every derivative there)."""
    path = fmu_file(tmp_path, FMI2.format(x_start="0", k_start="1",
                                          derivatives='      <Unknown index="2"/>'))
    quick_refusal(lambda: FMU(path), "lists 1 state derivative(s)", "2 variables are declared",
            "not listed: der(v)")


def test_a_listed_derivative_that_names_no_state_is_refused(tmp_path):
    """Before: AttributeError ('NoneType' object has no attribute 'name') when the engine
    read the states of it."""
    xml = FMI2.format(x_start="0", k_start="1", derivatives=BOTH + '\n      <Unknown index="5"/>')
    quick_refusal(lambda: FMU(fmu_file(tmp_path, xml)), "lists k as a state derivative",
            "names no state")


def test_a_real_binary_with_a_state_its_structure_leaves_out_is_refused():
    """tests/handmade/hpy_hidden: x' = v, v' = -x (x = sin t), both states declared, only
    der(x) listed. fmpy's validation passes it, and fmpy's simulate_fmu and (before) our
    engine gave it one state and ran it silently: x(3) = 3.0 instead of sin 3 = 0.141."""
    from fmpy.validation import validate_fmu
    from handmade_fmus import handmade_fmu
    path = handmade_fmu("hpy_hidden")
    assert validate_fmu(str(path)) == []  # the defect is one fmpy's validation lets through
    quick_refusal(lambda: FMU(path), "lists 1 state derivative(s), but 2 variables",
            "not listed: der(v)", "would not integrate their states")
