"""Test data shared by the LPV pass tests: seeded VPL sets, grids and cube symmetries."""

from __future__ import annotations

import itertools

import numpy as np

from explorer.lpv.grid import GridSpec
from explorer.lpv.vpl import VplArrays


def random_vpls(seed: int, spec: GridSpec, count: int, outside: int = 0,
                texel_area: float = 0.02) -> VplArrays:
    """``count`` VPLs inside the grid (kept 10% of a cell away from cell faces and from
    geometry-cell faces, so float32 and float64 pick the same cells) plus ``outside`` VPLs
    beyond its border."""
    rng = np.random.default_rng(seed)
    # a cube draws with one bound (the numbers every cubic test was written against)
    n = spec.cells[0] if spec.is_cube else np.asarray(spec.cells)
    cells = rng.integers(0, n, (count, 3))
    # Fractions in [0.1, 0.4] or [0.6, 0.9]: clear of 0/1 (light cells) and 0.5 (geometry).
    fractions = rng.uniform(0.1, 0.4, (count, 3)) + 0.5 * rng.integers(0, 2, (count, 3))
    grid_coords = cells + fractions
    if outside:
        edge = max(spec.cells)
        far = rng.uniform(edge + 0.5, edge + 3.0, (outside, 3)) * rng.choice([-1, 1], (outside, 3))
        grid_coords = np.vstack([grid_coords, far])
    positions = np.asarray(spec.origin) + grid_coords * spec.cell_size
    normals = rng.standard_normal((len(positions), 3))
    normals /= np.linalg.norm(normals, axis=1, keepdims=True)
    flux = rng.uniform(0.1, 1.0, (len(positions), 3))
    depth = rng.uniform(1.0, 3.0, len(positions))
    return VplArrays(positions, normals, flux, depth, texel_area)


def random_grid(seed: int, resolution: int, band1: float = 0.5) -> np.ndarray:
    """A (3, N, N, N, 4) grid with positive coefficient 0 and band 1 of relative size
    ``band1`` (so some face intensities are negative and the clamp acts)."""
    rng = np.random.default_rng(seed)
    grid = np.zeros((3,) + (resolution,) * 3 + (4,))
    grid[..., 0] = rng.uniform(0.2, 1.0, grid.shape[:4])
    grid[..., 1:] = band1 * rng.standard_normal(grid.shape[:4] + (3,))
    return grid

AUDIT_FIELDS = ("injected", "per_step", "border_loss", "clamp_gain", "occluded", "accumulated",
                "budget_withheld")
"""The propagation audit's terms a GPU run and the twin must agree on."""


def assert_audits_match(actual, expected, tolerance: float = 1e-4) -> None:
    """Every :data:`AUDIT_FIELDS` term of ``actual`` within ``tolerance`` of the injected
    flux's largest channel from ``expected``'s."""
    scale = float(np.abs(expected.injected).max())
    for name in AUDIT_FIELDS:
        got, want = getattr(actual, name), getattr(expected, name)
        assert got.shape == want.shape, name
        assert np.abs(got - want).max() <= tolerance * scale, name



def relative_error(actual: np.ndarray, expected: np.ndarray) -> float:
    """max |actual − expected| relative to max |expected| (the grid's largest value)."""
    scale = float(np.abs(expected).max())
    return float(np.abs(np.asarray(actual, np.float64) - expected).max()) / max(scale, 1e-30)


def cube_symmetries() -> list[np.ndarray]:
    """The 48 signed permutation matrices (rotations and reflections of the cube)."""
    matrices = []
    for permutation in itertools.permutations(range(3)):
        for signs in itertools.product((1, -1), repeat=3):
            matrix = np.zeros((3, 3), dtype=np.int64)
            for row, (column, sign) in enumerate(zip(permutation, signs)):
                matrix[row, column] = sign
            matrices.append(matrix)
    return matrices


def transform_grid(grid: np.ndarray, matrix: np.ndarray) -> np.ndarray:
    """The grid moved by the symmetry ``matrix`` about the grid centre: the cell at x goes
    to R(x − c) + c and its band-1 coefficients rotate as the vector w = (−f3, −f1, f2)
    they encode (f = (f0, −c1·w.y, c1·w.z, −c1·w.x) up to the common factor)."""
    n = grid.shape[1]
    centre = (n - 1) / 2.0
    cells = np.indices((n, n, n)).reshape(3, -1)
    moved = np.rint(matrix @ (cells - centre) + centre).astype(np.int64)
    coefficients = grid[:, cells[0], cells[1], cells[2]]           # (3, M, 4)
    vector = np.stack([-coefficients[..., 3], -coefficients[..., 1], coefficients[..., 2]], -1)
    rotated = vector @ matrix.T
    out = np.empty_like(grid)
    out[:, moved[0], moved[1], moved[2]] = np.stack(
        [coefficients[..., 0], -rotated[..., 1], rotated[..., 2], -rotated[..., 0]], -1)
    return out


def in_place_schedules(steps: list[np.ndarray], corrections, geometry=None,
                       geometry_albedo=None, bounces: int = 1,
                       reprojection: str = "face-normal") -> tuple[float, np.ndarray]:
    """For GPU in-place steps (grid_0 and the light each step added): the largest distance,
    relative to the largest accumulated value, between a step and the nearest value the
    in-place pass can produce (:func:`explorer.lpv.twin.light_grid.in_place_step_candidates`,
    given the GPU's own accumulation before and after the step), and per step the number
    of (channel, cell) pairs whose nearest read schedule is not the race-free one."""
    from explorer.lpv.twin.light_grid import in_place_step_candidates

    before = np.asarray(steps[0], np.float64)
    worst, raced = 0.0, []
    for step in steps[1:]:
        step = np.asarray(step, np.float64)
        after = before + step
        candidates = in_place_step_candidates(before, after, corrections, geometry,
                                              geometry_albedo, bounces, reprojection)
        distance = np.abs(candidates - step[None]).max(axis=-1)     # (64, 3, N, N, N)
        worst = max(worst, float(distance.min(axis=0).max()) / float(np.abs(after).max()))
        raced.append(int((distance.argmin(axis=0) != 0).sum()))
        before = after
    return worst, np.array(raced)


def run_frame(gl_context, settings, need_audit: str = "full"):
    """One FrameResult of ``settings`` on the tests' session context (for module fixtures
    that read a small frame), its energy audit measured in mode ``need_audit``."""
    from explorer.lpv.pipeline import Pipeline

    gl_context.__enter__()
    with Pipeline(settings, ctx=gl_context) as pipeline:
        return pipeline.run(settings, need_audit=need_audit)


def frame_view_lights(pipeline) -> list:
    """Every RSM view of ``pipeline``'s last frame with its own shadow map, as the media
    reference reads them (``twin_media.view_lights``): one per spot or directional
    light, six per point light."""
    from explorer.lpv.passes.rsm import read_texture
    from explorer.lpv.twin import media as twin_media

    sets = pipeline.light_views.rsm_sets
    return twin_media.view_lights(pipeline.light_views.views,
                                       [read_texture(rsm.position) for rsm in sets],
                                       [read_texture(rsm.normal) for rsm in sets])


def dump_small(folder, args: list[str]) -> tuple:
    """``render ARGS --dump`` of a small frame into ``folder``, read back: (folder, the
    arrays, the sidecar)."""
    import json

    from explorer.cli import main
    from explorer.exchange.files import read_npz

    assert main(["render", *args, "--dump", str(folder / "a.npz"),
                 "--out", str(folder / "a.png")]) == 0
    sidecar = json.loads((folder / "a.json").read_text(encoding="utf-8"))
    return folder, read_npz(folder / "a.npz"), sidecar
