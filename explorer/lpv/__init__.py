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
  context is created on first use when ``ctx`` is None); ``explorer.lpv.reference`` holds
  the same functions in pure numpy, ``STAGE_LIST`` the frame's stages.

Example::

    from explorer.lpv import Settings, render
    frame = render(Settings(grid_size=16), corrections="original")
    print(frame.audit.injected, frame.stages_run, frame.warnings)
"""

from explorer.lpv.corrections import PRESETS, Corrections
from explorer.lpv.frame import FrameResult, LevelResult
from explorer.lpv.inject import inject
from explorer.lpv.job import Job, Progress
from explorer.lpv.pipeline import Pipeline, render
from explorer.lpv.propagate import propagate
from explorer.lpv.settings import Settings
from explorer.lpv.stage_list import STAGE_LIST

__all__ = ["Corrections", "FrameResult", "Job", "LevelResult", "PRESETS", "Pipeline",
           "Progress", "STAGE_LIST", "Settings", "inject", "propagate", "render"]
