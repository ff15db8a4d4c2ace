"""Scenes: built-in ones and meshes read with trimesh, their camera and light.

``load_scene("cornell")`` / ``"single-source"`` / ``"room"`` / ``"atrium"`` or a path to a
mesh file.
"""

from explorer.scene.builtin import BUILTIN_SCENES
from explorer.scene.camera import Camera
from explorer.scene.lights import DirectionalLight, SpotLight
from explorer.scene.loader import load_scene, scene_from_mesh, srgb_to_linear
from explorer.scene.model import MeshBuilder, Scene, SceneError

__all__ = [
    "BUILTIN_SCENES", "Camera", "DirectionalLight", "MeshBuilder", "Scene", "SceneError",
    "SpotLight", "load_scene", "scene_from_mesh", "srgb_to_linear",
]
