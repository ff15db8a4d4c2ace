"""The energy audit's GPU reduction (``shaders/audit_reduce.glsl``): the per-cell records
the propagation writes, summed into the totals :class:`explorer.lpv.audit.GridAudit`
holds, and :class:`CellAuditRecords`, one cell's records read on demand; the audit's
data types are :mod:`explorer.lpv.audit`'s."""

from __future__ import annotations

import struct
from collections.abc import Callable, Sequence
from typing import NamedTuple

import moderngl
import numpy as np

from explorer.gl.gpu_sync import GL_SHADER_STORAGE_BUFFER_OFFSET_ALIGNMENT, DeferredRead, gl_integer
from explorer.gl.program import ProgramCache, set_uniform, set_uniforms
from explorer.lpv.audit import CellAudit
from explorer.lpv.grid import grid_cells, shape_text
from explorer.lpv.passes.textures import LpvGrid

AUDIT_VALUES = 21
"""Numbers per audit slot: flux, border loss, clamp gain, occluded, reflected, blocked,
withheld by the flux budget (3 channels each)."""
CELL_SUMS_BINDING = 5
"""Storage binding of the per-cell sums over the steps (``shaders/propagate.glsl``)."""
MAX_PARTIALS = 512
"""Partial records per audit slot at most (``audit_reduce.glsl`` stages 0 and 1): each
invocation of the first stage sums every P-th cell, P = min(⌈N³/64⌉, MAX_PARTIALS), so
the partial records of 1026 slots (1024 iterations) take 37 MB, within one storage
block."""


PING_GRID_UNIT = 8
"""Where the propagation's steps in a row keep ping's textures
(explorer/lpv/passes/propagate.py ``PING_TEXTURE_UNIT``, which is this)."""
PING_GRID_DEFINES = {"AUDIT_GRID_R": PING_GRID_UNIT, "AUDIT_GRID_G": PING_GRID_UNIT + 1,
                     "AUDIT_GRID_B": PING_GRID_UNIT + 2}
PING_FLUX = 3
"""The program id (besides the stages 0, 1, 2) of stage 0 reading its grid on
:data:`PING_GRID_UNIT`'s units instead of 0..2."""
_STAGE_DEFINES = {**{stage: {"AUDIT_STAGE": stage} for stage in (0, 1, 2)},
                  PING_FLUX: {"AUDIT_STAGE": 0, **PING_GRID_DEFINES}}
"""The defines of ``audit_reduce.glsl``'s three stages (partials of a grid's flux, of the
cell records; the fold) and of stage 0 on ping's units, and their program keys, made
once."""
_STAGE_KEYS = {stage: ProgramCache.key("audit_reduce.glsl", defines)
               for stage, defines in _STAGE_DEFINES.items()}

GRID_SAMPLERS: dict[str, object] = {}
"""The uniforms of the grid whose flux :meth:`AuditReducer.measure_flux` reduces: none,
its samplers are bound to units 0..2 by the shader's layout."""


KEPT_RECORDS_BYTES = 4 << 20
"""The per-cell records of the propagation's steps in a row are kept for one reduction of
them all (:meth:`AuditReducer.steps_recorder`) as far as this many bytes hold them (an
8³ grid's 16 steps: 0.7 MiB; from 32³ on, one step's)."""


SHRINK_OVER = 4
"""An audit buffer over this many times what a grid needs is made anew at its size."""


class AuditReducer:
    """Sums audit records on the GPU (``shaders/audit_reduce.glsl``) into result slots of
    21 floats (flux, border loss, clamp gain, occluded, reflected, blocked, withheld by
    the flux budget; 3 channels each). Each measurement (:meth:`measure_flux`,
    :meth:`sum_cell_records`) reduces its records to partial sums in its own slot's
    region; :meth:`read` folds every slot at once (one dispatch, no barrier: llvmpipe pays
    dearly for ``barrier()``) and reads them back, the only read-back.

    Storage buffers while a pass runs (see :meth:`bind`): 2 partial records (all slots),
    3 results, 4 per-cell records (written by ``propagate.glsl``, ``21·N³`` floats, the
    current step's), 5 their per-cell sums over the steps (``21·N³`` floats, zeroed by
    :meth:`begin`).
    """

    def __init__(self, ctx: moderngl.Context, programs: ProgramCache) -> None:
        self.ctx = ctx
        self.programs = programs
        self._buffers: dict[str, moderngl.Buffer] = {}
        self._sizes: dict[str, int] = {}
        """Each buffer's size in bytes."""
        self._slots = 0
        self._cells = (1, 1, 1)
        self._partials = 1
        self.generation = 0
        """Counts :meth:`begin` calls: the per-cell records of a propagation are current
        while it has not changed (:class:`CellAuditRecords`)."""
        self.has_records = False
        self._kept: dict[int, object] = {}
        """The stages' programs got since :meth:`begin` (see :meth:`_stage_program`)."""
        self._kept_releases = -1
        self._alignment: int | None = None
        self._record_stride = 0
        """Bytes from one step's per-cell records to the next's (kept steps, aligned)."""
        self.record_regions = 1
        """Steps whose per-cell records the buffer holds at once (:meth:`steps_recorder`)."""
        self._record_uniforms: dict[str, object] = {"u_record_stride": 0}
        self._records_at = 0
        """Where the last step's records start in the buffer (floats)."""

    def _buffer(self, name: str, size: int) -> moderngl.Buffer:
        """Buffer ``name`` of at least ``size`` bytes: kept while it fits, made anew when it
        is too small or over :data:`SHRINK_OVER` times the size (a 64³ grid's per-cell
        records, 42 MiB, are not kept for the 8³ grid that follows)."""
        buffer = self._buffers.get(name)
        made = self._sizes.get(name, 0)     # the buffer's size, kept (asking is a GL call)
        if buffer is None or made < size or made > SHRINK_OVER * max(size, 4):
            if buffer is not None:
                buffer.release()
            buffer = self._buffers[name] = self.ctx.buffer(reserve=max(size, 4))
            self._sizes[name] = max(size, 4)
        return buffer

    @property
    def partial_count(self) -> int:
        """Partial records per slot (of the grid :meth:`begin` prepared)."""
        return self._partials

    @property
    def _cell_count(self) -> int:
        return self._cells[0] * self._cells[1] * self._cells[2]

    def begin(self, cells: int | tuple[int, int, int], slots: int,
              cell_records: bool = True) -> None:
        """Prepare ``slots`` zeroed result slots for a grid of ``cells`` (one number: a
        cube), and the per-cell records of a propagation step when ``cell_records``."""
        self._cells = grid_cells(cells)
        self._partials = min(-(-self._cell_count // 64), MAX_PARTIALS)
        self._slots = int(slots)
        self.generation += 1
        self.has_records = bool(cell_records)
        self._kept.clear()      # got again once a run: the cache's use order stays fresh
        # every slot is measured once before read(): no clearing needed
        self._buffer("partials", self._slots * self.partial_count * AUDIT_VALUES * 4)
        self._records_at = 0
        if cell_records:
            size = self._cell_count * AUDIT_VALUES * 4
            align = self._offset_alignment()
            self._record_stride = -(-size // align) * align
            self.record_regions = max(1, min(self._slots - 2,
                                             KEPT_RECORDS_BYTES // self._record_stride))
            if self._record_uniforms.get("u_record_stride") != self._record_stride // 4:
                self._record_uniforms = {"u_record_stride": self._record_stride // 4}
            self._buffer("cells", self._record_stride * (self.record_regions - 1) + size)
            self._buffer("cell_sums", size).clear(size=size)
        self._buffer("results", self._slots * AUDIT_VALUES * 4)

    def _offset_alignment(self) -> int:
        """``GL_SHADER_STORAGE_BUFFER_OFFSET_ALIGNMENT`` (asked once)."""
        if self._alignment is None:
            self._alignment = max(4, gl_integer(GL_SHADER_STORAGE_BUFFER_OFFSET_ALIGNMENT,
                                                256))
        return self._alignment

    def bind(self) -> None:
        """Bind the storage buffers: partials 2, results 3, per-cell records 4 and their
        sums 5 (when allocated)."""
        for name, binding in (("partials", 2), ("results", 3), ("cells", 4),
                              ("cell_sums", CELL_SUMS_BINDING)):
            if name in self._buffers:
                self._buffers[name].bind_to_storage_buffer(binding)

    def read_cell_sums(self, linear: int) -> np.ndarray:
        """(21,) float64: cell ``linear``'s record summed over the steps so far (one read
        of 84 bytes at its offset)."""
        self.ctx.memory_barrier()
        raw = self._buffers["cell_sums"].read(size=AUDIT_VALUES * 4,
                                              offset=int(linear) * AUDIT_VALUES * 4)
        return np.frombuffer(raw, np.float32).astype(np.float64)

    def read_cell_terms(self, linear: int) -> np.ndarray:
        """(21,) float64: cell ``linear``'s record of the last step (quantity-major: one
        read of 4 bytes per number)."""
        self.ctx.memory_barrier()
        cells, at = self._cell_count, self._records_at
        buffer = self._buffers["cells"]
        return np.array([np.frombuffer(buffer.read(size=4, offset=(at + i * cells
                                                                   + int(linear)) * 4),
                                       np.float32)[0]
                         for i in range(AUDIT_VALUES)], np.float64)

    def _stage_program(self, stage: int):
        """Stage ``stage``'s program: got from the cache once per :meth:`begin` and kept
        while the cache releases none (``ProgramCache.releases``), so that a propagation's
        steps, each reducing its records, do not look it up every step."""
        programs = self.programs
        if self._kept_releases != programs.releases:
            self._kept.clear()
            self._kept_releases = programs.releases
        program = self._kept.get(stage)
        if program is None:
            program = self._kept[stage] = programs.get(
                "audit_reduce.glsl", _STAGE_DEFINES[stage], _STAGE_KEYS[stage])
        return program

    def _run_partials(self, stage: int, slot: int, uniforms: dict[str, object],
                      bound: bool = False, rows: int = 1) -> None:
        last = slot + rows - 1
        if not 0 <= slot <= last < self._slots:
            raise IndexError(f"audit slot {last if slot >= 0 else slot} outside "
                             f"0..{self._slots - 1}")
        if not bound:
            self.bind()
        program = self._stage_program(stage)
        # the grid's uniforms change with the grid (the levels' reducers share the
        # program, which keeps what was set last), the slot with every measurement
        partials = self._partials
        grid = (self._cells, partials, uniforms)
        if program.extra.get("audit grid") != grid:
            set_uniforms(program, {**uniforms, "u_grid_cells": self._cells,
                                   "u_partial_count": partials})
            program.extra["audit grid"] = grid
        set_uniform(program, "u_result_slot", slot)
        program.run(-(-partials // 64), rows)
        self.ctx.memory_barrier()

    def slot_measurer(self, stage: int) -> Callable[[int], None]:
        """A function of a slot that does what :meth:`measure_flux` (``stage`` 0, with the
        grid already on sampler units 0..2; :data:`PING_FLUX`, on ping's units) or
        :meth:`sum_cell_records` (``stage`` 1) does
        with ``bound``, once one of them has run on this grid since the cache last released
        a program: the slot's upload (when it changed), the dispatch and its barrier, for a
        propagation's steps in a row (explorer/lpv/passes/propagate.py)."""
        uniforms = self._record_uniforms if stage == 1 else GRID_SAMPLERS
        program = self._stage_program(stage)
        info = program.extra
        uploaded = info.get("values", {})
        if info.get("audit grid") != (self._cells, self._partials, uniforms) or \
                "u_result_slot" not in uploaded:
            return lambda slot: self._run_partials(stage, slot, uniforms, bound=True)
        # set_uniform's bookkeeping, kept as it keeps it
        kept = info.setdefault("uniforms", {})
        uniform = kept.get("u_result_slot")
        if uniform is None:
            uniform = kept["u_result_slot"] = program["u_result_slot"]
        info["last values"] = None
        write, run, barrier = uniform.write, program.run, self.ctx.memory_barrier
        groups, slots = -(-self._partials // 64), self._slots
        packed = _packed_ints(uniform.fmt, slots)

        def measure(slot: int) -> None:
            if not 0 <= slot < slots:
                raise IndexError(f"audit slot {slot} outside 0..{slots - 1}")
            stamp = (int, slot)
            if uploaded["u_result_slot"] != stamp:
                write(packed[slot])
                uploaded["u_result_slot"] = stamp
            run(groups)
            barrier()

        return measure

    def measure_flux(self, slot: int, grid: LpvGrid, bound: bool = False) -> None:
        """Reduce the flux of ``grid`` into ``slot`` (sampler units 0..2 while it runs);
        ``bound``: :meth:`bind`'s buffers are still bound."""
        if grid.cells != self._cells:
            raise ValueError(f"audit prepared for {shape_text(self._cells)} cells, the grid "
                             f"has {shape_text(grid.cells)}")
        grid.use_as_textures(0)
        self._run_partials(0, slot, GRID_SAMPLERS, bound)

    def sum_cell_records(self, slot: int, bound: bool = False) -> None:
        """Reduce the per-cell records a propagation step wrote into ``slot``; ``bound``:
        :meth:`bind`'s buffers are still bound (the step's own dispatch bound them)."""
        self._run_partials(1, slot, self._record_uniforms, bound)
        self._records_at = 0

    def steps_recorder(self) -> StepsRecorder:
        """How a propagation's steps in a row keep their per-cell records for one
        reduction (:data:`KEPT_RECORDS_BYTES`), with :meth:`bind`'s buffers bound: before
        the k-th step of a group (k from 0, at most ``regions`` steps a group)
        ``bind(4, offset=offsets[k], size=size)`` binds where it writes its records (for k
        0 nothing: the buffer bound whole starts there), and after a group's last step
        ``reduce(first_slot, steps)`` reduces them into their slots (what
        :meth:`sum_cell_records` after each step does, the same sums in the same order)
        and binds the buffer whole again."""
        cells, stride = self._buffers["cells"], self._record_stride
        bind = cells.bind_to_storage_buffer

        def reduce(first_slot: int, steps: int) -> None:
            if steps > 1:
                bind(4)
            self._run_partials(1, first_slot, self._record_uniforms, bound=True, rows=steps)
            self._records_at = (steps - 1) * stride // 4

        return StepsRecorder(self.record_regions, bind,
                             range(0, self.record_regions * stride, stride),
                             self._cell_count * AUDIT_VALUES * 4, reduce)

    def read(self) -> np.ndarray:
        """(slots, 21) float64: flux, border loss, clamp gain, occluded, reflected, blocked,
        withheld by the budget (3 channels each) of every slot, folded from their partial sums."""
        self.fold()
        raw = self._buffers["results"].read(size=self._slots * AUDIT_VALUES * 4)
        return self.sums(np.frombuffer(raw, np.float32))

    def read_later(self, read: DeferredRead, bound: bool = False) -> None:
        """:meth:`read` without waiting: the sums folded and copied into ``read``
        (explorer/gl/gpu_sync.py); :meth:`sums` of its array gives what :meth:`read`
        does. ``bound``: :meth:`bind`'s buffers are still bound (a measurement just
        ran)."""
        self.fold(bound)
        read.issue(self._buffers["results"], (self._slots * AUDIT_VALUES,), "f4")

    def fold(self, bound: bool = False) -> None:
        """Fold the partial sums into one row per slot (on the GPU); ``bound``: as
        :meth:`read_later`'s."""
        if not bound:
            self.bind()
        program = self._stage_program(2)
        set_uniforms(program, {"u_partial_count": self.partial_count,
                               "u_slot_count": self._slots})
        program.run(-(-self._slots * AUDIT_VALUES // 64))
        self.ctx.memory_barrier()

    def sums(self, raw: np.ndarray) -> np.ndarray:
        """The ``(slots, 21)`` float64 of :meth:`read` from the folded float32 values."""
        return np.asarray(raw, np.float32)[:self._slots * AUDIT_VALUES].reshape(
            self._slots, AUDIT_VALUES).astype(np.float64)

    def release(self) -> None:
        for buffer in self._buffers.values():
            buffer.release()
        self._buffers.clear()
        self.has_records = False
        self._kept.clear()


class StepsRecorder(NamedTuple):
    """:meth:`AuditReducer.steps_recorder`'s parts (read into locals by the step loop)."""

    regions: int
    bind: Callable[..., None]
    offsets: Sequence[int]
    size: int
    reduce: Callable[[int, int], None]


_PACKED_INTS: dict[str, list[bytes]] = {}
"""A uniform's format -> the bytes of 0, 1, 2, ... in it (the audit's slots)."""


def _packed_ints(fmt: str, count: int) -> list[bytes]:
    """The bytes ``struct.pack(fmt, k)`` of k = 0 .. at least ``count - 1`` (made once)."""
    packed = _PACKED_INTS.setdefault(fmt, [])
    if len(packed) < count:
        packed.extend(struct.pack(fmt, k) for k in range(len(packed), max(count, 64)))
    return packed


class CellAuditRecords:
    """The per-cell audit records one propagation left on the GPU, read one cell at a
    time: the sums over all steps (one read of 84 bytes at the cell's offset) and the last
    step's record (21 reads of 4 bytes: that buffer is laid out per quantity for the
    reduction). Reads are cached per cell. The buffers belong to the propagation pass: a
    later propagation overwrites them, after which :meth:`read` returns None (the frame
    that showed them is out of date)."""

    def __init__(self, reducer: AuditReducer, cells: int | tuple[int, int, int],
                 steps: int) -> None:
        self._reducer = reducer
        self._generation = reducer.generation
        self.cells = grid_cells(cells)
        self.steps = int(steps)
        self._cache: dict[tuple[int, int, int], tuple[CellAudit, CellAudit | None]] = {}

    @property
    def current(self) -> bool:
        """Whether the records on the GPU are still this propagation's."""
        return self._reducer.generation == self._generation and self._reducer.has_records

    def read(self, cell) -> tuple[CellAudit, CellAudit | None] | None:
        """(the sums over all steps, the last step's record or None without steps) of
        cell (i, j, k); None when the records were overwritten or released. An IndexError
        names a cell outside the grid."""
        index = tuple(int(v) for v in cell)
        n = self.cells
        if len(index) != 3 or not all(0 <= v < m for v, m in zip(index, n)):
            raise IndexError(f"cell {index} is outside the {shape_text(n)} grid")
        if index in self._cache:
            return self._cache[index]
        if not self.current:
            return None
        linear = index[0] + n[0] * (index[1] + n[1] * index[2])
        sums = self._reducer.read_cell_sums(linear)
        last = self._reducer.read_cell_terms(linear) if self.steps else None
        record = (CellAudit.from_record(sums),
                  None if last is None else CellAudit.from_record(last))
        self._cache[index] = record
        return record
