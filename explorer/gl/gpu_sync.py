"""GPU work the CPU does not wait for: fences, read-backs that complete a frame later,
and timer queries read once their result is there.

moderngl 5 has no sync objects and no way to ask whether a query's result is available,
so these few entry points are called through ``ctypes`` from the GL library the context
already uses (GLVND's ``libOpenGL``, else ``libGL``); they act on the current context,
as moderngl's own calls do, and touch no state moderngl caches.

* :class:`Fence`: ``glFenceSync`` after some commands; :meth:`Fence.signaled` asks
  without waiting, :meth:`Fence.wait` waits for exactly those commands (a caller that
  needs the number now).
* :class:`DeferredRead`: a texture or buffer copied into a buffer of its own on the GPU
  (a pixel-buffer read: ``read_into`` a :class:`moderngl.Buffer`), fenced; its bytes are
  taken once the fence has signaled, a frame or more later, with no wait
  (:meth:`DeferredRead.result`, or :meth:`DeferredRead.wait` for a caller that needs it).
* :class:`TimerQueries`: ``GL_TIME_ELAPSED`` queries whose results are collected when
  available (a frame later on a GPU) instead of bracketing each pass with ``finish``.
"""

from __future__ import annotations

import ctypes
import ctypes.util
import math
import time
import weakref
from collections.abc import Callable, Sequence

import moderngl
import numpy as np

GL_SYNC_GPU_COMMANDS_COMPLETE = 0x9117
GL_SYNC_FLUSH_COMMANDS_BIT = 0x1
GL_ALREADY_SIGNALED = 0x911A
GL_TIMEOUT_EXPIRED = 0x911B
GL_CONDITION_SATISFIED = 0x911C
GL_WAIT_FAILED = 0x911D
GL_TIME_ELAPSED = 0x88BF
GL_QUERY_RESULT = 0x8866
GL_QUERY_RESULT_AVAILABLE = 0x8867
_SIGNALED = (GL_ALREADY_SIGNALED, GL_CONDITION_SATISFIED)
WAIT_SLICE_NS = 1_000_000
"""A waiting :meth:`Fence.wait` asks the driver in slices of this many nanoseconds."""

_LIBRARIES = ("libOpenGL.so.0", "libGL.so.1", "OpenGL", "GL")


class _Gl:
    """The few GL entry points of this module, resolved once."""

    def __init__(self) -> None:
        library = None
        for name in _LIBRARIES:
            path = ctypes.util.find_library(name) if "." not in name else name
            if path is None:
                continue
            try:
                library = ctypes.CDLL(path)
                break
            except OSError:
                continue
        if library is None:
            raise OSError("no GL library (libOpenGL.so.0 or libGL.so.1) to call fences from")
        self.fence_sync = _function(library, "glFenceSync", ctypes.c_void_p,
                                    ctypes.c_uint, ctypes.c_uint)
        self.client_wait_sync = _function(library, "glClientWaitSync", ctypes.c_uint,
                                          ctypes.c_void_p, ctypes.c_uint, ctypes.c_uint64)
        self.delete_sync = _function(library, "glDeleteSync", None, ctypes.c_void_p)
        self.gen_queries = _function(library, "glGenQueries", None, ctypes.c_int,
                                     ctypes.POINTER(ctypes.c_uint))
        self.delete_queries = _function(library, "glDeleteQueries", None, ctypes.c_int,
                                        ctypes.POINTER(ctypes.c_uint))
        self.begin_query = _function(library, "glBeginQuery", None, ctypes.c_uint,
                                     ctypes.c_uint)
        self.end_query = _function(library, "glEndQuery", None, ctypes.c_uint)
        # one texture's texels into another's (explorer/gl/image_copy.py): no draw
        self.copy_image_sub_data = _function(library, "glCopyImageSubData", None,
                                             *([ctypes.c_uint, ctypes.c_uint, ctypes.c_int]
                                               + [ctypes.c_int] * 3) * 2,
                                             ctypes.c_int, ctypes.c_int, ctypes.c_int)
        # a rectangle of the bound read framebuffer into the bound 2D texture (the
        # window's figure pictures, explorer/ui/figure_cache.py): queued, no read-back
        self.copy_tex_sub_image_2d = _function(library, "glCopyTexSubImage2D", None,
                                               ctypes.c_uint, *[ctypes.c_int] * 7)
        self.get_integer_v = _function(library, "glGetIntegerv", None, ctypes.c_uint,
                                       ctypes.POINTER(ctypes.c_int))
        self.query_object_iv = _function(library, "glGetQueryObjectiv", None, ctypes.c_uint,
                                         ctypes.c_uint, ctypes.POINTER(ctypes.c_int))
        self.query_object_ui64v = _function(library, "glGetQueryObjectui64v", None,
                                            ctypes.c_uint, ctypes.c_uint,
                                            ctypes.POINTER(ctypes.c_uint64))


def _function(library, name: str, restype, *argtypes) -> Callable:
    function = getattr(library, name)
    function.restype, function.argtypes = restype, list(argtypes)
    return function


_gl: _Gl | None = None


def gl() -> _Gl:
    """The entry points (resolved on first use)."""
    global _gl
    if _gl is None:
        _gl = _Gl()
    return _gl


GL_MAX_IMAGE_UNITS = 0x8F38
GL_SHADER_STORAGE_BUFFER_OFFSET_ALIGNMENT = 0x90DF


def gl_integer(name: int, default: int = 0) -> int:
    """``glGetIntegerv(name)`` of the current context (a limit moderngl's ``info`` does not
    hold), ``default`` without a GL library."""
    try:
        entry_points = gl()
    except OSError:
        return default
    value = ctypes.c_int(default)
    entry_points.get_integer_v(name, ctypes.byref(value))
    return int(value.value)


class Fence:
    """A fence after every command issued so far to the current context; ``holders``:
    how many :meth:`release` calls delete it (reads issued together share one,
    :func:`issue_together`)."""

    def __init__(self, holders: int = 1) -> None:
        self._sync = gl().fence_sync(GL_SYNC_GPU_COMMANDS_COMPLETE, 0)
        self._done = False
        self._holders = holders

    def signaled(self) -> bool:
        """Whether the GPU has finished those commands (asks without waiting; the first
        ask flushes them, so that they start)."""
        if not self._done:
            status = gl().client_wait_sync(self._sync, GL_SYNC_FLUSH_COMMANDS_BIT, 0)
            self._done = status in _SIGNALED
            if status == GL_WAIT_FAILED:
                raise RuntimeError("glClientWaitSync failed (no current GL context?)")
        return self._done

    def wait(self, timeout_s: float | None = None) -> bool:
        """Wait until the commands are done (or ``timeout_s`` passed); True if done."""
        deadline = None if timeout_s is None else time.perf_counter() + timeout_s
        while not self._done:
            status = gl().client_wait_sync(self._sync, GL_SYNC_FLUSH_COMMANDS_BIT,
                                           WAIT_SLICE_NS)
            if status == GL_WAIT_FAILED:
                raise RuntimeError("glClientWaitSync failed (no current GL context?)")
            self._done = status in _SIGNALED
            if deadline is not None and time.perf_counter() >= deadline:
                break
        return self._done

    def release(self) -> None:
        """Drop one holder's hold; the last deletes the sync object."""
        self._holders -= 1
        if self._sync and self._holders <= 0:
            gl().delete_sync(self._sync)
            self._sync = None


DEFERRED_BUFFERS: weakref.WeakSet = weakref.WeakSet()
"""The buffers deferred reads copy into: reading one back after its fence signaled is no
round trip (explorer/gl/call_counter.py counts it apart from synchronous read-backs)."""


class DeferredRead:
    """A read-back issued now and taken later: the source is copied on the GPU into a
    buffer of this object's own, behind a fence (module docstring)."""

    def __init__(self, ctx: moderngl.Context) -> None:
        self.ctx = ctx
        self._buffer: moderngl.Buffer | None = None
        self._fence: Fence | None = None
        self.shape: tuple[int, ...] = ()
        self.dtype = np.dtype("f4")
        self._dtype_given: object = None
        """The ``dtype`` argument :attr:`dtype` was made from (what the next copy compares)."""
        self._size = 0
        self._buffer_size = 0
        self.serial = 0
        """Increases with every read issued (what a consumer compares)."""

    def issue(self, source, shape: tuple[int, ...], dtype: str | np.dtype = "f4",
              **read_options) -> None:
        """Copy ``source`` (a texture, framebuffer or buffer: anything with
        ``read_into``) into the buffer and fence it; ``shape`` and ``dtype`` say how its
        bytes are read. A read still in flight is replaced."""
        self.copy_unfenced(source, shape, dtype, **read_options)
        self.fenced(Fence())

    def copy_unfenced(self, source, shape: tuple[int, ...], dtype: str | np.dtype = "f4",
                      **read_options) -> None:
        """:meth:`issue`'s copy without its fence: the read is not issued until
        :meth:`fenced` gives it one made after this copy (:func:`issue_together`)."""
        if dtype is not self._dtype_given or shape != self.shape:
            # a stage reads the same shapes frame after frame: worked out when they change
            self.dtype, self.shape = np.dtype(dtype), tuple(shape)
            self._dtype_given = dtype
            self._size = math.prod(self.shape) * self.dtype.itemsize
        size = self._size
        if self._buffer is None or self._buffer_size != size:
            if self._buffer is not None:
                self._buffer.release()
            self._buffer = self.ctx.buffer(reserve=size, dynamic=True)
            self._buffer_size = size
            DEFERRED_BUFFERS.add(self._buffer)
        if isinstance(source, moderngl.Buffer):
            self.ctx.copy_buffer(self._buffer, source, size)
        else:
            source.read_into(self._buffer, **read_options)

    def fenced(self, fence: Fence) -> None:
        """The copy just made (:meth:`copy_unfenced`) is done when ``fence``, made after
        it, has signaled; the read holds the fence until it is issued again or
        released."""
        if self._fence is not None:
            self._fence.release()
        self._fence = fence
        self.serial += 1

    @property
    def issued(self) -> bool:
        return self._fence is not None

    @property
    def nbytes(self) -> int:
        """The bytes of its buffer (0 before a read or after :meth:`release`)."""
        return 0 if self._buffer is None else self._buffer.size

    def ready(self) -> bool:
        """The copy is done: :meth:`result` returns without waiting."""
        return self._fence is not None and self._fence.signaled()

    def result(self) -> np.ndarray | None:
        """The bytes as an array if the copy is done, else None (nothing waits)."""
        if not self.ready():
            return None
        return self._array()

    def wait(self) -> np.ndarray:
        """The bytes, waiting for exactly this copy if it is not done yet."""
        if self._fence is None:
            raise RuntimeError("no read was issued")
        if not self._fence.signaled():
            self._fence.wait()
        return self._array()

    def _array(self) -> np.ndarray:
        data = self._buffer.read()
        return np.frombuffer(data, self.dtype).reshape(self.shape)

    def release(self) -> None:
        if self._fence is not None:
            self._fence.release()
            self._fence = None
        if self._buffer is not None:
            self._buffer.release()
            self._buffer = None


def issue_together(reads: Sequence[DeferredRead], sources: Sequence,
                   shapes: Sequence[tuple[int, ...]], dtype: str | np.dtype = "f4") -> None:
    """``reads[i].issue(sources[i], shapes[i], dtype)`` for each, behind one fence after
    the last copy (it covers the copies before it too): a stage's textures read back in
    a row cost one fence, one poll and one delete instead of one each."""
    if not reads:
        return
    for read, source, shape in zip(reads, sources, shapes, strict=True):
        read.copy_unfenced(source, shape, dtype)
    fence = Fence(holders=len(reads))
    for read in reads:
        read.fenced(fence)


class TimerQueries:
    """``GL_TIME_ELAPSED`` queries around passes, read when the GPU has the result: a
    pass is measured without the CPU waiting for it (module docstring)."""

    def __init__(self) -> None:
        self._free: list[int] = []
        self._pending: list[tuple[int, object]] = []
        """(query id, what the caller tagged it with) in the order issued."""
        self._gl: _Gl | None = None
        """:func:`gl` (its entry points are looked up at each call: a call counter wraps
        them)."""
        self._available = ctypes.c_int(0)
        self._elapsed = ctypes.c_uint64(0)
        self._available_ref = ctypes.byref(self._available)
        self._elapsed_ref = ctypes.byref(self._elapsed)

    def begin(self) -> int:
        entry_points = self._gl
        if entry_points is None:
            entry_points = self._gl = gl()
        if not self._free:
            ids = (ctypes.c_uint * 8)()
            entry_points.gen_queries(8, ids)
            self._free.extend(ids)
        query = self._free.pop()
        entry_points.begin_query(GL_TIME_ELAPSED, query)
        return query

    def end(self, query: int, tag: object) -> None:
        entry_points = self._gl
        if entry_points is None:
            entry_points = self._gl = gl()
        entry_points.end_query(GL_TIME_ELAPSED)
        self._pending.append((query, tag))

    @property
    def pending(self) -> int:
        return len(self._pending)

    def collect(self, wait: bool = False) -> list[tuple[object, float]]:
        """``(tag, milliseconds)`` of the queries whose results are available, oldest
        first (results come in order: the first one not available ends the list);
        ``wait``: all of them, waiting for the GPU."""
        done: list[tuple[object, float]] = []
        pending = self._pending
        if not pending:
            return done
        entry_points = self._gl
        if entry_points is None:
            entry_points = self._gl = gl()
        available, elapsed = self._available, self._elapsed
        available_ref, elapsed_ref = self._available_ref, self._elapsed_ref
        taken = 0
        for query, tag in pending:
            if not wait:
                entry_points.query_object_iv(query, GL_QUERY_RESULT_AVAILABLE, available_ref)
                if not available.value:
                    break
            entry_points.query_object_ui64v(query, GL_QUERY_RESULT, elapsed_ref)
            taken += 1
            done.append((tag, elapsed.value / 1e6))
        if taken:
            self._free.extend(query for query, _ in pending[:taken])
            del pending[:taken]
        return done

    def release(self) -> None:
        ids = [query for query, _ in self._pending] + self._free
        if ids:
            array = (ctypes.c_uint * len(ids))(*ids)
            gl().delete_queries(len(ids), array)
        self._pending, self._free = [], []


class GpuWait:
    """What a stage's unit of work yields when its next unit reads back GPU work it has
    just issued (explorer/lpv/job.py): a job run within a frame budget does that unit in
    a later frame, once the reads are :meth:`ready`; ``progress`` is the unit's progress
    count (None: one more unit)."""

    def __init__(self, reads: list[DeferredRead], progress: int | None = None) -> None:
        self.reads = reads
        self.progress = progress

    def ready(self) -> bool:
        return all(read.ready() for read in self.reads)
