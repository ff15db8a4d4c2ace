"""The window fixes glibc's mmap threshold, so a large block freed goes back to the system."""

from __future__ import annotations

import ctypes
import ctypes.util

import numpy as np
import pytest

from explorer.ui import memory


def _resident_kib() -> int:
    with open("/proc/self/status", encoding="ascii") as status:
        return next(int(line.split()[1]) for line in status if line.startswith("VmRSS:"))


def test_a_freed_grid_sized_block_leaves_resident_memory():
    """After one 12 MiB block is freed glibc would serve the next from its heap (its
    dynamic threshold); with the threshold fixed each comes from mmap and goes back."""
    if ctypes.util.find_library("c") is None or not memory.return_large_blocks():
        pytest.skip("not glibc")
    size = 12 << 20
    np.ones(size // 8).sum()                     # freed once: the dynamic rule's trigger
    before = _resident_kib()
    for _ in range(8):
        block = np.ones(size // 8)
        block.sum()
        del block
    assert _resident_kib() - before < 4 << 10    # under 4 MiB stays resident
