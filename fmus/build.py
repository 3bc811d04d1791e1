"""Build a real FMU from a component: generate C, compile with gcc, zip.

One build is one FMI version: the library is compiled from the model, the
shared runtime (runtime.c, solver.c) and exactly one version adapter (fmi2.c or
fmi3.c), so it exports that version's functions and nothing else.

FMUs are cached by a content hash of everything that goes into them (FMI
version, generated C, modelDescription, the runtime sources, compiler flags), so
an unchanged component costs no compile. The cache lives in ``$MECHFMU_CACHE`` or
``~/.cache/mechfmu``.
"""
from __future__ import annotations

import hashlib
import os
import platform
import shutil
import subprocess
import sys
import tempfile
import zipfile
from collections.abc import Callable
from pathlib import Path

import fmpy

from components.component import Component
from components.errors import ComponentError, MechfmuError, check_tolerance, writable_file
from components.dae import flatten

from .codegen import generate_c
from .documentation import documentation_html
from .model_description import FMI_VERSIONS, model_description
from .sources import build_description

RUNTIME_DIR = Path(__file__).parent / "runtime"
FMI_HEADERS = Path(fmpy.__file__).parent / "c-code"
CFLAGS = ["-std=c99", "-O2", "-fPIC", "-fvisibility=hidden", "-shared", "-Wall"]


class BuildError(MechfmuError, RuntimeError):
    """The C compiler rejected a model: a bug in mechfmu, never in user input."""


def cache_dir() -> Path:
    return Path(os.environ.get("MECHFMU_CACHE", Path.home() / ".cache" / "mechfmu"))


def platform_folder(fmi_version: int) -> str:
    """binaries/<folder>: FMI 3 names machine and system (x86_64-linux), FMI 2 the system
    and word size (linux64)."""
    machine = {"AMD64": "x86_64", "arm64": "aarch64"}.get(platform.machine(), platform.machine())
    system = {"Linux": "linux", "Darwin": "darwin", "Windows": "windows"}[platform.system()]
    if fmi_version == 2:
        bits = 64 if sys.maxsize > 2**32 else 32
        return {"windows": "win"}.get(system, system) + str(bits)
    return f"{machine}-{system}"


def _runtime_sources() -> list[Path]:
    return sorted(RUNTIME_DIR.glob("*.c")) + sorted(RUNTIME_DIR.glob("*.h"))


def _c_files(fmi_version: int) -> list[Path]:
    """The runtime's C files for one FMI version: the core plus that version's adapter."""
    adapters = {f"fmi{v}.c" for v in FMI_VERSIONS}
    core = [p for p in sorted(RUNTIME_DIR.glob("*.c")) if p.name not in adapters]
    return core + [RUNTIME_DIR / f"fmi{fmi_version}.c"]


def _source_names(fmi_version: int) -> list[str]:
    """The C files under sources/ that are compiled, in compile order: the generated
    model.c, then _c_files(); the same list builds our binary, so it cannot drift."""
    return ["model.c"] + [p.name for p in _c_files(fmi_version)]


def content_hash(*texts: str) -> str:
    """Hex digest of `texts`, every runtime source and the compiler flags: the cache key
    of anything compiled against the runtime."""
    h = hashlib.sha256()
    for text in texts:
        h.update(text.encode())
        h.update(b"\0")
    for path in _runtime_sources():
        h.update(path.name.encode())
        h.update(path.read_bytes())
    h.update(" ".join(CFLAGS).encode())
    return h.hexdigest()


def compile_library(c_files: list[Path], library: Path, include_dirs: list[Path],
                    what: str, defines: list[str] = ()) -> None:
    """gcc with the FMUs' flags: one shared library from `c_files`. Everything mechfmu
    compiles goes through here, so every binary is built (and hashed) the same way."""
    cmd = (["gcc", *CFLAGS, *(f"-D{d}" for d in defines), *(f"-I{d}" for d in include_dirs),
            "-o", str(library)]
           + [str(f) for f in c_files] + ["-lm"])
    result = subprocess.run(cmd, capture_output=True, text=True)
    if result.returncode != 0:
        raise BuildError(f"gcc failed for {what}:\n{result.stderr}")


def token_from_digest(digest: str) -> str:
    """A GUID-shaped instantiation token from a hex content digest: the same content,
    the same token."""
    return "{%s-%s-%s-%s-%s}" % (digest[:8], digest[8:12], digest[12:16], digest[16:20],
                                 digest[20:32])


def cached_library(folder: str, stem: str, sources: list[Path], include_dirs: list[Path],
                   what: str, defines: list[str] = ()) -> Path:
    """The shared library compiled from `sources` (C files and the headers they include),
    in the cache under folder/stem-<hash>.so; built now only if this content, these
    defines and the compiler flags have never been built here."""
    h = hashlib.sha256()
    for path in sources:
        h.update(path.name.encode() + b"\0" + path.read_bytes() + b"\0")
    h.update(" ".join([*CFLAGS, *defines]).encode())
    target = cache_dir() / folder / f"{stem}-{h.hexdigest()[:16]}.so"
    if not target.exists():
        target.parent.mkdir(parents=True, exist_ok=True)
        partial = target.with_suffix(f".{os.getpid()}.partial")
        compile_library([p for p in sources if p.suffix == ".c"], partial, include_dirs, what,
                        defines)
        partial.replace(target)  # atomic: a parallel build never loads half a library
    return target


#: called with a line when an FMU is compiled (seconds, or minutes for a big beam): the
#: command line prints it, so that a run is never silent while it builds; None: quiet
announce: Callable[[str], None] | None = None


def build_fmu(component: Component, output: str | os.PathLike | None = None,
              fmi_version: int = 3, tolerance: float = 1e-8) -> Path:
    """Build (or fetch from the cache) the FMI 2.0 or 3.0 FMU of `component` under its profile.

    The component's current parameter values and state starts become the FMU's
    start values. Returns the path of the .fmu (`output` if given).
    """
    if not isinstance(component, Component):
        raise ComponentError(f"build_fmu: component must be a component instance (e.g. "
                             f"SpringBlock()), not {type(component).__name__} {component!r}")
    if fmi_version not in FMI_VERSIONS:
        raise ComponentError(f"build_fmu: fmi_version must be 2 or 3, not {fmi_version!r}")
    # checked before anything is written: the FMU would carry it as its default tolerance
    tolerance = check_tolerance(tolerance, "build_fmu: tolerance")
    if output is not None:  # before a build of seconds, not after
        output = writable_file(output, "build_fmu: output", ".fmu")
    model = flatten(component)
    identifier = type(component).__name__
    # the token is derived from the content, so compute both with a placeholder first
    c_source = generate_c(model, identifier, "@TOKEN@")
    xml = model_description(model, identifier, "@TOKEN@", component.default_stop_time, tolerance,
                            fmi_version=fmi_version, source_files=tuple(_source_names(fmi_version)))
    html = documentation_html(model, identifier, fmi_version)
    digest = content_hash(f"fmi{fmi_version}", c_source, xml, html)
    token = token_from_digest(digest)
    cached = cache_dir() / "fmus" / f"{identifier}-fmi{fmi_version}-{digest[:16]}.fmu"
    if not cached.exists():
        if announce:
            announce(f"building the FMU of {identifier} (FMI {fmi_version}, once per machine)")
        _compile(identifier, c_source.replace("@TOKEN@", token), xml.replace("@TOKEN@", token),
                 cached, fmi_version, html)
    if output is None:
        return cached
    shutil.copyfile(cached, output)
    return output


def _compile(identifier: str, c_source: str, xml: str, target: Path, fmi_version: int,
             documentation: str = "") -> None:
    target.parent.mkdir(parents=True, exist_ok=True)
    with tempfile.TemporaryDirectory(prefix="mechfmu-build-") as tmp:
        tmp = Path(tmp)
        # the binary is compiled from the very sources/ folder that the FMU ships
        sources = tmp / "sources"
        sources.mkdir()
        (sources / "model.c").write_text(c_source)
        for path in _c_files(fmi_version) + sorted(RUNTIME_DIR.glob("*.h")):
            shutil.copyfile(path, sources / path.name)
        c_files = _source_names(fmi_version)
        library = tmp / f"{identifier}.so"
        compile_library([sources / name for name in c_files], library,
                        [sources, FMI_HEADERS], identifier)
        if fmi_version == 3:
            (sources / "buildDescription.xml").write_text(build_description(identifier, c_files))
        partial = target.with_suffix(f".{os.getpid()}.partial")
        with zipfile.ZipFile(partial, "w", zipfile.ZIP_DEFLATED) as zf:
            zf.writestr("modelDescription.xml", xml)
            zf.write(library, f"binaries/{platform_folder(fmi_version)}/{identifier}.so")
            for path in sorted(sources.iterdir()):
                zf.write(path, f"sources/{path.name}")
            if documentation:
                zf.writestr("documentation/index.html", documentation)
        partial.replace(target)  # atomic: parallel builds never see half an FMU
