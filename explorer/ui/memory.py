"""Resident memory that follows what the window holds: large blocks go back to the system
when they are freed.

glibc serves a block from ``mmap`` above a threshold and gives it back on ``free``, but it
raises that threshold to the size of each such block freed (up to 32 MiB), so after the
first freed grid read-back (12 MiB at 64³) every later one comes from the heap, which
keeps its high-water mark: a soak's resident memory climbed by each visit to a 64³ grid
with two cascades and never came down (BENCHMARKS.md, issue #31). A fixed threshold stops
that adjustment.
"""

from __future__ import annotations

import ctypes
import ctypes.util

MMAP_THRESHOLD_BYTES = 1 << 20
"""Blocks from 1 MiB up are mapped on their own (numpy's images and grids)."""
_M_MMAP_THRESHOLD = -3
"""glibc's ``mallopt`` parameter number (malloc.h)."""


def return_large_blocks() -> bool:
    """Fix glibc's mmap threshold at :data:`MMAP_THRESHOLD_BYTES`; False where the C
    library is not glibc (nothing changes there)."""
    name = ctypes.util.find_library("c")
    try:
        libc = ctypes.CDLL(name)
        mallopt = libc.mallopt
    except (OSError, AttributeError, TypeError):
        return False
    mallopt.argtypes, mallopt.restype = [ctypes.c_int, ctypes.c_int], ctypes.c_int
    return mallopt(_M_MMAP_THRESHOLD, MMAP_THRESHOLD_BYTES) == 1
