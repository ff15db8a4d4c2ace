"""Cascaded LPV: nested grids around the viewer (docs/MODEL.md "Cascades").

Cascade ``k`` has the single grid's cells (``grid_size``³, or an exact grid's
``nx × ny × nz``) of edge ``c_k = c_0·2^k``. All cascades are
centred on one *focus point* on the camera's line of sight (``Settings.cascade_focus``:
0 = the eye, 1 = the camera's target), each snapped to the lattice of its own cell size
so that moving the camera moves a cascade only by whole cells (no swimming). The lattice
is anchored at the single grid's origin (:func:`single_spec`).

Every VPL is injected into every cascade that contains it (injection drops VPLs outside
a grid), so each cascade holds and propagates all the light inside it; the final gather
blends the cascades with weights that form a partition of unity, so no VPL is counted
twice (:func:`blend_weights`, mirrored in ``shaders/cascades.glsl``).

``cascades == 1`` is exactly the single scene-enclosing grid the pipeline always used.
"""

from __future__ import annotations

from collections.abc import Sequence
from dataclasses import dataclass

import numpy as np

from explorer.lpv.grid import GridSpec, grid_cells, shape_text
from explorer.lpv.settings import MAX_CASCADES  # = MAX_CASCADES in cascades.glsl

CASCADE_EDGE_CELLS = 0.5
"""Outer shell of a cascade (in its cells) where its weight is 0: within half a cell of
the border a trilinear lookup has no outer neighbour to blend with."""
CASCADE_BAND_CELLS = 2.0
"""Width (in the cascade's cells) of the band inside that shell over which a cascade's
weight rises from 0 to 1 (smoothstep)."""
MIN_CASCADE_GRID = 8
"""Smallest grid_size with several cascades: a cascade must hold its finer neighbour
(N/2 − 1 fine cells of room on each side, see :func:`cascade_specs`) plus the band."""
TEXEL_BYTES = {"rgba32f": 16, "rgba16f": 8}
GRIDS_PER_CASCADE = 4
"""Light grids one cascade keeps on the GPU: injected, ping, pong, accumulated."""
AUDIT_RECORD_BYTES = 84
"""One per-cell audit record (21 floats); one storage block holds one record per cell."""
AUDIT_BYTES_PER_CELL = 2 * AUDIT_RECORD_BYTES
"""Per-cell audit records the propagation keeps (only with the audit): the last step's
and the sum over the steps."""
DEFAULT_TEXTURE_BUDGET = 4 << 30
"""Default limit of the pipeline's LPV texture memory (bytes, all cascades together)."""


def focus_point(eye, target, focus: float) -> np.ndarray:
    """The point the cascades are centred on: ``eye + focus·(target − eye)``."""
    eye = np.asarray(eye, np.float64)
    return eye + float(focus) * (np.asarray(target, np.float64) - eye)


def cascade_specs(single: GridSpec, count: int, centre, finest_extent: float | None = None,
                  snap: bool = True) -> list[GridSpec]:
    """The ``count`` nested grids around ``centre``.

    ``single`` is the scene-enclosing grid: with ``count == 1`` it is returned unchanged.
    Otherwise cascade ``k`` has cell size ``c_k = c_0·2^k`` with
    ``c_0 = finest_extent/N`` (``finest_extent`` None: ``single.cell_size/2^(count−1)``,
    so the coarsest cascade has the single grid's cells and extent), and origin
    ``A + (round((centre − A)/c_k) − ⌊N/2⌋)·c_k`` with ``A = single.origin``: the lattice
    point nearest the centre, minus half a grid. Since ``|i_k − 2·i_{k+1}| ≤ 1`` (in
    cascade-``k`` cells) every cascade lies inside the next with at least ``N/2 − 1`` of
    its cells to spare on each side. ``snap`` False (``Settings.cascade_snap``) drops the
    rounding: origin ``centre − ⌊N/2⌋·c_k``, so every cascade moves with the centre by any
    fraction of a cell (the VPLs then land in other cells as it moves: the light swims).
    """
    count = int(count)
    if not 1 <= count <= MAX_CASCADES:
        raise ValueError(f"cascades must be 1..{MAX_CASCADES}, got {count}")
    if count == 1:
        return [single]
    cells = np.asarray(single.cells)
    if finest_extent is None:
        finest = single.cell_size / 2 ** (count - 1)
    else:
        if not finest_extent > 0:
            raise ValueError(f"cascade_extent must be positive, got {finest_extent!r}")
        finest = float(finest_extent) / int(cells.max())
    anchor = np.asarray(single.origin, np.float64)
    centre = np.asarray(centre, np.float64)
    specs = []
    for k in range(count):
        cell = finest * 2 ** k
        nearest = (centre - anchor) / cell
        if snap:
            nearest = np.round(nearest)
        origin = anchor + (nearest - cells // 2) * cell
        specs.append(GridSpec(tuple(float(v) for v in origin), cell, single.cells))
    return specs


def single_spec(settings, scene) -> GridSpec:
    """The one grid of a frame (docs/MODEL.md "Notation and storage"): the settings' exact grid
    (``grid_cells``, ``grid_origin``, ``grid_cell_size``), else the scene file's
    (``Scene.exact_grid``), else the ``grid_size``³ cube fitted around the scene's box."""
    if settings.grid_cells is not None:
        return GridSpec(settings.grid_origin, settings.grid_cell_size, settings.grid_cells)
    exact = scene.exact_grid
    if exact is not None:
        cells, origin, cell_size = exact
        return GridSpec(origin, cell_size, cells)
    return GridSpec.enclosing(scene.bounds_min, scene.bounds_max, settings.grid_size)


def frame_specs(settings, scene) -> list[GridSpec]:
    """The grids of a frame: :func:`single_spec`, or with ``settings.cascades`` > 1 the
    cascades around the camera's focus point (each with the single grid's cells)."""
    single = single_spec(settings, scene)
    if settings.cascades == 1:
        return [single]
    centre = focus_point(scene.camera.eye, scene.camera.target, settings.cascade_focus)
    return cascade_specs(single, settings.cascades, centre, settings.cascade_extent,
                         settings.cascade_snap)


def level_pass_name(stage: str, level: int, count: int) -> str:
    """How messages name ``stage``'s pass on cascade ``level`` of ``count``."""
    return stage if count == 1 else f"{stage} (cascade {level})"


def cascade_iterations(settings, k: int) -> int:
    """Propagation steps of cascade ``k`` (``Settings.cascade_iterations``): ``iterations``
    in every cascade ("same"), or ``iterations·2^(K−1−k)`` ("same-distance", so the fine
    cascades carry light as far in world units as the coarsest one)."""
    if settings.cascade_iterations == "same-distance":
        return int(settings.iterations) * 2 ** (int(settings.cascades) - 1 - int(k))
    return int(settings.iterations)


def own_weight(spec: GridSpec, points) -> np.ndarray:
    """Weight ``w_k`` of one cascade at world ``points`` (..., 3): 0 outside the grid and in
    its outer :data:`CASCADE_EDGE_CELLS`, rising by a smoothstep over
    :data:`CASCADE_BAND_CELLS`, 1 further inside. ``d`` is the distance (in cells) from the
    point to the nearest face of the grid."""
    g = spec.grid_coords(points)
    depth = np.min(np.minimum(g, np.asarray(spec.cells) - g), axis=-1)
    t = np.clip((depth - CASCADE_EDGE_CELLS) / CASCADE_BAND_CELLS, 0.0, 1.0)
    return t * t * (3.0 - 2.0 * t)


def blend_weights(specs: list[GridSpec], points) -> np.ndarray:
    """Final-gather weights ``W_k`` (..., K) of the cascades at world ``points`` (..., 3).

    Finest first: ``W_k = w_k·Π_{j<k}(1 − w_j)`` and the coarsest takes the rest,
    ``W_{K−1} = Π_{j<K−1}(1 − w_j)``, so ``Σ_k W_k = 1`` everywhere (the product
    telescopes). With one cascade ``W_0 = 1``: the single grid, sampled as before.
    """
    points = np.asarray(points, np.float64)
    weights = np.zeros(points.shape[:-1] + (len(specs),))
    remaining = np.ones(points.shape[:-1])
    for k, spec in enumerate(specs):
        w = own_weight(spec, points) if k < len(specs) - 1 else np.ones_like(remaining)
        weights[..., k] = w * remaining
        remaining = remaining * (1.0 - w)
    return weights


def texture_bytes(grid_size: int | tuple[int, int, int], cascades: int, grid_format: str,
                  geometry: bool, sh_groups: int = 1) -> int:
    """GPU memory the LPV stages hold for ``cascades`` grids of ``grid_size`` cells (one
    number: a cube; or (nx, ny, nz)): per cascade four light grids of three textures
    (``sh_groups`` texels per cell: 1 for L1, 3 for L2), the audit records, and the
    geometry volume of ``(nx+1)(ny+1)(nz+1)`` texels when it is on."""
    nx, ny, nz = grid_cells(grid_size)
    cells = nx * ny * nz
    texel = TEXEL_BYTES[grid_format]
    per_cascade = (GRIDS_PER_CASCADE * 3 * int(sh_groups) * texel * cells
                   + AUDIT_BYTES_PER_CELL * cells)
    if geometry:
        per_cascade += texel * (nx + 1) * (ny + 1) * (nz + 1)
    return int(cascades) * per_cascade


def check_limits(grid_size: int | tuple[int, int, int], cascades: int, grid_format: str,
                 geometry: bool, budget_bytes: int, max_texture_units: int,
                 sh_groups: int = 1) -> None:
    """A ValueError naming the limit when the cascades do not fit: the texture memory
    budget, or the fragment shader's texture units (5 + 3 per cascade). ``grid_size``:
    cells, one number (a cube) or (nx, ny, nz)."""
    shape = grid_cells(grid_size)
    if cascades > 1 and min(shape) < MIN_CASCADE_GRID:
        raise ValueError(f"cascades need grid_size >= {MIN_CASCADE_GRID} (each cascade must "
                         f"hold the next finer one), got {_size_text(grid_size)}")
    needed = texture_bytes(grid_size, cascades, grid_format, geometry, sh_groups)
    if budget_bytes and needed > budget_bytes:
        raise ValueError(
            f"{cascades} cascade(s) of {shape_text(shape)} cells in {grid_format} need "
            f"{needed / 2**20:.0f} MiB of LPV textures (4 grids x 3 channels"
            f"{' x 3 texels (L2)' if sh_groups > 1 else ''} + audit"
            f"{' + geometry volume' if geometry else ''} per cascade), more than the "
            f"budget of {budget_bytes / 2**20:.0f} MiB: use fewer cascades, a smaller "
            f"grid or rgba16f")
    units = 5 + 3 * cascades
    if cascades > 1 and max_texture_units and units > max_texture_units:
        raise ValueError(f"{cascades} cascades need {units} texture units in the final "
                         f"gather, this driver has GL_MAX_TEXTURE_IMAGE_UNITS "
                         f"{max_texture_units}")


@dataclass
class CascadeInput:
    """One cascade as the final gather samples it."""

    spec: GridSpec
    textures: tuple
    """The accumulated grid's r, g, b 3D textures (sampled as in the single-grid gather)."""


@dataclass(frozen=True)
class SampledGrid:
    """The grid the final gather and the fog sample: the accumulation of every cascade
    (finest first; a single grid is one cascade) and their SH order, which fixes the
    texel layout (explorer/lpv/passes/textures.py). One typed value the frame hands to both
    passes, in place of textures, spec, cascade list and order passed on one by one."""

    cascades: tuple[CascadeInput, ...]
    sh_order: int = 1

    def __post_init__(self) -> None:
        object.__setattr__(self, "cascades", tuple(self.cascades))
        if not 1 <= len(self.cascades) <= MAX_CASCADES:
            raise ValueError(f"a sampled grid has 1..{MAX_CASCADES} cascades, "
                             f"got {len(self.cascades)}")
        if self.sh_order not in (1, 2):
            raise ValueError(f"sh_order must be 1 or 2, got {self.sh_order}")

    @classmethod
    def single(cls, spec: GridSpec, textures: tuple, sh_order: int = 1) -> SampledGrid:
        """One grid: its spec and its r, g, b accumulation textures."""
        return cls((CascadeInput(spec, tuple(textures)),), sh_order)

    @property
    def finest(self) -> CascadeInput:
        """Level 0: the grid a single-grid gather samples (its units 5..7)."""
        return self.cascades[0]


def bind_cascades(cascades: Sequence[CascadeInput], first_unit: int) -> None:
    """Bind the cascades' textures to units ``first_unit`` … (three per cascade: r, g, b),
    as :func:`cascade_uniforms` does: a pass that keeps the uniforms it made binds them
    again each run (the units hold other textures between runs)."""
    for k, cascade in enumerate(cascades):
        for i, texture in enumerate(cascade.textures):
            texture.use(first_unit + 3 * k + i)


def cascade_uniforms(cascades: list[CascadeInput], first_unit: int) -> dict[str, object]:
    """Uniforms of ``cascades.glsl`` for these cascades, their textures bound to units
    ``first_unit`` … (three per cascade: r, g, b)."""
    count = len(cascades)
    if not 1 <= count <= MAX_CASCADES:
        raise ValueError(f"the gather samples 1..{MAX_CASCADES} cascades, got {count}")
    pad = MAX_CASCADES - count
    origins = [c.spec.origin for c in cascades] + [(0.0, 0.0, 0.0)] * pad
    cells = [float(c.spec.cell_size) for c in cascades] + [1.0] * pad
    units = {channel: [first_unit + 3 * k + i for k in range(count)] +
             [first_unit + i] * pad for i, channel in enumerate("rgb")}
    bind_cascades(cascades, first_unit)
    return {
        "u_cascade_count": count,
        "u_cascade_origin": origins,
        "u_cascade_cell_size": cells,
        "u_cascade_edge": CASCADE_EDGE_CELLS,
        "u_cascade_band": CASCADE_BAND_CELLS,
        "u_cascade_r": units["r"], "u_cascade_g": units["g"], "u_cascade_b": units["b"],
    }



def _size_text(grid_size: int | tuple[int, int, int]) -> str:
    return str(grid_size) if np.ndim(grid_size) == 0 else shape_text(grid_size)
