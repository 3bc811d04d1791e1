"""Build a real FMU from a component: generate C, compile with gcc, zip.

FMUs are cached by a content hash of everything that goes into them (generated
C, modelDescription, the runtime sources, compiler flags), so an unchanged
component costs no compile. The cache lives in ``$MECHFMU_CACHE`` or
``~/.cache/mechfmu``.
"""
from __future__ import annotations

import hashlib
import os
import platform
import shutil
import subprocess
import tempfile
import zipfile
from pathlib import Path

import fmpy

from components.component import Component
from components.dae import flatten

from .codegen import generate_c
from .model_description import model_description

RUNTIME_DIR = Path(__file__).parent / "runtime"
FMI_HEADERS = Path(fmpy.__file__).parent / "c-code"
CFLAGS = ["-std=c99", "-O2", "-fPIC", "-fvisibility=hidden", "-shared", "-Wall"]


class BuildError(RuntimeError):
    """The C compiler rejected a model: a bug in mechfmu, never in user input."""


def cache_dir() -> Path:
    return Path(os.environ.get("MECHFMU_CACHE", Path.home() / ".cache" / "mechfmu"))


def _platform_folder() -> str:
    machine = {"AMD64": "x86_64", "arm64": "aarch64"}.get(platform.machine(), platform.machine())
    system = {"Linux": "linux", "Darwin": "darwin", "Windows": "windows"}[platform.system()]
    return f"{machine}-{system}"


def _runtime_sources() -> list[Path]:
    return sorted(RUNTIME_DIR.glob("*.c")) + sorted(RUNTIME_DIR.glob("*.h"))


def _content_hash(*texts: str) -> str:
    h = hashlib.sha256()
    for text in texts:
        h.update(text.encode())
        h.update(b"\0")
    for path in _runtime_sources():
        h.update(path.name.encode())
        h.update(path.read_bytes())
    h.update(" ".join(CFLAGS).encode())
    return h.hexdigest()


def build_fmu(component: Component, output: str | os.PathLike | None = None,
              tolerance: float = 1e-8) -> Path:
    """Build (or fetch from the cache) the FMU of `component` under its profile.

    The component's current parameter values and state starts become the FMU's
    start values. Returns the path of the .fmu (`output` if given).
    """
    model = flatten(component)
    identifier = type(component).__name__
    # the token is derived from the content, so compute both with a placeholder first
    c_source = generate_c(model, identifier, "@TOKEN@")
    xml = model_description(model, identifier, "@TOKEN@", component.default_stop_time, tolerance)
    digest = _content_hash(c_source, xml)
    token = "{%s-%s-%s-%s-%s}" % (digest[:8], digest[8:12], digest[12:16], digest[16:20], digest[20:32])
    cached = cache_dir() / "fmus" / f"{identifier}-{digest[:16]}.fmu"
    if not cached.exists():
        _compile(identifier, c_source.replace("@TOKEN@", token), xml.replace("@TOKEN@", token), cached)
    if output is None:
        return cached
    output = Path(output)
    output.parent.mkdir(parents=True, exist_ok=True)
    shutil.copyfile(cached, output)
    return output


def _compile(identifier: str, c_source: str, xml: str, target: Path) -> None:
    target.parent.mkdir(parents=True, exist_ok=True)
    with tempfile.TemporaryDirectory(prefix="mechfmu-build-") as tmp:
        tmp = Path(tmp)
        (tmp / "model.c").write_text(c_source)
        library = tmp / f"{identifier}.so"
        cmd = (["gcc", *CFLAGS, f"-I{RUNTIME_DIR}", f"-I{FMI_HEADERS}", "-o", str(library),
                str(tmp / "model.c")] + [str(p) for p in sorted(RUNTIME_DIR.glob("*.c"))] + ["-lm"])
        result = subprocess.run(cmd, capture_output=True, text=True)
        if result.returncode != 0:
            raise BuildError(f"gcc failed for {identifier}:\n{result.stderr}")
        partial = target.with_suffix(f".{os.getpid()}.partial")
        with zipfile.ZipFile(partial, "w", zipfile.ZIP_DEFLATED) as zf:
            zf.writestr("modelDescription.xml", xml)
            zf.write(library, f"binaries/{_platform_folder()}/{identifier}.so")
        partial.replace(target)  # atomic: parallel builds never see half an FMU
