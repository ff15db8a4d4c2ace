"""An ``.npz`` (``--vpls``, ``--grid0``, ``diff``) is checked against its real size before
numpy allocates what its headers claim: a header lie, a zip directory claiming more than
the file holds, an object array, each one line naming the file and the array."""

from __future__ import annotations

import io
import struct
import zipfile

import numpy as np
import pytest

from explorer.exchange.files import FileFormatError, read_npz


def npy_bytes(array: np.ndarray, shape_text: bytes | None = None) -> bytes:
    """``array`` as ``.npy`` bytes, its header's shape replaced by ``shape_text`` (padded so
    the header keeps its length)."""
    buffer = io.BytesIO()
    np.save(buffer, array)
    raw = buffer.getvalue()
    if shape_text is None:
        return raw
    (length,) = struct.unpack("<H", raw[8:10])
    header = raw[10:10 + length].replace(str(array.shape).encode(), shape_text).rstrip()
    return raw[:10] + header + b" " * (length - 1 - len(header)) + b"\n" + raw[10 + length:]


def test_a_header_claiming_a_terabyte_array_is_refused_before_allocating(tmp_path):
    path = tmp_path / "lie.npz"
    with zipfile.ZipFile(path, "w") as archive:
        archive.writestr("positions.npy", npy_bytes(np.zeros((4, 3), np.float32),
                                                    b"(100000000000, 3)"))
    with pytest.raises(FileFormatError, match=r"--vpls .*lie\.npz: array 'positions' "
                       r"claims shape \(100000000000, 3\)"):
        read_npz(path, "--vpls")


def test_a_zip_directory_claiming_more_than_the_file_is_refused(tmp_path):
    path = tmp_path / "claim.npz"
    np.savez(path, a=np.zeros((64, 3), np.float32))
    data = bytearray(path.read_bytes())
    central = data.rindex(b"PK\x01\x02")                # the member's directory entry
    data[central + 20:central + 28] = struct.pack("<II", 10**9, 10**9)
    path.write_bytes(bytes(data))
    with pytest.raises(FileFormatError, match="claim"):
        read_npz(path)


def test_an_object_array_is_refused_unread(tmp_path):
    path = tmp_path / "objects.npz"
    np.savez(path, a=np.array([{"x": 1}], dtype=object))
    with pytest.raises(FileFormatError, match="Python objects"):
        read_npz(path)


def test_a_single_npy_is_not_an_archive(tmp_path):
    path = tmp_path / "one.npz"
    path.write_bytes(npy_bytes(np.zeros(3)))
    with pytest.raises(FileFormatError, match="not an .npz archive"):
        read_npz(path)


def test_a_valid_archive_reads_back(tmp_path):
    path = tmp_path / "ok.npz"
    np.savez(path, a=np.arange(6.0).reshape(2, 3), b=np.int32([1, 2]))
    arrays = read_npz(path)
    assert arrays["a"].shape == (2, 3) and arrays["b"].tolist() == [1, 2]
