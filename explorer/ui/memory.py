"""Resident memory that follows what the window holds: large blocks go back to the system
when they are freed.

glibc serves a block from ``mmap`` above a threshold and gives it back on ``free``, but it
raises that threshold to the size of each such block freed (up to 32 MiB), so after the
first freed grid read-back (12 MiB at 64³) every later one comes from the heap, which
keeps its high-water mark: a soak's resident memory climbed by each visit to a 64³ grid
with two cascades and never came down (BENCHMARKS.md, issue #31). A fixed threshold stops
that adjustment.

Smaller blocks (below the threshold) come from glibc's heaps, one per thread that
allocates (llvmpipe's too), and a freed block in the middle of a heap stays resident: after
a 64³ step a window falling idle held 170 MiB of such free pages (BENCHMARKS.md, issue
#31). :func:`give_back_free` hands them back (``malloc_trim``); the window calls it once
each time it falls idle, when no one waits on a frame, after :func:`release_between_runs`
has released what only a job in progress uses.
"""

from __future__ import annotations

import ctypes
import ctypes.util
from collections.abc import Iterable
from typing import Any

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


def _libc():
    name = ctypes.util.find_library("c")
    try:
        return ctypes.CDLL(name)
    except (OSError, TypeError):
        return None


def give_back_free() -> bool:
    """Hand the free pages of every malloc heap back to the system (glibc's
    ``malloc_trim(0)``); what is allocated stays as it is. False where the C library has no
    ``malloc_trim`` (nothing changes there)."""
    libc = _libc()
    trim = getattr(libc, "malloc_trim", None)
    if trim is None:
        return False
    trim.argtypes, trim.restype = [ctypes.c_size_t], ctypes.c_int
    trim(0)
    return True


def release_between_runs(sides: Iterable[Any]) -> int:
    """Release the GPU memory only a job in progress uses of every side that has a
    pipeline (``SideState``: :meth:`explorer.lpv.pipeline.Pipeline.release_between_runs`,
    a large grid's ping and pong, the injection's layers, the read-backs taken); the
    window calls it when it falls idle. Returns the bytes released."""
    return sum(side.pipeline.release_between_runs() for side in sides
               if side.pipeline is not None)
