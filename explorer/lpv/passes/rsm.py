"""Shadow map + reflective shadow map (docs/MODEL.md "Reflective shadow map").

One MRT pass renders, from the light, the world position (w = 1 where a surface was seen),
the normal (w = view depth, also the shadow map of the direct light) and the reflected flux
of every texel. The result is a :class:`~explorer.lpv.vpl.VplTextures`: each texel is a VPL.

Flux per texel. A spot light of total flux Φ_L has intensity I = Φ_L/(4π); a texel of
solid angle ρ lets I·ρ through, all of which lands on the surface the texel sees (a
surface tilted by θ_i covers a footprint of area ρ·r²/cos θ_i at irradiance I·cos θ_i/r²,
so the cosines cancel), and a diffuse surface reflects Φ_o = c_diff·I·ρ. ρ is computed
exactly per texel in the shader from the texel's corner directions. A directional light
of irradiance E gives Φ_o = c_diff·E·A_texel with A_texel the texel's area on a plane
facing the light. Surfaces facing away from the light reflect nothing.

Spot cone (docs/MODEL.md "Spot cone"). A spot with a cone radiates ``I·f(θ)``; its square
frustum is ``2·θ_outer`` wide, and each texel's flux is ``c_diff·I·ρ·f(θ_c)`` with ``θ_c``
the angle of the texel's centre direction from the axis (``f`` from shaders/spot.glsl,
the function the direct light uses too).

Several lights (docs/MODEL.md "Several lights"). Every light that shines has its own RSM
*views* (:func:`light_views`): a spot or a directional light one, a point light six (its
cube-map faces, each the RSM of a cone-less 90° spot of the same flux). A light's colour
scales its flux per channel (``u_light_colour``).
"""

from __future__ import annotations

from collections.abc import Mapping
from dataclasses import dataclass, replace

import moderngl
import numpy as np

from explorer.gl.program import ProgramCache, set_uniforms
from explorer.gl.targets import RenderTargets
from explorer.lpv.rsm_snap import snapped_directional_eye, snapped_light
from explorer.lpv.vpl import VplTextures
from explorer.scene.gpu import SceneBuffers
from explorer.scene.lights import CUBE_FACE_AXES, DirectionalLight, Light, PointLight
from explorer.scene.model import Scene
from explorer.scene.transforms import gl_matrix


@dataclass(frozen=True)
class LightView:
    """How the light sees the scene: matrices and the numbers the shaders need."""

    view: np.ndarray
    projection: np.ndarray
    orthographic: bool
    position: np.ndarray
    direction: np.ndarray
    intensity: float
    """Spot: Φ_L/(4π) [W/sr] (0 for a directional light)."""
    irradiance: float
    """Directional: E [W/m²] on a plane facing the light (0 for a spot)."""
    texel_area: float
    """``VplTextures.texel_area``: spot, area of a texel at view depth 1 (4t²/(W·H));
    directional, world area of a texel."""
    size: int
    spot_cone: bool = False
    """A spot with a cone: intensity I·f(θ) (shaders/spot.glsl); False: f = 1."""
    cone_cosines: tuple[float, float] = (-1.0, -1.0)
    """(cos θ_inner, cos θ_outer) of the cone."""
    frustum_half_width: float = 1.0
    """Spot: t = tan(fov/2), the frustum cuts the plane at view depth 1 in [-t, t]²."""
    colour: tuple[float, float, float] = (1.0, 1.0, 1.0)
    """The light's colour: its flux in channel c is the flux times colour[c]."""
    light_index: int = 0
    """Which of the scene's shining lights (``Scene.lights``) this view belongs to."""
    light_name: str = "light"
    kind: str = "spot"
    """``"spot"``, ``"directional"`` or ``"point"`` (one face of a point light's cube)."""
    face: int = -1
    """A point light's face: index into ``explorer.scene.lights.CUBE_FACE_AXES`` (-1 for
    other lights)."""

    @property
    def texel_world_size(self) -> float:
        """Edge of one texel at view depth 1 (spot) or in world units (directional)."""
        return float(np.sqrt(self.texel_area))

    def uniforms(self) -> dict[str, object]:
        """The light's uniforms, as rsm.glsl and gather.glsl declare them."""
        return {
            "u_light_view": gl_matrix(self.view),
            "u_light_projection": gl_matrix(self.projection),
            "u_orthographic": int(self.orthographic),
            "u_light_position": tuple(map(float, self.position)),
            "u_light_direction": tuple(map(float, self.direction)),
            "u_light_intensity": float(self.intensity),
            "u_light_irradiance": float(self.irradiance),
            # the spot cone's falloff (shaders/spot.glsl, read by both programs)
            "u_spot_cone": int(self.spot_cone),
            "u_spot_cos_inner": float(self.cone_cosines[0]),
            "u_spot_cos_outer": float(self.cone_cosines[1]),
            "u_light_colour": tuple(map(float, self.colour)),
        }

    def rsm_uniforms(self) -> dict[str, object]:
        """:meth:`uniforms` and the map's texel area, size and frustum (rsm.glsl only)."""
        return {**self.uniforms(), "u_texel_world_area": float(self.texel_area),
                "u_rsm_size": (float(self.size), float(self.size)),
                "u_frustum_half_width": float(self.frustum_half_width)}


def light_view(scene: Scene, size: int) -> LightView:
    """The primary light's (first) view for an RSM of ``size``² texels: the light's
    only view, or face +x of a point light (:func:`light_views` gives every view)."""
    return _views_of(scene.light, 0, scene, size)[0]


def light_views(scene: Scene, size: int, snap: bool = False,
                anchors: Mapping[str, Light] | None = None) -> list[LightView]:
    """Every RSM view of the lights that shine (``Scene.lights``, primary first): one per
    spot or directional light, six per point light (docs/MODEL.md "Several lights");
    ``snap`` (``Settings.rsm_snap``): each moved by whole texels only, on the lattice
    through its anchor (``anchors``: light name -> the light as the scene placed it;
    explorer/lpv/rsm_snap.py)."""
    anchors = anchors or {}
    return [view for index, light in enumerate(scene.lights)
            for view in _views_of(light, index, scene, size, snap, anchors.get(light.name))]


def view_count(scene: Scene) -> int:
    """``len(light_views(scene, size))`` without the views' matrices: six per point light,
    one per other light that shines."""
    return sum(len(CUBE_FACE_AXES) if isinstance(light, PointLight) else 1
               for light in scene.lights)


def _views_of(light: Light, index: int, scene: Scene, size: int, snap: bool = False,
              anchor: Light | None = None) -> list[LightView]:
    """The views of one light: its matrices and radiometry for RSMs of ``size``² texels
    (``snap``: on its texel lattice through ``anchor``)."""
    lo, hi = scene.bounds_min, scene.bounds_max
    if snap:
        light = snapped_light(light, lo, hi, size, anchor)
    common = {"size": int(size), "colour": tuple(map(float, light.colour)),
              "light_index": index, "light_name": light.name}
    if isinstance(light, PointLight):
        return [replace(_views_of(face, index, scene, size)[0], kind="point", face=k)
                for k, face in enumerate(light.faces())]
    if isinstance(light, DirectionalLight):
        eye = snapped_directional_eye(light, lo, hi, size, anchor) if snap else \
            light.eye(lo, hi)
        return [LightView(
            view=light.view_matrix(lo, hi, eye), projection=light.projection_matrix(lo, hi),
            orthographic=True, position=eye, direction=light.direction,
            intensity=0.0, irradiance=light.irradiance(lo, hi),
            texel_area=light.texel_area(size, size, lo, hi), kind="directional", **common)]
    return [LightView(
        view=light.view_matrix(lo, hi), projection=light.projection_matrix(lo, hi),
        orthographic=False, position=np.asarray(light.position, np.float64),
        direction=light.direction, intensity=light.intensity, irradiance=0.0,
        texel_area=light.texel_area(size, size, lo, hi), spot_cone=light.has_cone,
        cone_cosines=light.cone_cosines, frustum_half_width=light.frustum_half_width,
        kind="spot", **common)]


class RsmPass:
    """Renders the RSM of a scene into four ``rgba32f`` textures (position, normal, flux,
    albedo) and a depth buffer."""

    def __init__(self, ctx: moderngl.Context, programs: ProgramCache) -> None:
        self.ctx = ctx
        self.programs = programs
        self._targets = RenderTargets(ctx, ("f4",) * 4, depth=True,
                                      enable=moderngl.DEPTH_TEST)
        # the RSM's size changes only with Settings.rsm_size, never in a drag: a size
        # left is not kept (a 1024² RSM's four targets are 64 MiB)
        self._targets.keep_sizes = 0
        self._uniforms: dict[int, tuple[LightView, dict[str, object]]] = {}
        """id of a view (frozen) -> the view and its ``rsm_uniforms()``: the same dict for
        the same view (a frame's views are the last frame's while the lights are the same:
        the rsm stage keeps them), which ``set_uniforms`` skips as unchanged."""

    def run(self, geometry: SceneBuffers, view: LightView) -> VplTextures:
        """Render the RSM seen by ``view``; the returned textures belong to this pass and
        stay valid until the next run with another size or :meth:`release`."""
        max_size = int(self.ctx.info.get("GL_MAX_TEXTURE_SIZE", 0) or 0)
        if max_size and view.size > max_size:
            raise ValueError(f"rsm_size {view.size} exceeds this driver's GL_MAX_TEXTURE_SIZE "
                             f"{max_size}")
        self._targets.allocate((view.size, view.size))
        program = self.programs.get("rsm.glsl")
        kept = self._uniforms.get(id(view))
        if kept is None or kept[0] is not view:
            if len(self._uniforms) >= 16:
                self._uniforms.clear()
            kept = self._uniforms[id(view)] = (view, view.rsm_uniforms())
        set_uniforms(program, kept[1])
        with self._targets.drawing(clear=True):
            geometry.draw(program)
        position, normal, flux, albedo = self._targets.textures
        return VplTextures(position, normal, flux, texel_area=view.texel_area,
                           projection="orthographic" if view.orthographic else "perspective",
                           albedo=albedo)

    def release(self) -> None:
        self._targets.release()


def read_texture(texture: moderngl.Texture) -> np.ndarray:
    """A float32 RGBA 2D texture as an ``(H, W, 4)`` array, row 0 at the top (the texture's
    last row: OpenGL puts row 0 at the bottom)."""
    width, height = texture.size
    data = np.frombuffer(texture.read(), dtype=np.float32).reshape(height, width, 4)
    return data[::-1].copy()
