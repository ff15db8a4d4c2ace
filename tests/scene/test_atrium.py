"""The procedural ``atrium`` scene: size, determinism, closed solids with outward normals,
the fly-through path, and a headless frame with cascades."""

from __future__ import annotations

import math

import numpy as np
import pytest

from explorer.lpv.pipeline import Pipeline
from explorer.lpv.settings import Settings
from explorer.scene import BUILTIN_SCENES, load_scene
from explorer.scene import atrium as at


@pytest.fixture(scope="module")
def scene():
    return load_scene("atrium")


def solid(part) -> object:
    """A trimesh of a ``(tris, normals)`` part with its coincident corners merged."""
    trimesh = pytest.importorskip("trimesh")
    tris = np.asarray(part[0], np.float64)
    mesh = trimesh.Trimesh(tris.reshape(-1, 3), np.arange(len(tris) * 3).reshape(-1, 3),
                           process=False)
    mesh.merge_vertices(digits_vertex=6)
    return mesh


def test_atrium_is_large_built_in_and_deterministic(scene):
    assert "atrium" in BUILTIN_SCENES
    assert scene.triangle_count >= 100_000
    again = at.atrium()
    for name in ("positions", "normals", "albedo"):
        assert np.array_equal(getattr(scene, name), getattr(again, name))
    assert np.allclose(np.linalg.norm(scene.normals, axis=1), 1.0, atol=1e-5)
    assert np.all(scene.positions >= np.asarray(scene.bounds_min) - 1e-5)
    assert np.all(scene.positions <= np.asarray(scene.bounds_max) + 1e-5)
    # the drapes bring four colours besides the stone
    colours = {tuple(np.round(c, 3)) for c in np.unique(scene.albedo, axis=0)}
    for colour in at.DRAPE_COLOURS:
        assert tuple(np.round(np.float32(colour), 3)) in colours


@pytest.mark.parametrize("part", [
    at.cylinder((1.0, -2.0), 0.5, 3.0, 0.3, rings=5),
    at.box((1.0, 2.0, 3.0), (0.5, 1.5, 2.0)),
    at.arcade_wall(at.GROUND, 6.0),
    at.arcade_wall(at.UPPER, -6.0),
], ids=["cylinder", "box", "ground-arcade", "upper-arcade"])
def test_solids_are_closed_and_wound_outwards(part):
    mesh = solid(part)
    assert mesh.is_watertight and mesh.is_winding_consistent
    assert mesh.volume > 0.0                      # counter-clockwise seen from outside
    tris, normals = part
    face = np.cross(tris[:, 1] - tris[:, 0], tris[:, 2] - tris[:, 0])
    assert np.all(np.einsum("ij,ij->i", face, normals.sum(axis=1)) > 0.0)


def test_arcade_wall_volume_is_the_slab_minus_the_arches():
    storey = at.GROUND
    mesh = solid(at.arcade_wall(storey, 0.0))
    arch, _ = at.arch_profile(storey.arch_radius, at.PITCH / 2, storey.top - storey.spring)
    x, y = arch[:, 0], arch[:, 1]
    opening = 0.5 * abs(np.dot(x, np.roll(y, -1)) - np.dot(y, np.roll(x, -1)))  # shoelace
    slab = at.BAYS * at.PITCH * (storey.top - storey.spring)
    expected = (slab - at.BAYS * opening) * at.WALL_THICKNESS
    assert mesh.volume == pytest.approx(expected, rel=1e-9)
    assert opening == pytest.approx(math.pi * storey.arch_radius**2 / 2, rel=2e-3)


def test_column_normals_point_away_from_the_axis():
    tris, normals = at.cylinder((2.0, 3.0), 0.0, 4.0, 0.3, rings=4)
    side = np.abs(normals[..., 1]) < 0.5
    radial = tris[..., [0, 2]] - np.array([2.0, 3.0])
    outward = np.einsum("...i,...i->...", radial, normals[..., [0, 2]])
    assert np.all(outward[side] > 0.29 * 0.99)
    assert np.allclose(np.linalg.norm(radial[side], axis=-1), 0.3)


def test_fly_through_passes_the_keyframes_smoothly_inside_the_courtyard():
    keys = np.asarray(at.FLY_THROUGH)
    count = len(keys)
    for k in range(count):
        eye, target = at.fly_through(k / count)
        assert np.allclose(eye, keys[k, 0]) and np.allclose(target, keys[k, 1])
    assert np.allclose(at.fly_through(1.25)[0], at.fly_through(0.25)[0])       # a loop
    t = np.linspace(0.0, 1.0, 20001)
    eye, target = at.fly_through(t)
    # inside the open courtyard, clear of the columns, between the floor and the roofs
    assert np.all(np.abs(eye[:, 0]) < at.END_WALL_X - 1.0)
    assert np.all(np.abs(eye[:, 2]) < at.ARCADE_Z - 1.0)
    assert np.all((eye[:, 1] > 1.0) & (eye[:, 1] < at.HEIGHT - 1.0))
    # C¹: the velocity just before and just after every keyframe agree
    h = 1e-6
    for k in range(count):
        joint = k / count
        before = (at.fly_through(joint)[0] - at.fly_through(joint - h)[0]) / h
        after = (at.fly_through(joint + h)[0] - at.fly_through(joint)[0]) / h
        assert np.allclose(before, after, rtol=1e-3, atol=1e-3 * np.abs(after).max())
    # and the camera never jumps: bounded speed along the whole loop
    speed = np.linalg.norm(np.diff(eye, axis=0), axis=1) / (t[1] - t[0])
    assert speed.max() < 3.0 * speed.mean()
    assert np.all(np.linalg.norm(target - eye, axis=1) > 3.0)   # always looking somewhere


def test_atrium_renders_with_three_cascades(ctx):
    settings = Settings(scene="atrium", cascades=3, width=96, height=64, rsm_size=128,
                        grid_size=16, iterations=8)
    with Pipeline(settings, ctx=ctx) as pipeline:
        result = pipeline.run()
        cascade_image = pipeline.view("cascade-weights")
        position = pipeline.state.gbuffer.position
    assert len(result.cascade_specs) == 3
    assert all(np.all(audit.injected > 0) for audit in result.cascade_audits)
    assert np.isfinite(result.final_image).all() and result.final_image.max() > 0
    assert np.all(result.audit.gathered > 0)
    # every cascade is used somewhere on screen (each has its own colour)
    used = {tuple(np.round(c, 2)) for c in cascade_image.reshape(-1, 3)}
    assert len(used) >= 3
    # the sunlit drapes throw colour onto the floor: the indirect irradiance there (its
    # radiance over the floor's grey albedo) is far from grey at many pixels, more than
    # the stone's own tint (0.62/0.50 = 1.24) explains
    floor = (position[..., 3] > 0.5) & (np.abs(position[..., 1]) < 1e-3)
    irradiance = result.indirect[floor] / result.albedo[floor]
    irradiance = irradiance[irradiance.min(axis=1) > 0]
    assert len(irradiance) > 500
    chroma = irradiance.max(axis=1) / irradiance.min(axis=1)
    assert np.percentile(chroma, 90) > 1.4
