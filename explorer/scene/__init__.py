"""Scenes: built-in ones and meshes read with trimesh, their camera, lights, movable
objects and animation paths.

``load_scene("cornell")`` / ``"single-source"`` / ``"room"`` / ``"atrium"`` or a path to a
mesh file.
"""

from explorer.scene.builtin import BUILTIN_SCENES
from explorer.scene.camera import Camera
from explorer.scene.lights import DirectionalLight, PointLight, SpotLight
from explorer.scene.loader import load_scene
from explorer.scene.meshes import scene_from_mesh, srgb_to_linear
from explorer.scene.model import MAX_LIGHTS, MeshBuilder, Scene, SceneError
from explorer.scene.objects import ObjectTransform, SceneObject

__all__ = [
    "BUILTIN_SCENES", "Camera", "DirectionalLight", "MAX_LIGHTS", "MeshBuilder",
    "ObjectTransform", "PointLight", "Scene", "SceneError", "SceneObject", "SpotLight",
    "load_scene", "scene_from_mesh", "srgb_to_linear",
]
