"""The built-in scenes: ``cornell``, ``single-source``, ``room``, ``two-rooms`` and
``atrium`` (a large procedural courtyard, explorer/scene/atrium.py).

Units are metres; albedos are linear reflectances. Every light's flux comes from
:func:`~explorer.scene.lights.flux_for_irradiance` so that the main lit surface receives
about 2 W/m² (a white surface then has a direct radiance near 0.5 at exposure 1).

Each scene has a rig of lights of which one shines by default (``Settings.lights`` turns
the others on), named objects that can be moved (``Settings.object_transforms``) and
animation paths for its primary light and some objects (explorer/scene/animation.py).
"""

from __future__ import annotations

import numpy as np

from explorer.scene.atrium import atrium
from explorer.scene.camera import Camera
from explorer.scene.lights import (
    DirectionalLight,
    PointLight,
    SpotLight,
    flux_for_irradiance,
)
from explorer.scene.model import MeshBuilder, Scene
from explorer.scene.paths import KeyframePath

WHITE = (0.75, 0.75, 0.75)
RED = (0.80, 0.08, 0.06)
GREEN = (0.10, 0.65, 0.10)
ORANGE = (0.90, 0.45, 0.08)
BLUE = (0.20, 0.35, 0.80)

X, Y, Z = np.eye(3)
CORNELL_CONE_DEGREES = (40.0, 70.0)
"""Inner and outer half-angles of the Cornell box's spot cone."""
WARM = (1.0, 0.72, 0.42)
COOL = (0.55, 0.72, 1.0)
DAYLIGHT = (1.0, 0.95, 0.86)


def _turn(translation=(0.0, 0.0, 0.0), yaw: float = 0.0) -> tuple[float, ...]:
    """Nine transform numbers: a translation and a turn about the vertical axis."""
    return (*translation, 0.0, yaw, 0.0, 1.0, 1.0, 1.0)


def _sun(lo, hi, from_point, irradiance: float, name: str = "sun",
         colour=(1.0, 1.0, 1.0)) -> DirectionalLight:
    """A directional light of ``irradiance`` shining from ``from_point`` towards the
    origin (its flux is through the orthographic box that holds the scene)."""
    side = 2.0 * DirectionalLight.half_width(lo, hi)
    return DirectionalLight(tuple(map(float, from_point)), (0.0, 0.0, 0.0),
                            irradiance * side * side, name=name, colour=colour)


def cornell_box() -> Scene:
    """A 2 m Cornell box open towards +z: red wall at x = −1, green wall at x = +1, white
    floor, ceiling and back, two white blocks, and a spot light under the ceiling near the
    open front, aimed down at the back of the box. It lights the floor, the back wall and
    both coloured walls, which then bleed red and green onto the floor, the blocks and the
    back wall. The spot's cone (40° inner, 70° outer half-angle)
    lights the whole box and fades out smoothly towards the open front; with
    ``Settings.spot_cone`` off it is the 90° square frustum the lessons measure."""
    mesh = MeshBuilder()
    with mesh.object("box"):
        for name, centre, normal, u_axis, albedo in (
                ("floor", (0, -1, 0), Y, X, WHITE), ("ceiling", (0, 1, 0), -Y, X, WHITE),
                ("back wall", (0, 0, -1), Z, X, WHITE), ("left wall", (-1, 0, 0), X, Z, RED),
                ("right wall", (1, 0, 0), -X, Z, GREEN)):
            with mesh.part(name):
                mesh.rect(centre, normal, u_axis, 1, 1, albedo)
    with mesh.object("short block"), mesh.part("short block"):
        mesh.box((0.34, -0.7, 0.3), (0.6, 0.6, 0.6), WHITE, rotation_y_degrees=-18.0)
    with mesh.object("tall block"), mesh.part("tall block"):
        mesh.box((-0.34, -0.4, -0.32), (0.6, 1.2, 0.6), WHITE, rotation_y_degrees=18.0)
    positions, normals, albedo = mesh.arrays()
    lo, hi = (-1.0, -1.0, -1.0), (1.0, 1.0, 1.0)
    spot = SpotLight((0.0, 0.9, 0.9), (0.0, -0.5, -0.8), flux_for_irradiance(2.2),
                     name="spot", cone_degrees=CORNELL_CONE_DEGREES)
    rig = (
        spot,
        # a cool narrow spot from the right front onto the tall block
        SpotLight((0.8, 0.3, 0.95), (-0.34, -0.3, -0.32), flux_for_irradiance(1.7),
                  name="lamp", colour=COOL, cone_degrees=(18.0, 28.0)),
        # a warm bulb hanging in the left front corner: a point light (six RSM faces)
        PointLight((-0.55, 0.5, 0.45), flux_for_irradiance(1.0, 1.5), name="bulb",
                   colour=WARM),
        # low daylight through the open front
        _sun(lo, hi, (0.6, 1.6, 3.0), 1.2, colour=DAYLIGHT),
    )
    camera = Camera((0.0, 0.55, 4.4), (0.0, -0.15, 0.0), 38.0)
    circle = [(0.45 * np.sin(a), 0.9, 0.55 + 0.35 * np.cos(a), *spot.target)
              for a in np.linspace(0.0, 2.0 * np.pi, 8, endpoint=False)]
    return Scene("cornell", positions, normals, albedo, camera, rig, lo, hi,
                 objects=tuple(mesh.objects), **mesh.part_fields(), lights_on=("spot",),
                 light_path=KeyframePath(circle, 8.0),
                 object_paths=(("short block", KeyframePath(
                     [_turn(), _turn((0.15, 0.0, -0.1), 30.0), _turn((0.1, 0.0, 0.15), 60.0),
                      _turn((-0.1, 0.0, 0.1), 20.0)], 6.0)),))


def single_source() -> Scene:
    """One small white patch lit by a spot light 0.3 m above it, in an otherwise empty
    2 m box: the smallest scene that injects light (for lessons and tests). The cone's
    inner angle (40°) holds the whole patch (its corners are 35.3° off the axis) and its
    outer angle is the 90° frustum's, so the RSM is the same with the cone on or off."""
    mesh = MeshBuilder()
    with mesh.object("patch"):
        mesh.rect((0.0, -0.5, 0.0), Y, X, 0.15, 0.15, (0.8, 0.8, 0.8))
    positions, normals, albedo = mesh.arrays()
    light = SpotLight((0.0, -0.2, 0.0), (0.0, -0.5, 0.0), flux_for_irradiance(0.3),
                      name="spot", cone_degrees=(40.0, 45.0))
    bulb = PointLight((0.0, -0.2, 0.0), flux_for_irradiance(0.3), name="bulb", colour=WARM)
    camera = Camera((0.0, 0.6, 2.6), (0.0, -0.4, 0.0), 40.0)
    sway = [(x, -0.2, 0.0, x, -0.5, 0.0) for x in (0.0, 0.1, 0.0, -0.1)]
    return Scene("single-source", positions, normals, albedo, camera, (light, bulb),
                 (-1.0, -1.0, -1.0), (1.0, 1.0, 1.0), objects=tuple(mesh.objects),
                 lights_on=("spot",), light_path=KeyframePath(sway, 4.0),
                 object_paths=(("patch", KeyframePath(
                     [_turn(), _turn((0.1, 0.0, 0.0), 45.0), _turn(), _turn((-0.1, 0.0, 0.0),
                                                                           -45.0)], 4.0)),))


def room() -> Scene:
    """A 4 m roofless room with thin walls (thinner than a grid cell at usual sizes) and
    two pillars, lit by a low sun (directional light): shows light leaking through thin
    walls and what the geometry volume's occlusion does about it."""
    mesh = MeshBuilder()
    with mesh.object("room"):
        with mesh.part("floor"):
            mesh.rect((0.0, 0.0, 0.0), Y, X, 2.0, 2.0, WHITE)
        for name, centre, size, albedo in (
                ("back wall", (0.0, 0.6, -2.0), (4.0, 1.2, 0.06), WHITE),
                ("left wall", (-2.0, 0.6, 0.0), (0.06, 1.2, 4.0), BLUE),
                ("right wall", (2.0, 0.6, 0.0), (0.06, 1.2, 4.0), WHITE)):
            with mesh.part(name):
                mesh.box(centre, size, albedo)
    with mesh.object("thin wall"), mesh.part("thin wall"):
        mesh.box((0.3, 0.6, -0.75), (0.04, 1.2, 2.5), ORANGE)
    with mesh.object("pillars"), mesh.part("pillars"):
        mesh.box((-1.0, 0.6, 0.9), (0.2, 1.2, 0.2), WHITE)
        mesh.box((1.1, 0.6, 0.9), (0.2, 1.2, 0.2), WHITE)
    positions, normals, albedo = mesh.arrays()
    lo, hi = (-2.05, 0.0, -2.05), (2.05, 1.2, 2.05)
    sun = _sun(lo, hi, (-2.0, 3.0, 1.0), 2.0)
    lamp = PointLight((-1.2, 0.9, -1.2), flux_for_irradiance(1.0, 1.5), name="lamp",
                      colour=WARM)
    camera = Camera((0.0, 3.6, 5.2), (0.0, 0.2, -0.2), 45.0)
    # the sun goes round the room at the same height (its direction turns)
    orbit = [(np.sqrt(5.0) * np.cos(a), 3.0, np.sqrt(5.0) * np.sin(a), 0.0, 0.0, 0.0)
             for a in np.arctan2(1.0, -2.0) + np.linspace(0.0, 2.0 * np.pi, 8, endpoint=False)]
    return Scene("room", positions, normals, albedo, camera, (sun, lamp), lo, hi,
                 objects=tuple(mesh.objects), **mesh.part_fields(), lights_on=("sun",),
                 light_path=KeyframePath(orbit, 24.0),
                 object_paths=(("thin wall", KeyframePath(
                     [_turn(), _turn((0.5, 0.0, 0.0)), _turn((0.5, 0.0, 0.4), 30.0),
                      _turn((0.0, 0.0, 0.4))], 8.0)),))


def two_rooms() -> Scene:
    """Two closed 2 m × 2 m × 3 m rooms side by side, sharing a wall 6 cm thick at x = 0,
    with a spot light under the ceiling of the left room aimed at its floor, and the
    camera in the right room looking at the shared wall. The light cannot reach the right
    room, and its cone (20°/30°) does not reach the shared wall either, so the shadow map
    holds no surfel of it: every bit of LPV light in the right room leaked through that
    wall (docs/MODEL.md "Camera occluders"). Its rig adds a warm point light in the right
    room, ``lamp`` (off by default)."""
    mesh = MeshBuilder()
    for name, centre, normal, u_axis, half_u, half_v, albedo in (
            ("floor", (0.0, 0.0, 0.0), Y, X, 2.0, 1.5, WHITE),          # of both rooms
            ("ceiling", (0.0, 2.0, 0.0), -Y, X, 2.0, 1.5, WHITE),
            ("back walls", (0.0, 1.0, -1.5), Z, X, 2.0, 1.0, WHITE),
            ("front walls", (0.0, 1.0, 1.5), -Z, X, 2.0, 1.0, WHITE),
            ("left far wall", (-2.0, 1.0, 0.0), X, Z, 1.5, 1.0, RED),
            ("right far wall", (2.0, 1.0, 0.0), -X, Z, 1.5, 1.0, WHITE)):
        with mesh.part(name):
            mesh.rect(centre, normal, u_axis, half_u, half_v, albedo)
    with mesh.part("shared wall"):
        mesh.box((0.0, 1.0, 0.0), (0.06, 2.0, 3.0), WHITE)
    positions, normals, albedo = mesh.arrays()
    spot = SpotLight((-1.2, 1.9, 0.0), (-1.2, 0.0, 0.0), flux_for_irradiance(1.9),
                     name="spot", cone_degrees=(20.0, 30.0))
    # a warm bulb in the right room (off by default): it sees the shared wall's right face
    lamp = PointLight((1.2, 1.5, -0.6), flux_for_irradiance(1.0, 1.5), name="lamp",
                      colour=WARM)
    camera = Camera((1.9, 1.7, 1.4), (0.0, 0.45, -0.4), 75.0)
    return Scene("two-rooms", positions, normals, albedo, camera, (spot, lamp),
                 (-2.0, 0.0, -1.5), (2.0, 2.0, 1.5), **mesh.part_fields(),
                 lights_on=("spot",))


BUILTIN_SCENES = {
    "cornell": cornell_box,
    "single-source": single_source,
    "room": room,
    "two-rooms": two_rooms,
    "atrium": atrium,
}
