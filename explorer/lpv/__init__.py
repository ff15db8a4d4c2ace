"""The LPV frame as a library: what scripts, notebooks and other tools call.

* :func:`render` renders one frame with a throw-away headless pipeline and returns its
  :class:`FrameResult` (numpy arrays: the images, the RSM, the VPLs, every cascade's
  grids, the energy audit, the timings and the warnings);
* :class:`Pipeline` keeps its GPU resources between frames and re-runs only the stages
  whose inputs changed (``run``), or time-slices a frame (``start`` → ``Job.advance``);
* :class:`Settings` holds everything a frame depends on, each field typed and ranged
  (``Settings(grid_size=8)``, ``settings.with_changes(corrections="original")``);
  :class:`Corrections` the switches between published and corrected formulas, and
  ``PRESETS`` the named sets of them;
* :func:`inject` and :func:`propagate` run one GPU pass on numpy input (a headless
  context is created on first use when ``ctx`` is None): your VPLs as
  :class:`VplArrays`, placed in a :class:`GridSpec`; ``explorer.lpv.twin.light_grid``
  holds the same functions in pure numpy, ``STAGE_LIST`` the frame's stages (each stage's
  passes are in ``explorer.lpv.passes.<pass>``: ``RsmPass``, ``GBufferPass``...).

Example::

    from explorer.lpv import Settings, render
    frame = render(Settings(grid_size=16), corrections="original")
    print(frame.audit.injected, frame.stages_run, frame.warnings)
"""

import importlib

# inject and propagate share their names with their modules: bound now, so that importing
# the module later cannot shadow the function. The rest is imported on first use (PEP
# 562), so that ``import explorer.lpv.twin.light_grid`` (the numpy twin) loads neither
# the pipeline nor the generated constants mirror: the twin takes its constants from the
# derivations alone (tests/lpv/twin/test_twin.py).
from explorer.lpv.passes.inject import inject
from explorer.lpv.passes.propagate import propagate

_HOMES = {"Corrections": "corrections", "PRESETS": "corrections", "FrameResult": "frame",
          "LevelResult": "frame", "Job": "job", "Progress": "job",
          "Pipeline": "pipeline", "render": "pipeline", "Settings": "settings",
          "STAGE_LIST": "stage_list", "GridSpec": "grid", "VplArrays": "vpl"}


def __getattr__(name: str):
    if name in _HOMES:
        return getattr(importlib.import_module(f"explorer.lpv.{_HOMES[name]}"), name)
    raise AttributeError(f"module 'explorer.lpv' has no attribute {name!r}")


__all__ = ["Corrections", "FrameResult", "GridSpec", "Job", "LevelResult", "PRESETS",
           "Pipeline", "Progress", "STAGE_LIST", "Settings", "VplArrays", "inject",
           "propagate", "render"]
