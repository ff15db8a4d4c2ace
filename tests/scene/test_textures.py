"""Base-colour textures sampled per pixel (G-buffer albedo, RSM flux) with mipmaps, and
the RSM's radiometry with a texture (docs/MODEL.md "Textures")."""

from __future__ import annotations

import numpy as np
import pytest
import trimesh
from PIL import Image

from explorer.lpv.passes.gbuffer import GBufferPass
from explorer.lpv.passes.rsm import RsmPass, light_view
from explorer.scene import Camera, Scene, SpotLight, load_scene
from explorer.scene.gpu import SceneBuffers
from explorer.scene.meshes import srgb_to_linear

TEXELS = 64
CELL = 8                      # texels per checker cell
LIGHT_SRGB, DARK_SRGB, MARK_SRGB = (230, 200, 40), (30, 60, 200), (20, 220, 20)
# the quad y = 0, x and z in [-1, 1], facing +y; u = (x + 1)/2, v = (1 − z)/2
CORNERS = np.array([(-1, 0, 1), (1, 0, 1), (1, 0, -1), (-1, 0, -1)], np.float64)
UV = np.array([(0, 0), (1, 0), (1, 1), (0, 1)], np.float64)
FACES = np.array([[0, 1, 2], [0, 2, 3]])
# a spot 1 m above the quad's centre: its 90° frustum meets the quad's plane in exactly
# the quad, so each RSM texel of a 64² RSM sees exactly one texel of the texture
SPOT = SpotLight((0.0, 1.0, 0.0), (0.0, 0.0, 0.0), 10.0)
CAMERA = Camera((0.0, 1.6, 1.2), (0.0, 0.0, 0.0), 60.0)


def checker_srgb(marker: bool = True) -> np.ndarray:
    """(64, 64, 3) uint8: an 8×8 checker; with ``marker`` the image's top-left cell is
    green (so a flipped or turned texture is caught)."""
    index = np.arange(TEXELS) // CELL
    dark = (index[:, None] + index[None, :]) % 2 == 1
    image = np.where(dark[..., None], np.array(DARK_SRGB), np.array(LIGHT_SRGB))
    if marker:
        image[:CELL, :CELL] = MARK_SRGB
    return image.astype(np.uint8)


def linear(srgb) -> np.ndarray:
    return srgb_to_linear(np.asarray(srgb, np.float64) / 255.0).astype(np.float32)


def quad_scene(albedo=(1.0, 1.0, 1.0), texture: np.ndarray | None = None) -> Scene:
    """The quad, untextured with ``albedo`` or textured (factor ``albedo``) by the linear
    image ``texture``."""
    corners = CORNERS[FACES].reshape(-1, 3).astype(np.float32)
    normals = np.tile(np.float32([0, 1, 0]), (6, 1))
    fields = {}
    if texture is not None:
        fields = {"uv": UV[FACES].reshape(-1, 2).astype(np.float32), "textures": (texture,),
                  "triangle_texture": np.zeros(2, np.int64)}
    return Scene("quad", corners, normals, np.tile(np.float32(albedo), (6, 1)), CAMERA,
                 SPOT, (-1.0, -1.0, -1.0), (1.0, 1.0, 1.0), **fields)


def glb_quad(path) -> Scene:
    """The checker quad written as glTF (baseColorTexture, factor 1) and loaded back."""
    material = trimesh.visual.material.PBRMaterial(
        baseColorTexture=Image.fromarray(checker_srgb(), "RGB"),
        baseColorFactor=[255, 255, 255, 255], doubleSided=True)
    mesh = trimesh.Trimesh(CORNERS, FACES, process=False,
                           visual=trimesh.visual.TextureVisuals(uv=UV, material=material))
    mesh.export(path)
    scene = load_scene(str(path))
    return Scene("quad", scene.positions, scene.normals, scene.albedo, CAMERA, SPOT,
                 (-1.0, -1.0, -1.0), (1.0, 1.0, 1.0), uv=scene.uv, textures=scene.textures,
                 triangle_texture=scene.triangle_texture)


def read(texture) -> np.ndarray:
    width, height = texture.size
    return np.frombuffer(texture.read(), np.float32).reshape(height, width, 4).copy()


def rsm_arrays(ctx, programs, scene: Scene) -> tuple[np.ndarray, np.ndarray]:
    """(position, flux) of the spot's 64² RSM of ``scene``."""
    geometry, rsm = SceneBuffers(ctx, scene), RsmPass(ctx, programs)
    try:
        textures = rsm.run(geometry, light_view(scene, TEXELS))
        return read(textures.position), read(textures.flux)
    finally:
        rsm.release()
        geometry.release()


def gbuffer_arrays(ctx, programs, scene: Scene, size=(160, 120)):
    """(position, albedo) of the camera's G-buffer of ``scene``."""
    geometry, gbuffer = SceneBuffers(ctx, scene), GBufferPass(ctx, programs)
    try:
        gbuffer.run(geometry, scene, size)
        return read(gbuffer.position), read(gbuffer.albedo)
    finally:
        gbuffer.release()
        geometry.release()


def texel_of(position: np.ndarray) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """(row, column) of the texel a world position on the quad shows, and its distance in
    texels to the nearest cell edge."""
    u = (position[..., 0] + 1.0) / 2.0
    v = (1.0 - position[..., 2]) / 2.0
    s, t = u * TEXELS, (1.0 - v) * TEXELS           # texel coordinates, row 0 at the top
    column = np.clip(s.astype(int), 0, TEXELS - 1)
    row = np.clip(t.astype(int), 0, TEXELS - 1)
    to_edge = np.minimum(np.minimum(s % CELL, CELL - s % CELL), np.minimum(t % CELL,
                                                                          CELL - t % CELL))
    return row, column, to_edge


def test_loaded_checker_keeps_its_texture_and_uv(tmp_path):
    scene = glb_quad(tmp_path / "checker.glb")
    assert len(scene.textures) == 1 and scene.textures[0].shape == (TEXELS, TEXELS, 3)
    assert np.array_equal(scene.textures[0], linear(checker_srgb()))
    assert np.allclose(scene.albedo, 1.0)        # the factor; the colour is in the texture


def test_checker_is_per_pixel_in_the_albedo_view(ctx, programs, tmp_path):
    scene = glb_quad(tmp_path / "checker.glb")
    position, albedo = gbuffer_arrays(ctx, programs, scene)
    seen = position[..., 3] == 1.0
    row, column, to_edge = texel_of(position[..., :3])
    expected = linear(checker_srgb())[row, column]
    # away from the cells' edges (where filtering blends two cells) every pixel shows its
    # cell's colour: the texture sampled per pixel, not interpolated between vertices
    inside = seen & (to_edge > 1.0)
    assert inside.sum() > 0.4 * seen.sum()
    assert np.allclose(albedo[inside, :3], expected[inside], atol=2e-3)
    # both colours of the checker and the green marker cell are on screen
    for colour in (LIGHT_SRGB, DARK_SRGB, MARK_SRGB):
        hits = np.all(np.abs(albedo[inside, :3] - linear(colour)) < 2e-3, axis=1)
        assert hits.sum() > 20, colour


def test_checker_is_per_texel_in_the_rsm_flux(ctx, programs, tmp_path):
    textured = glb_quad(tmp_path / "checker.glb")
    position, flux = rsm_arrays(ctx, programs, textured)
    _, white = rsm_arrays(ctx, programs, quad_scene())
    assert np.all(position[..., 3] == 1.0)         # the quad fills the RSM
    row, column, to_edge = texel_of(position[..., :3])
    expected = linear(checker_srgb())[row, column]
    # each RSM texel sees one texture texel: flux = (white flux) × that texel's albedo
    inside = to_edge > 0.75
    assert np.allclose(flux[inside, :3], white[inside, :3] * expected[inside], rtol=1e-5,
                       atol=0.0)


def test_constant_texture_reproduces_the_untextured_flux_exactly(ctx, programs):
    colour = linear((180, 120, 60))
    constant = np.broadcast_to(colour, (TEXELS, TEXELS, 3)).copy()
    _, plain = rsm_arrays(ctx, programs, quad_scene(albedo=colour))
    _, textured = rsm_arrays(ctx, programs, quad_scene(texture=constant))
    assert np.array_equal(plain, textured)
    # the camera's slanted view interpolates the untextured albedo with barycentric
    # weights (not exact in float) and blends mip levels for the textured one: both are
    # the colour to a unit or two in the last place
    position, plain_albedo = gbuffer_arrays(ctx, programs, quad_scene(albedo=colour))
    _, textured_albedo = gbuffer_arrays(ctx, programs, quad_scene(texture=constant))
    seen = position[..., 3] == 1.0
    assert seen.sum() > 1000
    for albedo in (plain_albedo, textured_albedo):
        assert np.allclose(albedo[seen, :3], colour, rtol=2.5e-7, atol=0.0)


def test_checker_flux_sum_is_the_texture_mean_prediction(ctx, programs):
    """Σ flux = mean(texture) × Σ white flux: the irradiance under the spot is symmetric
    under x → −x, which swaps the checker's two colours (docs/MODEL.md "Textures")."""
    checker = linear(checker_srgb(marker=False))
    _, flux = rsm_arrays(ctx, programs, quad_scene(texture=checker))
    _, white = rsm_arrays(ctx, programs, quad_scene())
    predicted = checker.reshape(-1, 3).astype(np.float64).mean(axis=0) * \
        white[..., :3].sum(axis=(0, 1), dtype=np.float64)
    assert np.allclose(flux[..., :3].sum(axis=(0, 1), dtype=np.float64), predicted, rtol=1e-5)


def test_mipmaps_average_the_checker_far_away(ctx, programs):
    """Seen from far, a texel of the view covers many checker cells: the trilinear
    (mipmapped) lookup returns about the mean albedo, not one cell's colour (aliasing)."""
    checker = linear(checker_srgb(marker=False))
    scene = quad_scene(texture=checker)
    far = Scene("far", scene.positions, scene.normals, scene.albedo,
                Camera((0.0, 40.0, 0.01), (0.0, 0.0, 0.0), 20.0), SPOT, scene.bounds_min,
                scene.bounds_max, uv=scene.uv, textures=scene.textures,
                triangle_texture=scene.triangle_texture)
    # 16² pixels: the quad covers about 3 × 3, each pixel about 23 × 23 texels (mip level
    # 4.5: levels 4 and 5, whose texels are 2 × 2 and 4 × 4 whole cells)
    position, albedo = gbuffer_arrays(ctx, programs, far, size=(16, 16))
    seen = position[..., 3] == 1.0
    assert seen.sum() >= 4
    mean = checker.reshape(-1, 3).mean(axis=0)
    assert np.allclose(albedo[seen, :3], mean, rtol=1e-3)


@pytest.mark.parametrize("writer", ["obj", "glb"])
def test_map_kd_and_base_colour_texture_load(tmp_path, writer):
    image = Image.fromarray(checker_srgb(), "RGB")
    if writer == "obj":
        visual = trimesh.visual.TextureVisuals(uv=UV, image=image)
    else:
        visual = trimesh.visual.TextureVisuals(uv=UV, material=(
            trimesh.visual.material.PBRMaterial(baseColorTexture=image,
                                                baseColorFactor=[128, 255, 255, 255])))
    path = tmp_path / f"quad.{writer}"
    trimesh.Trimesh(CORNERS, FACES, process=False, visual=visual).export(path)
    scene = load_scene(str(path))
    assert np.array_equal(scene.textures[0], linear(checker_srgb()))
    # OBJ: map_Kd alone (trimesh writes Kd 0.4 beside it); glTF: the linear factor
    factor = [1.0, 1.0, 1.0] if writer == "obj" else [128 / 255, 1.0, 1.0]
    assert np.allclose(scene.albedo, factor)
    # the per-vertex approximation samples each corner's texel: (0, 0) is the image's
    # bottom-left corner, (0, 1) its top-left (the green marker)
    corner_albedo = scene.corner_albedo()
    top_left = np.flatnonzero(np.all(np.isclose(scene.uv, (0.0, 1.0)), axis=1))
    assert np.allclose(corner_albedo[top_left], linear(MARK_SRGB) * factor, atol=1e-6)


def test_a_huge_texture_is_reduced_to_fit():
    from explorer.scene.meshes import MAX_TEXTURE_EDGE, texture_linear

    wide = Image.new("RGB", (MAX_TEXTURE_EDGE + 8, 4), (200, 10, 10))
    reduced = texture_linear(wide)
    assert max(reduced.shape[:2]) <= MAX_TEXTURE_EDGE
    assert np.allclose(reduced, linear((200, 10, 10)))
