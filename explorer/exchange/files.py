"""Float files in and out: ``.npz`` archives of named arrays, ``.npy`` arrays and ``.exr``
images (the OpenEXR package, the ``exr`` extra).

Reading never unpickles (``allow_pickle=False``): a file holding Python objects is refused
with a one-line :class:`FileFormatError`, as is anything that is not the format its suffix
names.
"""

from __future__ import annotations

import zipfile
from pathlib import Path

import numpy as np

FLOAT_IMAGE_SUFFIXES = (".exr", ".npy")
"""Suffixes ``render --out`` writes as float data instead of an 8-bit picture."""
EXR_MISSING = ("writing .exr needs the OpenEXR package: pip install 'lpv-explorer[exr]' "
               "(or write .npy)")


class FileFormatError(ValueError):
    """A file that is not what it should be (the message is one line, naming the file)."""


def write_npz(path: Path, arrays: dict[str, np.ndarray]) -> None:
    """``arrays`` into an uncompressed ``.npz`` at ``path`` (each array as it is: dtype and
    shape kept)."""
    with open(path, "wb") as handle:
        np.savez(handle, **arrays)


def read_npz(path: Path | str, what: str = "file") -> dict[str, np.ndarray]:
    """Every array of the ``.npz`` at ``path`` by name; ``what`` names the file in the
    errors (``--vpls x.npz``). Each member's ``.npy`` header is read and checked against
    the member's real size before numpy allocates the array it claims."""
    from explorer.safe_files import UserFileError, open_regular

    path = Path(path)
    try:        # a regular file within the cap: a FIFO would make np.load wait forever
        handle = open_regular(path, "array file")
    except UserFileError as exc:
        raise FileFormatError(f"{what} {exc}") from None
    try:
        with handle:
            if not zipfile.is_zipfile(handle):
                raise FileFormatError(f"{what} {path}: not an .npz archive of named arrays "
                                      f"(a single .npy array, or not numpy data)")
            handle.seek(0)
            check_npz_headers(handle, f"{what} {path}")
            handle.seek(0)
            with np.load(handle, allow_pickle=False) as archive:
                return {name: archive[name] for name in archive.files}
    except FileFormatError:
        raise
    except (zipfile.BadZipFile, EOFError, OSError) as exc:
        raise FileFormatError(f"{what} {path}: not a readable .npz archive ({exc})") from None
    except ValueError as exc:       # an object array: numpy refuses to unpickle it
        raise FileFormatError(f"{what} {path}: holds Python objects, which are never "
                              f"unpickled; store plain numeric arrays ({exc})") from None


def npy_header(stream, where: str) -> tuple[tuple[int, ...], np.dtype, int]:
    """``(shape, dtype, header bytes)`` of the ``.npy`` data at ``stream``'s position,
    parsed without reading the data (numpy's own bounded header parser)."""
    fmt = np.lib.format
    try:
        start = stream.tell()
        version = fmt.read_magic(stream)
        if version == (1, 0):
            shape, _, dtype = fmt.read_array_header_1_0(stream)
        elif version == (2, 0):
            shape, _, dtype = fmt.read_array_header_2_0(stream)
        else:
            raise ValueError(f"format version {version}")
        return tuple(shape), np.dtype(dtype), stream.tell() - start
    except (ValueError, TypeError, SyntaxError, EOFError) as exc:
        raise FileFormatError(f"{where}: not a readable .npy header ({exc})") from None


def check_npz_headers(handle, where: str) -> None:
    """Refuse an ``.npz`` whose members' headers claim arrays other than their real sizes
    (a header claiming a (10¹¹, 3) array would otherwise allocate terabytes), or hold
    Python objects."""
    import os

    from explorer.safe_files import CAPS

    real_size = os.fstat(handle.fileno()).st_size
    total = 0
    with zipfile.ZipFile(handle) as archive:
        for member in archive.infolist():
            if not member.filename.endswith(".npy"):
                continue
            name = member.filename[:-4]
            # the sizes the zip directory claims, against the file's: stored data is as
            # long as it says and inside the file; deflate expands at most ~1032 times
            total += member.file_size
            expands = member.file_size > (member.compress_size if member.compress_type
                                          == zipfile.ZIP_STORED else
                                          1032 * member.compress_size + 1024)
            if expands or member.header_offset + member.compress_size > real_size \
                    or total > CAPS["array file"]:
                raise FileFormatError(f"{where}: array {name!r} claims {member.file_size:,} "
                                      f"bytes, more than the file can hold")
            with archive.open(member) as stream:
                shape, dtype, header = npy_header(stream, f"{where}: array {name!r}")
            if dtype.hasobject:
                raise FileFormatError(f"{where}: array {name!r} holds Python objects, which "
                                      f"are never unpickled; store plain numeric arrays")
            claimed = header + int(np.prod(shape, dtype=object)) * dtype.itemsize
            if claimed != member.file_size:
                raise FileFormatError(
                    f"{where}: array {name!r} claims shape {shape} of {dtype} "
                    f"({claimed:,} bytes) but its member holds {member.file_size:,}")


def write_npy(path: Path, array: np.ndarray) -> None:
    with open(path, "wb") as handle:
        np.save(handle, np.asarray(array), allow_pickle=False)


def has_openexr() -> bool:
    try:
        import OpenEXR  # noqa: F401
    except ImportError:
        return False
    return True


def write_exr(path: Path, image: np.ndarray, comment: str | None = None) -> None:
    """An ``(H, W, 3)`` (or ``(H, W)``) float image, row 0 at the top, as a 32-bit float
    EXR (RGB, or one Y channel), lossless ZIP; ``comment``: what it holds (the header's
    ``comments`` attribute)."""
    try:
        import OpenEXR
    except ImportError:
        raise RuntimeError(EXR_MISSING) from None
    pixels = np.ascontiguousarray(np.asarray(image, np.float32))
    if pixels.ndim == 2:
        channels = {"Y": pixels}
    elif pixels.ndim == 3 and pixels.shape[2] in (3, 4):
        channels = {"RGB" if pixels.shape[2] == 3 else "RGBA": pixels}
    else:
        raise ValueError(f"an EXR image is (H, W), (H, W, 3) or (H, W, 4), got {pixels.shape}")
    header = {"compression": OpenEXR.ZIP_COMPRESSION, "type": OpenEXR.scanlineimage}
    if comment:
        header["comments"] = comment
    with OpenEXR.File(header, channels) as image_file:
        image_file.write(str(path))


def read_exr(path: Path | str) -> np.ndarray:
    """The pixels of an EXR written by :func:`write_exr`: ``(H, W, 3|4)`` or ``(H, W)``
    float32."""
    try:
        import OpenEXR
    except ImportError:
        raise RuntimeError(EXR_MISSING.replace("writing", "reading")) from None
    try:
        with OpenEXR.File(str(path)) as image_file:
            channels = image_file.channels()
            name = next(iter(channels))
            return np.asarray(channels[name].pixels, np.float32)
    except (RuntimeError, OSError) as exc:
        raise FileFormatError(f"{path}: not a readable EXR image ({exc})") from None


def write_float_image(path: Path, image: np.ndarray, comment: str | None = None) -> None:
    """``image`` as float data in the format ``path``'s suffix names (.exr, with
    ``comment`` in its header, or .npy)."""
    suffix = path.suffix.lower()
    if suffix == ".exr":
        write_exr(path, image, comment)
    elif suffix == ".npy":
        write_npy(path, image)
    else:
        raise ValueError(f"{path}: float images are written as {FLOAT_IMAGE_SUFFIXES}")
