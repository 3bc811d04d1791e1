"""What a source FMU carries under ``sources/`` and how an importer builds it.

Every FMU ships, next to its binary, exactly the C files the binary was compiled from
(the generated model.c, the shared runtime, the solver(s), one FMI version adapter and
our headers), so that an importer on another platform can compile it. The FMI headers
(fmi2*.h / fmi3*.h) are not shipped: the standards expect a source FMU to be compiled
against the importer's own copy of them (FMI 2 names them as the exception to "all
sources needed"; FMI 3 importers bring theirs), and ours come from fmpy at build time.

FMI 3 describes the build in ``sources/buildDescription.xml``; FMI 2 lists the files
in ``<SourceFiles>`` of modelDescription.xml (written by :mod:`fmus.model_description`).
"""
from __future__ import annotations

from xml.sax.saxutils import quoteattr


def build_description(identifier: str, c_files: list[str]) -> str:
    """FMI 3.0 buildDescription.xml: one configuration, one C99 file set, the headers
    next to the C files (include directory "." is sources/ itself), and libm."""
    files = "\n".join(f"      <SourceFile name={quoteattr(name)}/>" for name in c_files)
    return f"""<?xml version="1.0" encoding="UTF-8"?>
<fmiBuildDescription fmiVersion="3.0">
  <BuildConfiguration modelIdentifier={quoteattr(identifier)}>
    <SourceFileSet language="C99">
{files}
      <IncludeDirectory name="."/>
    </SourceFileSet>
    <Library name="m" external="true" description="the C math library (link with -lm where it is separate)"/>
  </BuildConfiguration>
</fmiBuildDescription>
"""
