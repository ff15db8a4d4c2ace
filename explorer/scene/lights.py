"""Lights that render a reflective shadow map (docs/MODEL.md, "Reflective shadow map").

* :class:`SpotLight`: a point light of total flux ``Φ_L`` radiating the intensity
  ``Φ_L/(4π)·f(θ)``. Without a cone ``f = 1`` inside a 90° square frustum (the published
  setup); with a cone (``cone_degrees = (inner, outer)`` half-angles) ``f`` falls smoothly
  from 1 inside the inner angle to 0 at the outer one (:func:`spot_falloff`, docs/MODEL.md
  "Spot cone"), and the RSM frustum is the square one that holds the outer cone.
* :class:`DirectionalLight`: parallel light of irradiance ``E`` (on a plane facing the
  light) through an orthographic box that holds the scene; ``flux`` is the flux through
  that box, ``E = flux / (2R)²`` with ``R`` the box's half width.
* :class:`PointLight`: an isotropic point light of total flux ``Φ_L`` (intensity
  ``Φ_L/(4π)`` in every direction). Its RSM is a cube map: six 90° square frusta along
  ±x, ±y, ±z (:meth:`PointLight.faces`), each exactly the RSM of a cone-less spot light of
  the same flux, so the six faces' texel solid angles cover the sphere once and a closed
  room of reflectance ``c`` reflects ``c·Φ_L`` (docs/MODEL.md "Several lights").

Every light has a ``name`` (unique within a scene) and a ``colour``: it radiates
``flux·colour[c]`` in colour channel ``c`` (white: ``(1, 1, 1)``).
"""

from __future__ import annotations

import math
from dataclasses import dataclass, replace
from typing import TypeVar

import numpy as np

from explorer.scene.camera import depth_range
from explorer.scene.transforms import look_at, normalized, orthographic, perspective

FULL_SPHERE_SR = 4.0 * math.pi
"""Solid angle of the whole sphere [sr]: an isotropic point light spreads Φ_L over it
(the derivations' ``solid_angles.sphere``; the scene sits below ``explorer.lpv`` and so
does not read the generated constants)."""

SPOT_FOV_DEGREES = 90.0
"""Field of view of a spot light without a cone (its square frustum)."""
MAX_CONE_DEGREES = 80.0
"""Largest outer half-angle of a spot cone: the RSM frustum is 2·outer wide, and its
texels at the edge grow as 1/cos² of it."""
WHITE_LIGHT = (1.0, 1.0, 1.0)
_LightT = TypeVar("_LightT", bound="_LightBase")
LIGHT_KINDS = ("spot", "point", "directional")


def _check_colour(light) -> None:
    """Normalise ``light.colour`` to three finite floats >= 0 (not all zero)."""
    try:
        colour = tuple(float(c) for c in light.colour)
    except (TypeError, ValueError):
        colour = ()
    if len(colour) != 3 or not all(math.isfinite(c) and c >= 0.0 for c in colour) or \
            not any(colour):
        raise ValueError(f"light {light.name!r}: colour must be three finite numbers >= 0, "
                         f"not all 0, got {light.colour!r}")
    object.__setattr__(light, "colour", colour)


class _LightBase:
    """What every light offers: a new flux, and the flux per colour channel."""

    def with_flux(self: _LightT, flux: float) -> _LightT:
        return replace(self, flux=float(flux))

    @property
    def channel_flux(self) -> np.ndarray:
        """(3,) ``flux·colour``: the watts of each colour channel."""
        return float(self.flux) * np.asarray(self.colour, np.float64)


@dataclass(frozen=True)
class _AimedLight(_LightBase):
    """What the spot and the directional light share: they shine from ``position``
    towards ``target`` with ``flux`` watts per colour channel (times ``colour``); what
    the flux means is the subclass's."""

    position: tuple[float, float, float]
    target: tuple[float, float, float]
    flux: float
    name: str = "light"
    colour: tuple[float, float, float] = WHITE_LIGHT

    def __post_init__(self) -> None:
        _check_colour(self)

    @property
    def direction(self) -> np.ndarray:
        return normalized(np.subtract(self.target, self.position))

    def moved(self: _LightT, position, target) -> _LightT:
        return replace(self, position=tuple(map(float, position)),
                       target=tuple(map(float, target)))


def spot_falloff(cos_axis, cos_inner: float, cos_outer: float) -> np.ndarray:
    """The spot cone's angular falloff ``f`` at the angle θ from the axis, given as
    ``cos θ`` (docs/MODEL.md "Spot cone"): ``smoothstep(cos θ_o, cos θ_i, cos θ)``, i.e.
    ``3t² − 2t³`` with ``t = clamp((cos θ − cos θ_o)/(cos θ_i − cos θ_o), 0, 1)``; a hard
    step at the outer angle when inner = outer. The numpy twin of ``spot_falloff`` in
    shaders/spot.glsl."""
    c = np.asarray(cos_axis, np.float64)
    if cos_inner <= cos_outer:
        return (c >= cos_outer).astype(np.float64)
    t = np.clip((c - cos_outer) / (cos_inner - cos_outer), 0.0, 1.0)
    return t * t * (3.0 - 2.0 * t)


@dataclass(frozen=True)
class SpotLight(_AimedLight):
    """``flux``: the total flux Φ_L in watts per colour channel (white light) the point
    light would radiate over the whole sphere; the cone lets ``Φ_L/(4π)·∫f dω`` out.
    ``cone_degrees``: ``(inner, outer)`` half-angles of the cone in degrees,
    ``0 ≤ inner ≤ outer ≤`` :data:`MAX_CONE_DEGREES`, or None for the 90° square frustum
    with uniform intensity."""

    cone_degrees: tuple[float, float] | None = None

    projection = "perspective"
    kind = "spot"

    def __post_init__(self) -> None:
        super().__post_init__()
        if self.cone_degrees is None:
            return
        try:
            inner, outer = (float(v) for v in self.cone_degrees)
        except (TypeError, ValueError):
            raise ValueError(f"cone_degrees must be (inner, outer) half-angles in degrees, "
                             f"got {self.cone_degrees!r}") from None
        if not (0.0 <= inner <= outer <= MAX_CONE_DEGREES and outer > 0.0):
            raise ValueError(f"cone_degrees (inner, outer) must satisfy 0 <= inner <= outer "
                             f"<= {MAX_CONE_DEGREES:g} with outer > 0, got "
                             f"{self.cone_degrees!r}")
        object.__setattr__(self, "cone_degrees", (inner, outer))

    @property
    def intensity(self) -> float:
        """Radiant intensity on the axis ``Φ_L/(4π)`` [W/sr] (times ``f`` off the axis)."""
        return self.flux / FULL_SPHERE_SR

    @property
    def has_cone(self) -> bool:
        return self.cone_degrees is not None

    @property
    def cone_cosines(self) -> tuple[float, float]:
        """``(cos θ_inner, cos θ_outer)``; ``(-1, -1)`` without a cone (``f = 1``)."""
        if self.cone_degrees is None:
            return -1.0, -1.0
        inner, outer = self.cone_degrees
        return math.cos(math.radians(inner)), math.cos(math.radians(outer))

    @property
    def fov_degrees(self) -> float:
        """Field of view of the square RSM frustum: 90°, or twice the outer angle (the
        square frustum that just holds the cone)."""
        return SPOT_FOV_DEGREES if self.cone_degrees is None else 2.0 * self.cone_degrees[1]

    @property
    def frustum_half_width(self) -> float:
        """``tan(fov/2)``: the frustum cuts the plane at view depth 1 in the square
        ``[-t, t]²`` (exactly 1 for the 90° frustum)."""
        if self.cone_degrees is None:
            return 1.0
        return math.tan(math.radians(self.cone_degrees[1]))

    def falloff(self, cos_axis) -> np.ndarray:
        """``f`` at the angle from the axis given as ``cos θ`` (1 without a cone)."""
        if self.cone_degrees is None:
            return np.ones_like(np.asarray(cos_axis, np.float64))
        return spot_falloff(cos_axis, *self.cone_cosines)

    def with_cone(self, cone_degrees: tuple[float, float] | None) -> SpotLight:
        """This light with another cone (None: the 90° square frustum)."""
        return replace(self, cone_degrees=cone_degrees)

    def view_matrix(self, bounds_min=None, bounds_max=None) -> np.ndarray:
        """World -> light view (the scene box is not needed for a spot)."""
        return look_at(self.position, self.target)

    def projection_matrix(self, bounds_min, bounds_max) -> np.ndarray:
        near, far = depth_range(self.position, bounds_min, bounds_max)
        return perspective(self.fov_degrees, 1.0, near, far)

    def texel_area(self, width: int, height: int, bounds_min=None, bounds_max=None) -> float:
        """Area of one RSM texel on the plane at view depth 1: the frustum cuts that plane
        in a ``2t × 2t`` square, so ``4t²/(W·H)`` (``4/(W·H)`` for the 90° frustum;
        ``VplArrays.texel_area``)."""
        t = self.frustum_half_width
        return 4.0 * t * t / (width * height)


@dataclass(frozen=True)
class DirectionalLight(_AimedLight):
    """``position``: a point on the side the light comes from; only ``target - position``
    matters for the direction, the box is centred on the scene. ``flux``: watts per channel
    through the orthographic box (``E·(2R)²``)."""

    projection = "orthographic"
    kind = "directional"

    @staticmethod
    def half_width(bounds_min, bounds_max) -> float:
        """``R``: radius of the sphere around the scene box; the box is ``2R`` wide."""
        lo, hi = np.asarray(bounds_min, np.float64), np.asarray(bounds_max, np.float64)
        return 0.5 * float(np.linalg.norm(hi - lo)) * 1.001

    def irradiance(self, bounds_min, bounds_max) -> float:
        side = 2.0 * self.half_width(bounds_min, bounds_max)
        return self.flux / (side * side)

    def eye(self, bounds_min, bounds_max) -> np.ndarray:
        centre = 0.5 * (np.asarray(bounds_min, np.float64) + np.asarray(bounds_max, np.float64))
        return centre - self.direction * 2.0 * self.half_width(bounds_min, bounds_max)

    def view_matrix(self, bounds_min, bounds_max, eye=None) -> np.ndarray:
        """World -> light view from :meth:`eye` (or another ``eye``, e.g. snapped)."""
        eye = self.eye(bounds_min, bounds_max) if eye is None else np.asarray(eye, np.float64)
        return look_at(eye, eye + self.direction)

    def projection_matrix(self, bounds_min, bounds_max) -> np.ndarray:
        radius = self.half_width(bounds_min, bounds_max)
        return orthographic(radius, radius, radius * 1e-3, 4.0 * radius)

    def texel_area(self, width: int, height: int, bounds_min, bounds_max) -> float:
        """World area of one RSM texel: the box face ``(2R)²`` split into ``W·H`` texels."""
        side = 2.0 * self.half_width(bounds_min, bounds_max)
        return side * side / (width * height)


CUBE_FACE_AXES = ((1.0, 0.0, 0.0), (-1.0, 0.0, 0.0), (0.0, 1.0, 0.0), (0.0, -1.0, 0.0),
                  (0.0, 0.0, 1.0), (0.0, 0.0, -1.0))
"""The forward axes of a point light's six RSM faces (+x, −x, +y, −y, +z, −z)."""


@dataclass(frozen=True)
class PointLight(_LightBase):
    """An isotropic point light: ``flux`` is the total flux Φ_L in watts per colour
    channel (times ``colour``), radiated as ``Φ_L/(4π)`` W/sr in every direction."""

    position: tuple[float, float, float]
    flux: float
    name: str = "light"
    colour: tuple[float, float, float] = WHITE_LIGHT

    projection = "perspective"
    kind = "point"

    def __post_init__(self) -> None:
        _check_colour(self)

    @property
    def intensity(self) -> float:
        """Radiant intensity ``Φ_L/(4π)`` [W/sr] in every direction."""
        return self.flux / FULL_SPHERE_SR

    @property
    def target(self) -> tuple[float, float, float]:
        """A point below the light (a point light has no direction; Settings.light's
        ``(position, target)`` pair keeps this one)."""
        x, y, z = self.position
        return (x, y - 1.0, z)

    def moved(self, position, target=None) -> PointLight:
        """The light at ``position`` (``target`` is ignored: it shines everywhere)."""
        return replace(self, position=tuple(map(float, position)))

    def faces(self) -> tuple[SpotLight, ...]:
        """The six cube-map faces as cone-less 90° spot lights of the same flux and colour,
        aimed along :data:`CUBE_FACE_AXES`: their frusta tile the sphere of directions, so
        their RSMs together are the point light's (docs/MODEL.md "Several lights")."""
        position = np.asarray(self.position, np.float64)
        return tuple(SpotLight(tuple(map(float, position)),
                               tuple(map(float, position + np.asarray(axis))), self.flux,
                               name=self.name, colour=self.colour)
                     for axis in CUBE_FACE_AXES)


Light = SpotLight | DirectionalLight | PointLight


DEFAULT_IRRADIANCE = 2.0
"""W/m² a light gets where it is meant when neither its flux nor its irradiance is given:
a ``[[lights]]`` table of a scene file and ``--light`` of another kind alike
(:func:`default_flux`)."""
POINT_LIGHT_NEAREST = 0.25
"""A point light's default flux is meant at the box's centre, but at least this share of
the box's half-diagonal from the light (one hung at the centre would get almost none)."""


def default_flux(kind: str, position, target, bounds_min, bounds_max,
                 irradiance: float = DEFAULT_IRRADIANCE) -> float:
    """The flux of a new ``kind`` light that gives ``irradiance`` W/m² on a surface facing it
    (the one declaration of the default, for scene files and ``--light``): a spot at its
    ``target``; a directional light on any plane facing it (``E·(2R)²``, R the half width of
    its box); a point light at the centre of the box ``bounds_min``–``bounds_max`` (it has
    no direction: ``target`` is ignored), at least :data:`POINT_LIGHT_NEAREST` of the box's
    half-diagonal away."""
    if kind == "directional":
        side = 2.0 * DirectionalLight.half_width(bounds_min, bounds_max)
        return irradiance * side * side
    if kind == "point":
        lo, hi = np.asarray(bounds_min, np.float64), np.asarray(bounds_max, np.float64)
        radius = 0.5 * float(np.linalg.norm(hi - lo))
        distance = float(np.linalg.norm(0.5 * (lo + hi) - np.asarray(position, np.float64)))
        return flux_for_irradiance(max(distance, POINT_LIGHT_NEAREST * radius, 1e-6),
                                   irradiance)
    if kind != "spot":
        raise ValueError(f"light kind must be one of {', '.join(LIGHT_KINDS)}, got {kind!r}")
    distance = float(np.linalg.norm(np.subtract(target, position)))
    return flux_for_irradiance(max(distance, 1e-6), irradiance)


def new_light(kind: str, position, target, flux: float, name: str = "light",
              colour=WHITE_LIGHT, cone_degrees: tuple[float, float] | None = None):
    """A ``kind`` light (:data:`LIGHT_KINDS`) at ``position`` aimed at ``target`` (a point
    light ignores it) with ``flux``; ``cone_degrees`` only for a spot (None: no cone)."""
    position, colour = tuple(map(float, position)), tuple(map(float, colour))
    if kind == "point":
        return PointLight(position, float(flux), name=name, colour=colour)
    target = tuple(map(float, target))
    if kind == "directional":
        return DirectionalLight(position, target, float(flux), name=name, colour=colour)
    if kind != "spot":
        raise ValueError(f"light kind must be one of {', '.join(LIGHT_KINDS)}, got {kind!r}")
    return SpotLight(position, target, float(flux), name=name, colour=colour,
                     cone_degrees=None if cone_degrees is None else tuple(cone_degrees))


def flux_for_irradiance(distance: float, irradiance: float = DEFAULT_IRRADIANCE) -> float:
    """Spot flux ``Φ_L = 4π·r²·E`` that gives irradiance ``E`` at normal incidence at
    distance ``r``: how built-in and loaded scenes pick a flux that is well exposed at any
    scale (``E = 2`` lights a white surface to a radiance near 0.5, leaving room for the
    indirect light)."""
    return FULL_SPHERE_SR * distance * distance * irradiance

