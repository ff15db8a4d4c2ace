"""Propagation of the light grid (docs/MODEL.md "Propagation", "Iterations and
accumulation") with the energy audit measured on the GPU alongside every step.

:class:`PropagatePass` starts a :class:`PropagationRun` (a step in :func:`slabs`, grid_0's
copy into the accumulation a channel at a time for a large grid) or runs all steps at
once into a :class:`PropagationOutput`; :func:`grid_audit` reads the audit back;
:class:`BaselinePropagatePass` is the minimal kernel; :func:`propagate` and
:func:`propagate_with_audit` run numpy grids through the GPU."""

from __future__ import annotations

import time
from dataclasses import dataclass

import moderngl
import numpy as np

from explorer.gl.gpu_sync import GL_MAX_IMAGE_UNITS, DeferredRead, gl_integer
from explorer.gl.program import ProgramCache, set_uniforms
from explorer.lpv.audit import GridAudit, audit_mode
from explorer.lpv.corrections import uniforms_read_by
from explorer.lpv.grid import GridSpec, grid_cells, shape_text
from explorer.lpv.kept_steps import KeptSteps
from explorer.lpv.neighbours import check_flux_budget, check_neighbours
from explorer.lpv.passes.audit_reduce import (
    PING_FLUX,
    PING_GRID_UNIT,
    AuditReducer,
    CellAuditRecords,
)
from explorer.lpv.passes.geometry import GeometryVolume
from explorer.lpv.passes.textures import (
    LpvGrid,
    check_volume_array,
    copied_apart,
    copy_volume,
    copy_volumes,
    default_context,
    dispatch_size,
    image_format_defines,
    per_context,
    programs_for,
    sh_defines,
    sh_order_of,
)
from explorer.lpv.settings import GEOMETRY_VISIBILITY_MODES, REPROJECTION_MODES, Corrections


@dataclass
class PropagationOutput:
    accumulated: LpvGrid
    """acc_N = Σ grid_t. Owned by the pass: valid until its next run or release."""
    steps: KeptSteps | None
    """grid_0..grid_N as (3, N, N, N, 4) arrays when keep_steps (each kept as its box of
    cells that hold light: explorer/lpv/kept_steps.py). In place, grid_t is the light step
    t added (acc_t − acc_{t−1}), so Σ grid_t = acc_N in both modes."""
    audit: GridAudit
    cell_records: CellAuditRecords | None = None
    """Each cell's audit record (its sum over the steps, the last step's), read one cell
    at a time from the GPU; None without the audit."""


def copy_grid(programs: ProgramCache, source: LpvGrid, target: LpvGrid) -> None:
    for source_volume, target_volume in zip(source.volumes, target.volumes):
        copy_volume(programs, source_volume.texture, target_volume)


SPARE_GRID_BYTES = 8 << 20
"""Ping and pong grids from this size up are released when the window falls idle
(:meth:`PropagatePass.release_between_runs`): a 64³ L1 grid is 12 MiB (L2 27 MiB), and a
64³ frame with two cascades and a second side kept 12 of them (two thirds of 180 MiB)
between runs; making one again costs 7 ms (L1) to 19 ms (L2) at 64³ on llvmpipe, a
48³ L1 grid (5 MiB) stays."""


class PropagatePass:
    """Propagates an injected grid ``iterations`` times (``shaders/propagate.glsl``),
    ping-pong or in place (``corrections.ping_pong``; in place is the DX11 shader's data race,
    kept on purpose), measuring what the audit mode asks (:data:`explorer.lpv.audit.AUDIT_MODES`;
    True ``full``, False ``off``; :func:`grid_audit` reads each mode back).

    :meth:`start` returns a :class:`PropagationRun` that advances one step at a time;
    :meth:`run` does all steps at once. GPU memory besides the input: three grids (ping,
    pong, accumulation) in its format and, with the full audit, 168 bytes per cell of audit
    records (≈350 MB at 128³).
    """

    GEOMETRY_UNIT = 6
    ALBEDO_UNIT = 7
    BUDGET_BINDING = 6
    """Storage block of the flux budget's factors (``shaders/propagate.glsl``)."""
    STAGE = "propagate"
    """Its program reads this stage's correction switches."""

    def __init__(self, ctx: moderngl.Context, programs: ProgramCache) -> None:
        self.ctx = ctx
        self.programs = programs
        self.audit = AuditReducer(ctx, programs)
        self._grids: dict[str, LpvGrid] = {}
        self._run_uniforms: dict[tuple[GridSpec, Corrections], dict[str, object]] = {}
        self._programs_of: dict[tuple, tuple[dict[str, object], tuple, tuple[str, ...]]] = {}
        self._budget: moderngl.Buffer | None = None
        self._image_units: int | None = None

    def image_units(self) -> int:
        """The context's ``GL_MAX_IMAGE_UNITS`` (asked once): a run puts ping and pong on
        units of their own (:data:`EVEN_STEP_UNITS`) only where there are enough."""
        if self._image_units is None:
            self._image_units = gl_integer(GL_MAX_IMAGE_UNITS, 8)
        return self._image_units

    def budget_buffer(self, cells: tuple[int, int, int]) -> moderngl.Buffer:
        """The flux budget's factors (one vec4 per cell), kept between runs."""
        size = 16 * int(np.prod(cells))
        if self._budget is None or self._budget.size != size:
            if self._budget is not None:
                self._budget.release()
            self._budget = self.ctx.buffer(reserve=size)
        return self._budget

    def run_uniforms(self, spec: GridSpec, corrections: Corrections) -> dict[str, object]:
        """A run's uniforms (the grid, the switches, the units), the same dict for the same
        grid and switches (never changed once made): a frame's run then sets them again
        without stamping them (``set_uniforms`` skips the dict of its last call)."""
        key = (spec, corrections)
        made = self._run_uniforms.get(key)
        if made is None:
            if len(self._run_uniforms) >= 16:
                self._run_uniforms.clear()
            made = self._run_uniforms[key] = {
                **spec.uniforms(), **corrections.as_uniforms(),
                "u_geometry": self.GEOMETRY_UNIT, "u_geometry_albedo": self.ALBEDO_UNIT,
                "u_cell_offset": (0, 0, 0)}
        return made

    def program_of(self, fmt: str, sh_order: int, corrections: Corrections, audit: bool,
                   geometry: bool, reflect: bool, neighbours: int, visibility: str,
                   flux_budget: bool, reprojection: str
                   ) -> tuple[dict[str, object], tuple, tuple[str, ...]]:
        """A run's program: its defines (:func:`program_defines`), its cache key and the
        uniforms it must read (:func:`uniforms_read_at_run_time`), made once per variant
        (a frame's run would otherwise build and sort them anew); never changed once
        made."""
        variant = (fmt, sh_order, corrections, audit, geometry, reflect, neighbours,
                   visibility, flux_budget, reprojection)
        made = self._programs_of.get(variant)
        if made is None:
            if len(self._programs_of) >= 16:
                self._programs_of.clear()
            defines = program_defines(
                fmt, sh_order, corrections, audit=audit, geometry=geometry, reflect=reflect,
                neighbours=neighbours, visibility=visibility, flux_budget=flux_budget,
                reprojection=reprojection)
            made = self._programs_of[variant] = (
                defines, self.programs.key("propagate.glsl", defines),
                uniforms_read_at_run_time(neighbours, flux_budget))
        return made

    def scratch_grid(self, name: str, cells: int | tuple[int, int, int], fmt: str,
                     sh_order: int) -> LpvGrid:
        """The pass's own grid ``name`` (accumulation, ping, pong) of these cells, format
        and order, kept between runs and made anew when any of them changes."""
        cells = grid_cells(cells)
        grid = self._grids.get(name)
        if grid is None or grid.cells != cells or grid.format != fmt or \
                grid.sh_order != sh_order:
            if grid is not None:
                grid.release()
            grid = self._grids[name] = LpvGrid(self.ctx, cells, fmt, sh_order)
        return grid

    def start(self, injected: LpvGrid, spec: GridSpec, corrections: Corrections,
              iterations: int, geometry: GeometryVolume | None = None,
              keep_steps: bool = False, bounces: int = 1, audit: str | bool = "full",
              neighbours: int = 6, visibility: str = "linear",
              flux_budget: bool = False, reprojection: str = "face-normal"
              ) -> PropagationRun:
        """Copy grid_0 into the accumulation and prepare ``iterations`` steps; nothing is
        propagated yet. ``bounces`` 2: the geometry volume reflects the light it blocks
        (``shaders/reflection.glsl``, docs/MODEL.md "More bounces"); needs ``geometry``.
        The injected grid's ``sh_order`` selects L1 or L2 propagation; ``neighbours`` 26
        propagates to all 26 neighbours (docs/MODEL.md "26 neighbours"); ``visibility``
        how the geometry volume's blocking becomes visibility, ``flux_budget`` whether no
        cell sends more than it holds (docs/MODEL.md "Geometry volume", "Flux budget"),
        ``reprojection`` the axis of each face's reprojected lobe (docs/MODEL.md
        "Propagation")."""
        n = spec.cells
        check_neighbours(neighbours, corrections, bounces)
        check_flux_budget(flux_budget, corrections, bounces)
        if visibility not in GEOMETRY_VISIBILITY_MODES:
            raise ValueError(f"visibility must be one of "
                             f"{', '.join(GEOMETRY_VISIBILITY_MODES)}, got {visibility!r}")
        if reprojection not in REPROJECTION_MODES:
            raise ValueError(f"reprojection must be one of {', '.join(REPROJECTION_MODES)}, "
                             f"got {reprojection!r}")
        if bounces not in (1, 2) or isinstance(bounces, bool):
            raise ValueError(f"bounces must be 1 or 2, got {bounces!r}")
        if bounces == 2 and geometry is None:
            raise ValueError("bounces=2 reflects the light the geometry volume blocks: pass "
                             "a geometry volume")
        if injected.cells != n:
            raise ValueError(f"the injected grid has {shape_text(injected.cells)} cells but "
                             f"the grid spec has {shape_text(n)}")
        if geometry is not None and geometry.cells != n:
            raise ValueError(f"the geometry volume belongs to a {shape_text(geometry.cells)} "
                             f"grid, the light grid has {shape_text(n)} cells")
        if int(iterations) != iterations or iterations < 0:
            raise ValueError(f"iterations must be a whole number >= 0, got {iterations!r}")
        return PropagationRun(self, injected, spec, corrections, int(iterations), geometry,
                              keep_steps, bounces, audit_mode(audit), int(neighbours),
                              visibility, bool(flux_budget), reprojection)

    def run(self, injected: LpvGrid, spec: GridSpec, corrections: Corrections,
            iterations: int, geometry: GeometryVolume | None = None,
            keep_steps: bool = False, bounces: int = 1, audit: str | bool = "full",
            neighbours: int = 6, visibility: str = "linear",
            flux_budget: bool = False, reprojection: str = "face-normal"
            ) -> PropagationOutput:
        """All ``iterations`` steps at once (see :meth:`start`)."""
        progress = self.start(injected, spec, corrections, iterations, geometry, keep_steps,
                              bounces, audit, neighbours, visibility, flux_budget,
                              reprojection)
        while not progress.finished:
            progress.step()
        return progress.finish()

    def release_between_runs(self, min_bytes: int | None = None) -> int:
        """Release the ping and pong grids (only a run in progress uses them: the
        accumulation holds the result) of :data:`SPARE_GRID_BYTES` or more each; the next
        :meth:`start` makes them anew. Call only while no run of this pass is in progress.
        Returns the bytes released."""
        least = SPARE_GRID_BYTES if min_bytes is None else min_bytes
        released = 0
        for name in ("ping", "pong"):
            grid = self._grids.get(name)
            if grid is not None and grid.nbytes >= least:
                released += grid.nbytes
                grid.release()
                del self._grids[name]
        return released

    def release(self) -> None:
        for grid in self._grids.values():
            grid.release()
        self._grids.clear()
        self.audit.release()
        if self._budget is not None:
            self._budget.release()
            self._budget = None


PING_TEXTURE_UNIT, PONG_IMAGE_UNIT = PING_GRID_UNIT, 6
"""Where a run's steps in a row (:meth:`PropagationRun.advance_for`) keep ping-pong's
grids: ping's images on units 0..2 (the odd steps' target) and its textures on sampler
units 8..10 (the even steps' source), pong's images on units 6..8 (the even steps'
target) and its textures on units 0..2 (the odd steps' source, after grid_0 there): the
odd steps run the run's program, the even ones its second program of the same variant
with :data:`EVEN_STEP_UNITS`, and no step binds anything anew (but step 3, pong in
grid_0's place; with the flux audit, which reads the step's target on sampler units
0..2 or ping's (``audit_reduce.PING_FLUX``), step 2, pong in grid_0's place). Sampler
units 6 and 7 hold the geometry volume, image units 3..5 the accumulation."""
EVEN_STEP_UNITS = {
    "PROPAGATE_SOURCE_R": PING_TEXTURE_UNIT, "PROPAGATE_SOURCE_G": PING_TEXTURE_UNIT + 1,
    "PROPAGATE_SOURCE_B": PING_TEXTURE_UNIT + 2, "PROPAGATE_TARGET_R": PONG_IMAGE_UNIT,
    "PROPAGATE_TARGET_G": PONG_IMAGE_UNIT + 1, "PROPAGATE_TARGET_B": PONG_IMAGE_UNIT + 2}
"""The even steps' program's defines besides the run's (``shaders/propagate.glsl``)."""
LAYOUT_IMAGE_UNITS = PONG_IMAGE_UNIT + 3
"""Image units the layout needs (GL 4.3 promises 8; llvmpipe has 192): with fewer, every
step binds its source and target as a single program needs."""


COMPILED_SWITCHES = {"u_ping_pong": "PROPAGATE_PING_PONG"}
"""Correction switches the propagation reads when its program is compiled (a define chosen
from the switch) instead of as a uniform: they choose a code path, and llvmpipe runs both
sides of a branch on a uniform (``shaders/propagate.glsl``)."""


NOT_READ_OVER_26 = ("u_side_faces", "u_model_face_weights")
"""Switches the 26-neighbour step has no form for: they must be on
(:func:`explorer.lpv.neighbours.check_neighbours`), and its program does not read them."""


NOT_READ_UNDER_BUDGET = ("u_clamp_front_face",)
"""Under the flux budget every face is clamp+ (docs/MODEL.md "Flux budget")."""


def uniforms_read_at_run_time(neighbours: int = 6, flux_budget: bool = False
                              ) -> tuple[str, ...]:
    """The propagation's correction uniforms (``uniforms_read_by``) less
    :data:`COMPILED_SWITCHES`, which its program reads as defines, with ``neighbours``
    26 less :data:`NOT_READ_OVER_26` and with ``flux_budget`` less
    :data:`NOT_READ_UNDER_BUDGET`."""
    skipped = (set(COMPILED_SWITCHES) | (set(NOT_READ_OVER_26) if neighbours == 26 else set())
               | (set(NOT_READ_UNDER_BUDGET) if flux_budget else set()))
    return tuple(name for name in uniforms_read_by(PropagatePass.STAGE)
                 if name not in skipped)


def program_defines(fmt: str, sh_order: int, corrections: Corrections, audit: bool = False,
                    geometry: bool = False, reflect: bool = False, neighbours: int = 6,
                    visibility: str = "linear", flux_budget: bool = False,
                    reprojection: str = "face-normal") -> dict[str, object]:
    """The defines ``shaders/propagate.glsl`` is compiled with: the grid format and SH order,
    the full audit, the switches of :data:`COMPILED_SWITCHES`, whether a geometry volume
    occludes, whether it reflects (bounces 2, which needs it), over how many neighbours
    light moves (6 or 26), the volume's visibility (index in
    :data:`GEOMETRY_VISIBILITY_MODES`), whether the flux budget limits each cell and the
    reprojection's axis (index in :data:`REPROJECTION_MODES`)."""
    switches = corrections.as_uniforms()
    return {**image_format_defines(fmt), **sh_defines(sh_order),
            "PROPAGATE_AUDIT": int(audit),
            **{define: int(switches[uniform]) for uniform, define in COMPILED_SWITCHES.items()},
            "PROPAGATE_GEOMETRY": int(geometry), "PROPAGATE_REFLECT": int(reflect and geometry),
            "PROPAGATE_NEIGHBOURS": int(neighbours),
            "PROPAGATE_VISIBILITY": GEOMETRY_VISIBILITY_MODES.index(visibility),
            "PROPAGATE_FLUX_BUDGET": int(flux_budget),
            "PROPAGATE_REPROJECTION": REPROJECTION_MODES.index(reprojection)}


_NOTHING_BOUND: frozenset[str] = frozenset()
_RUN, _RUN_AUDIT = frozenset({"run"}), frozenset({"run", "audit"})
_SOURCE, _AUDIT_SOURCE = frozenset({"source"}), frozenset({"audit", "source"})
"""What :attr:`PropagationRun._bound` holds, made once (a step makes no set)."""

SLAB_CELLS = 32 ** 3
"""Cells one unit of a propagation step covers at most (a slab of z layers, a multiple of
the 4-layer workgroup): a 64³ step is 8 units, each a few frames' budget on llvmpipe."""


def slabs(cells: int | tuple[int, int, int], slab_cells: int | None = None
          ) -> list[tuple[int, int]]:
    """z ranges ``(first, end)`` of the slabs one step of a grid of ``cells`` (one number:
    a cube) is dispatched in: ``slab_cells`` (default :data:`SLAB_CELLS`) / (nx·ny) layers
    each, rounded down to a multiple of 4 (the workgroup's depth, so no cell is in two
    slabs), at least 4."""
    nx, ny, nz = grid_cells(cells)
    slab_cells = SLAB_CELLS if slab_cells is None else int(slab_cells)
    depth = max(4, slab_cells // (nx * ny) // 4 * 4)
    return [(z, min(z + depth, nz)) for z in range(0, nz, depth)]


def kernel_slab_cells(ping_pong: bool, bounces: int, neighbours: int, sh_order: int) -> int:
    """Cells a slab of this kernel covers at most: :data:`SLAB_CELLS`, halved for a kernel
    that costs 2–4× the one-bounce, 6-neighbour L1 one (64³ on llvmpipe, a slab's CPU ms:
    6 that one, 23 with two bounces, 18 with 26 neighbours, 26 at L2), so its slabs fit a
    frame's share too. In place (no ping-pong) the slabs stay as they are: there a slab
    reads what the step wrote before it, and another split would change the race's
    outcome; with ping-pong the slabs are independent and any split gives the same grid."""
    heavy = bounces == 2 or neighbours == 26 or sh_order == 2
    return SLAB_CELLS // 2 if ping_pong and heavy else SLAB_CELLS


class PropagationRun:
    """One propagation in progress (made by :meth:`PropagatePass.start`): :meth:`advance`
    dispatches one slab of the current step (:func:`slabs`; a step's slabs are
    independent in ping-pong, since they read grid t−1 and write their own cells),
    :meth:`step` a whole step, :meth:`finish` measures the audit and returns the
    :class:`PropagationOutput`. Between steps :attr:`accumulated` holds
    acc_t = Σ_{t'≤t} grid_t' (the light gathered so far, for a progressive picture)."""

    def __init__(self, owner: PropagatePass, injected: LpvGrid, spec: GridSpec,
                 corrections: Corrections, iterations: int, geometry: GeometryVolume | None,
                 keep_steps: bool, bounces: int, audit: str, neighbours: int = 6,
                 visibility: str = "linear", flux_budget: bool = False,
                 reprojection: str = "face-normal") -> None:
        n, fmt, order = spec.cells, injected.format, injected.sh_order
        self._owner = owner
        self._corrections = corrections
        self._geometry = geometry
        self._keep_steps = keep_steps
        self._mode = audit
        self._with_audit = audit == "full"
        self.iterations = iterations
        self.done = 0
        self._accumulated = owner.scratch_grid("accumulated", n, fmt, order)
        self._scratch = {name: owner.scratch_grid(name, n, fmt, order) if corrections.ping_pong
                         else None for name in ("ping", "pong")}
        self._copies = list(zip(injected.volumes, self._accumulated.volumes))
        """grid_0's channels still to copy into the accumulation (:meth:`copy_next`): all
        of them copied here unless they are copied apart (:func:`copied_apart`)."""
        if not copied_apart(self._accumulated.volumes[0].shape):
            self._copy_rest()
        # slots: 0 the injected flux, 1..N the steps (full or flux audit), last the
        # accumulation
        self._slots = iterations + 2 if audit != "off" else 2
        owner.audit.begin(n, self._slots, cell_records=self._with_audit)
        owner.audit.measure_flux(0, injected)
        self._previous = injected.read() if keep_steps else None
        self.steps = KeptSteps([self._previous]) if keep_steps else None
        self._source = injected
        self._defines, self._key, self._reads = owner.program_of(
            fmt, order, corrections, self._with_audit, geometry is not None, bounces == 2,
            neighbours, visibility, flux_budget, reprojection)
        self._budget = owner.budget_buffer(n) if flux_budget else None
        self._uniforms = owner.run_uniforms(spec, corrections)
        self._program = None
        self._program_releases = -1
        self._budget_program: tuple[dict[str, object], tuple] | None = None
        self._even_variant: tuple[dict[str, object], tuple] | None = None
        self._even = None
        self._program_now()
        # step t writes ping (t odd) or pong (t even); in place, the accumulation
        self._targets = ((self._scratch["pong"], self._scratch["ping"]) if corrections.ping_pong
                         else (self.accumulated, self.accumulated))
        self._groups = dispatch_size(n)
        self._slabs = slabs(n, kernel_slab_cells(corrections.ping_pong, bounces, neighbours,
                                                 order))
        self._slab = 0
        if self.iterations >= 2 and self._in_a_row() and self._on_own_units():
            # the even steps' program is got with the run's, not when a unit first has
            # time left for a second step: which programs a run makes does not depend on
            # the machine's speed (the soak's GL counts, issue #31; linking is cheap,
            # llvmpipe compiles a program's code at its first dispatch)
            self._even_program()
        self._bound: frozenset[str] = _NOTHING_BOUND
        """What the last :meth:`advance` left bound that the next may keep (``bound``):
        ``run`` the accumulation images and the geometry volume, ``audit`` the audit's
        buffers, ``source`` the next step's source on sampler units 0..2."""

    @property
    def copies_left(self) -> int:
        """Channels of grid_0 not yet copied into the accumulation (a large grid's:
        :func:`copied_apart`): :meth:`copy_next` does one (a unit of its own in a
        time-sliced frame: 8 ms at 64³ on llvmpipe); whatever reads or writes the
        accumulation first does the rest."""
        return len(self._copies)

    def copy_next(self) -> None:
        """Copy the next channel of grid_0 into the accumulation."""
        source, target = self._copies.pop(0)
        copy_volume(self._owner.programs, source.texture, target)

    def _copy_rest(self) -> bool:
        """Copy the channels left (:meth:`copy_next`); False when there were some."""
        if not self._copies:
            return True
        copies, self._copies = self._copies, []
        copy_volumes(self._owner.programs, [source.texture for source, _ in copies],
                     [target for _, target in copies])
        return False

    @property
    def accumulated(self) -> LpvGrid:
        """acc_t, the light gathered so far (grid_0's copies done first)."""
        self._copy_rest()
        return self._accumulated

    def _program_now(self):
        """The run's program, got from the cache for each slab: a run spans frames, and
        the cache may have released the program it had (``ProgramCache.capacity``), or a
        hot reload replaced it; a new one gets the run's uniforms first."""
        programs = self._owner.programs
        program = programs.get("propagate.glsl", self._defines, self._key)
        self._program_releases = programs.releases
        if program is not self._program:
            set_uniforms(program, self._uniforms, reads=self._reads)
            program.extra["cell_offset"] = 0
            self._program = program
        return program

    def _even_program(self):
        """The run's second program (:data:`EVEN_STEP_UNITS`), got from the cache once per
        unit; a new one gets the run's uniforms first."""
        if self._even_variant is None:
            defines = {**self._defines, **EVEN_STEP_UNITS}
            self._even_variant = (defines, ProgramCache.key("propagate.glsl", defines))
        program = self._owner.programs.get("propagate.glsl", *self._even_variant)
        if program is not self._even:
            set_uniforms(program, self._uniforms, reads=self._reads)
            self._even = program
        return program

    def _run_budget_pass(self) -> None:
        """The flux budget's factors of the step's source grid (bound on units 0..2), for
        every cell, before the step's first slab reads them."""
        if self._budget_program is None:
            defines = {**self._defines, "PROPAGATE_BUDGET_PASS": 1, "PROPAGATE_AUDIT": 0}
            self._budget_program = (defines, ProgramCache.key("propagate.glsl", defines))
        program = self._owner.programs.get("propagate.glsl", *self._budget_program)
        # the run's uniforms hold u_cell_offset (0, 0, 0): the budget pass covers the grid
        set_uniforms(program, self._uniforms)
        program.extra["cell_offset"] = 0
        program.run(*self._groups)
        self._owner.ctx.memory_barrier()

    @property
    def finished(self) -> bool:
        """True when every step has run (:meth:`finish` may be called)."""
        return self.done >= self.iterations

    @property
    def units_per_step(self) -> int:
        """Slabs (calls of :meth:`advance`) per step."""
        return len(self._slabs)

    @property
    def fraction(self) -> float:
        """How far along the propagation is, 0..1 (slabs included)."""
        if not self.iterations:
            return 1.0
        return (self.done + self._slab / len(self._slabs)) / self.iterations

    def step(self) -> None:
        """Propagate one more step (docs/MODEL.md "Iterations and accumulation")."""
        target = self.done + 1
        while self.done < target:
            self.advance()

    def advance_for(self, limit_ms: float, start: float) -> None:
        """Slabs in a row until ``limit_ms`` milliseconds since ``start`` (a
        ``time.perf_counter()``) are spent, at least one, or every step has run: the first
        by :meth:`advance`, the rest keeping its bindings (``bound``). Steps of one slab
        each with nothing to do between them but the audit's measurement (no flux budget,
        no kept grid: a small grid's, every frame) go through :meth:`_steps_in_a_row`,
        the same GL calls with less Python around them."""
        clock, deadline = time.perf_counter, start + limit_ms / 1e3
        self.advance()
        if self.finished or clock() >= deadline:
            return
        if self._in_a_row():
            self._steps_in_a_row(clock, deadline)
            return
        while not self.finished:
            self.advance(bound=True)
            if clock() >= deadline:
                return

    def _in_a_row(self) -> bool:
        """Whether :meth:`advance_for` runs this run's steps through
        :meth:`_steps_in_a_row` (one-slab steps, no flux budget, no kept grid)."""
        return len(self._slabs) == 1 and self._budget is None and not self._keep_steps

    def _on_own_units(self) -> bool:
        """Whether steps in a row keep ping and pong on units of their own
        (:data:`PING_TEXTURE_UNIT`): ping-pong on a context with
        :data:`LAYOUT_IMAGE_UNITS`."""
        return (self._corrections.ping_pong
                and self._owner.image_units() >= LAYOUT_IMAGE_UNITS)

    def _steps_in_a_row(self, clock, deadline: float) -> None:
        """:meth:`advance` with ``bound`` of one-slab steps until ``clock()`` reaches
        ``deadline`` or every step has run, after an :meth:`advance` of this run (which got
        the program, set its offset and bound what every step keeps). Ping-pong on a
        context with :data:`LAYOUT_IMAGE_UNITS`: ping and pong on units of their own
        (:data:`PING_TEXTURE_UNIT`), each step the dispatch of its parity's program and its
        barrier; otherwise (in place, or fewer image units) each step binds its source on
        sampler units 0..2 (the flux audit's reduction left it there) and its target's
        images.
        The full audit's steps write their per-cell records each to a region of its own
        (``AuditReducer.steps_recorder``), reduced in one dispatch for the unit's steps
        (or as many as the buffer holds); the flux audit reduces each step's grid."""
        owner, mode = self._owner, self._mode
        first, end = self._slabs[0]
        groups = (self._groups[0], self._groups[1], -(-(end - first) // 4))
        # the full audit's steps keep their records, reduced a group at a time
        recorder = owner.audit.steps_recorder() if mode == "full" else None
        # ping and pong on units of their own (PING_TEXTURE_UNIT); in place one grid
        own_units = self._on_own_units()
        if not (self._steps_on_own_units if own_units else self._steps_binding)(
                clock, deadline, groups, recorder):
            while not self.finished:            # the cache released programs: as usual
                self.advance(bound=True)
                if clock() >= deadline:
                    return
            return
        self._bound = _RUN_AUDIT if mode != "off" else _RUN
        if mode == "flux" and not own_units:
            self._bound |= _SOURCE          # the last target, the next source, on 0..2

    def _steps_on_own_units(self, clock, deadline: float, groups: tuple[int, int, int],
                            recorder) -> bool:
        """:meth:`_steps_in_a_row` with ping and pong on units of their own; False (and
        nothing done) when getting its programs made the cache release any (a cache too
        small for a unit's programs: the caller steps as :meth:`advance` does)."""
        owner = self._owner
        releases = self._program_releases       # the run's program was got at it
        flux = self._mode == "flux"
        if flux:        # pong's flux read on units 0..2, ping's on its own
            measure_pong = owner.audit.slot_measurer(0)
            measure_ping = owner.audit.slot_measurer(PING_FLUX)
        even = self._even_program()
        if owner.programs.releases != releases:
            return False
        run, run_even, barrier = self._program.run, even.run, owner.ctx.memory_barrier
        ping, pong = self._scratch["ping"], self._scratch["pong"]
        ping.bind_images(0)
        pong.bind_images(PONG_IMAGE_UNIT)
        ping.use_as_textures(PING_TEXTURE_UNIT)
        on_zero = None                              # the grid on sampler units 0..2
        regions, bind_records, offsets, size, reduce_records = \
            recorder or (0, None, (), 0, None)
        group, first_slot = 0, self.done + 1
        done, iterations, source, targets = self.done, self.iterations, self._source, \
            self._targets
        while True:
            done += 1
            if recorder is not None:
                if group == regions:
                    reduce_records(first_slot, group)
                    group, first_slot = 0, done
                if group:
                    bind_records(4, offset=offsets[group], size=size)
                group += 1
            if done % 2 == 0:
                run_even(*groups)
                barrier()
                if flux:
                    if on_zero is not pong:
                        pong.use_as_textures(0)
                        on_zero = pong
                    measure_pong(done)
            else:
                if on_zero is not source:
                    source.use_as_textures(0)
                    on_zero = source
                run(*groups)
                barrier()
                if flux:
                    measure_ping(done)
            source = targets[done % 2]
            if done >= iterations or clock() >= deadline:
                break
        if recorder is not None:
            reduce_records(first_slot, group)
        self._source, self.done = source, done
        return True

    def _steps_binding(self, clock, deadline: float, groups: tuple[int, int, int],
                       recorder) -> bool:
        """:meth:`_steps_in_a_row` binding each step's source and target (one program);
        False, as :meth:`_steps_on_own_units`."""
        owner, mode = self._owner, self._mode
        measure = owner.audit.slot_measurer(0) if mode == "flux" else None
        if owner.programs.releases != self._program_releases:
            return False
        run, barrier = self._program.run, owner.ctx.memory_barrier
        regions, bind_records, offsets, size, reduce_records = \
            recorder or (0, None, (), 0, None)
        group, first_slot = 0, self.done + 1
        done, iterations, source, targets = self.done, self.iterations, self._source, \
            self._targets
        while True:
            done += 1
            if recorder is not None:
                if group == regions:
                    reduce_records(first_slot, group)
                    group, first_slot = 0, done
                if group:
                    bind_records(4, offset=offsets[group], size=size)
                group += 1
            target = targets[done % 2]
            if measure is None:         # the flux reduction left the source on 0..2
                r, g, b = source.textures
                r.use(0)
                g.use(1)
                b.use(2)
            r, g, b = target.textures
            r.bind_to_image(0)
            g.bind_to_image(1)
            b.bind_to_image(2)
            run(*groups)
            barrier()
            if measure is not None:
                r.use(0)
                g.use(1)
                b.use(2)
                measure(done)
            source = target
            if done >= iterations or clock() >= deadline:
                break
        if recorder is not None:
            reduce_records(first_slot, group)
        self._source, self.done = source, done
        return True

    def advance(self, bound: bool = False) -> None:
        """Dispatch the next slab of the current step; after the step's last slab, its
        audit, its kept grid and the swap of the grids. ``bound``: the last GL work was
        this run's previous :meth:`advance` (a unit of several slabs), so the accumulation
        images, the geometry volume and the audit's buffers are still bound."""
        if self.finished:
            raise RuntimeError(f"all {self.iterations} propagation steps have run")
        # grid_0's copies left before any binding (they use units 0): then nothing is bound
        bound = self._copy_rest() and bound
        owner, step = self._owner, self.done + 1
        # in place, the race: the dispatch reads its neighbours from the grid it writes
        target = self._targets[step % 2]
        kept = self._bound if bound else _NOTHING_BOUND
        if "source" not in kept:
            self._source.use_as_textures(0)
        if self._budget is not None:
            self._budget.bind_to_storage_buffer(owner.BUDGET_BINDING)
            if self._slab == 0:
                self._run_budget_pass()
        target.bind_images(0)
        if "run" not in kept:
            if self._geometry is not None:
                self._geometry.use_as_texture(owner.GEOMETRY_UNIT)
                self._geometry.albedo.texture.use(owner.ALBEDO_UNIT)
            self.accumulated.bind_images(3)
        if self._with_audit and "audit" not in kept:
            owner.audit.bind()          # only the full audit's kernel writes the records
        self._bound = _RUN_AUDIT if self._with_audit or "audit" in kept else _RUN
        first, end = self._slabs[self._slab]
        # one slab a step up to 32³: set once. The offset last set is kept with the
        # program, which the cascades' runs share (interleaved, each with its slabs).
        # Within a unit (``bound``) the program the last slab got is still the cache's
        # while the cache has released none: got again at each unit's start only.
        if bound and self._program_releases == owner.programs.releases:
            program = self._program
        else:
            program = self._program_now()
        if program.extra.get("cell_offset") != first:
            set_uniforms(program, {"u_cell_offset": (0, 0, first)})
            program.extra["cell_offset"] = first
        program.run(self._groups[0], self._groups[1], -(-(end - first) // 4))
        owner.ctx.memory_barrier()
        self._slab += 1
        if self._slab < len(self._slabs):
            self._bound |= _SOURCE          # the step's next slab reads the same grid
            return
        self._slab = 0
        if self._with_audit:
            owner.audit.sum_cell_records(step, bound=True)   # the kernel's buffers
        elif self._mode == "flux":
            # in place the step's grid is not kept apart: the slot holds acc_t and
            # grid_audit takes the differences (the flux is linear in the grid); the
            # reduction leaves the audit's buffers bound and the target, the next step's
            # source, on sampler units 0..2
            owner.audit.measure_flux(step, target, bound="audit" in self._bound)
            self._bound |= _AUDIT_SOURCE
        if self._keep_steps:
            current = target.read()
            self.steps.append(current if self._corrections.ping_pong
                              else current - self._previous)
            self._previous = current
        self._source = target
        self.done = step

    def finish(self) -> PropagationOutput:
        """The accumulation, the kept steps and the audit (after the last step)."""
        audit = self._measure_last()
        return self._output(audit.read())

    def finish_later(self, read: DeferredRead) -> None:
        """:meth:`finish` without waiting: the audit's sums are copied into ``read``
        (explorer/gl/gpu_sync.py), and :meth:`output` of it then gives what :meth:`finish`
        does."""
        # the last measurement bound the audit's buffers just before
        self._measure_last().read_later(read, bound=True)

    def output(self, read: DeferredRead) -> PropagationOutput:
        """:meth:`finish`'s output from :meth:`finish_later`'s copy (waiting only if the
        copy is not done yet)."""
        return self._output(self._owner.audit.sums(read.wait()))

    def _measure_last(self):
        if not self.finished:
            raise RuntimeError(f"propagation stopped after {self.done} of "
                               f"{self.iterations} steps")
        audit = self._owner.audit
        audit.measure_flux(self._slots - 1, self.accumulated)
        return audit

    def _output(self, sums: np.ndarray) -> PropagationOutput:
        audit = self._owner.audit
        records = (CellAuditRecords(audit, self.accumulated.cells, self.iterations)
                   if self._with_audit else None)
        return PropagationOutput(accumulated=self.accumulated, steps=self.steps,
                                 audit=grid_audit(sums, self.iterations, self._mode,
                                                  self._corrections.ping_pong),
                                 cell_records=records)



def grid_audit(sums: np.ndarray, iterations: int, mode: str = "full",
               ping_pong: bool = True) -> GridAudit:
    """The :class:`GridAudit` of the reduced slots ``sums`` (slot 0 the injected flux, the
    last the accumulation, the steps between in modes ``full`` and ``flux``; in mode
    ``off`` the per-step flux after step 0 is NaN). Mode ``flux`` without ``ping_pong``:
    the step slots hold acc_t, whose differences are the steps' flux. The terms a mode
    does not measure are None."""
    mode = audit_mode(mode)
    if mode == "full":
        return GridAudit(
            injected=sums[0, 0:3],
            per_step=sums[: iterations + 1, 0:3],
            border_loss=sums[1: iterations + 1, 3:6],
            clamp_gain=sums[1: iterations + 1, 6:9],
            occluded=sums[1: iterations + 1, 9:12],
            accumulated=sums[iterations + 1, 0:3],
            reflected=sums[1: iterations + 1, 12:15],
            blocked=sums[1: iterations + 1, 15:18],
            budget_withheld=sums[1: iterations + 1, 18:21],
        )
    if mode == "flux":
        per_step = sums[: iterations + 1, 0:3].copy()
        if not ping_pong:
            per_step[1:] = np.diff(per_step, axis=0)
        accumulated = sums[iterations + 1, 0:3]
    else:
        per_step = np.concatenate([sums[0:1, 0:3], np.full((iterations, 3), np.nan)])
        accumulated = sums[1, 0:3]
    return GridAudit(injected=sums[0, 0:3], per_step=per_step, border_loss=None,
                     clamp_gain=None, occluded=None, accumulated=accumulated, reflected=None,
                     blocked=None, budget_withheld=None, mode=mode)


def propagate_with_audit(grid: np.ndarray, corrections: Corrections | None = None,
                         iterations: int = 1, geometry: np.ndarray | None = None,
                         ctx: moderngl.Context | None = None, fmt: str = "rgba32f",
                         geometry_albedo: np.ndarray | None = None, bounces: int = 1,
                         audit: str | bool = "full", neighbours: int = 6,
                         visibility: str = "linear", flux_budget: bool = False,
                         reprojection: str = "face-normal",
                         ) -> tuple[list[np.ndarray], np.ndarray, GridAudit]:
    """GPU propagation of a numpy grid: (grid_0..grid_N, acc_N, audit). The last axis of
    ``grid`` (4 or 9 coefficients) selects L1 or L2.
    ``grid``: ``(3, nx, ny, nz, C)``, any shape (the grid's cells are of size 1 at the
    origin). ``geometry``, ``geometry_albedo``: the geometry volume's
    ``(nx+1, ny+1, nz+1, 4)`` blocking and albedo sums (``bounces`` 2).
    ``audit``: what the audit measures (:data:`explorer.lpv.audit.AUDIT_MODES`);
    ``neighbours``: 6 or 26 (docs/MODEL.md "26 neighbours"); ``visibility``,
    ``flux_budget``, ``reprojection``: see :meth:`PropagatePass.start`."""
    grid = np.asarray(grid)
    if grid.ndim != 5 or grid.shape[0] != 3:
        raise ValueError(f"grid must have shape (3, nx, ny, nz, 4) or (3, nx, ny, nz, 9), "
                         f"got {grid.shape}")
    n = tuple(int(v) for v in grid.shape[1:4])
    order = sh_order_of(grid.shape[4])
    grid = check_volume_array(grid, n, "grid", channels=3, coefficients=grid.shape[4])
    corrections = corrections or Corrections()
    ctx = ctx or default_context()
    spec = GridSpec((0.0, 0.0, 0.0), 1.0, n)
    injected = LpvGrid(ctx, n, fmt, order)
    volume = None
    try:
        injected.write(grid)
        if geometry is not None:
            volume = GeometryVolume(ctx, n, fmt)
            corners = tuple(v + 1 for v in n)
            volume.write(check_volume_array(geometry, corners, "geometry"),
                         None if geometry_albedo is None else
                         check_volume_array(geometry_albedo, corners, "geometry_albedo"))
        propagator = per_context(ctx, "propagate",
                                 lambda: PropagatePass(ctx, programs_for(ctx)))
        output = propagator.run(injected, spec, corrections, iterations, volume,
                                keep_steps=True, bounces=bounces, audit=audit,
                                neighbours=neighbours, visibility=visibility,
                                flux_budget=flux_budget, reprojection=reprojection)
        return output.steps, output.accumulated.read(), output.audit
    finally:
        injected.release()
        if volume is not None:
            volume.release()


def propagate(grid: np.ndarray, corrections: Corrections | None = None, iterations: int = 1,
              geometry: np.ndarray | None = None, ctx: moderngl.Context | None = None,
              fmt: str = "rgba32f") -> list[np.ndarray]:
    """GPU propagation of a ``(3, N, N, N, 4)`` (L1) or ``(3, N, N, N, 9)`` (L2) grid:
    grid_0..grid_N as float32 arrays (``geometry``: an optional ``(N+1, N+1, N+1, 4)`` L1
    geometry volume)."""
    return propagate_with_audit(grid, corrections, iterations, geometry, ctx, fmt)[0]
