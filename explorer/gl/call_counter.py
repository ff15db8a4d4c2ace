"""Counts the GL work a piece of Python issues: every call into moderngl's objects, the
dispatches, draws, barriers, finishes, uniform uploads, bindings and read-backs among them,
and how much of the wall time passed inside those calls (``lpv-explorer bench
--overhead``).

moderngl's classes are thin Python wrappers around its C extension (``self.mglo``), so
wrapping their public methods and the ``Uniform.value`` setter for the duration of a
:class:`GlCallCounter` sees every GL call the explorer makes. Only the outermost wrapped
call is timed (``Program.__setitem__`` sets a ``Uniform.value`` inside: one call, one
upload). The time outside the calls is the Python side of the work: what a GPU, which
runs the calls' work in parallel with the CPU, would not hide. On a software renderer the
time inside a dispatch or a draw holds the rendering itself (llvmpipe renders there or at
the next finish), so only the outside time is a CPU figure.

Read-backs are told apart: a ``read``/``read_into`` that returns bytes is a synchronous
read-back (the CPU waits for the GPU); ``read_into`` a :class:`moderngl.Buffer` is a
queued copy (a pixel-buffer read, explorer/gl/gpu_sync.py ``DeferredRead``), and reading
such a buffer back is a deferred read. :class:`~explorer.gl.gpu_sync.Fence` waits count as
finishes (a wait for the GPU), its polls as polls. The GL entry points
explorer/gl/gpu_sync.py calls through ``ctypes`` (timer queries begun, ended and asked
for their results, fences made and deleted) are GL calls too: a driver may flush its
queue in them (llvmpipe does when a query's result is asked for).
"""

from __future__ import annotations

import functools
import time
from collections import Counter
from dataclasses import dataclass, field

import moderngl

KINDS = {
    ("ComputeShader", "run"): "dispatches",
    ("ComputeShader", "run_indirect"): "dispatches",
    ("VertexArray", "render"): "draws",
    ("VertexArray", "render_indirect"): "draws",
    ("Context", "memory_barrier"): "barriers",
    ("Context", "finish"): "finishes",
    ("Program", "__setitem__"): "uniform uploads",
    ("ComputeShader", "__setitem__"): "uniform uploads",
    ("Uniform", "value"): "uniform uploads",
    ("Uniform", "write"): "uniform uploads",
    ("Texture", "use"): "bindings",
    ("Texture3D", "use"): "bindings",
    ("TextureArray", "use"): "bindings",
    ("TextureCube", "use"): "bindings",
    ("Texture", "bind_to_image"): "bindings",
    ("Texture3D", "bind_to_image"): "bindings",
    ("TextureArray", "bind_to_image"): "bindings",
    ("Buffer", "bind_to_storage_buffer"): "bindings",
    ("Buffer", "bind_to_uniform_block"): "bindings",
    ("Sampler", "use"): "bindings",
    ("Framebuffer", "use"): "bindings",
    ("Texture", "read"): "read-backs",
    ("Fence", "wait"): "finishes",
    ("Fence", "signaled"): "fence polls",
    ("Texture3D", "read"): "read-backs",
    ("TextureArray", "read"): "read-backs",
    ("Texture", "read_into"): "read-backs",
    ("Texture3D", "read_into"): "read-backs",
    ("Buffer", "read"): "read-backs",
    ("Buffer", "read_into"): "read-backs",
    ("Framebuffer", "read"): "read-backs",
    ("Framebuffer", "read_into"): "read-backs",
    ("Query", "__enter__"): "queries",
}
"""(class, method) -> the kind a call is counted as besides "GL calls" (all of them)."""

SYNC_CLASSES = ("Fence",)
"""explorer.gl.gpu_sync's classes whose waits and polls are counted."""
CTYPES_ENTRY_POINTS = {"begin_query": "queries", "end_query": None, "query_object_iv": None,
                       "query_object_ui64v": None, "gen_queries": None,
                       "delete_queries": None, "fence_sync": None, "delete_sync": None,
                       "client_wait_sync": None, "copy_image_sub_data": "copies",
                       "copy_tex_sub_image_2d": "copies", "get_integer_v": None}
"""explorer.gl.gpu_sync's ``ctypes`` GL functions (``gl()``'s attributes) -> their kind."""
CLASSES = ("Context", "Buffer", "Texture", "Texture3D", "TextureArray", "TextureCube",
           "Framebuffer", "Renderbuffer", "VertexArray", "Program", "ComputeShader",
           "Sampler", "Query", "Scope", "Uniform")
"""The moderngl classes whose public methods are counted."""

_SKIPPED = ("__init__", "__repr__", "__eq__", "__hash__", "__del__", "__getattr__",
            "__getitem__", "__contains__", "__iter__", "__len__", "__exit__", "get",
            "release")
"""Methods that issue no GL work (attribute access, set-up) or that are not per frame."""


@dataclass
class CallTally:
    """What a :class:`GlCallCounter` saw: calls per kind and the seconds inside them."""

    calls: Counter = field(default_factory=Counter)
    inside_s: float = 0.0

    def per(self, frames: int) -> dict[str, float]:
        """Calls of each kind per frame over ``frames`` frames (``GL calls``: all)."""
        return {kind: count / max(frames, 1) for kind, count in sorted(self.calls.items())}


class GlCallCounter:
    """A context manager that counts moderngl calls (module docstring) into :attr:`tally`.
    Not re-entrant and not thread-safe: one counter at a time, for a measurement."""

    def __init__(self) -> None:
        self.tally = CallTally()
        self._saved: list[tuple[object, str, object]] = []
        self._depth = 0

    def __enter__(self) -> GlCallCounter:
        from explorer.gl import gpu_sync

        try:
            entry_points = gpu_sync.gl()
        except OSError:                 # no GL library: nothing calls these
            entry_points = None
        if entry_points is not None:
            for name, kind in CTYPES_ENTRY_POINTS.items():
                self._saved.append((entry_points, name, vars(entry_points)[name]))
                setattr(entry_points, name, self._wrap(vars(entry_points)[name], kind))
        for cls in (getattr(gpu_sync, name) for name in SYNC_CLASSES):
            for name in ("wait", "signaled"):
                member = vars(cls)[name]
                self._saved.append((cls, name, member))
                setattr(cls, name, self._wrap(member, KINDS[(cls.__name__, name)]))
        for class_name in CLASSES:
            cls = getattr(moderngl, class_name, None)
            if cls is None:
                continue
            for name, member in list(vars(cls).items()):
                if name in _SKIPPED or (name.startswith("_") and name != "__setitem__"
                                        and name != "__enter__"):
                    continue
                kind = KINDS.get((class_name, name))
                if isinstance(member, property):
                    if member.fset is None or kind is None:
                        continue       # reading a property is bookkeeping, not a GL call
                    wrapped = property(member.fget, self._wrap(member.fset, kind),
                                       member.fdel, member.__doc__)
                elif callable(member):
                    wrapped = self._wrap(member, kind)
                else:
                    continue
                self._saved.append((cls, name, member))
                setattr(cls, name, wrapped)
        return self

    def __exit__(self, *exc_info) -> None:
        for cls, name, member in reversed(self._saved):
            setattr(cls, name, member)
        self._saved.clear()

    def _wrap(self, function, kind: str | None):
        tally = self.tally

        clock = time.perf_counter

        @functools.wraps(function)
        def counted(*args, **kwargs):
            # the clock starts first and stops last: the counter's own bookkeeping is not
            # the Python time outside GL that it measures
            start = clock()
            if self._depth:
                return function(*args, **kwargs)
            tally.calls["GL calls"] += 1
            counted_as = _read_kind(args) if kind == "read-backs" else kind
            if counted_as is not None:
                tally.calls[counted_as] += 1
            self._depth += 1
            try:
                return function(*args, **kwargs)
            finally:
                self._depth -= 1
                tally.inside_s += clock() - start

        return counted


def _read_kind(args: tuple) -> str:
    """What a read call is (module docstring): ``args`` are the call's, ``self`` first."""
    from explorer.gl.gpu_sync import DEFERRED_BUFFERS

    source = args[0]
    if isinstance(source, moderngl.Buffer) and source in DEFERRED_BUFFERS:
        return "deferred reads"
    if len(args) > 1 and isinstance(args[1], moderngl.Buffer):
        return "queued copies"
    return "read-backs"
