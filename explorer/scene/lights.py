"""Lights that render a reflective shadow map (docs/MODEL.md, "Reflective shadow map").

* :class:`SpotLight`: a point light of total flux ``Φ_L`` radiating the isotropic
  intensity ``Φ_L/(4π)``, seen through a 90° square frustum (only what lies in the frustum
  is lit: that is what makes it a spot).
* :class:`DirectionalLight`: parallel light of irradiance ``E`` (on a plane facing the
  light) through an orthographic box that holds the scene; ``flux`` is the flux through
  that box, ``E = flux / (2R)²`` with ``R`` the box's half width.
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
_LightT = TypeVar("_LightT", bound="_AimedLight")


@dataclass(frozen=True)
class _AimedLight:
    """What both lights share: they shine from ``position`` towards ``target`` with
    ``flux`` watts per colour channel (white light); what the flux means is the
    subclass's."""

    position: tuple[float, float, float]
    target: tuple[float, float, float]
    flux: float

    @property
    def direction(self) -> np.ndarray:
        return normalized(np.subtract(self.target, self.position))

    def moved(self: _LightT, position, target) -> _LightT:
        return replace(self, position=tuple(map(float, position)),
                       target=tuple(map(float, target)))

    def with_flux(self: _LightT, flux: float) -> _LightT:
        return replace(self, flux=float(flux))


@dataclass(frozen=True)
class SpotLight(_AimedLight):
    """``flux``: the total flux Φ_L in watts per colour channel (white light)."""

    projection = "perspective"

    @property
    def intensity(self) -> float:
        """Isotropic radiant intensity ``Φ_L/(4π)`` [W/sr]."""
        return self.flux / FULL_SPHERE_SR

    def view_matrix(self, bounds_min=None, bounds_max=None) -> np.ndarray:
        """World -> light view (the scene box is not needed for a spot)."""
        return look_at(self.position, self.target)

    def projection_matrix(self, bounds_min, bounds_max) -> np.ndarray:
        near, far = depth_range(self.position, bounds_min, bounds_max)
        return perspective(SPOT_FOV_DEGREES, 1.0, near, far)

    def texel_area(self, width: int, height: int, bounds_min=None, bounds_max=None) -> float:
        """Area of one RSM texel on the plane at view depth 1: the 90° frustum cuts that
        plane in a 2×2 square, so ``4/(W·H)`` (``VplArrays.texel_area``)."""
        return 4.0 / (width * height)


@dataclass(frozen=True)
class DirectionalLight(_AimedLight):
    """``position``: a point on the side the light comes from; only ``target - position``
    matters for the direction, the box is centred on the scene. ``flux``: watts per channel
    through the orthographic box (``E·(2R)²``)."""

    projection = "orthographic"

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

    def view_matrix(self, bounds_min, bounds_max) -> np.ndarray:
        eye = self.eye(bounds_min, bounds_max)
        return look_at(eye, eye + self.direction)

    def projection_matrix(self, bounds_min, bounds_max) -> np.ndarray:
        radius = self.half_width(bounds_min, bounds_max)
        return orthographic(radius, radius, radius * 1e-3, 4.0 * radius)

    def texel_area(self, width: int, height: int, bounds_min, bounds_max) -> float:
        """World area of one RSM texel: the box face ``(2R)²`` split into ``W·H`` texels."""
        side = 2.0 * self.half_width(bounds_min, bounds_max)
        return side * side / (width * height)


Light = SpotLight | DirectionalLight


def flux_for_irradiance(distance: float, irradiance: float = 2.0) -> float:
    """Spot flux ``Φ_L = 4π·r²·E`` that gives irradiance ``E`` at normal incidence at
    distance ``r``: how built-in and loaded scenes pick a flux that is well exposed at any
    scale (``E = 2`` lights a white surface to a radiance near 0.5, leaving room for the
    indirect light)."""
    return FULL_SPHERE_SR * distance * distance * irradiance

