"""Numbers in and out: every stage of a frame as float arrays (``render --dump``), their
JSON sidecar, float images (EXR, NPY), an engine's own VPLs or injected grid fed into the
pipeline (``--vpls``, ``--grid0``) and the stage-by-stage diff (``lpv-explorer diff``).

* :mod:`explorer.exchange.stages`: a FrameResult as named arrays, and what each holds;
* :mod:`explorer.exchange.sidecar`: the JSON that says where the arrays sit in the world;
* :mod:`explorer.exchange.files`: reading (never unpickling) and writing ``.npz``, ``.npy``
  and ``.exr`` files;
* :mod:`explorer.exchange.inputs`: VPLs and a grid_0 from a file, checked, and the frame
  that propagates a given grid_0;
* :mod:`explorer.exchange.diff`: the largest and relative error per stage, and where.
"""
