"""``atrium``: a procedurally generated courtyard in the spirit of Sponza, large enough
(over 100 000 triangles) to exercise cascades and the passes' cost on real geometry.

Layout (metres, y up): an open courtyard ``x ∈ [−12, 12]``, ``z ∈ [−6, 6]`` under the
sky, closed at ``x = ±13.5`` by end walls. Each long side (``z = ±6``) has two storeys of
arcades: round arches on columns (:data:`BAYS` bays of :data:`PITCH` metres), with a
gallery behind them (back wall at ``z = ±9``), a floor slab between the storeys, a
parapet along the upper gallery and a roof slab over it. Coloured drapes hang in the
arcades: a long curtain in every ground bay, a shorter banner in every upper bay, red,
green, blue and gold. The sun (a directional light) shines into the courtyard from the
south onto the arcades of the north side (``z = −6``), whose drapes throw their colours
onto the shaded floor in front of them.

Everything is built from numpy arrays here, with no external assets and no randomness:
the same triangles on every call. Closed solids (columns, boxes, the arcade walls) have
outward normals and consistent winding; the drapes are single sheets (the renderer
shades both sides). :func:`fly_through` is a closed camera path through the courtyard.
"""

from __future__ import annotations

import math

import numpy as np

from explorer.scene.camera import Camera
from explorer.scene.lights import DirectionalLight, PointLight, flux_for_irradiance
from explorer.scene.model import MeshBuilder, Scene
from explorer.scene.paths import KeyframePath, catmull_rom

PITCH = 3.0
"""Distance between neighbouring columns along x."""
BAYS = 8
"""Arches per storey and side; columns stand at x = (k − BAYS/2)·PITCH, k = 0..BAYS."""
HALF_LENGTH = BAYS * PITCH / 2.0           # 12: the outermost columns
END_WALL_X = HALF_LENGTH + 1.5             # 13.5
ARCADE_Z = 6.0                             # the arcades' plane, on both sides
BACK_WALL_Z = 9.0                          # the galleries' back walls
HEIGHT = 10.0                              # top of the roof slabs
WALL_THICKNESS = 0.3
SEGMENTS = 48
"""Segments around a column and along an arch."""

STONE = (0.62, 0.57, 0.50)
STONE_DARK = (0.48, 0.44, 0.38)
FLOOR_LIGHT = (0.58, 0.55, 0.50)
FLOOR_DARK = (0.40, 0.38, 0.34)
DRAPE_COLOURS = ((0.70, 0.06, 0.05), (0.08, 0.48, 0.10), (0.07, 0.14, 0.60),
                 (0.75, 0.52, 0.08))
"""Red, green, blue, gold (linear albedo)."""


class Storey:
    """One storey of an arcade: columns (base, shaft, capital) carrying round arches,
    and the wall above the arches up to ``top``."""

    def __init__(self, floor: float, column_radius: float, shaft_height: float,
                 top: float) -> None:
        self.floor = floor
        self.column_radius = column_radius
        self.base_height = 0.3
        self.capital_height = 0.25
        self.shaft_height = shaft_height
        self.top = top
        self.capital_half_width = column_radius + 0.12

    @property
    def spring(self) -> float:
        """Height where the arches start (top of the capitals)."""
        return self.floor + self.base_height + self.shaft_height + self.capital_height

    @property
    def arch_radius(self) -> float:
        """Inner radius: each arch spans from one capital's edge to the next."""
        return PITCH / 2.0 - self.capital_half_width


GROUND = Storey(floor=0.0, column_radius=0.3, shaft_height=3.05, top=5.0)
UPPER = Storey(floor=5.3, column_radius=0.22, shaft_height=2.35, top=9.8)
STOREYS = (GROUND, UPPER)


def column_xs() -> np.ndarray:
    return (np.arange(BAYS + 1) - BAYS / 2) * PITCH


def bay_centres() -> np.ndarray:
    return column_xs()[:-1] + PITCH / 2.0


# --- primitives: (T, 3, 3) corner positions and normals -----------------------------------

def _quads(grid: np.ndarray, normals: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """Two triangles per cell of an ``(R, C, 3)`` grid of points (and their normals)."""
    a, b = grid[:-1, :-1], grid[:-1, 1:]
    c, d = grid[1:, 1:], grid[1:, :-1]
    na, nb = normals[:-1, :-1], normals[:-1, 1:]
    nc, nd = normals[1:, 1:], normals[1:, :-1]
    tris = np.concatenate([np.stack([a, b, c], -2), np.stack([a, c, d], -2)])
    norms = np.concatenate([np.stack([na, nb, nc], -2), np.stack([na, nc, nd], -2)])
    return tris.reshape(-1, 3, 3), norms.reshape(-1, 3, 3)


def oriented(tris: np.ndarray, normals: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """The triangles wound counter-clockwise seen from the side their normals point to
    (corners 1 and 2 swapped where the winding disagreed), so a closed solid built from
    parts with outward normals has consistent, outward winding."""
    tris, normals = tris.copy(), normals.copy()
    face = np.cross(tris[:, 1] - tris[:, 0], tris[:, 2] - tris[:, 0])
    flip = np.einsum("ij,ij->i", face, normals.sum(axis=1)) < 0
    tris[flip] = tris[flip][:, [0, 2, 1]]
    normals[flip] = normals[flip][:, [0, 2, 1]]
    return tris, normals


def cylinder(centre: tuple[float, float], bottom: float, height: float, radius: float,
             rings: int, segments: int = SEGMENTS) -> tuple[np.ndarray, np.ndarray]:
    """A closed vertical cylinder: smooth side (outward radial normals) and flat caps."""
    phi = np.linspace(0.0, 2.0 * math.pi, segments + 1)
    phi[-1] = 0.0                                     # the seam closes exactly
    ys = bottom + height * np.linspace(0.0, 1.0, rings + 1)
    radial = np.stack([np.cos(phi), np.zeros_like(phi), np.sin(phi)], -1)
    grid = np.array([centre[0], 0.0, centre[1]]) + radius * radial[None, :, :]
    grid = np.repeat(grid, rings + 1, axis=0) + np.array([0.0, 1.0, 0.0]) * ys[:, None, None]
    side = _quads(grid, np.broadcast_to(radial, grid.shape))
    parts = [side]
    for y, sign in ((bottom, -1.0), (bottom + height, 1.0)):
        rim = grid[0 if sign < 0 else -1]
        hub = np.array([centre[0], y, centre[1]])
        tris = np.stack([np.broadcast_to(hub, rim[:-1].shape), rim[:-1], rim[1:]], 1)
        parts.append((tris, np.broadcast_to([0.0, sign, 0.0], tris.shape)))
    return oriented(*(np.concatenate(p) for p in zip(*parts)))


_UNIT_CUBE = np.array([(sx, sy, sz) for sx in (-1, 1) for sy in (-1, 1) for sz in (-1, 1)],
                      np.float64) / 2.0
_CUBE_FACES = ((0, 1, 3, 2), (4, 6, 7, 5), (0, 4, 5, 1), (2, 3, 7, 6), (0, 2, 6, 4),
               (1, 5, 7, 3))
"""Corner indices of the faces −x, +x, −y, +y, −z, +z of :data:`_UNIT_CUBE`."""
_CUBE_NORMALS = np.array([(-1, 0, 0), (1, 0, 0), (0, -1, 0), (0, 1, 0), (0, 0, -1),
                          (0, 0, 1)], np.float64)


def box(centre, size) -> tuple[np.ndarray, np.ndarray]:
    """A closed axis-aligned box, flat outward normals (12 triangles)."""
    corners = np.asarray(centre, np.float64) + _UNIT_CUBE * np.asarray(size, np.float64)
    quads = corners[np.array(_CUBE_FACES)]                         # (6, 4, 3)
    tris = np.concatenate([quads[:, [0, 1, 2]], quads[:, [0, 2, 3]]])
    normals = np.repeat(np.tile(_CUBE_NORMALS, (2, 1))[:, None, :], 3, axis=1)
    return oriented(tris, normals)


def arch_profile(radius: float, half_width: float, height: float, segments: int = SEGMENTS
                 ) -> tuple[np.ndarray, np.ndarray]:
    """One bay of an arcade wall in its own plane, relative to the arch's centre: points
    on the semicircle of ``radius`` and, on the same rays from the centre, the points where
    the rays leave the bay's rectangle ``[−half_width, half_width] × [0, height]``. The
    rays include the rectangle's two top corners, so consecutive ray pairs bound convex
    quads. Returns ``(arch, outer)``, each ``(n, 2)``, from left (angle π) to right (0)."""
    corner = math.atan2(height, half_width)
    angles = np.linspace(math.pi, 0.0, segments + 1)
    angles = np.unique(np.concatenate([angles, [corner, math.pi - corner]]))[::-1]
    direction = np.stack([np.cos(angles), np.sin(angles)], -1)
    arch = radius * direction
    with np.errstate(divide="ignore"):
        to_side = np.where(np.abs(direction[:, 0]) > 1e-12,
                           half_width / np.abs(direction[:, 0]), np.inf)
        to_top = np.where(direction[:, 1] > 1e-12, height / direction[:, 1], np.inf)
    outer = direction * np.minimum(to_side, to_top)[:, None]
    outer[0], outer[-1] = (-half_width, 0.0), (half_width, 0.0)       # exact bottom corners
    return arch, outer


def arcade_wall(storey: Storey, z_centre: float, thickness: float = WALL_THICKNESS
                ) -> tuple[np.ndarray, np.ndarray]:
    """The wall of one storey above its columns, from the arches' spring line to
    ``storey.top``, with a round arch opening in every bay: one closed solid (front and
    back faces, the arches' soffits, the top, the strips resting on the capitals and the
    two ends), outward normals."""
    arch, outer = arch_profile(storey.arch_radius, PITCH / 2.0, storey.top - storey.spring)
    z0, z1 = z_centre - thickness / 2.0, z_centre + thickness / 2.0
    parts = []

    def lift(points2: np.ndarray, x: float, z: float) -> np.ndarray:
        return np.stack([x + points2[:, 0], storey.spring + points2[:, 1],
                         np.full(len(points2), z)], -1)

    for x in bay_centres():
        for z, sign in ((z1, 1.0), (z0, -1.0)):                    # front (+z) and back
            grid = np.stack([lift(arch, x, z), lift(outer, x, z)], 1)   # (n, 2, 3)
            parts.append(_quads(grid, np.broadcast_to([0.0, 0.0, sign], grid.shape)))
        # soffit: the arch's underside, facing its centre
        inward = -np.stack([arch[:, 0], arch[:, 1], np.zeros(len(arch))], -1)
        inward /= np.linalg.norm(inward, axis=1, keepdims=True)
        grid = np.stack([lift(arch, x, z0), lift(arch, x, z1)], 1)
        parts.append(_quads(grid, np.repeat(inward[:, None, :], 2, axis=1)))
        # top, the strips on the capitals and the ends: the outer points that lie on them
        on_top = np.isclose(outer[:, 1], storey.top - storey.spring)
        top = lift(outer[on_top], x, z0)
        grid = np.stack([top, top + [0.0, 0.0, thickness]], 1)
        parts.append(_quads(grid, np.broadcast_to([0.0, 1.0, 0.0], grid.shape)))
        for end in (0, -1):                                        # capital strips
            strip = np.stack([lift(arch[[end]], x, z0), lift(outer[[end]], x, z0)], 1)[0]
            grid = np.stack([strip, strip + [0.0, 0.0, thickness]], 1)
            parts.append(_quads(grid, np.broadcast_to([0.0, -1.0, 0.0], grid.shape)))
    for x, side, sign in ((bay_centres()[0], outer[:, 0] < -PITCH / 2 + 1e-9, -1.0),
                          (bay_centres()[-1], outer[:, 0] > PITCH / 2 - 1e-9, 1.0)):
        edge = lift(outer[side], x, z0)
        grid = np.stack([edge, edge + [0.0, 0.0, thickness]], 1)
        parts.append(_quads(grid, np.broadcast_to([sign, 0.0, 0.0], grid.shape)))
    return oriented(*(np.concatenate(p) for p in zip(*parts)))


def drape(x_centre: float, width: float, top: float, bottom: float, z: float,
          folds: int, depth: float, columns: int = 48, rows: int = 64
          ) -> tuple[np.ndarray, np.ndarray]:
    """A hanging cloth: a sheet ``width`` wide from ``top`` down to ``bottom`` in the plane
    ``z``, with ``folds`` vertical folds whose depth grows towards the hem, and a hem that
    swings out a little. Smooth normals (one side; the renderer shades both)."""
    u = np.linspace(0.0, 1.0, columns + 1)
    v = np.linspace(0.0, 1.0, rows + 1)[:, None]             # 0 at the rod, 1 at the hem
    fold = np.sin(2.0 * math.pi * folds * u)[None, :] * (0.35 + 0.65 * v)
    x = x_centre + width * (u - 0.5)[None, :] * (0.9 + 0.1 * v)   # gathered at the rod
    y = top - (top - bottom) * v
    offset = depth * fold + 0.6 * depth * v * v
    points = np.stack(np.broadcast_arrays(x, y, z + np.sign(-z) * offset), -1)
    du = np.gradient(points, axis=1)
    dv = np.gradient(points, axis=0)
    normals = np.cross(dv, du)
    normals /= np.linalg.norm(normals, axis=-1, keepdims=True)
    return oriented(*_quads(points, normals))


# --- the scene --------------------------------------------------------------------------

def _add(mesh: MeshBuilder, part: tuple[np.ndarray, np.ndarray], albedo) -> None:
    tris, normals = part
    mesh.add_triangles(tris.reshape(-1, 3), normals.reshape(-1, 3), albedo)


def _floor(mesh: MeshBuilder) -> None:
    """Square flagstones (1.5 m) of alternating shade over the courtyard and galleries."""
    xs = np.arange(-END_WALL_X, END_WALL_X + 1e-9, 1.5)
    zs = np.arange(-BACK_WALL_Z, BACK_WALL_Z + 1e-9, 1.5)
    grid = np.stack(np.meshgrid(xs, [0.0], zs, indexing="ij"), -1)[:, 0]   # (X, Z, 3)
    tris, normals = oriented(*_quads(grid, np.broadcast_to([0.0, 1.0, 0.0], grid.shape)))
    # _quads lists every cell's first triangles, then every cell's second ones
    cells = np.add.outer(np.arange(len(xs) - 1), np.arange(len(zs) - 1)).ravel()
    light = np.tile(cells % 2 == 0, 2)
    with mesh.part("floor"):
        for pick, shade in ((light, FLOOR_LIGHT), (~light, FLOOR_DARK)):
            _add(mesh, (tris[pick], normals[pick]), shade)


def column_parts(storey: Storey) -> list[tuple[np.ndarray, np.ndarray, tuple]]:
    """One column of ``storey`` standing at x = z = 0: a square base, the shaft, a round
    echinus and a square abacus, each a closed solid, as ``(tris, normals, albedo)``."""
    r, y, w = storey.column_radius, storey.floor, 2 * storey.capital_half_width
    capital = y + storey.base_height + storey.shaft_height
    return [
        (*box((0.0, y + storey.base_height / 2, 0.0), (w, storey.base_height, w)), STONE_DARK),
        (*cylinder((0.0, 0.0), y + storey.base_height, storey.shaft_height, r, rings=16),
         STONE),
        (*cylinder((0.0, 0.0), capital, storey.capital_height * 0.4, r * 1.25, rings=2),
         STONE_DARK),
        (*box((0.0, capital + storey.capital_height * 0.7, 0.0),
              (w, storey.capital_height * 0.6, w)), STONE_DARK),
    ]


def _column(mesh: MeshBuilder, parts, x: float, z: float) -> None:
    for tris, normals, albedo in parts:
        _add(mesh, (tris + np.array([x, 0.0, z]), normals), albedo)


def side_name(sign: float) -> str:
    """The long side at ``z`` of ``sign``: north (z < 0, the sunlit arcades) or south."""
    return "north" if sign < 0 else "south"


def _side(mesh: MeshBuilder, sign: float) -> None:
    """One long side (``z`` of the sign): two arcades, the gallery slabs, the parapet and
    the back wall, each a part named after the side (``north columns``, ...)."""
    z = sign * ARCADE_Z
    side = side_name(sign)
    for storey in STOREYS:
        parts = column_parts(storey)
        with mesh.part(f"{side} columns"):
            for x in column_xs():
                _column(mesh, parts, x, z)
        with mesh.part(f"{side} arcade walls"):
            _add(mesh, arcade_wall(storey, z), STONE)
    slab_depth = BACK_WALL_Z - ARCADE_Z + WALL_THICKNESS / 2
    slab_z = sign * (ARCADE_Z - WALL_THICKNESS / 2 + slab_depth / 2)
    length = 2 * END_WALL_X
    with mesh.part(f"{side} gallery floor"):
        _add(mesh, box((0.0, (GROUND.top + UPPER.floor) / 2, slab_z),
                       (length, UPPER.floor - GROUND.top, slab_depth)), STONE_DARK)
    with mesh.part(f"{side} roof"):
        _add(mesh, box((0.0, (UPPER.top + HEIGHT) / 2, slab_z),
                       (length, HEIGHT - UPPER.top, slab_depth)), STONE_DARK)
    width = PITCH - 2 * UPPER.capital_half_width
    with mesh.part(f"{side} parapet"):
        for x in bay_centres():
            _add(mesh, box((x, UPPER.floor + 0.5, z), (width, 1.0, 0.2)), STONE)
    with mesh.part(f"{side} back wall"):
        _add(mesh, box((0.0, HEIGHT / 2, sign * (BACK_WALL_Z + WALL_THICKNESS / 2)),
                       (length, HEIGHT, WALL_THICKNESS)), STONE)


def _drapes(mesh: MeshBuilder, sign: float) -> None:
    """A long curtain in every ground bay and a banner in every upper bay, cycling
    through :data:`DRAPE_COLOURS` (the banner of a bay differs from its curtain, and the
    two sides start at different colours)."""
    start = 0 if sign < 0 else 2
    count = len(DRAPE_COLOURS)
    side = side_name(sign)
    for k, x in enumerate(bay_centres()):
        with mesh.part(f"{side} curtains"):
            _add(mesh, drape(x, PITCH - 0.75, GROUND.spring - 0.1, 0.3,
                             sign * (ARCADE_Z - 0.55), folds=7, depth=0.07, columns=40,
                             rows=56), DRAPE_COLOURS[(start + k) % count])
        with mesh.part(f"{side} banners"):
            _add(mesh, drape(x, PITCH - 1.0, UPPER.spring - 0.1, UPPER.floor + 1.2,
                             sign * (ARCADE_Z - 0.35), folds=5, depth=0.05, columns=28,
                             rows=36), DRAPE_COLOURS[(start + k + 2) % count])


SUN_FROM = (3.0, 10.0, 10.0)
"""A point on the sun's side: the sun shines from there towards the origin (44° above the
horizon, from the south, a little east). The south wing's shadow covers the courtyard
floor up to z ≈ −4 while the north arcades and their drapes are in full sun, so the
drapes throw their colours onto the shaded floor in front of them."""


def atrium() -> Scene:
    """The atrium scene (module docstring): over 100 000 triangles, a camera in the
    courtyard looking along it (the first key of :data:`FLY_THROUGH`), and the sun
(:data:`SUN_FROM`) lighting the north arcades."""
    mesh = MeshBuilder()
    _floor(mesh)
    for sign in (-1.0, 1.0):
        _side(mesh, sign)
        _drapes(mesh, sign)
        with mesh.part("west end wall" if sign < 0 else "east end wall"):
            _add(mesh, box((sign * (END_WALL_X + WALL_THICKNESS / 2), HEIGHT / 2, 0.0),
                           (WALL_THICKNESS, HEIGHT, 2 * BACK_WALL_Z + 2 * WALL_THICKNESS)),
                 STONE)
    positions, normals, albedo = mesh.arrays()
    lo = (-END_WALL_X - WALL_THICKNESS, 0.0, -BACK_WALL_Z - WALL_THICKNESS)
    hi = (END_WALL_X + WALL_THICKNESS, HEIGHT, BACK_WALL_Z + WALL_THICKNESS)
    sun_irradiance = 2.0
    side = 2.0 * DirectionalLight.half_width(lo, hi)
    sun = DirectionalLight(SUN_FROM, (0.0, 0.0, 0.0), sun_irradiance * side * side,
                           name="sun")
    # warm lamps under the two ground arcades, off by default (Settings.lights)
    lamps = tuple(PointLight((x, 2.6, sign * (ARCADE_Z + 1.5)), flux_for_irradiance(2.0, 1.5),
                             name=name, colour=(1.0, 0.7, 0.4))
                  for name, x, sign in (("lamp north", -4.5, -1.0), ("lamp south", 4.5, 1.0)))
    eye, target = FLY_THROUGH[0]
    return Scene("atrium", positions, normals, albedo, Camera(eye, target, 60.0),
                 (sun, *lamps), lo, hi, **mesh.part_fields(), lights_on=("sun",),
                 light_path=SUN_PATH, camera_path=FLY_THROUGH_PATH)


# --- fly-through ----------------------------------------------------------------------------

FLY_THROUGH: tuple[tuple[tuple[float, float, float], tuple[float, float, float]], ...] = (
    ((-11.0, 2.5, 4.0), (0.0, 1.2, -4.0)),
    ((-5.0, 2.0, 4.0), (4.0, 1.5, -5.0)),
    ((2.0, 3.0, 4.2), (9.0, 2.0, -3.0)),
    ((9.5, 4.0, 2.0), (0.0, 1.5, -5.0)),
    ((10.0, 2.5, -2.5), (-4.0, 3.0, 2.0)),
    ((4.0, 1.8, -4.0), (-8.0, 2.0, 4.5)),
    ((-3.0, 2.8, -3.5), (-10.0, 1.5, 3.0)),
    ((-9.5, 2.0, -1.0), (0.0, 2.5, 4.0)),
)
"""Keyframes (eye, target) of a closed loop around the courtyard, at the heights of a
walker and a little above; :func:`fly_through` interpolates them."""
FLY_THROUGH_PATH = KeyframePath(tuple((*eye, *target) for eye, target in FLY_THROUGH), 1.0)
"""The same keys as the scene's camera path (one loop per unit of its parameter)."""
SUN_PATH = KeyframePath(tuple((*where, 0.0, 0.0, 0.0) for where in (
    SUN_FROM, (10.0, 10.0, 4.0), (-3.0, 12.0, 9.0), (-10.0, 10.0, 4.0))), 60.0)
"""The sun's path (the primary light's animation): a loop from :data:`SUN_FROM` over the
east, back over the south wing and round the west, in a minute."""


def fly_through(t: float | np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """Camera ``(eye, target)`` at time ``t`` (one loop per unit, wrapping) along
    :data:`FLY_THROUGH`, each interpolated with :func:`catmull_rom`."""
    keys = np.asarray(FLY_THROUGH, np.float64)
    return catmull_rom(keys[:, 0], t), catmull_rom(keys[:, 1], t)
