"""RSM snapping (``Settings.rsm_snap``, docs/MODEL.md "Moving objects and temporal
stability"): a light's RSM view moves only by whole texels in its image plane, so that a
light moving by a fraction of a texel keeps its VPLs where they were (they do not swim)
and a move across a snap shifts them by one texel of a world-fixed lattice.

With the view's right and up axes ``r, u``, the texel pitch ``s`` on a reference plane and
the lattice's origin ``o``, the eye ``e`` becomes
``e + Σ_{a∈{r,u}} (round((e − o)·a/s)·s − (e − o)·a)·a``: its image-plane coordinates
from ``o`` are whole multiples of ``s`` and it moves by at most ``s/2`` along each axis
(``s/√2`` in all, under one texel). The direction stays, so the view's axes, the frustum's
shape and the light's radiometry stay too. The origin is where the scene places the light
(its *anchor*: the light of that name as the scene was loaded), so a light that has not
moved is not moved by snapping, and a still frame is the unsnapped one; without an
anchor, the world's origin (a point light: the box's minimum corner).

* spot: ``s = 2t·d/N`` (``t`` the frustum's half width at depth 1, ``d`` the distance to
  the target, ``N`` the RSM's texels per side), the pitch on the plane through the target;
  the light itself moves (the shadow map and the direct light read the same view).
* directional: ``s = 2R/N``, the box's texel; the box is centred on the scene's box, which
  does not move, so only a turning light changes it.
* point: the six faces share one position, snapped to the cubic lattice of pitch ``2R/N``
  anchored at the box's minimum corner (every face's image-plane axes are world axes).
"""

from __future__ import annotations

import numpy as np

from explorer.scene.lights import DirectionalLight, Light, PointLight
from explorer.scene.transforms import look_at


def plane_snap(eye, view: np.ndarray, pitch: float, origin=(0.0, 0.0, 0.0)) -> np.ndarray:
    """The shift ``δ`` (3,) that puts ``eye − origin``'s coordinates along ``view``'s right
    and up axes (its rows 0 and 1) on whole multiples of ``pitch`` (module docstring)."""
    relative = np.asarray(eye, np.float64) - np.asarray(origin, np.float64)
    if not pitch > 0.0:
        raise ValueError(f"the snapping pitch must be positive, got {pitch!r}")
    shift = np.zeros(3)
    for axis in (view[0, :3], view[1, :3]):
        along = float(relative @ axis)
        shift += (np.round(along / pitch) * pitch - along) * axis
    return shift


def spot_pitch(light, size: int) -> float:
    """A spot's texel pitch on the plane through its target: ``2t·d/N``."""
    distance = float(np.linalg.norm(np.subtract(light.target, light.position)))
    return 2.0 * light.frustum_half_width * distance / int(size)


def box_pitch(bounds_min, bounds_max, size: int) -> float:
    """``2R/N``: a directional light's texel (R the half width of its box)."""
    return 2.0 * DirectionalLight.half_width(bounds_min, bounds_max) / int(size)


def _anchor_of(light: Light, anchor: Light | None) -> Light | None:
    """``anchor`` when it is a light of ``light``'s kind (a kind override has none)."""
    return anchor if anchor is not None and type(anchor) is type(light) else None


def snapped_light(light: Light, bounds_min, bounds_max, size: int,
                  anchor: Light | None = None) -> Light:
    """A spot or point ``light`` moved onto its lattice through ``anchor``'s position
    (module docstring); a directional light is returned as it is (its eye is snapped by
    :func:`snapped_directional_eye`)."""
    anchor = _anchor_of(light, anchor)
    if isinstance(light, DirectionalLight):
        return light
    if isinstance(light, PointLight):
        pitch = box_pitch(bounds_min, bounds_max, size)
        origin = np.asarray(bounds_min if anchor is None else anchor.position, np.float64)
        offset = np.asarray(light.position, np.float64) - origin
        return light.moved(origin + np.round(offset / pitch) * pitch)
    origin = (0.0, 0.0, 0.0) if anchor is None else anchor.position
    shift = plane_snap(light.position, look_at(light.position, light.target),
                       spot_pitch(light, size), origin)
    return light.moved(np.add(light.position, shift), np.add(light.target, shift))


def snapped_directional_eye(light: DirectionalLight, bounds_min, bounds_max, size: int,
                            anchor: Light | None = None) -> np.ndarray:
    """A directional light's eye (``DirectionalLight.eye``) moved onto its texel lattice
    through ``anchor``'s eye."""
    anchor = _anchor_of(light, anchor)
    eye = light.eye(bounds_min, bounds_max)
    origin = (0.0, 0.0, 0.0) if anchor is None else anchor.eye(bounds_min, bounds_max)
    return eye + plane_snap(eye, look_at(eye, eye + light.direction),
                            box_pitch(bounds_min, bounds_max, size), origin)
