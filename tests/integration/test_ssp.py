"""Export: the assembly as an SSP file that fmpy's SSP runner simulates, and as one FMU."""
import xml.etree.ElementTree as ET
import zipfile

import numpy as np
from fmpy.ssp.simulation import simulate_ssp
from fmpy.validation import validate_fmu

from assemblies.masters.cosim import cosimulate
from assemblies.masters.monolithic import composite, simulate_monolithic
from assemblies.scenes import scene
from assemblies.ssp import SSC, export_ssp
from fmus import build_fmu

STOP, STEP = 20.0, 0.1


def test_fmpy_runs_the_exported_stick_slip_like_our_cosim(tmp_path):
    sc = scene("stick_slip")
    path = export_ssp(sc.build(), tmp_path / "stick_slip.ssp", STOP)
    ssd = ET.fromstring(zipfile.ZipFile(path).read("SystemStructure.ssd"))
    factors = [t.get("factor") for t in ssd.iter(f"{{{SSC}}}LinearTransformation")]
    assert factors == ["-1.0"]  # the one flow coupling, block.flange_a.f -> driver.flange.f
    fmpy_result = simulate_ssp(str(path), stop_time=STOP, step_size=STEP)  # validates the ssd
    ours = cosimulate(sc.build(), STOP, STEP, record=["block.x", "driver.flange.f"])
    # fmpy labels each row with the start of the step whose end values it holds
    np.testing.assert_allclose(fmpy_result["block.x"], ours["block.x"][1:], rtol=0, atol=1e-9)
    assert np.ptp(ours["block.x"]) > 0.5  # it slipped: several stick-slip cycles compared
    # fmpy 0.3.32 drops the LinearTransformation: the reaction it reports has the wrong sign
    np.testing.assert_allclose(fmpy_result["driver.flange.f"][5:], -ours["driver.flange.f"][6:],
                               rtol=0, atol=1e-9)


def test_the_assembly_as_one_fmu_validates_and_reproduces_the_scene(tmp_path):
    sc = scene("two_block_belt")
    fmu = build_fmu(composite(sc.build()), tmp_path / "two_block_belt.fmu")
    assert validate_fmu(str(fmu)) == []
    via_fmu = simulate_monolithic(sc.build(), 12.0, 0.1, 1e-10, record=sc.record, engine="fmu")
    reference = simulate_monolithic(sc.build(), 12.0, 0.1, 1e-10, record=sc.record)
    np.testing.assert_allclose(via_fmu["block1.s"], reference["block1.s"], rtol=0, atol=1e-7)
    np.testing.assert_allclose(via_fmu["block2.s"], reference["block2.s"], rtol=0, atol=1e-7)


def test_cli_export_writes_both_files(tmp_path, capsys):
    from assemblies.cli import main
    ssp, fmu = tmp_path / "a.ssp", tmp_path / "a.fmu"
    assert main(["export", "axle_motor", "--ssp", str(ssp), "--fmu", str(fmu)]) == 0
    assert validate_fmu(str(fmu)) == []
    names = zipfile.ZipFile(ssp).namelist()
    assert "SystemStructure.ssd" in names and "resources/motor.fmu" in names
    assert main(["export", "axle_motor"]) == 2
    assert "export needs --ssp" in capsys.readouterr().err
