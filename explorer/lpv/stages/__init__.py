"""One module per stage of the frame, named after it (``gather.py`` for the ``gather``
stage of :data:`explorer.lpv.stage_list.STAGE_LIST`), each with its ``Stage`` class: the
stage's passes and programs, its parameters taken from Settings (a ``Params.of(settings)``
of its own), its units of work as a generator, its read-back into
:class:`~explorer.lpv.frame_state.FrameState`. :func:`make_stages` makes one of each, in
the declared order; the declared list is the only list of stages (a stage's module is
found by its name, so adding a stage is one line in the list and one module here).
"""

from __future__ import annotations

import importlib

from explorer.lpv.stage_list import STAGE_LIST
from explorer.lpv.stages.base import Stage, StageHost

__all__ = ["Stage", "StageHost", "make_stages", "stage_class"]


def stage_class(name: str) -> type[Stage]:
    """The ``Stage`` class of the module named after stage ``name``."""
    module = importlib.import_module(f"{__name__}.{name}")
    cls = getattr(module, "Stage", None)
    if not (isinstance(cls, type) and issubclass(cls, Stage)):
        raise TypeError(f"{module.__name__} must define Stage, a subclass of "
                        f"explorer.lpv.stages.base.Stage")
    return cls


def make_stages(host: StageHost) -> dict[str, Stage]:
    """Stage name -> its object for ``host`` (the pipeline), in the declared order."""
    return {decl.name: stage_class(decl.name)(host, decl) for decl in STAGE_LIST}
