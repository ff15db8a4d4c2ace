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

Every problem names the file and the array: a missing array, a wrong shape, a dtype that
is not floating point, a value that is not finite, a normal that is not unit (each bad row
by number). A VPL file's problems come together in one line, not only the first.
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


ROWS_NAMED = 20
"""Rows a problem names one by one; it counts the rest (a file of a million bad normals
gives a message of a line, not of a million rows)."""


class Problems:
    """The problems found in one file, reported together: one line naming the file, then
    each problem (``FileFormatError``)."""

    def __init__(self, where: str) -> None:
        self.where = where
        self.found: list[str] = []

    def add(self, problem: str) -> None:
        self.found.append(problem)

    def raise_if_any(self) -> None:
        if len(self.found) == 1:
            raise FileFormatError(f"{self.where}: {self.found[0]}")
        if self.found:
            listed = "; ".join(f"({k}) {problem}" for k, problem in enumerate(self.found, 1))
            raise FileFormatError(f"{self.where}: {len(self.found)} problems: {listed}")


def _rows(rows: np.ndarray, describe) -> str:
    """``row i (describe(i))`` for the first :data:`ROWS_NAMED` rows, then how many more."""
    named = ", ".join(f"row {int(i)} ({describe(int(i))})" for i in rows[:ROWS_NAMED])
    rest = rows.size - ROWS_NAMED
    return named + (f" and {rest} more row{'s' if rest > 1 else ''}" if rest > 0 else "")


def _count(n: int) -> str:
    return f"{n} row{'s' if n != 1 else ''}"


def _checked_array(arrays: dict, name: str, shape: tuple, problems: Problems
                   ) -> np.ndarray | None:
    """``arrays[name]`` checked: present, floating point, ``shape`` (None: any length),
    finite; float32, or None after adding what is wrong to ``problems``. The non-finite
    values of an ``(M, k)`` array are named by row."""
    if name not in arrays:
        problems.add(f"no array {name!r} (it holds {', '.join(sorted(arrays)) or 'nothing'})")
        return None
    array = arrays[name]
    if not np.issubdtype(array.dtype, np.floating):
        problems.add(f"{name} must be float32 or float64, got {array.dtype}")
        return None
    if len(array.shape) != len(shape) or any(
            want is not None and got != want for got, want in zip(array.shape, shape)):
        wanted = "(" + ", ".join("M" if w is None else str(w) for w in shape) + \
            ("," if len(shape) == 1 else "") + ")"
        problems.add(f"{name} must have shape {wanted}, got {array.shape}")
        return None
    bad = ~np.isfinite(array)
    if np.any(bad):
        if array.ndim in (1, 2):
            flat = bad.reshape(array.shape[0], -1)
            rows = np.flatnonzero(flat.any(axis=1))
            where_in = (lambda i: "value " + str(array[i])) if array.ndim == 1 else \
                (lambda i: "column " + ", ".join(map(str, np.flatnonzero(flat[i]))))
            problems.add(f"{name} is not finite in {_count(rows.size)}: "
                         f"{_rows(rows, where_in)}")
        else:
            first = tuple(int(i) for i in np.argwhere(bad)[0])
            problems.add(f"{name} is not finite at index {first}"
                         + (f" ({int(bad.sum())} values)" if bad.sum() > 1 else ""))
        return None
    return np.asarray(array, np.float32)


def _float_array(arrays: dict, name: str, shape: tuple, where: str) -> np.ndarray:
    """:func:`_checked_array` raising its problem (one array alone)."""
    problems = Problems(where)
    array = _checked_array(arrays, name, shape, problems)
    problems.raise_if_any()
    return array


def load_vpls(path: Path | str, geometry_volume: bool = False,
              what: str = "--vpls") -> VplArrays:
    """The VPLs of the file at ``path`` (module docstring); ``geometry_volume``: the frame
    builds one, so ``vpl_depth`` and ``vpl_texel_area`` are required. Every problem of the
    file is reported in one :class:`FileFormatError`, each bad row named."""
    problems = Problems(f"{what} {path}")
    arrays = read_npz(path, what)
    positions = _checked_array(arrays, "vpl_position", (None, 3), problems)
    count = None if positions is None else positions.shape[0]
    if count == 0:
        problems.add("vpl_position holds no VPL")
    normals = _checked_array(arrays, "vpl_normal", (count, 3), problems)
    flux = _checked_array(arrays, "vpl_flux", (count, 3), problems)
    if normals is not None:
        lengths = np.linalg.norm(normals.astype(np.float64), axis=1)
        off = np.flatnonzero(np.abs(lengths - 1.0) > UNIT_TOLERANCE)
        if off.size:
            problems.add(f"vpl_normal is not unit in {_count(off.size)}: "
                         f"{_rows(off, lambda i: f'length {lengths[i]:.6g}')}")
    has_area = "vpl_depth" in arrays and "vpl_texel_area" in arrays
    if geometry_volume and not has_area:
        problems.add("the geometry volume needs vpl_depth (M,) and vpl_texel_area () for "
                     "each VPL's surfel area; add them or use --geometry-volume off")
    depth, texel_area = np.ones(count or 0, np.float32), 1.0
    if has_area:    # unused without a geometry volume (only its surfels have an area)
        depth = _checked_array(arrays, "vpl_depth", (count,), problems)
        area = _checked_array(arrays, "vpl_texel_area", (), problems)
        if area is not None:
            texel_area = float(arrays["vpl_texel_area"])      # kept in double precision
            if not texel_area > 0:
                problems.add(f"vpl_texel_area must be positive, got {texel_area}")
    projection = "perspective"
    if "vpl_orthographic" in arrays:
        flag = arrays["vpl_orthographic"]
        if flag.shape != () or flag.dtype.kind not in "biu" or int(flag) not in (0, 1):
            problems.add(f"vpl_orthographic must be one bool (or 0/1), got {flag.dtype} of "
                         f"shape {flag.shape}")
        else:
            projection = "orthographic" if int(flag) else "perspective"
    albedo = None
    if "vpl_albedo" in arrays:
        albedo = _checked_array(arrays, "vpl_albedo", (count, 3), problems)
    problems.raise_if_any()
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
