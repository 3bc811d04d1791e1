"""The assembly as an SSP 1.0 file: SystemStructure.ssd plus one FMI 2.0 CS FMU per instance.

Each instance is built under the profile the causality resolution gave it, with its
current parameter and start values baked into the FMU (``fmus.build_fmu``) and also
written as inline ParameterBindings, so a tool that applies bindings and one that
does not (fmpy) see the same values. Our couplings become SSP connections; the flow
coupling (``f_motion_side = -f_force_side``) carries ``<ssc:LinearTransformation
factor="-1"/>``, the SSP way to say it.

FMI 2.0 because fmpy 0.3.32's SSP runner (``fmpy.ssp.simulation``) instantiates
FMI 1/2 slaves only. What that runner does NOT do, read in its source:
- it ignores connection transformations (``end.value = start.value``), so the flow's
  -1 is lost: harmless where the flow input only reports a reaction (a kinematic
  source's ``flange.f``), wrong where a force drives a mass;
- it ignores ParameterBindings (only a ``parameter_set`` argument is applied), hence
  the values baked into the FMUs;
- it starts every input at 0 for the first step and labels each row with the time at
  the START of the step whose end values it holds.
"""
from __future__ import annotations

import tempfile
import zipfile
from pathlib import Path
from xml.sax.saxutils import quoteattr

from components.component import Component
from fmus import build_fmu

from .assembly import Assembly, AssemblyError

SSD = "http://ssp-standard.org/SSP1/SystemStructureDescription"
SSC = "http://ssp-standard.org/SSP1/SystemStructureCommon"
SSV = "http://ssp-standard.org/SSP1/SystemStructureParameterValues"


def _connectors(md) -> list[str]:
    out = []
    for v in md.modelVariables:
        if v.causality in ("input", "output") and v.type == "Real":
            out.append(f'        <ssd:Connector name={quoteattr(v.name)} kind="{v.causality}">'
                       "<ssc:Real/></ssd:Connector>")
    return out


def _bindings(name: str, component) -> list[str]:
    values = {**component.values, **component.starts}
    lines = ["      <ssd:ParameterBindings>", "        <ssd:ParameterBinding>",
             "          <ssd:ParameterValues>",
             f'            <ssv:ParameterSet version="1.0" name={quoteattr(name)}>',
             "              <ssv:Parameters>"]
    for key, value in values.items():
        lines.append(f"                <ssv:Parameter name={quoteattr(key)}>"
                     f'<ssv:Real value="{value!r}"/></ssv:Parameter>')
    lines += ["              </ssv:Parameters>", "            </ssv:ParameterSet>",
              "          </ssd:ParameterValues>", "        </ssd:ParameterBinding>",
              "      </ssd:ParameterBindings>"]
    return lines


def system_structure(assembly: Assembly, fmus: dict[str, Path], stop_time: float) -> str:
    """The SystemStructure.ssd text for `assembly` whose instances live in `fmus`."""
    from fmpy import read_model_description
    lines = ['<?xml version="1.0" encoding="UTF-8"?>',
             f'<ssd:SystemStructureDescription xmlns:ssd="{SSD}" xmlns:ssc="{SSC}" '
             f'xmlns:ssv="{SSV}" version="1.0" name={quoteattr(assembly.name)}>',
             f"  <ssd:System name={quoteattr(assembly.name)}>", "    <ssd:Elements>"]
    for name, component in assembly.components.items():
        lines.append(f'      <ssd:Component name={quoteattr(name)} '
                     f'type="application/x-fmu-sharedlibrary" source="resources/{name}.fmu">')
        lines += ["      <ssd:Connectors>", *_connectors(read_model_description(fmus[name])),
                  "      </ssd:Connectors>"]
        lines += _bindings(name, component)
        lines.append("      </ssd:Component>")
    lines += ["    </ssd:Elements>", "    <ssd:Connections>"]
    for c in assembly.couplings():
        attrs = (f"startElement={quoteattr(c.source[0])} startConnector={quoteattr(c.source[1])} "
                 f"endElement={quoteattr(c.target[0])} endConnector={quoteattr(c.target[1])}")
        if c.gain == 1.0:
            lines.append(f"      <ssd:Connection {attrs}/>")
        else:  # flows sum to zero: the force on one side is minus the other's
            lines += [f"      <ssd:Connection {attrs}>",
                      f'        <ssc:LinearTransformation factor="{c.gain!r}"/>',
                      "      </ssd:Connection>"]
    lines += ["    </ssd:Connections>", "  </ssd:System>",
              f'  <ssd:DefaultExperiment startTime="0.0" stopTime="{stop_time!r}"/>',
              "</ssd:SystemStructureDescription>", ""]
    return "\n".join(lines)


def export_ssp(assembly: Assembly, path: str | Path, stop_time: float = 10.0) -> Path:
    """Write `assembly` as an SSP archive at `path` (see the module doc)."""
    path = Path(path)
    for name, component in assembly.components.items():
        if not isinstance(component, Component):  # nothing to build it from
            raise AssemblyError(f"assembly '{assembly.name}': SSP export builds an FMI 2 FMU "
                                f"from each component's equations, but instance '{name}' is a "
                                "foreign FMU; exporting foreign FMUs is not supported yet")
    assembly.resolve_causality()
    with tempfile.TemporaryDirectory() as tmp:
        fmus = {name: build_fmu(component, Path(tmp) / f"{name}.fmu", fmi_version=2)
                for name, component in assembly.components.items()}
        ssd = system_structure(assembly, fmus, stop_time)
        path.parent.mkdir(parents=True, exist_ok=True)
        with zipfile.ZipFile(path, "w", zipfile.ZIP_DEFLATED) as archive:
            archive.writestr("SystemStructure.ssd", ssd)
            for name, fmu in fmus.items():
                archive.write(fmu, f"resources/{name}.fmu")
    return path


__all__ = ["export_ssp", "system_structure"]
