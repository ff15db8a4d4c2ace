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
    errors (``--vpls x.npz``)."""
    from explorer.safe_files import UserFileError, check_regular_file

    path = Path(path)
    try:        # a regular file within the cap: a FIFO would make np.load wait forever
        check_regular_file(path, "array file")
    except UserFileError as exc:
        raise FileFormatError(f"{what} {exc}") from None
    try:
        with np.load(path, allow_pickle=False) as archive:
            if not isinstance(archive, np.lib.npyio.NpzFile):
                raise FileFormatError(f"{what} {path}: a single .npy array, not an .npz "
                                      f"archive of named arrays")
            return {name: archive[name] for name in archive.files}
    except FileNotFoundError:
        raise FileFormatError(f"{what} {path}: no such file") from None
    except IsADirectoryError:
        raise FileFormatError(f"{what} {path} is a folder, not an .npz file") from None
    except (zipfile.BadZipFile, EOFError, OSError) as exc:
        raise FileFormatError(f"{what} {path}: not a readable .npz archive ({exc})") from None
    except ValueError as exc:       # an object array: numpy refuses to unpickle it
        raise FileFormatError(f"{what} {path}: holds Python objects, which are never "
                              f"unpickled; store plain numeric arrays ({exc})") from None


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
