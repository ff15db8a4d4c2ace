"""Surface masks (explorer/scene/parts.py, explorer/truth/surface_masks.py) and
``lpv-explorer compare --region-mask``: every triangle has one name, a mask holds exactly
the pixels of its surface (checked against the G-buffer and the known geometry of the
Cornell box), the masks partition the pixels that see a surface, and compare's figures
over a mask are the numpy ones over the same pixels."""

from __future__ import annotations

import math

import numpy as np
import pytest

from explorer.cli import build_parser
from explorer.scene import BUILTIN_SCENES, load_scene
from explorer.scene.parts import surface_names
from explorer.truth.gbuffer import render_gbuffer
from explorer.truth.surface_masks import check_surface_names, render_triangle_ids, surface_masks

CORNELL_SURFACES = ("floor", "ceiling", "back wall", "left wall", "right wall",
                    "short block", "tall block")
SIZE = (64, 48)
EPS = 1e-4          # world units: a G-buffer position on a plane of the box


@pytest.mark.parametrize("name", list(BUILTIN_SCENES))
def test_every_triangle_has_one_known_name(name):
    scene = load_scene(name)
    surfaces = surface_names(scene)
    assert len(set(surfaces.names)) == len(surfaces.names)
    assert surfaces.triangle_names.shape == (scene.triangle_count,)
    assert surfaces.triangle_names.min() >= 0
    assert set(np.unique(surfaces.triangle_names)) == set(range(len(surfaces.names)))


def test_scene_surface_names():
    assert surface_names(load_scene("cornell")).names == CORNELL_SURFACES
    assert surface_names(load_scene("single-source")).names == ("patch",)   # its object
    atrium = surface_names(load_scene("atrium")).names
    for part in ("floor", "north columns", "north arcade walls", "north curtains",
                 "south banners", "east end wall", "west end wall"):
        assert part in atrium
    with pytest.raises(ValueError, match="no surface named 'curtains'; its surfaces are: "
                                         "floor, north columns"):
        check_surface_names(load_scene("atrium"), ["curtains"])


def _inside_box(points, centre, size, yaw_degrees, eps=EPS):
    """Points within the MeshBuilder.box of ``centre``, ``size`` turned by ``yaw``."""
    angle = math.radians(yaw_degrees)
    rot = np.array([[math.cos(angle), 0.0, math.sin(angle)], [0.0, 1.0, 0.0],
                    [-math.sin(angle), 0.0, math.cos(angle)]])
    local = (points - np.asarray(centre)) @ rot       # rot.T applied to each row
    return np.all(np.abs(local) <= np.asarray(size) / 2 + eps, axis=-1)


@pytest.fixture(scope="module")
def cornell_views(gl_context):
    scene = load_scene("cornell")
    ids = render_triangle_ids(gl_context, scene, *SIZE)
    gbuffer = render_gbuffer(gl_context, scene, *SIZE)
    return scene, ids, gbuffer


def test_masks_select_the_pixels_of_their_surface(cornell_views):
    scene, ids, gbuffer = cornell_views
    masks = surface_masks(scene, ids, CORNELL_SURFACES)
    valid, p, n = gbuffer.valid, gbuffer.position, gbuffer.normal
    assert np.array_equal(ids >= 0, valid)
    tall = valid & _inside_box(p, (-0.34, -0.4, -0.32), (0.6, 1.2, 0.6), 18.0)
    short = valid & _inside_box(p, (0.34, -0.7, 0.3), (0.6, 0.6, 0.6), -18.0)
    blocks = tall | short
    def plane(axis: int, at: float) -> np.ndarray:
        """Pixels on the box's plane ``axis = at`` facing into the box (a pixel on the
        edge of two planes belongs to the one its normal faces from)."""
        return valid & (np.abs(p[..., axis] - at) < EPS) & (n[..., axis] * at < -0.999)

    expected = {     # the box's planes, less the pixels on a block's face in that plane
        "floor": plane(1, -1.0) & ~blocks, "ceiling": plane(1, 1.0),
        "back wall": plane(2, -1.0), "left wall": plane(0, -1.0),
        "right wall": plane(0, 1.0), "short block": short, "tall block": tall,
    }
    for name, mask in masks.items():
        assert mask.any(), name
        assert np.array_equal(mask, expected[name]), (
            f"{name}: {int((mask != expected[name]).sum())} pixels differ")
    # the left and right walls' albedo is red and green: the masks agree with the G-buffer
    assert np.all(gbuffer.albedo[masks["left wall"]][:, 0] > gbuffer.albedo[
        masks["left wall"]][:, 1])
    assert np.all(gbuffer.albedo[masks["right wall"]][:, 1] > gbuffer.albedo[
        masks["right wall"]][:, 0])


def test_masks_partition_the_covered_pixels(cornell_views):
    scene, ids, gbuffer = cornell_views
    masks = surface_masks(scene, ids, CORNELL_SURFACES)
    count = np.sum([m.astype(int) for m in masks.values()], axis=0)
    assert np.array_equal(count, gbuffer.valid.astype(int))    # each covered pixel once


def test_mask_follows_a_moved_object(gl_context):
    from explorer.lpv.settings import Settings
    from explorer.truth.gbuffer import scene_for

    moved = scene_for(Settings(scene="cornell",
                               object_transforms={"tall block": [0.4, 0.0, 0.3]}))
    ids = render_triangle_ids(gl_context, moved, *SIZE)
    gbuffer = render_gbuffer(gl_context, moved, *SIZE)
    mask = surface_masks(moved, ids, ["tall block"])["tall block"]
    inside = gbuffer.valid & _inside_box(gbuffer.position, (0.06, -0.4, -0.02),
                                         (0.6, 1.2, 0.6), 18.0)
    assert mask.any() and np.array_equal(mask, inside)


def test_compare_mask_rows_are_the_numpy_figures_over_the_same_pixels(gl_context):
    from explorer.commands import options
    from explorer.commands.compare import format_table, plan_runs, run_comparison
    from explorer.truth.gbuffer import scene_for

    args = build_parser().parse_args(
        ["compare", "--scene", "cornell", "--preset", "corrected", "--reference",
         "unoccluded", "--size", "40x32", "--rsm-size", "8", "--grid-size", "8",
         "--iterations", "4", "--region-mask", "tall block", "--region-mask", "floor",
         "--quiet"])
    base = options.settings_from_args(args)
    scene = scene_for(base)
    comparison = run_comparison(args, plan_runs(args, base), gl_context, scene)
    lpv = np.asarray(comparison.images["corrected"], np.float64)
    reference = np.asarray(comparison.reference, np.float64)
    masks = surface_masks(scene, render_triangle_ids(gl_context, scene, 40, 32),
                          ["tall block", "floor"])
    rows = {row.region: row for row in comparison.rows}
    assert set(rows) == {"image", "tall block", "floor"}
    for name, mask in masks.items():
        row = rows[name]
        assert row.stats.pixels == int(mask.sum()) > 0
        ratio = lpv[mask].sum() / reference[mask].sum()
        # the reference is float32: its sums differ from float64 ones by ~1e-7
        assert row.stats.flux_ratio == pytest.approx(ratio, rel=1e-6)
        assert row.means == pytest.approx((lpv[mask].mean(), reference[mask].mean()),
                                          rel=1e-6)
        assert row.means[0] / row.means[1] == pytest.approx(row.stats.flux_ratio, rel=1e-6)
    table = format_table(comparison.rows, args, comparison.frame)
    line = next(line for line in table.splitlines() if "| tall block |" in line)
    assert f"| {int(masks['tall block'].sum())} |" in line
