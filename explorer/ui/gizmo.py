"""The ImGuizmo gizmo that moves the selected object in the 3D view.

The Lights & objects panel selects an object (``Animation.selected``) and the operation
(move, turn, scale); :func:`draw` shows ImGuizmo's handles over the view image, at the
object's frame ``T(pivot + t)·R·S`` (explorer/scene/objects.py), seen through the camera
of the frame on screen. A drag gives a new matrix, which becomes the object's transform
in ``Settings.object_transforms``: the scene stage poses the object and the stages after
it run again, like any other change of settings. While a handle is dragged the window
renders at the camera drag's reduced size (``runtime.view.interaction``).
"""

from __future__ import annotations

import time

import numpy as np
from imgui_bundle import imguizmo

from explorer.scene import ObjectTransform, SceneError
from explorer.scene.objects import IDENTITY_VALUES, check_transform_values
from explorer.scene.transforms import gl_matrix
from explorer.ui.animation import animation_of, scene_of

_GIZMO = imguizmo.im_guizmo
GIZMO_SIZE = 0.18
"""The gizmo's size as a fraction of the view (ImGuizmo's default 0.1 is small beside
the Cornell box's blocks)."""
OPERATIONS = {"move": _GIZMO.OPERATION.translate, "turn": _GIZMO.OPERATION.rotate,
              "scale": _GIZMO.OPERATION.scale}


def using() -> bool:
    """A handle is being dragged (as of the last :func:`draw`)."""
    return bool(_GIZMO.is_using())


def hovered() -> bool:
    """The mouse is over a handle (as of the last :func:`draw`): the view must not take
    the click for the camera."""
    return bool(_GIZMO.is_over() or _GIZMO.is_using())


def object_transform(settings, name: str) -> ObjectTransform:
    """The transform ``settings`` give object ``name`` (identity when none)."""
    return ObjectTransform.from_values(dict(settings.object_transforms).get(
        name, IDENTITY_VALUES))


def draw(state, origin, end) -> bool:
    """Draw the gizmo of the selected object into the current window over the image
    from ``origin`` to ``end`` (screen coordinates) and apply a drag to the settings.
    Returns True while the gizmo is hovered or dragged."""
    animation, scene, result = animation_of(state), scene_of(state), state.runtime.frame.result
    if animation.selected is None or scene is None or \
            result is None or result.camera is None or result.scene_bounds is None:
        return False
    try:
        obj = scene.object_named(animation.selected)
    except SceneError:
        animation.selected = None
        return False
    transform = object_transform(state.settings, obj.name)
    height, width = np.asarray(result.direct).shape[:2]
    camera = result.camera
    view = camera.view_matrix()
    projection = camera.projection_matrix(width / height, *result.scene_bounds)
    _GIZMO.set_orthographic(False)
    _GIZMO.set_gizmo_size_clip_space(GIZMO_SIZE)
    _GIZMO.set_drawlist()
    _GIZMO.set_rect(origin.x, origin.y, end.x - origin.x, end.y - origin.y)
    matrix = _GIZMO.Matrix16(list(gl_matrix(transform.model_matrix(obj.pivot))))
    mode = _GIZMO.MODE.world if animation.operation == "move" else _GIZMO.MODE.local
    if _GIZMO.manipulate(_GIZMO.Matrix16(list(gl_matrix(view))),
                         _GIZMO.Matrix16(list(gl_matrix(projection))),
                         OPERATIONS[animation.operation], mode, matrix):
        moved = np.asarray(matrix.values, np.float64).reshape(4, 4).T   # column-major
        if apply_matrix(state, obj, moved):
            # a move like the camera's: the window renders at the drag's size meanwhile
            state.runtime.view.interaction.moved_at = time.monotonic()
    return hovered()


def apply_matrix(state, obj, model) -> bool:
    """Set object ``obj``'s transform from the gizmo's model matrix; a matrix no transform
    holds (a mirror, a scale out of range) is ignored. True when the settings changed."""
    try:
        transform = ObjectTransform.from_model_matrix(model, obj.pivot)
    except ValueError:
        return False
    values = check_transform_values(transform.values())
    if values is None:
        return False
    current = dict(state.settings.object_transforms)
    current[obj.name] = values
    return state.update(object_transforms=current)
