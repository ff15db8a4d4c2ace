"""Bounds on a mesh file before trimesh reads it: a regular file, at most
:data:`MAX_MESH_BYTES` on disk, and, for the compressed forms trimesh opens (``.zip``,
``.bz2``, ``.tar.gz``, ``.tar.bz2``, also ``.gz``), at most :data:`MAX_UNPACKED_BYTES`
once unpacked. A few hundred bytes of bzip2 can unpack to gigabytes (a decompression
bomb): the size is measured by unpacking in bounded chunks, never trusted from a header,
and the file is refused as soon as the cap is passed."""

from __future__ import annotations

import bz2
import gzip
import tarfile
import zipfile
from pathlib import Path

from explorer.safe_files import CAPS, MiB, UserFileError, check_regular_file

MAX_MESH_BYTES = CAPS["mesh"]
MAX_UNPACKED_BYTES = 512 * MiB
"""Largest mesh once unpacked: a 10-million-triangle binary STL is about 500 MB."""

_CHUNK = 4 * MiB


def _too_large(path: Path) -> UserFileError:
    return UserFileError(f"{path}: the mesh unpacks to more than "
                         f"{MAX_UNPACKED_BYTES // MiB} MB, the most a mesh may have")


def _stream_size(path: Path, stream) -> int:
    """Bytes ``stream`` unpacks to, read in chunks; raises past the cap."""
    total = 0
    while True:
        chunk = stream.read(_CHUNK)
        if not chunk:
            return total
        total += len(chunk)
        if total > MAX_UNPACKED_BYTES:
            raise _too_large(path)


def compression_of(path: Path) -> str | None:
    """The compressed form trimesh would unpack ``path`` as, or None."""
    name = path.name.lower()
    for suffix in (".tar.gz", ".tar.bz2", ".zip", ".bz2", ".gz"):
        if name.endswith(suffix):
            return suffix
    return None


def check_mesh_file(path: Path) -> None:
    """Raise :class:`UserFileError` (one line, the cap named) unless ``path`` is a regular
    mesh file within the caps (a FIFO or a device is refused before trimesh could wait on
    it)."""
    if check_regular_file(path, "mesh", MAX_MESH_BYTES) == 0:
        raise UserFileError(f"{path}: the file is empty")
    form = compression_of(path)
    if form is None:
        return
    try:
        if form == ".zip":
            with zipfile.ZipFile(path) as archive:
                total = 0
                for member in archive.infolist():
                    with archive.open(member) as stream:
                        total += _stream_size(path, stream)
                    if total > MAX_UNPACKED_BYTES:
                        raise _too_large(path)
        elif form.startswith(".tar"):
            with tarfile.open(path) as archive:
                total = 0
                for member in archive:
                    stream = archive.extractfile(member)
                    if stream is not None:
                        total += _stream_size(path, stream)
                    if total > MAX_UNPACKED_BYTES:
                        raise _too_large(path)
        else:
            opener = bz2.open if form == ".bz2" else gzip.open
            with opener(path, "rb") as stream:
                _stream_size(path, stream)
    except UserFileError:
        raise
    except (OSError, EOFError, ValueError, zipfile.BadZipFile, tarfile.TarError) as exc:
        raise UserFileError(f"{path}: not a readable {form} archive "
                            f"({type(exc).__name__}: {exc})") from None
