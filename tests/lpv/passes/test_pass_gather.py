"""Final gather of a hand-made grid against numpy (docs/MODEL.md "Final gather")."""

from __future__ import annotations

import math

import numpy as np
import pytest
from gather_cases import (
    FILTERS,
    IMAGE,
    TOLERANCE,
    N,
    filtering,
    read_gbuffer,
    smooth_grid,
    visible_points,
)
from lpv_cases import relative_error

from explorer.gl.program import ProgramCache
from explorer.lpv.cascades import SampledGrid
from explorer.lpv.grid import GridSpec
from explorer.lpv.passes.display import DisplayPass, exposed_image
from explorer.lpv.passes.gather import EXACT_FILTER, GatherInputs, linear_filter_error
from explorer.lpv.passes.light_records import ShadowMaps
from explorer.lpv.passes.rsm import read_texture
from explorer.lpv.passes.textures import LpvGrid
from explorer.lpv.twin import light_grid as twin
from explorer.lpv.twin.tonemap import linear_to_srgb


@FILTERS
@pytest.mark.parametrize("damping", [False, True], ids=["plain", "damping"])
def test_indirect_matches_numpy(setup, damping, shader_filter):
    ctx, scene, view, shadow, gbuffer, gather, grid, spec = setup
    values = smooth_grid(spec)
    if damping:   # brighter towards −y: the floor (normal +y) gets light from behind
        values = values[:, :, ::-1].copy()
    grid.write(values)
    with filtering(gather, shader_filter):
        gather.run(gbuffer, ShadowMaps(shadow, view), SampledGrid.single(spec, grid.textures),
                   GatherInputs(damping=damping))
    points, normals, albedo, valid = visible_points(gbuffer)
    indirect = read_texture(gather.targets["indirect"])[..., :3]
    assert valid.mean() > 0.3
    irradiance = twin.gather(values, spec, points, normals, damping)
    assert relative_error(indirect[valid], twin.indirect_radiance(albedo, irradiance)) \
        < TOLERANCE
    assert np.all(indirect[~valid] == 0.0)
    # received = E · pixel area; summed, it is the flux the visible surfaces receive
    received = read_texture(gather.targets["received"])[..., :3]
    area = read_texture(gbuffer.normal)[..., 3]
    assert relative_error(received[valid], irradiance * area[valid, None]) < TOLERANCE
    if damping:   # and damping takes some of it away
        assert irradiance.sum() < 0.99 * twin.gather(values, spec, points, normals).sum()


@pytest.mark.parametrize("damping", [False, True], ids=["plain", "damping"])
def test_the_dx11_gather_matches_numpy(setup, damping):
    """irradiance_gather off: the DX11 shader's clamp+(⟨s, Y(−n)⟩), no 1/h², on the GPU
    as in the twin; and not what the model gathers."""
    ctx, scene, view, shadow, gbuffer, gather, grid, spec = setup
    values = smooth_grid(spec)
    grid.write(values)
    switches = (("u_irradiance_gather", 0),)
    gather.run(gbuffer, ShadowMaps(shadow, view), SampledGrid.single(spec, grid.textures),
               GatherInputs(damping=damping, switches=switches))
    points, normals, albedo, valid = visible_points(gbuffer)
    indirect = read_texture(gather.targets["indirect"])[..., :3]
    dx11 = twin.gather(values, spec, points, normals, damping, irradiance=False)
    assert relative_error(indirect[valid], twin.indirect_radiance(albedo, dx11)) < TOLERANCE
    model = twin.gather(values, spec, points, normals, damping)
    assert relative_error(dx11, model) > 0.5


@FILTERS
def test_l2_indirect_matches_numpy(setup, shader_filter):
    """sh_order 2: E = <s, lobe_L2(−n)>/cell², with s sampled trilinearly from the 3 texel
    groups stacked along z (clamped to each group's own edge)."""
    ctx, scene, view, shadow, gbuffer, gather, _, _ = setup
    # the back wall (z = −0.7) at grid z = 0.2: below the first texel centre, where a
    # plain lookup into the stacked texture would blend in another group
    spec = GridSpec((-1.0, -1.0, -0.75), 0.25, N)
    values = np.concatenate([smooth_grid(spec), np.zeros((3, N, N, N, 5), np.float32)], -1)
    idx = np.indices((N, N, N)).transpose(1, 2, 3, 0) / N
    for k in range(4, 9):   # band 2 varying along z, so a blend across groups would show
        values[..., k] = 0.006 * (k - 6) * (1.0 + idx[..., 2] - idx[..., k % 3])
    grid = LpvGrid(ctx, N, sh_order=2)
    try:
        grid.write(values)
        with filtering(gather, shader_filter):
            gather.run(gbuffer, ShadowMaps(shadow, view),
                       SampledGrid.single(spec, grid.textures, sh_order=2))
    finally:
        grid.release()
    points, normals, albedo, valid = visible_points(gbuffer)
    indirect = read_texture(gather.targets["indirect"])[..., :3]
    assert (spec.grid_coords(points)[:, 2] < 0.5).sum() > 20
    expected = twin.indirect_radiance(albedo, twin.gather(values, spec, points, normals))
    assert relative_error(indirect[valid], expected) < TOLERANCE
    l1_only = twin.indirect_radiance(albedo, twin.gather(values[..., :4], spec, points,
                                                       normals))
    assert relative_error(indirect[valid], l1_only) > 100 * TOLERANCE


def test_pixel_areas_add_up_to_the_visible_surface(setup):
    ctx, scene, view, shadow, gbuffer, gather, grid, spec = setup
    position = read_texture(gbuffer.position)
    area = read_texture(gbuffer.normal)[..., 3]
    floor = (position[..., 3] > 0.5) & np.isclose(position[..., 1], -0.5, atol=1e-4)
    # every floor pixel covers the floor's area seen through it: a fraction of 1.8²
    assert 0.0 < area[floor].sum() < 1.8 * 1.8
    assert np.all(area[floor] > 0)


def test_direct_light_is_the_shadowed_lambertian(setup):
    ctx, scene, view, shadow, gbuffer, gather, grid, spec = setup
    grid.clear()
    gather.run(gbuffer, ShadowMaps(shadow, view), SampledGrid.single(spec, grid.textures))
    position, normal, albedo, valid = read_gbuffer(gbuffer)
    direct = read_texture(gather.targets["direct"])[..., :3]
    offset = np.asarray(scene.light.position) - position[..., :3]
    r2 = np.sum(offset**2, axis=-1)
    cos = np.sum(normal * offset, axis=-1) / np.sqrt(r2)
    # inside the spot's frustum (with a margin for the frustum edge)
    to_point = -offset / np.sqrt(r2)[..., None]
    axis = view.direction
    local = to_point @ view.view[:3, :3].T
    inside = np.all(np.abs(local[..., :2] / -local[..., 2:3]) < 0.9, axis=-1)
    pick = valid & inside & (cos > 0.2)
    assert pick.sum() > 100
    expected = albedo * (scene.light.flux / (4 * math.pi)) * (cos / r2)[..., None] / math.pi
    assert np.allclose(direct[pick], expected[pick], rtol=1e-3)
    assert axis[1] < 0
    # outside the frustum: no direct light
    outside = valid & ~np.all(np.abs(local[..., :2] / -local[..., 2:3]) < 1.05, axis=-1)
    assert np.all(direct[outside] == 0.0)


def test_display_pass_exposes_and_encodes_the_linear_buffers(setup):
    """The display stage (shaders/display.glsl): exposure·(direct + indirect), or
    exposure·indirect, clipped and sRGB-encoded; the gather itself stays linear."""
    ctx, scene, view, shadow, gbuffer, gather, grid, spec = setup
    grid.write(smooth_grid(spec))
    gather.run(gbuffer, ShadowMaps(shadow, view), SampledGrid.single(spec, grid.textures))
    direct = read_texture(gather.targets["direct"])[..., :3]
    indirect = read_texture(gather.targets["indirect"])[..., :3]
    assert direct.max() > 0 and indirect.max() > 0
    display = DisplayPass(ctx, ProgramCache(ctx))
    width, height = IMAGE
    try:
        for indirect_only in (False, True):
            shown_linear = indirect if indirect_only else direct + indirect
            exposure = 2.0 / float(shown_linear.max())   # the brightest pixels clip
            texture = display.run(gather.targets["direct"], gather.targets["indirect"],
                                  exposure, indirect_only)
            shown = np.frombuffer(texture.read(), np.uint8).reshape(
                height, width, 4)[::-1, :, :3] / 255.0
            exposed = exposed_image(direct, indirect, exposure, indirect_only)
            assert np.allclose(exposed, exposure * shown_linear, rtol=1e-6, atol=1e-8)
            assert np.allclose(shown, linear_to_srgb(exposed), atol=1.5 / 255)
            assert np.any(shown == 1.0) and np.any((shown > 0.05) & (shown < 0.95))
    finally:
        display.release()


def test_the_gather_filters_in_the_shader_where_the_texture_unit_is_not_exact(setup):
    """filter_probe.glsl measures the texture unit's weights: any conformant filter errs by
    less than 1/256 (8 fractional bits); the gather interpolates in the shader exactly when
    the error is above EXACT_FILTER (llvmpipe: about 1e-7, so the texture unit is used)."""
    ctx, *_, gather, _, _ = setup
    error = linear_filter_error(ctx)
    assert 0.0 <= error < 2.0 ** -8
    assert gather.shader_filter == (error > EXACT_FILTER)
    assert linear_filter_error(ctx) == error   # measured once per context
