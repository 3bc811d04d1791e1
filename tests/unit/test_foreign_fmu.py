"""Any FMU as an assembly instance: ports, parameters, units and types from its model
description, and one clear line for each way it can be misused.

Most cases use hand-made archives (tests/foreign_fmus.py: ``fake_fmu``) whose binaries
are empty: loading an FMU instance reads only its model description and archive
listing, and the mode checks run before anything is loaded, so nothing here runs an FMU.
"""
import math

import pytest

from assemblies import FMU, Assembly, AssemblyError, FmuError, cosimulate, simulate_me, \
    simulate_monolithic
from components import ComponentError, Force, ForceSensor, MassWithFriction, SpeedSensor
from components.interfaces import signal

from foreign_fmus import fake_fmu

# FMI 3 Co-Simulation, with what a model description can hold that ours never does:
# a structured name, an Int32 output, an output without a unit, an Int32 parameter
# with a range, a Boolean input (a port of its own type)
FAKE_MD = """<?xml version="1.0" encoding="UTF-8"?>
<fmiModelDescription fmiVersion="3.0" modelName="Model" instantiationToken="{0000}">
  <CoSimulation modelIdentifier="Model" canGetAndSetFMUState="true"/>
  <ModelVariables>
    <Float64 name="time" valueReference="0" causality="independent" variability="continuous"/>
    <Float64 name="a.b[1]" valueReference="1" causality="input" start="0.5" unit="N"/>
    <Int32 name="count" valueReference="2" causality="output" variability="discrete" initial="exact" start="0"/>
    <Float64 name="y" valueReference="3" causality="output"/>
    <Int32 name="n" valueReference="4" causality="parameter" variability="fixed" start="3" min="1" max="10"/>
    <Float64 name="gain" valueReference="5" causality="parameter" variability="tunable" start="1" min="0"/>
    <Boolean name="on" valueReference="6" causality="input" start="true"/>
  </ModelVariables>
  <ModelStructure>
    <Output valueReference="2"/>
    <Output valueReference="3"/>
  </ModelStructure>
</fmiModelDescription>
"""


@pytest.fixture
def fake(tmp_path):
    return fake_fmu(tmp_path / "fake.fmu", FAKE_MD)


def one_line(err) -> str:
    text = str(err.value)
    assert "\n" not in text, text
    return text


def test_ports_and_parameters_come_from_the_model_description(casadi_pi):
    ctrl = FMU(casadi_pi)
    ports = {p.name: p for p in ctrl.ports}
    assert set(ports) == {"v", "f"}
    assert ports["v"].domain == signal("m/s") and ports["v"].optional
    assert ports["f"].domain == signal("N")
    assert ctrl.profile.ports == {"v": "input", "f": "output"}
    # the FMU's own start values are the defaults; the input's start is settable too
    assert ctrl.values == {"v": 0.0, "v_ref": 1.0, "k": 2.0, "Ti": 0.5}
    assert ctrl.interfaces == ("ModelExchange",) and ctrl.fmi_version == 3
    assert FMU(casadi_pi, k=3.0).values["k"] == 3.0


def test_structured_names_int32_and_unitless_variables(fake, casadi_pi):
    x = FMU(fake)
    ports = {p.name: p.domain for p in x.ports}
    assert ports == {"a.b[1]": signal("N"), "count": signal("", "Int32"),
                     "y": signal(""), "on": signal("", "Boolean")}
    asm = Assembly("a")
    asm.add("x", x)
    asm.add("ctrl", FMU(casadi_pi))
    asm.connect("ctrl.f", "x.a.b[1]")  # "instance.port" splits at the first dot only
    assert [(c.source, c.target) for c in asm.couplings()] == [(("ctrl", "f"), ("x", "a.b[1]"))]


def test_parameters_are_checked_like_ours(casadi_pi, fake):
    asm = Assembly("a")
    asm.add("ctrl", FMU(casadi_pi))
    asm.add("x", FMU(fake))
    asm.set("ctrl.k", 3.0)
    assert asm.component("ctrl").values["k"] == 3.0
    for bad in (math.nan, math.inf):
        with pytest.raises(ComponentError) as err:
            asm.set("ctrl.k", bad)
        assert "FMU 'ctrl' (PIController.fmu): parameter k" in one_line(err)
        assert "finite" in str(err.value)
    with pytest.raises(ComponentError, match=r"unknown name 'gain'; settable names: v, v_ref, "
                                             r"k, Ti"):
        asm.set("ctrl.gain", 1.0)
    with pytest.raises(ComponentError, match=r"n = 2.5 is not allowed; n is an Int32 variable"):
        asm.set("x.n", 2.5)
    with pytest.raises(ComponentError, match=r"parameter n = 0 is not allowed; n \(parameter n "
                                             r"of fake.fmu\) must be >= 1 and <= 10"):
        FMU(fake, n=0)
    with pytest.raises(ComponentError, match=r"parameter gain = -1 is not allowed.*>= 0"):
        FMU(fake, gain=-1)
    asm.set("x.n", 4)
    asm.set("x.on", False)  # a Boolean is set as one (before issue 24: "unknown name")
    assert asm.components["x"].values["on"] == 0.0
    with pytest.raises(ComponentError, match=r"on = 2 is not allowed; on is a Boolean "
                                             r"variable: it takes True/False \(1/0\)"):
        asm.set("x.on", 2)


def test_connections_check_units_and_types_and_name_both_sides(casadi_pi, fake, tmp_path):
    asm = Assembly("a")
    asm.add("ctrl", FMU(casadi_pi))
    asm.add("x", FMU(fake))
    asm.add("force", Force())
    asm.add("speed", SpeedSensor())
    with pytest.raises(AssemblyError) as err:
        asm.connect("ctrl.v", "force.f")  # no: an input to an input, and m/s against N
    assert one_line(err) == ("cannot connect ctrl.v to force.f: ctrl.v is Float64 [m/s], "
                             "force.f is Float64 [N]; a connection joins signals of one type "
                             "and unit")
    # types follow value_types.feeds: never a float into a Boolean (nor into an integer)
    with pytest.raises(AssemblyError) as err:
        asm.connect("speed.v", "x.on")
    assert one_line(err).startswith("cannot connect speed.v to x.on: a Float64 output cannot "
                                    "feed a Boolean input; an output feeds")
    # a unit the FMU leaves out connects to any unit (FMI says nothing then)...
    asm.connect("x.y", "force.f")
    # ...unless it is declared: units= fills in what the FMU left out, and is checked
    asm.add("x2", FMU(fake, units={"y": "m/s"}))
    asm.add("force2", Force())
    with pytest.raises(AssemblyError, match=r"x2.y is Float64 \[m/s\], force2.f is Float64 \[N\]"):
        asm.connect("x2.y", "force2.f")
    with pytest.raises(FmuError, match=r"units= gives a.b\[1\] the unit 'm' but the FMU "
                                       r"declares 'N'|the FMU declares 'N'"):
        FMU(fake, units={"a.b[1]": "m"})
    with pytest.raises(FmuError, match=r"units= names variables that are not among its ports: "
                                       r"speed; ports: a.b\[1\], count, y, on"):
        FMU(fake, units={"speed": "m/s"})


def test_unknown_variables_and_a_doubly_fed_input_are_named(casadi_pi):
    asm = Assembly("a")
    asm.add("ctrl", FMU(casadi_pi))
    asm.add("force", Force())
    asm.add("sensor", ForceSensor())
    with pytest.raises(AssemblyError) as err:
        asm.connect("ctrl.nope", "force.f")
    assert one_line(err) == ("assembly 'a': FMU 'ctrl' (PIController.fmu) has no port 'nope'; "
                             "ports: v, f")
    asm.connect("ctrl.f", "force.f")
    with pytest.raises(AssemblyError) as err:
        asm.connect("sensor.f", "force.f")
    assert one_line(err) == ("cannot connect sensor.f to force.f: input force.f is already fed "
                             "by ctrl.f; an input takes one source")


def test_an_unconnected_fmu_input_keeps_its_start_value_but_ours_must_be_connected(casadi_pi):
    asm = Assembly("a")
    asm.add("ctrl", FMU(casadi_pi))  # ctrl.v open: it stays at its start value
    asm.add("force", Force())
    asm.add("mass", MassWithFriction())
    asm.connect("ctrl.f", "force.f")
    asm.connect("force.flange", "mass.flange_a")
    assert asm.resolve_causality() == {"ctrl": "fmu", "force": "applied", "mass": "on_ground"}
    asm.add("other", Force())
    asm.connect("other.flange", "mass.flange_b")
    with pytest.raises(AssemblyError, match=r"other.f is a dangling required input"):
        asm.resolve_causality()


@pytest.mark.parametrize("content, message", [
    (None, r"FMU file '.*missing.fmu' does not exist"),
    (b"not a zip", r"'.*bad.fmu' is not an FMU: an FMU is a zip archive with a modelDescription"),
    ("no-md", r"'.*bad.fmu' is not an FMU: the archive has no modelDescription.xml"),
    ("md-garbage", r"cannot read the modelDescription.xml of '.*bad.fmu': "),
    ("win-only", r"'.*bad.fmu' has no binary for this platform \(x86_64-linux\): expected "
                 r"binaries/x86_64-linux/Model.so; it has binaries for x86_64-windows"),
])
def test_unusable_files_are_one_line_errors_naming_the_file(tmp_path, content, message):
    path = tmp_path / ("missing.fmu" if content is None else "bad.fmu")
    if isinstance(content, bytes):
        path.write_bytes(content)
    elif content == "no-md":
        fake_fmu(path, None)
    elif content == "md-garbage":
        fake_fmu(path, "<fmiModelDescription")
    elif content == "win-only":
        fake_fmu(path, FAKE_MD, binaries=("x86_64-windows",))
    with pytest.raises(FmuError, match=message) as err:
        FMU(path)
    one_line(err)
    assert isinstance(err.value, AssemblyError)


def test_each_mode_says_which_instance_it_cannot_run_and_which_modes_can(casadi_pi, fake):
    asm = Assembly("loop")
    asm.add("ctrl", FMU(casadi_pi))  # Model Exchange only
    with pytest.raises(AssemblyError) as err:
        cosimulate(asm, 1.0, 0.1)
    assert one_line(err) == ("assembly 'loop': mode 'cosim' steps Co-Simulation FMUs, but "
                             "instance 'ctrl' (PIController.fmu) is ModelExchange only; run it "
                             "with mode 'me'")
    with pytest.raises(AssemblyError, match=r"mode 'monolithic' joins the CasADi equations of "
                                            r"our components into one FMU, but instance 'ctrl' "
                                            r"is a compiled FMU \(PIController.fmu\) with no "
                                            r"equations to join; run it with mode 'me'"):
        simulate_monolithic(asm, 1.0, 0.1)
    cs_only = Assembly("cs")
    cs_only.add("x", FMU(fake))
    with pytest.raises(AssemblyError, match=r"mode 'me' integrates Model Exchange FMUs in one "
                                            r"solver, but instance 'x' \(fake.fmu\) is "
                                            r"CoSimulation only; run it with mode 'cosim'"):
        simulate_me(cs_only, 1.0, 0.1)
    asm.add("x", FMU(fake))
    with pytest.raises(AssemblyError, match=r"no mode runs all of ctrl \(ModelExchange only\), "
                                            r"x \(CoSimulation only\)"):
        simulate_me(asm, 1.0, 0.1)


def test_ssp_export_refuses_a_foreign_fmu_by_name(casadi_pi, tmp_path):
    from assemblies.ssp import export_ssp
    asm = Assembly("loop")
    asm.add("ctrl", FMU(casadi_pi))
    with pytest.raises(AssemblyError, match=r"instance 'ctrl' is a foreign FMU; exporting "
                                            r"foreign FMUs is not supported yet"):
        export_ssp(asm, tmp_path / "loop.ssp")
