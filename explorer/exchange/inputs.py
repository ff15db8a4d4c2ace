"""An engine's own numbers fed into the pipeline: its VPLs (``--vpls FILE.npz``) or its
injected grid (``--grid0 FILE.npz``), in the layout ``render --dump`` writes
(:data:`explorer.exchange.stages.ARRAYS`).

VPL file: ``vpl_position``, ``vpl_normal``, ``vpl_flux`` ``(M, 3)`` float arrays (world
units, unit normals, watts per colour channel); optional ``vpl_depth`` ``(M,)`` and
``vpl_texel_area`` ``()`` (the geometry volume's surfel area ``texel_area·depth²``, so
required when the geometry volume is on; without it they are unused) and ``vpl_albedo``
``(M, 3)`` (bounces 2) and ``vpl_orthographic`` ``()`` bool (a directional light's
texel area is a world area). Grid file: ``grid_0`` ``(3, nx, ny, nz, C)`` float (W/sr SH
coefficients, index [colour, x, y, z, k], C = 4 for ``--sh-order 1``, 9 for 2), and
optionally ``grid_origin`` ``(3,)`` / ``grid_cell_size`` ``()``, which must then be the
frame's grid (the grid is placed by the scene's box; the dump's sidecar says where).

Every problem is one line naming the file and the array: a missing array, a wrong shape,
a dtype that is not floating point, a value that is not finite, a normal that is not unit.
"""

from __future__ import annotations

from pathlib import Path

import numpy as np

from explorer.exchange.files import FileFormatError, read_npz
from explorer.lpv.grid import shape_text
from explorer.lpv.vpl import VplArrays
from explorer.scene.scene_file import is_scene_file

UNIT_TOLERANCE = 1e-3
"""Largest |‖n‖ − 1| accepted for a VPL normal (float32 normals from an engine)."""


def _float_array(arrays: dict, name: str, shape: tuple, where: str) -> np.ndarray:
    """``arrays[name]`` checked: present, floating point, ``shape`` (None: any length),
    finite; returned as float32."""
    if name not in arrays:
        raise FileFormatError(f"{where}: no array {name!r} (it holds "
                              f"{', '.join(sorted(arrays)) or 'nothing'})")
    array = arrays[name]
    if not np.issubdtype(array.dtype, np.floating):
        raise FileFormatError(f"{where}: {name} must be float32 or float64, got {array.dtype}")
    if len(array.shape) != len(shape) or any(
            want is not None and got != want for got, want in zip(array.shape, shape)):
        wanted = "(" + ", ".join("M" if w is None else str(w) for w in shape) + \
            ("," if len(shape) == 1 else "") + ")"
        raise FileFormatError(f"{where}: {name} must have shape {wanted}, got {array.shape}")
    if not np.all(np.isfinite(array)):
        bad = tuple(int(i) for i in np.argwhere(~np.isfinite(array))[0])
        raise FileFormatError(f"{where}: {name} is not finite at index {bad}")
    return np.asarray(array, np.float32)


def load_vpls(path: Path | str, geometry_volume: bool = False,
              what: str = "--vpls") -> VplArrays:
    """The VPLs of the file at ``path`` (module docstring); ``geometry_volume``: the frame
    builds one, so ``vpl_depth`` and ``vpl_texel_area`` are required."""
    where = f"{what} {path}"
    arrays = read_npz(path, what)
    positions = _float_array(arrays, "vpl_position", (None, 3), where)
    count = positions.shape[0]
    if count == 0:
        raise FileFormatError(f"{where}: vpl_position holds no VPL")
    normals = _float_array(arrays, "vpl_normal", (count, 3), where)
    flux = _float_array(arrays, "vpl_flux", (count, 3), where)
    lengths = np.linalg.norm(normals.astype(np.float64), axis=1)
    off = np.flatnonzero(np.abs(lengths - 1.0) > UNIT_TOLERANCE)
    if off.size:
        raise FileFormatError(f"{where}: vpl_normal {off[0]} has length {lengths[off[0]]:.6g}, "
                              f"not 1 ({off.size} normals are not unit)")
    has_area = "vpl_depth" in arrays and "vpl_texel_area" in arrays
    if geometry_volume and not has_area:
        raise FileFormatError(f"{where}: the geometry volume needs vpl_depth (M,) and "
                              f"vpl_texel_area () for each VPL's surfel area; add them or "
                              f"use --geometry-volume off")
    if has_area:
        depth = _float_array(arrays, "vpl_depth", (count,), where)
        _float_array(arrays, "vpl_texel_area", (), where)
        texel_area = float(arrays["vpl_texel_area"])      # kept in double precision
        if not texel_area > 0:
            raise FileFormatError(f"{where}: vpl_texel_area must be positive, got {texel_area}")
    else:   # unused without a geometry volume (only its surfels have an area)
        depth, texel_area = np.ones(count, np.float32), 1.0
    projection = "perspective"
    if "vpl_orthographic" in arrays:
        flag = arrays["vpl_orthographic"]
        if flag.shape != () or flag.dtype.kind not in "biu" or int(flag) not in (0, 1):
            raise FileFormatError(f"{where}: vpl_orthographic must be one bool (or 0/1), got "
                                  f"{flag.dtype} of shape {flag.shape}")
        projection = "orthographic" if int(flag) else "perspective"
    albedo = None
    if "vpl_albedo" in arrays:
        albedo = _float_array(arrays, "vpl_albedo", (count, 3), where)
    return VplArrays(positions, normals, flux, depth, texel_area, projection, albedo)


def load_grid0(path: Path | str, settings, what: str = "--grid0") -> np.ndarray:
    """The ``grid_0`` of the file at ``path`` for a frame with ``settings`` (its grid's
    cells and SH order), float32. A scene file may give its own exact grid, so with one
    (and no ``grid_cells`` setting) the cells are checked against the frame's grid in
    :func:`check_grid_placement`."""
    where = f"{what} {path}"
    arrays = read_npz(path, what)
    known = settings.grid_cells is not None or not is_scene_file(settings.scene)
    n = settings.grid_shape
    coefficients = 4 if settings.sh_order == 1 else 9
    if "grid_0" in arrays and arrays["grid_0"].ndim == 5:
        got = arrays["grid_0"].shape
        if known and got[0] == 3 and got[1:4] != n:
            raise FileFormatError(grid_shape_error(where, got[1:4], n))
        if got[0] == 3 and got[4] != coefficients and got[4] in (4, 9):
            raise FileFormatError(f"{where}: grid_0 has {got[4]} SH coefficients, the frame "
                                  f"{coefficients} (set --sh-order {1 if got[4] == 4 else 2})")
    shape = (3, *n, coefficients) if known else (3, None, None, None, coefficients)
    return _float_array(arrays, "grid_0", shape, where)


def grid_shape_error(where: str, theirs: tuple, ours: tuple) -> str:
    """The one-line error of a ``grid_0`` whose cells are not the frame's."""
    if len(set(theirs)) == 1:
        fix = f"set --grid-size {theirs[0]}"
    else:
        fix = f"set --grid-cells {','.join(map(str, theirs))} with --grid-origin and " \
              f"--grid-cell-size"
    return f"{where}: grid_0 is a {_cells(theirs)} grid, the frame's is {_cells(ours)} ({fix})"


def _cells(shape: tuple) -> str:
    return f"{shape[0]}³" if len(set(shape)) == 1 else shape_text(shape)


def check_grid_placement(path: Path | str, spec, what: str = "--grid0") -> None:
    """The file's ``grid_0`` of the frame's cells, and its ``grid_origin`` and
    ``grid_cell_size``, when it has them, equal to the frame's GridSpec ``spec`` (to
    float32 rounding)."""
    where = f"{what} {path}"
    arrays = read_npz(path, what)
    cells = tuple(arrays["grid_0"].shape[1:4])
    if cells != spec.cells:
        raise FileFormatError(grid_shape_error(where, cells, spec.cells))
    for name, ours in (("grid_origin", np.asarray(spec.origin)),
                       ("grid_cell_size", np.asarray(spec.cell_size))):
        if name in arrays:
            theirs = _float_array(arrays, name, ours.shape, where)
            if not np.allclose(theirs, ours, rtol=1e-6, atol=1e-6 * spec.cell_size):
                raise FileFormatError(f"{where}: {name} {theirs.tolist()} is not the frame's "
                                      f"grid ({ours.tolist()}); the grid encloses the scene's "
                                      f"box")


def run_with_grid0(pipeline, settings, grid0: np.ndarray, progress=None, vpls=None,
                   check=None):
    """The frame of ``settings`` propagated from ``grid0`` instead of the injected grid,
    its steps kept: the frame runs (RSM, VPLs, injection), ``check(spec)`` sees level 0's
    GridSpec, ``grid0`` replaces its injected grid on the GPU and the propagation and
    everything after it run again (``Pipeline.invalidate("propagate")``). The result's
    ``steps[0]`` is checked to be ``grid0``, so the replacement cannot silently miss.
    ``vpls``: hand-made VPLs for both runs (the geometry volume's occluders). One cascade,
    rgba32f. The frame's warnings are the caller's to print (``result.warnings``)."""
    if settings.cascades != 1:
        raise ValueError("--grid0 feeds one grid: use --cascades 1")
    if settings.grid_format != "rgba32f":
        raise ValueError("--grid0 needs --grid-format rgba32f (a 16-bit grid would round it)")
    pipeline.run(settings, vpls=vpls, need_audit="off", progress=progress)
    injected, spec, _ = pipeline.propagation_inputs(0)
    if check is not None:
        check(spec)
    injected.write(np.ascontiguousarray(grid0, np.float32))
    pipeline.invalidate("propagate")
    result = pipeline.run(settings, keep_steps=True, vpls=vpls, progress=progress)
    if not np.array_equal(result.steps[0], grid0):
        raise RuntimeError("the pipeline re-injected its own VPLs over the given grid_0")
    return result
