"""What an FMU carries besides its binary: ranges and display units in modelDescription.xml,
documentation/index.html, and C sources from which an importer can rebuild it alone."""
import math
import re
import shutil
import subprocess
import zipfile

import numpy as np
import pytest
from fmpy import extract, read_model_description, simulate_fmu
from fmpy.build import build_platform_binary
from fmpy.validation import validate_fmu

from components import RigidBodyOnAxle, RollingCoin, SpringBlock
from fmus import build, build_fmu

VERSIONS = (2, 3)


@pytest.mark.parametrize("version", VERSIONS)
def test_parameter_ranges_and_display_units(version, tmp_path):
    path = build_fmu(RigidBodyOnAxle(), tmp_path / "axle.fmu", fmi_version=version)
    assert validate_fmu(str(path)) == []
    md = read_model_description(str(path))
    v = {var.name: var for var in md.modelVariables}
    # strict m > 0: the inclusive bound FMI can state, and the description says 0 is out
    assert v["m"].min == "0.0" and v["m"].max is None and "0 is excluded" in v["m"].description
    assert v["c"].min == "0.0" and "excluded" not in v["c"].description
    assert v["r_x"].min is None and v["r_x"].max is None  # unbounded: nothing declared
    # angles are shown in degrees by default; rates may be shown in deg/s or rpm
    assert v["theta"].unit == "rad" and v["theta"].displayUnit == "deg"
    units = {u.name: {d.name: d.factor for d in u.displayUnits} for u in md.unitDefinitions}
    assert units["rad"]["deg"] == pytest.approx(180 / math.pi, rel=1e-15)
    assert units["rad/s"]["rpm"] == pytest.approx(60 / (2 * math.pi), rel=1e-15)


@pytest.mark.parametrize("version", VERSIONS)
def test_documentation_lists_the_model(version, tmp_path):
    block = SpringBlock(profile="driven")
    with zipfile.ZipFile(build_fmu(block, tmp_path / "b.fmu", fmi_version=version)) as zf:
        html = zf.read("documentation/index.html").decode()
    assert html.startswith("<!DOCTYPE html>") and html.rstrip().endswith("</html>")
    assert not re.search(r"(src|href)\s*=", html)  # self-contained: no external assets
    for text in ("mu_s", "N.s/m", "&gt; 0", "flange_a", "driven", "<td>support</td>",
                 "friction mode", "flange_a.f", "f_friction", "Fig. 9.2"):
        assert text in html, text
    # per mode, the folded equations: stuck means no acceleration
    assert "while mode = 0" in html and "der(v) = 0" in html and "der(x) = v" in html


def test_long_equations_are_cut_with_a_note(tmp_path):
    with zipfile.ZipFile(build_fmu(RollingCoin(), tmp_path / "c.fmu")) as zf:
        html = zf.read("documentation/index.html").decode()
    assert "der(psi_dot) = " in html and "characters cut; the full expression is in" in html


@pytest.mark.parametrize("version", VERSIONS)
def test_sources_are_listed_and_shipped(version, tmp_path):
    path = build_fmu(SpringBlock(), tmp_path / "b.fmu", fmi_version=version)
    md = read_model_description(str(path))  # FMI 3: validates buildDescription.xml too
    (config,) = md.buildConfigurations
    listed = config.sourceFileSets[0].sourceFiles
    assert listed == build._source_names(version)  # the very list the binary is built from
    assert listed[0] == "model.c" and f"fmi{version}.c" in listed
    assert f"fmi{5 - version}.c" not in listed
    with zipfile.ZipFile(path) as zf:
        shipped = {n[len("sources/"):] for n in zf.namelist() if n.startswith("sources/")}
    assert set(listed) <= shipped
    assert {"model.h", "runtime.h", "solver.h"} <= shipped
    assert not any(n.startswith("fmi") and n.endswith(".h") for n in shipped)  # importer's own
    assert ("buildDescription.xml" in shipped) == (version == 3)


@pytest.mark.parametrize("builder", ["gcc", "fmpy"])
@pytest.mark.parametrize("version", VERSIONS)
def test_sources_alone_rebuild_the_fmu(version, builder, tmp_path):
    """Compile sources/ alone (gcc with fmpy's FMI headers, or fmpy's own CMake build of
    source FMUs), then run the same Co-Simulation as the shipped binary: the
    trajectories agree to 1e-12."""
    if builder == "fmpy" and shutil.which("cmake") is None:
        pytest.skip("fmpy builds source FMUs with CMake, which is not installed")
    block = SpringBlock(m=1, k=1, g=1, mu_k=0.6, mu_s=0.6, x=6.55)  # seed 9.4: events
    path = build_fmu(block, tmp_path / "b.fmu", fmi_version=version)
    unzipped = tmp_path / "rebuilt"
    extract(str(path), str(unzipped))
    shutil.rmtree(unzipped / "binaries")
    if builder == "fmpy":
        (tmp_path / "cmake").mkdir()
        build_platform_binary(str(unzipped), build_dir=tmp_path / "cmake")
    else:
        binary = unzipped / "binaries" / build.platform_folder(version) / "SpringBlock.so"
        binary.parent.mkdir(parents=True)
        sources = unzipped / "sources"
        config = read_model_description(str(unzipped)).buildConfigurations[0]
        files = config.sourceFileSets[0].sourceFiles
        subprocess.run(["gcc", *build.CFLAGS, f"-I{sources}", f"-I{build.FMI_HEADERS}", "-o",
                        str(binary), *[str(sources / f) for f in files], "-lm"], check=True)
    kw = dict(fmi_type="CoSimulation", stop_time=18.0, output_interval=0.1, output=["x", "v"])
    rebuilt = simulate_fmu(str(unzipped), **kw)
    shipped = simulate_fmu(str(path), **kw)
    assert abs(rebuilt["x"][-1] - (-0.55)) < 1e-6  # it really simulated: stuck at -0.55
    for name in ("x", "v"):
        np.testing.assert_allclose(rebuilt[name], shipped[name], rtol=0, atol=1e-12)
