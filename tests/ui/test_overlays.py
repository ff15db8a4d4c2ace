"""Overlays of the main view (explorer/ui/overlays): the numbers they draw and pick come
from the FrameResult's arrays, and the compositor draws them over the frame without
running a pass. Headless (EGL); the window tests are in test_app_overlays.py."""

from __future__ import annotations

import json
import math

import numpy as np
import pytest

from explorer.lpv import constants as C
from explorer.lpv.grid import GridSpec
from explorer.lpv.pipeline import Pipeline
from explorer.lpv.settings import Settings
from explorer.lpv.twin import light_grid as twin
from explorer.lpv.vpl import VplArrays
from explorer.ui import persist
from explorer.ui.overlays import picking
from explorer.ui.overlays import quantities as Q
from explorer.ui.overlays.compositor import Compositor, vpl_radius_scale
from explorer.ui.overlays.describe import cell_rows, pixel_rows
from explorer.ui.state import AppState, OverlayState
from explorer.ui.textures import diverging, heat

CORNELL = Settings(scene="cornell", grid_size=16, iterations=6, rsm_size=64, width=96,
                   height=72, geometry_volume="one-sided")


@pytest.fixture(scope="module")
def frame(gl_context):
    """(pipeline, result) of the Cornell box with its propagation steps kept."""
    pipeline = Pipeline(CORNELL, ctx=gl_context)
    result = pipeline.run(CORNELL, keep_steps=True)
    yield pipeline, result
    pipeline.release()


def _surface_pixels(result) -> np.ndarray:
    ys, xs = np.nonzero(result.gbuffer_position[..., 3] > 0.5)
    return np.stack([xs, ys], axis=1)


# ------------------------------------------------------------------------- picking
def test_picking_a_pixel_returns_the_frames_arrays(frame):
    _, result = frame
    x, y = 30, 62          # the Cornell box's floor, left of the short block
    pick = picking.pick_pixel(result, x, y)
    assert pick.surface
    assert np.array_equal(pick.position, result.gbuffer_position[y, x, :3])
    assert np.array_equal(pick.normal, result.gbuffer_normal[y, x, :3])
    assert pick.pixel_area == result.gbuffer_normal[y, x, 3]
    for name, array in (("direct", result.direct), ("indirect", result.indirect),
                        ("final", result.final_image), ("albedo", result.albedo)):
        assert np.array_equal(getattr(pick, name), array[y, x]), name
    assert pick.normal[1] > 0.99                      # the floor faces up
    cell = pick.cells[0]
    assert cell.index == tuple(result.grid_spec.cell_index(pick.position))
    assert np.array_equal(cell.coefficients, result.accumulated[(slice(None),) + cell.index])
    assert pick.reference is None
    ref = np.full(result.final_image.shape, 0.5, np.float32)
    assert np.array_equal(picking.pick_pixel(result, x, y, reference=ref).reference,
                          [0.5, 0.5, 0.5])
    assert picking.pick_pixel(result, -1, 0) is None
    assert picking.pick_pixel(result, 96, 0) is None
    assert not picking.pick_pixel(result, 1, 1).surface        # background corner
    assert dict(pixel_rows(pick))["pixel"] == f"({x}, {y})"


def test_the_indirect_light_recomputed_from_the_grid_matches_the_gather(frame):
    """albedo/π·E from a numpy trilinear lookup of acc_N (docs/MODEL.md "Final gather")
    against what the gather shader wrote, on every 7th surface pixel."""
    _, result = frame
    pixels = _surface_pixels(result)[::7]
    gpu = np.array([picking.pick_pixel(result, x, y).indirect for x, y in pixels])
    numpy = np.array([picking.pick_pixel(result, x, y).indirect_from_grid for x, y in pixels])
    assert gpu.max() > 0
    assert np.abs(gpu - numpy).max() <= 1e-4 * gpu.max()


def test_the_picked_indirect_light_follows_the_net_flux_gather(gl_context):
    """With Settings.gather_net_flux the recomputed light adds the pixel's own exitance
    (docs/MODEL.md "Net-flux gather") and still matches the shader."""
    settings = CORNELL.with_changes(gather_net_flux=True)
    with Pipeline(settings, ctx=gl_context) as pipeline:   # not the module's frame
        result = pipeline.run(settings)
    pixels = _surface_pixels(result)[::7]
    gpu = np.array([picking.pick_pixel(result, x, y).indirect for x, y in pixels])
    numpy = np.array([picking.pick_pixel(result, x, y).indirect_from_grid for x, y in pixels])
    assert gpu.max() > 0
    assert np.abs(gpu - numpy).max() <= 1e-4 * gpu.max()


def test_the_frames_camera_projects_each_surface_point_into_its_pixel(frame):
    _, result = frame
    pixels = _surface_pixels(result)
    points = result.gbuffer_position[pixels[:, 1], pixels[:, 0], :3]
    projected = picking.project(result, points)
    assert np.abs(projected - (pixels + 0.5)).max() < 1e-3
    eye, direction = picking.pixel_ray(result, *pixels[0])
    to_point = points[0] - eye
    assert np.linalg.norm(np.cross(direction, to_point)) < 1e-3 * np.linalg.norm(to_point)


def test_picking_a_cell_gives_its_coefficients_and_its_audit(frame):
    _, result = frame
    i, j, k = np.unravel_index(np.argmax(result.accumulated[0, ..., 0]),
                               result.accumulated.shape[1:4])
    cell = picking.pick_cell(result, 0, i, j, k)
    acc = result.accumulated[:, i, j, k]
    assert np.array_equal(cell.coefficients, acc)
    assert np.allclose(cell.flux, C.SH_FLUX_FACTOR * acc[:, 0].astype(np.float64), rtol=1e-12)
    total = C.SH_FLUX_FACTOR * result.accumulated[..., 0].reshape(3, -1).sum(1)
    assert np.allclose(cell.share, cell.flux / total)
    # acc_N = Σ_t grid_t holds cell by cell
    assert cell.in_flight.shape == (CORNELL.iterations + 1, 3)
    assert np.allclose(cell.accumulated_from_steps, cell.flux, rtol=1e-5)
    assert np.allclose(cell.injected, C.SH_FLUX_FACTOR * result.steps[0][:, i, j, k, 0])
    expected_area = result.geometry_volume[i:i + 2, j:j + 2, k:k + 2, 0].mean() / \
        C.SH_COSLOBE_C0
    assert cell.blocker_area == pytest.approx(expected_area)
    assert picking.pick_cell(result, 0, 16, 0, 0) is None
    assert picking.pick_cell(result, 1, 0, 0, 0) is None        # one cascade only
    assert dict(cell_rows(cell))["cell"] == f"({i}, {j}, {k}) of cascade 0"


def test_the_slice_is_hit_in_front_of_the_surface_only(frame):
    _, result = frame
    spec = result.grid_spec
    # the camera looks down -z into the box: a z slice in the middle of the room is seen
    # at the centre pixel before the back wall
    x, y = 48, 30
    hit = picking.slice_hit(result, spec, "z", 8, x, y)
    assert hit is not None and hit[2] == 8
    eye, direction = picking.pixel_ray(result, x, y)
    plane = spec.origin[2] + 8.5 * spec.cell_size
    point = eye + (plane - eye[2]) / direction[2] * direction
    assert hit == tuple(int(v) for v in spec.cell_index(point)[:2]) + (8,)
    # a layer behind the back wall is hidden, unless the slice is drawn over everything
    back = int(spec.cell_index(result.gbuffer_position[y, x, :3])[2]) - 1
    assert picking.slice_hit(result, spec, "z", back, x, y) is None
    assert picking.slice_hit(result, spec, "z", back, x, y, on_top=True) is not None


def test_a_picked_point_is_found_again_in_the_frame(frame):
    """pixel_of: the pixel that shows a surface point (None when hidden); cell_at: the
    cell holding it."""
    _, result = frame
    for x, y in _surface_pixels(result)[::11]:
        point = result.gbuffer_position[y, x, :3]
        assert picking.pixel_of(result, point) == (x, y)
        assert picking.cell_at(result, 0, point) == tuple(result.grid_spec.cell_index(point))
    # the back wall's point behind the short block is hidden in this frame
    eye = np.asarray(result.camera.eye)
    front = result.gbuffer_position[62, 70, :3]          # the short block
    behind = eye + 1.3 * (front - eye)
    assert picking.pixel_of(result, behind) is None
    assert picking.pixel_of(result, (0.0, 50.0, 0.0)) is None   # out of the image
    assert picking.cell_at(result, 0, (0.0, 50.0, 0.0)) is None


@pytest.mark.parametrize("rect, mouse, pixel", [
    ((100, 50, 500, 350), (100, 50), (0, 0)),
    ((100, 50, 500, 350), (499.9, 349.9), (95, 71)),
    ((100, 50, 500, 350), (300, 200), (48, 36)),
    ((100, 50, 500, 350), (99, 200), None),
    ((100, 50, 500, 350), (300, 350), None),
])
def test_view_pixel_maps_the_view_rect_to_the_image(rect, mouse, pixel):
    """The rect is in framebuffer pixels, the image has its own (render-scaled) size."""
    assert picking.view_pixel(rect, mouse, (96, 72)) == pixel


def test_view_pixel_is_independent_of_the_render_scale():
    rect = (0.0, 0.0, 800.0, 600.0)
    for scale in (0.25, 0.5, 1.0, 2.0):
        size = (int(800 * scale), int(600 * scale))
        x, y = picking.view_pixel(rect, (400.5, 150.5), size)
        assert (x, y) == (int(400.5 / 800 * size[0]), int(150.5 / 600 * size[1]))


# ------------------------------------------------------------------------- quantities
def test_slice_quantities_are_the_grids_values(frame):
    _, result = frame
    grid = result.accumulated.astype(np.float64)
    up = np.array([0.0, 1.0, 0.0])
    intensity = Q.quantity_field(grid, "intensity", up)
    expected = np.einsum("cxyzk,k->xyz", grid, twin.sh_basis(up)) / 3.0
    assert np.allclose(intensity, expected)
    assert np.allclose(Q.quantity_field(grid, "flux"), C.SH_FLUX_FACTOR * grid[..., 0].mean(0))
    assert np.allclose(Q.quantity_field(grid, "sh2"), grid[..., 2].mean(0))
    with pytest.raises(ValueError, match="sh_order 2"):
        Q.quantity_field(grid, "sh5")
    step = Q.slice_field(result, OverlayState(slice_quantity="in-flight", slice_step=3))
    assert np.allclose(step.values, C.SH_FLUX_FACTOR * result.steps[3][..., 0].mean(0))
    assert step.label.startswith("light in flight after step 3")
    signed = Q.slice_field(result, OverlayState(slice_quantity="sh3"))
    assert signed.colour_map == "diverging" and signed.low == -signed.high
    fixed = Q.slice_field(result, OverlayState(slice_scale=2.5, colour_map="heat"))
    assert (fixed.low, fixed.high) == (0.0, 2.5)


@pytest.mark.parametrize("axis", ["x", "y", "z"])
def test_slice_layer_values_sit_under_the_plane_quad(axis):
    """slice_values[i, j] is the cell at (i + ½, j + ½)/N of the quad's u, v edges."""
    spec = GridSpec((-1.0, -2.0, 0.5), 0.25, 4)
    values = np.arange(64, dtype=np.float64).reshape(4, 4, 4)
    layer = 1
    plane = Q.slice_values(values, axis, layer)
    corner, edge_u, edge_v = Q.plane_corners(spec, axis, layer)
    for i in range(4):
        for j in range(4):
            world = corner + (i + 0.5) / 4 * edge_u + (j + 0.5) / 4 * edge_v
            assert plane[i, j] == values[tuple(spec.cell_index(world))]


def test_the_colour_table_is_the_colour_bars_map():
    t = np.linspace(0.0, 1.0, Q.COLOUR_MAP_SIZE)
    assert np.allclose(Q.colour_table("heat"), heat(t))
    assert np.allclose(Q.colour_table("diverging"), diverging(2 * t - 1, 1.0))
    field = Q.SliceField(np.zeros((1, 1, 1)), -2.0, 2.0, "diverging", "", None, 0)
    assert np.allclose(Q.map_colours(np.array([-2.0, 0.0, 2.0]), field),
                       diverging(np.array([-1.0, 0.0, 1.0]), 1.0), atol=1e-2)


def test_a_log_slice_spans_its_decades(frame):
    _, result = frame
    field = Q.slice_field(result, OverlayState(slice_log=True, slice_scale=2.0))
    assert field.log and field.high == 2.0
    assert field.low == pytest.approx(2.0 * 10 ** -Q.LOG_DECADES)
    assert np.allclose(field.position([2.0, field.low, 2.0 * 10 ** (-Q.LOG_DECADES / 2), 0.0,
                                       5.0]), [1.0, 0.0, 0.5, 0.0, 1.0])
    assert field.value_at(0.5) == pytest.approx(2.0 * 10 ** (-Q.LOG_DECADES / 2))
    signed = Q.slice_field(result, OverlayState(slice_log=True, slice_quantity="sh1"))
    assert not signed.log                      # the diverging map stays linear


def test_glyph_lobes_are_the_cells_intensity_and_fit_their_spacing(frame):
    _, result = frame
    overlays = OverlayState(glyphs=True, slice_axis="y", slice_index=5, glyph_sizing="linear")
    glyphs = Q.glyphs(result, overlays)
    assert glyphs.stride == Q.auto_glyph_stride(16) == 1
    directions, _ = Q.glyph_directions()
    lobes = np.abs(glyphs.coefficients.astype(np.float64) @
                   twin.sh_basis(directions.astype(np.float64), 2).T)
    reach = glyphs.scales[:, None] * lobes
    assert reach.max() == pytest.approx(0.5 * glyphs.spacing, rel=1e-5)
    # every glyph lies in layer 5 and shows the mean of its cell's channels
    cells = result.grid_spec.cell_index(glyphs.centres)
    assert np.all(cells[:, 1] == 5)
    first = tuple(cells[0])
    assert np.allclose(glyphs.coefficients[0, :4],
                       result.accumulated[(slice(None),) + first].mean(0), rtol=1e-6)
    # the same lobes at any grid size: stride grows, spacing follows
    big = Q.glyph_cells(OverlayState(), GridSpec((0.0, 0.0, 0.0), 1.0 / 64, 64))
    assert big[1] == 4 and len(big[0]) == 16 * 16
    equal = Q.glyphs(result, OverlayState(glyph_sizing="equal", glyph_scale=2.0))
    peaks = (equal.scales[:, None] * np.abs(
        equal.coefficients.astype(np.float64) @
        twin.sh_basis(directions.astype(np.float64), 2).T)).max(1)
    assert np.allclose(peaks, equal.spacing, rtol=1e-5)
    spec = result.grid_spec
    overlays = OverlayState(glyph_cells="picked")
    overlays.pick("cell", "A", 0, spec.cell_centre(np.array([0, 5, 15])))
    picked = Q.glyph_cells(overlays, spec)[0]
    assert len(picked) == 2 * 3 * 2                 # a corner cell keeps 12 neighbours
    assert [0, 5, 15] in picked.tolist()


def test_vpl_discs_have_their_surfels_area():
    rng = np.random.default_rng(3)
    count = 500
    normals = rng.normal(size=(count, 3))
    vpls = VplArrays(rng.uniform(-1, 1, (count, 3)),
                     normals / np.linalg.norm(normals, axis=1, keepdims=True),
                     rng.uniform(0, 2, (count, 3)), rng.uniform(1, 3, count), 1e-3)
    splats = Q.vpl_splats(vpls, max_radius=1.0)
    order = Q.vpl_order(count)
    assert np.allclose(math.pi * splats.radii ** 2, vpls.surfel_area(True)[order], rtol=1e-5)
    assert np.allclose(splats.positions, vpls.positions[order])
    assert splats.colours.max() <= 1.0 and splats.packed().shape == (count, 10)
    assert Q.vpl_splats(vpls, max_radius=1e-3).radii.max() <= 1e-3
    # thinning to a quarter doubles the radius: the discs cover the same area
    assert vpl_radius_scale(0.7, 125, 500) == pytest.approx(1.4)


def test_blockers_are_the_surfels_the_geometry_volume_holds():
    spec = GridSpec((0.0, 0.0, 0.0), 0.5, 4)
    normal = np.array([0.0, 0.6, 0.8])
    vpls = VplArrays(np.array([[1.0, 1.0, 1.0]]), normal[None], np.ones((1, 3)),
                     np.array([1.0]), 0.02, "orthographic")
    volume = twin.inject_geometry(vpls, spec, mode="one-sided")
    splats = Q.blocker_splats(volume, spec, "one-sided", (0.0, 0.0, -1.0))
    assert splats.count == 1
    assert np.allclose(splats.positions[0], [1.0, 1.0, 1.0])     # on the corner (2, 2, 2)
    assert np.allclose(splats.normals[0], normal, atol=1e-6)
    assert math.pi * splats.radii[0] ** 2 == pytest.approx(0.02, rel=1e-5)
    double = twin.inject_geometry(vpls, spec, mode="double-sided")
    facing = Q.blocker_splats(double, spec, "double-sided", (0.0, 0.0, -1.0))
    assert np.allclose(facing.normals[0], [0.0, 0.0, 1.0])       # no orientation: faces us
    assert math.pi * facing.radii[0] ** 2 == pytest.approx(0.02, rel=1e-5)


def test_wireframe_segments():
    spec = GridSpec((0.0, 0.0, 0.0), 1.0, 3)
    box = Q.grid_box(spec)
    assert box.shape == (12, 2, 3)
    assert np.allclose(np.linalg.norm(box[:, 1] - box[:, 0], axis=1), 3.0)
    lattice = Q.lattice_segments(spec, "y", 0)
    assert lattice.shape == (8, 2, 3) and np.allclose(lattice[..., 1], 0.5)
    assert np.allclose(Q.cell_box(spec, (1, 2, 0)).reshape(-1, 3).min(0), [1, 2, 0])


# ------------------------------------------------------------------------- state
def test_overlay_state_persists_and_refuses_bad_values(tmp_path):
    state = AppState()
    state.overlays = OverlayState(slice=True, slice_axis="x", slice_index=3,
                                  slice_quantity="sh2", vpls=True, vpl_density=0.1,
                                  picked_kind="cell", picked_wx=0.25, picked_wy=-0.5)
    path = tmp_path / "settings.json"
    persist.save_state(state, path)
    loaded = AppState()
    assert persist.load_state(loaded, path) is None
    assert loaded.overlays == state.overlays
    data = json.loads(path.read_text())
    for field, value, complaint in (("slice_axis", "w", "slice_axis"),
                                    ("vpl_density", 3.0, "vpl_density"),
                                    ("glyphs", "yes", "glyphs must be true or false"),
                                    ("no_such", 1, "no_such")):
        bad = json.loads(json.dumps(data))
        bad["overlays"][field] = value
        path.write_text(json.dumps(bad))
        fresh = AppState()
        problem = persist.load_state(fresh, path)
        assert problem and complaint in problem, problem
        assert fresh.overlays == OverlayState()


def _lobe_glyphs(coefficients) -> Q.Glyphs:
    rows = np.zeros((len(coefficients), 9), np.float32)
    rows[:, :4] = coefficients
    return Q.Glyphs(np.zeros((len(rows), 3), np.float32), rows,
                    np.ones(len(rows), np.float32), 1.0, 1)


def test_each_glyph_that_leans_gets_an_arrow_along_its_axis():
    """The arrow follows the band-1 vector in world axes (a cosine lobe around n has
    coefficients (C_L0, −C_L1·n_y, C_L1·n_z, −C_L1·n_x)); it reaches past the lobe's
    surface by AXIS_REACH·scale·|b|; a round lobe and a negative one get none."""
    glyphs = []
    normals = [(1.0, 0.0, 0.0), (0.0, -1.0, 0.0), (0.0, 0.6, 0.8)]
    for n in normals:
        glyphs.append((C.SH_COSLOBE_C0, -C.SH_COSLOBE_C1 * n[1], C.SH_COSLOBE_C1 * n[2],
                       -C.SH_COSLOBE_C1 * n[0]))
    glyphs.append((C.SH_COSLOBE_C0, 0.0, 0.0, 0.0))                  # round: no axis
    glyphs.append((-C.SH_COSLOBE_C0, 0.0, 0.0, -C.SH_COSLOBE_C1))    # negative: none
    segments, colours = Q.glyph_axes(_lobe_glyphs(glyphs))
    assert segments.shape == (5 * 3, 2, 3) and colours.shape == (15, 4)
    shafts = segments[:3]
    for shaft, n in zip(shafts, normals):
        axis = shaft[1] - shaft[0]
        assert np.allclose(axis / np.linalg.norm(axis), n, atol=1e-6)
        lean = C.SH_C1 * C.SH_COSLOBE_C1           # |b| of a unit cosine lobe
        lobe = C.SH_C0 * C.SH_COSLOBE_C0 + lean    # f(n)
        assert np.linalg.norm(axis) == pytest.approx(lobe + Q.AXIS_REACH * lean, rel=1e-5)
    # every head stroke starts at its shaft's tip and points back towards the centre
    for k in range(4):
        strokes = segments[3 * (k + 1):3 * (k + 2)]
        assert np.allclose(strokes[:, 0], shafts[:, 1])
        back = np.einsum("gi,gi->g", strokes[:, 1] - strokes[:, 0], shafts[:, 1] - shafts[:, 0])
        assert (back < 0).all()


# ------------------------------------------------------------------------- compositor
@pytest.fixture
def compositor(ctx):
    comp = Compositor(ctx)
    yield comp
    comp.release()


def _picture(compositor, pipeline, result, **overlays) -> np.ndarray:
    compositor.compose("A", result, pipeline.final_texture.glo, False,
                       OverlayState(**overlays))
    return compositor.read("A").astype(np.int16)


def test_the_compositor_shows_the_frame_unchanged_with_no_overlay(frame, compositor):
    pipeline, result = frame
    image = _picture(compositor, pipeline, result)
    display = np.frombuffer(pipeline.final_texture.read(), np.uint8).reshape(
        72, 96, 4)[::-1, :, :3]
    assert np.array_equal(image, display)


@pytest.mark.parametrize("overlay", [
    dict(slice=True), dict(glyphs=True), dict(vpls=True), dict(lattice=True),
    dict(cascade_boxes=True), dict(blockers=True),
    "picked",
])
def test_each_overlay_changes_the_picture_and_runs_no_pass(frame, compositor, overlay):
    pipeline, result = frame
    if overlay == "picked":            # a point on the floor, x, y = 30, 62
        overlay = dict(picked_kind="pixel", picked_wx=float(result.gbuffer_position[62, 30, 0]),
                       picked_wy=float(result.gbuffer_position[62, 30, 1]),
                       picked_wz=float(result.gbuffer_position[62, 30, 2]))
    before = _picture(compositor, pipeline, result)
    keys = dict(pipeline.keys)
    after = _picture(compositor, pipeline, result, **overlay)
    assert np.abs(after - before).sum(axis=2).astype(bool).sum() >= 10, overlay
    assert pipeline.keys == keys and pipeline.last_result is result
    assert compositor.notes["A"] == []


def test_the_glyphs_are_drawn_with_their_axes(frame, compositor):
    """Light arrows over the orange and blue lobes: pixels no glyph colour reaches (the
    lobes' blue channel stays under 40 % where their red is high, and the reverse)."""
    pipeline, result = frame
    before = _picture(compositor, pipeline, result)
    after = _picture(compositor, pipeline, result, glyphs=True, slice_axis="z",
                     slice_index=8)
    changed = np.abs(after - before).sum(axis=2) > 0
    light = after.min(axis=2) > 150
    assert (changed & light).sum() >= 5


def test_the_slice_is_hidden_behind_nearer_surfaces(frame, compositor):
    """Depth test against the frame's G-buffer: where a surface is nearer than the slice
    plane the picture keeps the frame's colour; on top it covers them too."""
    pipeline, result = frame
    before = _picture(compositor, pipeline, result)
    behind = _picture(compositor, pipeline, result, slice=True, slice_axis="z",
                      slice_index=2, slice_opacity=1.0)
    over = _picture(compositor, pipeline, result, slice=True, slice_axis="z",
                    slice_index=2, slice_opacity=1.0, slice_on_top=True)
    spec = result.grid_spec
    plane = spec.origin[2] + 2.5 * spec.cell_size
    eye = np.asarray(result.camera.eye)
    position = result.gbuffer_position
    seen = position[..., 3] > 0.5
    inside = np.zeros(seen.shape, bool)
    for y, x in zip(*np.nonzero(seen)):
        if picking.slice_hit(result, spec, "z", 2, x, y, on_top=True) is not None:
            inside[y, x] = True
    nearer = seen & inside & (np.abs(position[..., 2] - eye[2]) <
                              abs(plane - eye[2]) - 2 * spec.cell_size)
    assert nearer.sum() > 20
    changed = np.abs(behind - before).sum(axis=2) > 0
    assert not changed[nearer].any()
    assert (np.abs(over - before).sum(axis=2) > 0)[nearer].mean() > 0.9


@pytest.mark.parametrize("log", [False, True])
def test_the_slice_shows_each_cells_value_in_the_colour_bars_colour(frame, compositor, log):
    """Every pixel whose ray crosses the slice (drawn opaque, over everything) has the
    colour map's colour of the cell the ray crosses (quantities.map_colours); on a log
    scale the cells below the bar are drawn faint and left out here."""
    pipeline, result = frame
    overlays = dict(slice=True, slice_axis="z", slice_index=7, slice_opacity=1.0,
                    slice_on_top=True, slice_log=log)
    picture = _picture(compositor, pipeline, result, **overlays)
    field = compositor.slice_field("A")
    expected, seen = [], []
    for y in range(0, 72, 3):
        for x in range(0, 96, 3):
            cell = picking.slice_hit(result, field.spec, "z", 7, x, y, on_top=True)
            if cell is not None and field.position(field.values[cell]) > 0:
                expected.append(Q.map_colours(field.values[cell], field))
                seen.append(picture[y, x])
    expected = np.rint(np.asarray(expected) * 255.0)
    assert len(seen) > 50
    close = np.abs(np.asarray(seen) - expected).max(axis=1) <= 2
    assert close.mean() > 0.97          # a few pixels sit on a cell border


def test_an_unchanged_request_draws_nothing_and_a_moved_slice_redraws(frame, compositor):
    pipeline, result = frame
    overlays = OverlayState(slice=True)
    compositor.compose("A", result, pipeline.final_texture.glo, False, overlays)
    drawn = compositor.compositions
    compositor.compose("A", result, pipeline.final_texture.glo, False, overlays)
    assert compositor.compositions == drawn
    first = compositor.read("A")
    overlays.slice_index = 3
    compositor.compose("A", result, pipeline.final_texture.glo, False, overlays)
    assert compositor.compositions == drawn + 1
    assert not np.array_equal(compositor.read("A"), first)
    assert compositor.slice_field("A").spec == result.grid_spec


def test_every_overlay_draw_releases_the_scope_it_binds_its_target_with(frame, compositor,
                                                                        monkeypatch):
    """A moderngl scope dropped without ``release()`` stays alive (the context frees
    nothing itself): each draw of an overlay releases its own; only the render targets'
    scopes, made once per size, live on."""
    import moderngl

    pipeline, result = frame
    overlays = OverlayState(slice=True, glyphs=True, vpls=True, lattice=True,
                            cascade_boxes=True, blockers=True, picked_kind="pixel",
                            picked_wx=float(result.gbuffer_position[62, 30, 0]),
                            picked_wy=float(result.gbuffer_position[62, 30, 1]),
                            picked_wz=float(result.gbuffer_position[62, 30, 2]))
    compositor.compose("A", result, pipeline.final_texture.glo, False, overlays)
    made = []
    scope = moderngl.Context.scope

    def recorded(self, *args, **kwargs):
        made.append(scope(self, *args, **kwargs))
        return made[-1]

    monkeypatch.setattr(moderngl.Context, "scope", recorded)
    overlays.vpl_density, overlays.slice_index = 0.5, 3     # static and top layers redrawn
    static = compositor.static_draws
    compositor.compose("A", result, pipeline.final_texture.glo, False, overlays)
    assert compositor.static_draws == static + 1 and compositor.notes["A"] == []
    assert len(made) >= 5               # background, copy, slice, glyphs, lines, splats
    alive = [s for s in made if not isinstance(s.mglo, moderngl.InvalidObject)]
    assert alive == []


def test_moving_the_slice_reuses_the_layer_of_vpls(frame, compositor):
    pipeline, result = frame
    overlays = OverlayState(slice=True, vpls=True, vpl_density=1.0)
    compositor.compose("A", result, pipeline.final_texture.glo, False, overlays)
    first, static = compositor.read("A"), compositor.static_draws
    for layer in (2, 9, -1):
        overlays.slice_index = layer
        compositor.compose("A", result, pipeline.final_texture.glo, False, overlays)
    assert compositor.static_draws == static
    assert np.array_equal(compositor.read("A"), first)     # back in the middle
    overlays.vpl_density = 0.5
    compositor.compose("A", result, pipeline.final_texture.glo, False, overlays)
    assert compositor.static_draws == static + 1
    assert not np.array_equal(compositor.read("A"), first)


def test_a_missing_input_is_a_note_not_an_error(frame, compositor):
    pipeline, result = frame
    pipeline.invalidate("propagate")   # a frame with kept steps satisfies one without
    no_steps = pipeline.run(CORNELL, keep_steps=False)
    assert no_steps.steps is None
    compositor.compose("A", no_steps, pipeline.final_texture.glo, False,
                       OverlayState(slice=True, slice_quantity="in-flight"))
    assert any("steps" in note for note in compositor.notes["A"])
    compositor.compose("A", no_steps, pipeline.final_texture.glo, False,
                       OverlayState(slice=True, slice_quantity="sh6"))
    assert any("sh_order 2" in note for note in compositor.notes["A"])
    pipeline.run(CORNELL, keep_steps=True)


def test_an_edited_overlay_shader_is_reloaded_and_redrawn(frame, compositor, monkeypatch):
    from explorer.gl import program as program_module

    pipeline, result = frame
    stamp = [program_module.ProgramCache.newest_change()]
    monkeypatch.setattr(program_module.ProgramCache, "newest_change",
                        staticmethod(lambda: stamp[0]))
    overlays = OverlayState(slice=True)
    compositor.compose("A", result, pipeline.final_texture.glo, False, overlays)
    drawn = compositor.compositions
    stamp[0] += 10.0                                   # a shader file changed
    compositor._shader_poll = 0.0
    compositor.compose("A", result, pipeline.final_texture.glo, False, overlays)
    assert compositor.compositions == drawn + 1
    assert compositor.programs.errors == {}


@pytest.mark.parametrize("axis", ["x", "y", "z"])
def test_overlays_follow_each_axis_of_a_grid_of_any_shape(axis):
    """On a 3 × 5 × 2 grid the slice quad, lattice, glyph cells and box span each axis's
    own cells."""
    spec = GridSpec((0.0, 0.0, 0.0), 0.5, (3, 5, 2))
    a, u, v = Q.plane_axes(axis)
    corner, edge_u, edge_v = Q.plane_corners(spec, axis, 0)
    assert edge_u[u] == 0.5 * spec.cells[u] and edge_v[v] == 0.5 * spec.cells[v]
    lattice = Q.lattice_segments(spec, axis, 0)
    assert len(lattice) == spec.cells[u] + spec.cells[v] + 2
    cells, stride = Q.glyph_cells(OverlayState(slice_axis=axis, glyph_stride=1), spec)
    assert stride == 1 and len(cells) == spec.cells[u] * spec.cells[v]
    assert np.all(cells[:, a] == Q.slice_layer(OverlayState(), spec.cells[a]))
    assert np.all(spec.inside(cells))
    assert Q.layers_along(spec, axis) == spec.cells[a]
    assert np.allclose(Q.grid_box(spec).reshape(-1, 3).max(0), [1.5, 2.5, 1.0])
