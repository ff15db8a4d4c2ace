"""Writes examples/textured-room/room.glb: a closed 4 m × 2.5 m × 4 m room (walls facing
inwards, one-sided as glTF's default says) with a checker-textured floor, a red wall, a
blue wall and a block, for examples/textured-room/scene.toml.

Run from the repository root: ``python examples/make_textured_room.py``. The asset is
small (a 64×64 texture) and checked in; this script is how it was made.
"""

from __future__ import annotations

from pathlib import Path

import numpy as np
import trimesh
from PIL import Image

HERE = Path(__file__).resolve().parent / "textured-room"
CELLS = 8
TEXELS = 64


def checker(light=(225, 220, 205), dark=(70, 60, 55)) -> Image.Image:
    """A CELLS × CELLS checker of TEXELS² sRGB texels (8 texels per cell)."""
    index = np.arange(TEXELS) // (TEXELS // CELLS)
    dark_cell = (index[:, None] + index[None, :]) % 2 == 1
    image = np.where(dark_cell[..., None], np.array(dark, np.uint8), np.array(light, np.uint8))
    return Image.fromarray(image.astype(np.uint8), "RGB")


def quad(corners, uv=None) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """Two triangles, counter-clockwise seen from the front (the room's inside)."""
    faces = np.array([[0, 1, 2], [0, 2, 3]])
    uv = np.array([[0, 0], [1, 0], [1, 1], [0, 1]], float) if uv is None else uv
    return np.asarray(corners, float), faces, uv


def material(colour=(255, 255, 255), texture=None):
    return trimesh.visual.material.PBRMaterial(
        baseColorFactor=[*colour, 255], baseColorTexture=texture, doubleSided=False,
        metallicFactor=0.0, roughnessFactor=1.0)


def mesh(parts, mat) -> trimesh.Trimesh:
    vertices, faces, uvs = [], [], []
    for corners, quad_faces, uv in parts:
        faces.append(quad_faces + sum(len(v) for v in vertices))
        vertices.append(corners)
        uvs.append(uv)
    return trimesh.Trimesh(np.vstack(vertices), np.vstack(faces), process=False,
                           visual=trimesh.visual.TextureVisuals(uv=np.vstack(uvs), material=mat))


def room() -> trimesh.Scene:
    x, y, z = 2.0, 2.5, 2.0
    floor = quad([(-x, 0, z), (x, 0, z), (x, 0, -z), (-x, 0, -z)])
    ceiling = quad([(-x, y, -z), (x, y, -z), (x, y, z), (-x, y, z)])
    back = quad([(-x, 0, -z), (x, 0, -z), (x, y, -z), (-x, y, -z)])
    front = quad([(x, 0, z), (-x, 0, z), (-x, y, z), (x, y, z)])
    left = quad([(-x, 0, z), (-x, 0, -z), (-x, y, -z), (-x, y, z)])
    right = quad([(x, 0, -z), (x, 0, z), (x, y, z), (x, y, -z)])
    scene = trimesh.Scene()
    scene.add_geometry(mesh([floor], material(texture=checker())), node_name="floor",
                       geom_name="floor")
    scene.add_geometry(mesh([ceiling, back, front], material((191, 191, 191))),
                       node_name="walls", geom_name="walls")
    scene.add_geometry(mesh([left], material((204, 20, 15))), node_name="red wall",
                       geom_name="red wall")
    scene.add_geometry(mesh([right], material((40, 80, 204))), node_name="blue wall",
                       geom_name="blue wall")
    block = trimesh.creation.box(extents=(0.8, 1.2, 0.8))
    block.apply_translation((0.6, 0.6, -0.7))
    block.visual = trimesh.visual.TextureVisuals(
        uv=np.zeros((len(block.vertices), 2)), material=material((191, 191, 191)))
    scene.add_geometry(block, node_name="block", geom_name="block")
    return scene


if __name__ == "__main__":
    HERE.mkdir(exist_ok=True)
    target = HERE / "room.glb"
    room().export(target)
    print(f"wrote {target} ({target.stat().st_size} bytes)")
