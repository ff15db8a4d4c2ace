"""Numpy twin of what goes beyond diffuse one-bounce LPV: camera occluders, fog and
glossy reflections (docs/MODEL.md "Camera occluders", "Fog", "Glossy reflections").

Written from docs/MODEL.md, in float64, beside :mod:`explorer.lpv.twin.light_grid` (whose SH
basis, trilinear lookup and constants it uses: every constant is the float64 value of its
exact derivation). Images and maps are arrays with row 0 at the top, as
:class:`~explorer.lpv.frame.FrameResult` holds them; a pixel ``(row, column)`` of an
``H``-row image is GL texel ``(column, H − 1 − row)``.

* :class:`ViewLight` and :class:`LightMap`: one RSM view's light (``light_arrival`` of
  ``shaders/light_records.glsl``) and its shadow map; :func:`light_map_reaches`: the
  shadow-map test of ``shaders/light_map.glsl``;
* :func:`camera_surfels`: the G-buffer pixels that become occluder surfels (those no view
  holds), with their areas (``CAMERA_SURFELS`` in ``shaders/geometry_inject.glsl``);
* :func:`lobe_radiance`: the LPV's radiance through a Henyey–Greenstein lobe
  (``shaders/lpv_lobe.glsl``), the building block of the next two;
* :func:`march_fog`: the fog's transmittance and in-scattered radiance along view rays
  (``shaders/fog.glsl``);
* :func:`glossy`: the glossy march of the final gather (``shaders/glossy.glsl``).
"""

from __future__ import annotations

from collections.abc import Sequence
from dataclasses import dataclass

import numpy as np

from explorer.lpv.cascades import blend_weights
from explorer.lpv.grid import GridSpec
from explorer.lpv.twin.light_grid import K, grid_sh_order, sample_grid, sh_basis
from explorer.lpv.vpl import VplArrays
from explorer.scene.lights import spot_falloff

MAX_SLOPE = 10.0
"""tan θ cap of the camera surfels' reprojection bias (grazing light)."""
DEPTH_SLACK = 1e-4
"""Share of the depth every shadow-map comparison allows for float rounding."""
FOG_BIAS_TEXELS = 1.0
"""The fog's shadow test bias in texel footprints."""


@dataclass(frozen=True)
class LightMap:
    """One RSM view's shadow map as the twin reads it: ``view`` and ``projection``
    (4×4, world → clip), whether it is orthographic, a texel's edge at depth 1 (spot) or in
    world units (``LightView.texel_world_size``), and the RSM's position ``(H, W, 4)``
    (w = seen) and normal ``(H, W, 4)`` (w = view depth) arrays, row 0 at the top."""

    view: np.ndarray
    projection: np.ndarray
    orthographic: bool
    texel: float
    position: np.ndarray
    normal: np.ndarray

    @classmethod
    def of(cls, light, position: np.ndarray, normal: np.ndarray) -> LightMap:
        """From a :class:`~explorer.lpv.passes.rsm.LightView` and the frame's RSM arrays."""
        return cls(np.asarray(light.view, np.float64), np.asarray(light.projection, np.float64),
                   bool(light.orthographic), float(light.texel_world_size),
                   np.asarray(position), np.asarray(normal))


@dataclass(frozen=True)
class ViewLight:
    """The light of one RSM view, as the gather and the fog see it
    (``light_arrival`` in shaders/light_records.glsl): a spot (``position``, ``axis``,
    ``intensity`` Φ_L/(4π), its cone's cosines or None), one face of a point light
    (``axis`` the face's axis: it lights only the points whose direction from the light
    falls in that face), or a directional light (``axis`` its direction of travel,
    ``irradiance`` E); ``colour`` scales every channel."""

    kind: str
    position: np.ndarray
    axis: np.ndarray
    intensity: float
    irradiance: float
    cone_cosines: tuple[float, float] | None
    colour: np.ndarray

    @classmethod
    def of(cls, view) -> ViewLight:
        """From a :class:`~explorer.lpv.passes.rsm.LightView`."""
        return cls(str(view.kind), np.asarray(view.position, np.float64),
                   np.asarray(view.direction, np.float64), float(view.intensity),
                   float(view.irradiance),
                   tuple(view.cone_cosines) if view.spot_cone else None,
                   np.asarray(view.colour, np.float64))

    def to_light(self, points: np.ndarray) -> np.ndarray:
        """(P, 3) unit directions from each point towards the light."""
        points = np.asarray(points, np.float64)
        if self.kind == "directional":
            return np.broadcast_to(-self.axis, points.shape)
        offset = self.position - points
        return offset / np.sqrt(np.maximum(np.sum(offset * offset, axis=1), 1e-12))[:, None]

    def arrival(self, points: np.ndarray) -> np.ndarray:
        """(P,) irradiance on a plane facing the light, without colour or shadow: I·f/r²
        (spot), I/r² where this point-light face holds the point (else 0), E
        (directional)."""
        points = np.asarray(points, np.float64)
        if self.kind == "directional":
            return np.full(len(points), self.irradiance)
        travel = points - self.position
        distance_squared = np.maximum(np.sum(travel * travel, axis=1), 1e-12)
        falloff = 1.0 if self.cone_cosines is None else spot_falloff(
            (travel / np.sqrt(distance_squared)[:, None]) @ self.axis, *self.cone_cosines)
        irradiance = self.intensity / distance_squared * falloff
        if self.kind == "point":
            irradiance = np.where(in_cube_face(travel, self.axis), irradiance, 0.0)
        return irradiance


def in_cube_face(directions: np.ndarray, axis: np.ndarray) -> np.ndarray:
    """(P,) whether each direction falls in the cube face whose axis is ``axis``: its
    largest |component| (ties going to x, then y, then z) is the face's, with its sign
    (docs/MODEL.md "Several lights")."""
    directions = np.asarray(directions, np.float64)
    magnitude = np.abs(directions)
    major = np.where((magnitude[:, 0] >= magnitude[:, 1]) & (magnitude[:, 0] >= magnitude[:, 2]),
                     0, np.where(magnitude[:, 1] >= magnitude[:, 2], 1, 2))
    face = int(np.argmax(np.abs(axis)))
    return (major == face) & (directions[:, face] * axis[face] > 0)


def view_lights(views, rsm_positions: Sequence[np.ndarray], rsm_normals: Sequence[np.ndarray]
                ) -> list[tuple[ViewLight, LightMap]]:
    """Each RSM view (:class:`~explorer.lpv.passes.rsm.LightView`) with its shadow map, from the
    views' own RSM position and normal arrays (row 0 at the top)."""
    views = list(views)
    if not len(views) == len(rsm_positions) == len(rsm_normals):
        raise ValueError(f"{len(views)} views need as many RSM position and normal arrays")
    return [(ViewLight.of(view), LightMap.of(view, position, normal))
            for view, position, normal in zip(views, rsm_positions, rsm_normals)]


def _homogeneous(points: np.ndarray) -> np.ndarray:
    points = np.asarray(points, np.float64)
    return np.concatenate([points, np.ones(points.shape[:-1] + (1,))], -1)


def light_map_reaches(points: np.ndarray, light: LightMap, bias_texels) -> np.ndarray:
    """(P,) whether the light reaches each world point: inside its frustum, and no surface
    the map stores in the texel the point falls in lies more than ``bias_texels`` texel
    footprints (plus 10⁻⁴ of the depth) in front of it; a texel that saw nothing hides
    nothing (shaders/light_map.glsl)."""
    view_points = _homogeneous(points) @ light.view.T
    clip = view_points @ light.projection.T
    depth = -view_points[:, 2]
    footprint = light.texel if light.orthographic else light.texel * depth
    w = clip[:, 3]
    safe_w = np.where(w > 0, w, 1.0)
    ndc = clip[:, :2] / safe_w[:, None]
    inside = (w > 0) & np.all(np.abs(ndc) <= 1.0, axis=1)
    rows, columns = light.normal.shape[:2]
    size = np.array([columns, rows])
    texel = np.clip(np.floor((ndc * 0.5 + 0.5) * size).astype(np.int64), 0, size - 1)
    row = rows - 1 - texel[:, 1]
    seen = light.position[row, texel[:, 0], 3] > 0.5
    stored = light.normal[row, texel[:, 0], 3].astype(np.float64)
    bias = footprint * np.asarray(bias_texels, np.float64) + DEPTH_SLACK * depth
    return inside & (~seen | (depth <= stored + bias))


def camera_pixel_area(fov_y_degrees: float, height: int) -> float:
    """``(2·tan(fov_y/2)/H)²`` (docs/MODEL.md "Camera occluders")."""
    return (2.0 * np.tan(np.radians(fov_y_degrees) / 2.0) / height) ** 2


def camera_surfels(position: np.ndarray, normal: np.ndarray, albedo: np.ndarray, camera,
                   views: Sequence[tuple[ViewLight, LightMap]]) -> VplArrays:
    """The G-buffer pixels that become occluder surfels: every pixel that shows a surface
    no RSM view of ``views`` reaches (each view's shadow test with the bias (√2/2)·tan θ
    texels, θ the angle between the normal and that view's light ray, tan θ ≤ 10). Each
    is a "VPL" without flux whose ``depth`` is its view depth from the camera and whose
    ``texel_area`` is the pixel's area at depth 1, so
    :func:`explorer.lpv.twin.light_grid.inject_geometry` gives it the area ``pixel_area·w²``."""
    height = position.shape[0]
    seen = position[..., 3] > 0.5
    points = np.asarray(position[seen, :3], np.float64)
    normals = np.asarray(normal[seen, :3], np.float64)
    held = np.zeros(len(points), bool)
    for light, light_map in views:
        to_light = light.to_light(points)
        cos_light = np.maximum(np.abs(np.sum(normals * to_light, axis=1)), 1e-6)
        tangent = np.minimum(np.sqrt(np.maximum(1.0 - cos_light**2, 0.0)) / cos_light,
                             MAX_SLOPE)
        held |= light_map_reaches(points, light_map, np.sqrt(0.5) * tangent)
    keep = ~held
    depth = -(_homogeneous(points[keep]) @ np.asarray(camera.view_matrix(), np.float64).T)[:, 2]
    return VplArrays(points[keep], normals[keep], np.zeros((int(keep.sum()), 3)), depth,
                     camera_pixel_area(camera.fov_y_degrees, height),
                     albedo=np.asarray(albedo[seen, :3], np.float64)[keep])


# --------------------------------------------------------------------------- the LPV's lobes


def lobe_kernel(direction: np.ndarray, g: float, sh_order: int = 1) -> np.ndarray:
    """(..., K) ``Y(ω)`` with band ``l`` scaled by ``g^l``: the SH of a Henyey–Greenstein
    lobe of asymmetry ``g`` around ``ω`` (derivation media.hg_band_factors)."""
    basis = sh_basis(direction, sh_order)
    factors = np.array([1.0] + [g] * 3 + [g * g] * 5)[: basis.shape[-1]]
    return basis * factors


def lobe_radiance(grids: list[np.ndarray], specs: list[GridSpec], points: np.ndarray,
                  directions: np.ndarray, g: float) -> np.ndarray:
    """(P, 3) radiance travelling in each unit direction at each point, through an HG lobe
    of asymmetry ``g``: ``Σ_k W_k·clamp+(<s_k(x), Y(ω) ⊙ g^l>)/c_k²`` with the cascades'
    blend weights (one grid: ``W_0 = 1``) and trilinear lookups (docs/MODEL.md "Fog")."""
    points = np.asarray(points, np.float64)
    kernel = lobe_kernel(np.asarray(directions, np.float64), g, grid_sh_order(grids[0]))
    weights = blend_weights(list(specs), points)
    total = np.zeros((len(points), 3))
    for k, (grid, spec) in enumerate(zip(grids, specs)):
        samples = sample_grid(grid, spec, points)                  # (3, P, K)
        radiance = np.einsum("cpk,pk->pc", samples, kernel)
        total += weights[:, k:k + 1] * np.maximum(radiance, 0.0) / spec.cell_size**2
    return total


# --------------------------------------------------------------------------- fog


def hg_phase(cosine: np.ndarray, g: float) -> np.ndarray:
    """Henyey–Greenstein phase function, normalised over the sphere (1/(4π) at g = 0)."""
    denominator = 1.0 + g * g - 2.0 * g * np.asarray(cosine, np.float64)
    return K.INV_FOUR_PI * (1.0 - g * g) / denominator**1.5


def direct_inscattering(points: np.ndarray, to_eye: np.ndarray,
                        views: Sequence[tuple[ViewLight, LightMap]], g: float) -> np.ndarray:
    """(P, 3) ``Σ_v κ_v·p(<ω_v, ω_o>)·E⊥_v·V_v`` of the direct light of every RSM view at
    points in the medium, each view tested against its own shadow map."""
    points = np.asarray(points, np.float64)
    total = np.zeros((len(points), 3))
    for light, light_map in views:
        irradiance = light.arrival(points)
        visible = light_map_reaches(points, light_map, FOG_BIAS_TEXELS) & (irradiance > 0)
        cosine = np.sum(-light.to_light(points) * to_eye, axis=1)
        total += np.where(visible, hg_phase(cosine, g) * irradiance, 0.0)[:, None] \
            * light.colour
    return total


def ray_box(origins: np.ndarray, directions: np.ndarray, box_min, box_max
            ) -> tuple[np.ndarray, np.ndarray]:
    """``(t0, t1)`` per ray: its parameter interval inside the box (empty when t1 <= t0)."""
    with np.errstate(divide="ignore", invalid="ignore"):
        inverse = 1.0 / np.asarray(directions, np.float64)
        a = (np.asarray(box_min, np.float64) - origins) * inverse
        b = (np.asarray(box_max, np.float64) - origins) * inverse
    near = np.nan_to_num(np.minimum(a, b), nan=-np.inf)
    far = np.nan_to_num(np.maximum(a, b), nan=np.inf)
    return near.max(axis=1), far.min(axis=1)


def pixel_rays(eye, inverse_view_projection: np.ndarray, position: np.ndarray
               ) -> tuple[np.ndarray, np.ndarray]:
    """``(directions (H, W, 3), distances (H, W))`` of the view rays through each pixel
    centre: to the G-buffer's surface, or (background, distance inf) through the far
    plane of the camera's projection."""
    height, width = position.shape[:2]
    eye = np.asarray(eye, np.float64)
    offset = np.asarray(position[..., :3], np.float64) - eye
    distance = np.linalg.norm(offset, axis=-1)
    rows, columns = np.mgrid[0:height, 0:width]
    ndc = np.stack([(columns + 0.5) / width * 2 - 1, (height - 1 - rows + 0.5) / height * 2 - 1,
                    np.ones_like(rows, dtype=np.float64), np.ones_like(rows, dtype=np.float64)],
                   -1)
    far = ndc @ np.asarray(inverse_view_projection, np.float64).T
    background = far[..., :3] / far[..., 3:] - eye
    background /= np.linalg.norm(background, axis=-1, keepdims=True)
    seen = position[..., 3] > 0.5
    directions = np.where(seen[..., None], offset / np.maximum(distance, 1e-30)[..., None],
                          background)
    return directions, np.where(seen, distance, np.inf)


def march_fog(eye, directions: np.ndarray, distances: np.ndarray, box, grids: list[np.ndarray],
              specs: list[GridSpec], density: float, albedo: float, g: float, steps: int,
              views: Sequence[tuple[ViewLight, LightMap]]
              ) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """``(transmittance (P,), direct (P, 3), lpv (P, 3))`` of view rays from ``eye`` along
    unit ``directions`` that end at ``distances`` (inf: never), in a medium filling
    ``box = (min, max)``, lit by the grids and the RSM ``views`` (:func:`view_lights`)
    (docs/MODEL.md "Fog"): the part of the ray inside the box,
    ``[t0, t1]`` of length ℓ, split into ``steps`` equal segments ``[a, b]`` sampled at
    their midpoints, each weighted by ``α·(T(a) − T(b))``; ``T = exp(−σ_t·ℓ)``."""
    directions = np.asarray(directions, np.float64)
    eye = np.asarray(eye, np.float64)
    origins = np.broadcast_to(eye, directions.shape)
    t0, t1 = ray_box(origins, directions, *box)
    t0 = np.maximum(t0, 0.0)
    t1 = np.minimum(t1, np.asarray(distances, np.float64))
    path = np.maximum(t1 - t0, 0.0)
    step = path / steps
    to_eye = -directions
    direct = np.zeros((len(directions), 3))
    lpv = np.zeros((len(directions), 3))
    marching = path > 0
    for i in range(steps):
        weight = albedo * (np.exp(-density * step * i) - np.exp(-density * step * (i + 1)))
        active = marching & (weight > 0)
        if not active.any():
            continue
        points = eye + (t0[active] + (i + 0.5) * step[active])[:, None] * directions[active]
        direct[active] += weight[active, None] * direct_inscattering(points, to_eye[active],
                                                                     views, g)
        lpv[active] += weight[active, None] * lobe_radiance(grids, specs, points,
                                                            to_eye[active], g)
    return np.exp(-density * path), direct, lpv


# --------------------------------------------------------------------------- glossy


def glossy(grids: list[np.ndarray], specs: list[GridSpec], positions: np.ndarray,
           normals: np.ndarray, eye, roughness: float, strength: float, samples: int
           ) -> np.ndarray:
    """(P, 3) glossy radiance ``k_s·(1/M)·Σ_j L(x_j, −r)`` through an HG lobe of
    ``g = 1 − roughness``, at ``x_j = p + (j + ½)·c_0·r``, ``r`` the view direction
    reflected about the normal (docs/MODEL.md "Glossy reflections")."""
    positions = np.asarray(positions, np.float64)
    normals = np.asarray(normals, np.float64)
    view = positions - np.asarray(eye, np.float64)
    view /= np.linalg.norm(view, axis=1, keepdims=True)
    reflected = view - 2.0 * np.sum(view * normals, axis=1, keepdims=True) * normals
    step = specs[0].cell_size
    total = np.zeros((len(positions), 3))
    for j in range(samples):
        points = positions + (j + 0.5) * step * reflected
        total += lobe_radiance(grids, specs, points, -reflected, 1.0 - roughness)
    return strength * total / samples
