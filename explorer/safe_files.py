"""Reading the user's files and writing the user's outputs without hanging, exhausting
memory or losing anything.

Every file the explorer reads from a place the user chooses (settings, the dock layout,
lessons, scene files, meshes, shaders, arrays) goes through :func:`read_bytes`: only a
regular file is read (a FIFO, a device, a socket or a folder is refused at once, never
waited on: the file is opened with ``O_NONBLOCK`` and checked with ``fstat`` before a
byte is read), and never more than the cap of its kind, named in the message. The
parsers (:func:`parse_json`, :func:`parse_toml`) bound the nesting depth, since the
standard parsers recurse and end in ``RecursionError`` on a deeply nested file.

Every file the explorer writes goes through :func:`write_atomically`: the content goes to
a unique temporary name in the same folder (``mkstemp``: never a name a user file could
already have), then is renamed over the target, so a reader sees the old file or the new
one, never half of one, and two processes writing the same file never share a temporary.
"""

from __future__ import annotations

import errno
import json
import math
import os
import stat
import sys
import tempfile
from collections.abc import Callable
from pathlib import Path
from typing import Any

if sys.version_info >= (3, 11):
    import tomllib
else:  # pragma: no cover - Python 3.10
    import tomli as tomllib

MiB = 1024 * 1024

CAPS: dict[str, int] = {
    "settings file": 1 * MiB,
    "layout file": 1 * MiB,
    "lesson": 256 * 1024,
    "scene file": 1 * MiB,
    "shader": 1 * MiB,
    "mesh": 512 * MiB,
    "mesh asset": 512 * MiB,
    "texture": 256 * MiB,
    "array file": 2048 * MiB,
}
"""Largest file of each kind the explorer reads. A lesson is prose: the longest shipped
lesson is about 13 KB, so 256 KB leaves room for far more while a 10 MB lesson the window
could not draw fluidly is refused (the lesson reader also caps a step's text and formulas); a
settings or layout file is a few KB. A mesh asset is a file a mesh names (an OBJ's
material library, a glTF's buffer), a texture an image it names."""

MAX_NESTING = 32
"""Deepest nesting of tables and arrays in a JSON or TOML file the explorer accepts: its
own files nest at most 4 deep, the standard parsers recurse once per level."""


class UserFileError(ValueError):
    """A file the user gave cannot be read; the message is one line naming the file."""


def _kind_cap(kind: str, cap: int | None) -> int:
    return CAPS.get(kind, 64 * MiB) if cap is None else cap


def _a(kind: str) -> str:
    """``kind`` with its indefinite article ("a mesh", "an array file")."""
    return f"{'an' if kind[:1] in 'aeiou' else 'a'} {kind}"


def _file_noun(kind: str) -> str:
    """``kind`` as a kind of file ("a texture file", "an array file", never "file file")."""
    return _a(kind if kind.endswith("file") else f"{kind} file")


def _size_text(size: int) -> str:
    """``size`` in MB or KB, rounded up to a tenth below ten units (so a file just over a
    cap never reads as the cap itself: 1.5 MB, not "1 MB, over the 1 MB")."""
    unit, name = (MiB, "MB") if size >= MiB else (1024, "KB")
    if size % unit == 0 or size >= 10 * unit:
        return f"{size / unit:.0f} {name}"
    return f"{math.ceil(size * 10 / unit) / 10:.1f} {name}"


def _open_regular(path: Path, kind: str, limit: int) -> int:
    """A descriptor of the regular file ``path`` no larger than ``limit`` bytes."""
    try:
        # O_NONBLOCK: opening a FIFO with no writer would otherwise wait forever.
        fd = os.open(path, os.O_RDONLY | os.O_NONBLOCK | getattr(os, "O_NOCTTY", 0))
    except OSError as exc:
        if exc.errno == errno.ENXIO:     # a socket, or a FIFO opened for writing only
            raise UserFileError(f"{path}: not a regular file (the {kind} must be "
                                f"{_file_noun(kind)})") from None
        if exc.errno == errno.ELOOP:     # a symbolic link that names itself, or a longer cycle
            raise UserFileError(f"{path}: is a symbolic link that leads nowhere (a loop), "
                                f"not {_file_noun(kind)}") from None
        raise UserFileError(f"{path}: cannot read the {kind} "
                            f"({exc.strerror or exc})") from None
    try:
        info = os.fstat(fd)
        if not stat.S_ISREG(info.st_mode):
            what = ("a folder" if stat.S_ISDIR(info.st_mode) else
                    "a FIFO" if stat.S_ISFIFO(info.st_mode) else
                    "a device" if stat.S_ISCHR(info.st_mode) or stat.S_ISBLK(info.st_mode)
                    else "a socket or another special file")
            raise UserFileError(f"{path}: is {what}, not {_file_noun(kind)}")
        if info.st_size > limit:
            raise UserFileError(f"{path}: the {kind} is {_size_text(info.st_size)}, over "
                                f"the {_size_text(limit)} {_a(kind)} may have")
    except BaseException:
        os.close(fd)
        raise
    return fd


def check_regular_file(path: Path | str, kind: str, cap: int | None = None) -> int:
    """The size of the regular file ``path``, read nothing; :class:`UserFileError` as
    :func:`read_bytes` gives (for files another library then opens itself)."""
    path = Path(path)
    fd = _open_regular(path, kind, _kind_cap(kind, cap))
    try:
        return os.fstat(fd).st_size
    finally:
        os.close(fd)


def open_regular(path: Path | str, kind: str, cap: int | None = None):
    """A binary file object of the regular file ``path`` within the kind's cap (for
    readers that seek, such as an archive's); :class:`UserFileError` as :func:`read_bytes`
    gives."""
    return os.fdopen(_open_regular(Path(path), kind, _kind_cap(kind, cap)), "rb")


def read_bytes(path: Path | str, kind: str, cap: int | None = None) -> bytes:
    """The bytes of the regular file ``path``; :class:`UserFileError` for anything else
    (missing, not a regular file, unreadable, larger than the kind's cap)."""
    path = Path(path)
    limit = _kind_cap(kind, cap)
    fd = _open_regular(path, kind, limit)
    try:
        chunks, total = [], 0
        while True:
            chunk = os.read(fd, min(MiB, limit + 1 - total))
            if not chunk:
                break
            chunks.append(chunk)
            total += len(chunk)
            if total > limit:            # the file grew while it was read
                raise UserFileError(f"{path}: the {kind} is over the {_size_text(limit)} "
                                    f"{_a(kind)} may have")
        return b"".join(chunks)
    except OSError as exc:
        raise UserFileError(f"{path}: cannot read the {kind} "
                            f"({exc.strerror or exc})") from None
    finally:
        os.close(fd)


def decode_text(data: bytes, path: Path | str, kind: str) -> str:
    """``data`` as UTF-8; the error names the line of the first bad byte."""
    try:
        return data.decode("utf-8")
    except UnicodeDecodeError as exc:
        line = data.count(b"\n", 0, exc.start) + 1
        raise UserFileError(f"{path}:{line}: the {kind} is not UTF-8 text (byte "
                            f"0x{data[exc.start]:02x})") from None


def read_text(path: Path | str, kind: str, cap: int | None = None) -> str:
    """The UTF-8 text of the regular file ``path`` (see :func:`read_bytes`)."""
    return decode_text(read_bytes(path, kind, cap), path, kind)


def nesting_depth(value: Any, limit: int = MAX_NESTING) -> int:
    """How deeply dicts and lists nest in ``value`` (iteratively: no recursion), counted
    up to ``limit + 1``."""
    deepest = 0
    stack = [(value, 1)]
    while stack:
        item, depth = stack.pop()
        if isinstance(item, dict):
            children = item.values()
        elif isinstance(item, list):
            children = item
        else:
            continue
        deepest = max(deepest, depth)
        if deepest > limit:
            return deepest
        stack.extend((child, depth + 1) for child in children)
    return deepest


def _bounded(parse: Callable[[str], Any], text: str, where: str, fmt: str,
             limit: int) -> Any:
    try:
        data = parse(text)
    except RecursionError:
        raise UserFileError(f"{where}: the {fmt} nests deeper than the "
                            f"{limit} levels a file may have") from None
    if nesting_depth(data, limit) > limit:
        raise UserFileError(f"{where}: the {fmt} nests deeper than the {limit} levels a "
                            f"file may have")
    return data


def parse_json(text: str, where: Path | str, limit: int = MAX_NESTING) -> Any:
    """``json.loads(text)`` with the nesting bounded; :class:`UserFileError` (one line,
    with the line and column) for bad JSON."""
    try:
        return _bounded(json.loads, text, str(where), "JSON", limit)
    except json.JSONDecodeError as exc:
        raise UserFileError(f"{where}:{exc.lineno}:{exc.colno}: not valid JSON "
                            f"({exc.msg})") from None


def parse_toml(text: str, where: Path | str, limit: int = MAX_NESTING) -> Any:
    """``tomllib.loads(text)`` with the nesting bounded. A syntax error propagates as
    ``tomllib.TOMLDecodeError`` (its callers name the line)."""
    return _bounded(tomllib.loads, text, str(where), "TOML", limit)


def temporary_beside(path: Path) -> Path:
    """A new, empty file with a unique name in ``path``'s folder, ending in ``path``'s
    suffix (writers such as PIL pick the format from it). Created exclusively, so it can
    never be a file that was already there."""
    fd, name = tempfile.mkstemp(prefix=f".{path.stem}.", suffix=f".partial{path.suffix}",
                                dir=path.parent)
    os.close(fd)
    return Path(name)


def output_mode(path: Path | str) -> int:
    """The permission bits a file written to ``path`` gets: those of the file it replaces,
    else what a new file gets under the process's umask (``mkstemp``'s temporaries are
    private, 0600, which a renamed output must not keep)."""
    try:
        return stat.S_IMODE(os.stat(path).st_mode)
    except OSError:
        mask = os.umask(0)
        os.umask(mask)
        return 0o666 & ~mask


def write_atomically(path: Path | str, save: Callable[[Path], None] | bytes | str) -> Path:
    """Write ``path`` whole: ``save(temporary)`` (or the given bytes/text) into a unique
    temporary beside it, then rename it into place. On any failure (a full disk, an
    interrupt) the temporary is removed and ``path`` is as it was."""
    path = Path(path)
    partial = temporary_beside(path)
    try:
        if callable(save):
            save(partial)
        elif isinstance(save, bytes):
            partial.write_bytes(save)
        else:
            partial.write_text(save, encoding="utf-8")
        os.chmod(partial, output_mode(path))
        os.replace(partial, path)
    except BaseException:
        partial.unlink(missing_ok=True)
        raise
    return path


def os_error_text(exc: OSError) -> str:
    """An OSError as a few words ("No space left on device", "File name too long")."""
    return exc.strerror or str(exc) or type(exc).__name__
