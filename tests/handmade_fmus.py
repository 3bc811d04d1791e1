"""FMUs written by hand in C for the tests: foreign FMUs with one known behaviour each.

Our own runtime never shows the defects other exporters' FMUs have (a state restore that
does nothing, outputs that read stale, termination the FMI 2 way, array variables...),
so each of them is reproduced by a small FMU of its own under ``tests/handmade/<name>/``:
``model.c`` (the FMI functions, written directly against the standard's headers, no code
of ours; an FMI 2 one takes the functions it leaves at their plainest from
``tests/handmade/fmi2_defaults.h``) and ``modelDescription.xml``. :func:`handmade_fmu` compiles it with gcc against
the FMI headers fmpy ships and zips it, once per content, into the cache.

The model identifier is the folder's name; the FMI version is read from the description.
"""
from __future__ import annotations

import hashlib
import os
import re
import subprocess
import zipfile
from pathlib import Path

from fmus.build import FMI_HEADERS, cache_dir, platform_folder

HANDMADE = Path(__file__).parent / "handmade"


def handmade_fmu(name: str) -> Path:
    """The FMU built from tests/handmade/<name>/ (cached by the content of its files)."""
    folder = HANDMADE / name
    source, xml_path = folder / "model.c", folder / "modelDescription.xml"
    xml = xml_path.read_text()
    version = re.search(r'fmiVersion="(\d)', xml)
    if version is None:
        raise ValueError(f"{xml_path}: no fmiVersion")
    fmi_version = int(version.group(1))
    shared = (HANDMADE / "fmi2_defaults.h").read_bytes()  # included by the FMI 2 ones
    # another handmade FMU's model.c included whole (one model, two descriptions)
    for other in re.findall(r'#include "\.\./(\w+)/model\.c"', source.read_text()):
        shared += b"\0" + (HANDMADE / other / "model.c").read_bytes()
    digest = hashlib.sha256(source.read_bytes() + b"\0" + xml.encode() + b"\0"
                            + shared).hexdigest()[:16]
    target = cache_dir() / "handmade" / f"{name}-{digest}.fmu"
    if target.exists():
        return target
    target.parent.mkdir(parents=True, exist_ok=True)
    library = target.with_suffix(f".{os.getpid()}.so")
    cmd = ["gcc", "-std=c99", "-O1", "-fPIC", "-shared", "-Wall", f"-I{FMI_HEADERS}",
           "-o", str(library), str(source), "-lm"]
    done = subprocess.run(cmd, capture_output=True, text=True)
    if done.returncode != 0:
        raise RuntimeError(f"gcc failed for the handmade FMU {name}:\n{done.stderr}")
    partial = target.with_suffix(f".{os.getpid()}.partial")
    try:
        with zipfile.ZipFile(partial, "w", zipfile.ZIP_DEFLATED) as zf:
            zf.writestr("modelDescription.xml", xml)
            zf.write(library, f"binaries/{platform_folder(fmi_version)}/{name}.so")
        partial.replace(target)  # atomic: a parallel test never reads half an archive
    finally:
        library.unlink(missing_ok=True)
        partial.unlink(missing_ok=True)
    return target
