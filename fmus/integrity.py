"""Checksums of what the cache holds, so that a damaged file is rebuilt, not loaded.

A cached library or FMU is named by the hash of what it is built from, not of what was
written: a disk that fills up, a copy cut short or a stray write leaves a file under the
right name with the wrong bytes, and loading it crashes every later run (a truncated
shared library is a SIGBUS inside dlopen, no Python error at all). So each build records
the SHA-256 of the file it wrote beside it (``NAME.sha256``), and each process checks a
file once against its record before it uses it; one that fails is removed, rebuilt and
reported once (:func:`report`). Hashing costs about 1 ms per MB, once per file and process.
"""
from __future__ import annotations

import hashlib
import os
import warnings
import zipfile
import zlib
from collections.abc import Callable
from pathlib import Path

SUFFIX = ".sha256"


class CacheRepaired(UserWarning):
    """A damaged file of the cache was found and is rebuilt (said once per file)."""


_checked: dict[tuple, bool] = {}  # (path, mtime, size) -> intact, for this process


def _digest(path: Path) -> str:
    h = hashlib.sha256()
    with open(path, "rb") as f:
        for block in iter(lambda: f.read(1 << 20), b""):
            h.update(block)
    return h.hexdigest()


def record(path: Path, written: Path | None = None) -> None:
    """Write the checksum of `path` beside it, atomically; `written`: the file whose bytes
    become `path` (a build's partial file, recorded before it is moved into place, so
    that no reader finds the file without its record)."""
    path = Path(path)
    partial = path.with_name(f"{path.name}{SUFFIX}.{os.getpid()}.partial")
    partial.write_text(_digest(Path(written or path)) + "\n")
    partial.replace(path.with_name(path.name + SUFFIX))


def intact(path: Path, unrecorded: Callable[[Path], bool] | None = None) -> bool:
    """Does `path` hold the bytes its build recorded? A file without a record (written
    before records were kept) is intact if `unrecorded(path)` says so, and is then
    recorded; without that check it is not trusted."""
    path = Path(path)
    try:
        stat = path.stat()
    except OSError:
        return False
    key = (str(path), stat.st_mtime_ns, stat.st_size)
    if key in _checked:
        return _checked[key]
    try:
        expected = path.with_name(path.name + SUFFIX).read_text().strip()
    except OSError:
        expected = None
    if expected is None:
        ok = unrecorded is not None and unrecorded(path)
        if ok:
            record(path)
    else:
        ok = _digest(path) == expected
    _checked[key] = ok
    return ok


def elf_is_whole(path: Path) -> bool:
    """An ELF shared library that is all there: its header's magic, and its section header
    table (which the linker writes last) within the file. Garbage fails the first,
    a truncated file the second."""
    import struct
    try:
        with open(path, "rb") as f:
            head = f.read(64)
            size = os.fstat(f.fileno()).st_size
    except OSError:
        return False
    if len(head) < 52 or head[:4] != b"\x7fELF" or head[4] not in (1, 2):
        return False
    order = "<" if head[5] == 1 else ">"
    if head[4] == 2:  # 64-bit: e_shoff at 40, e_shentsize and e_shnum at 58 and 60
        if len(head) < 64:
            return False
        shoff = struct.unpack_from(order + "Q", head, 40)[0]
        shentsize, shnum = struct.unpack_from(order + "HH", head, 58)
    else:  # 32-bit: e_shoff at 32, e_shentsize and e_shnum at 46 and 48
        shoff = struct.unpack_from(order + "I", head, 32)[0]
        shentsize, shnum = struct.unpack_from(order + "HH", head, 46)
    return shnum > 0 and shoff + shentsize * shnum <= size


def zip_is_whole(path: Path) -> bool:
    """A zip archive whose every member reads back with its stored CRC."""
    try:
        with zipfile.ZipFile(path) as zf:
            return zf.testzip() is None
    except (OSError, zipfile.BadZipFile, EOFError, ValueError):
        return False


def extracted_intact(archive: Path, folder: Path) -> bool:
    """Does `folder` hold every file of zip `archive` as it is stored (size and CRC-32)?"""
    try:
        with zipfile.ZipFile(archive) as zf:
            members = [i for i in zf.infolist() if not i.is_dir()]
        for info in members:
            file = folder / info.filename
            if file.stat().st_size != info.file_size:
                return False
            crc = 0
            with open(file, "rb") as f:
                for block in iter(lambda: f.read(1 << 20), b""):
                    crc = zlib.crc32(block, crc)
            if crc != info.CRC:
                return False
    except (OSError, zipfile.BadZipFile, EOFError, ValueError):
        return False
    return True


def discard(path: Path) -> None:
    """Remove a damaged file and its record."""
    path = Path(path)
    path.unlink(missing_ok=True)
    path.with_name(path.name + SUFFIX).unlink(missing_ok=True)


_reported: set[str] = set()


def report(path: Path, what: str, announce: Callable[[str], None] | None,
           remedy: str = "rebuilding it") -> None:
    """Say once per file and process that a damaged cache file is rebuilt: through
    `announce` where the caller prints (the command line), else as a CacheRepaired
    warning."""
    if str(path) in _reported:
        return
    _reported.add(str(path))
    line = (f"the cached {what} {path} was damaged (its bytes differ from what its build "
            f"wrote); {remedy}")
    if announce is not None:
        announce(line)
    else:
        warnings.warn(line, CacheRepaired, stacklevel=3)
