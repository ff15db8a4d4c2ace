"""The scripting API (``explorer.lpv``, also reachable as ``explorer.<name>``), used the
way a script uses it: render a frame, keep a pipeline, switch corrections, run one pass on
numpy input and hold it against the numpy twin."""

from __future__ import annotations

import inspect

import numpy as np
import pytest
from lpv_cases import random_vpls, relative_error

import explorer
import explorer.lpv as lpv
from explorer.lpv.twin import light_grid as twin

SMALL = dict(scene="cornell", grid_size=8, iterations=4, rsm_size=32, width=40, height=32)


def test_the_api_is_exported_and_documented():
    for name in lpv.__all__:
        obj = getattr(lpv, name)
        if inspect.isclass(obj) or inspect.isfunction(obj):
            assert (obj.__doc__ or "").strip(), f"explorer.lpv.{name} has no docstring"
    for name in lpv.__all__:
        assert getattr(explorer, name) is getattr(lpv, name)
        assert name in dir(explorer)
    with pytest.raises(AttributeError):
        explorer.no_such_name  # noqa: B018


def test_a_script_renders_compares_presets_and_keeps_a_pipeline(gl_context):
    frame = lpv.render(lpv.Settings(**SMALL), ctx=gl_context)
    assert isinstance(frame, lpv.FrameResult) and frame.final_image.shape == (32, 40, 3)
    assert frame.stages_run[0] == "scene" and frame.warnings == []
    assert np.all(frame.audit.gathered > 0)
    # the published formulas inject π times the flux (docs/MODEL.md "Corrections")
    published = lpv.render(lpv.Settings(**SMALL), corrections="original", ctx=gl_context)
    ratio = published.audit.injected.sum() / frame.audit.injected.sum()
    assert ratio == pytest.approx(np.pi, rel=1e-4)
    assert published.settings.corrections == lpv.PRESETS["original"]
    with pytest.raises(ValueError, match="unknown setting"):
        lpv.render(grid_sise=8)
    with lpv.Pipeline(lpv.Settings(**SMALL), ctx=gl_context) as pipeline:
        first = pipeline.run()
        assert np.array_equal(first.final_image, frame.final_image)
        brighter = pipeline.run(pipeline.settings.with_changes(exposure=2.0))
        assert brighter.stages_run == ("display",)
        job = pipeline.start(pipeline.settings.with_changes(iterations=6))
        while not job.done:
            progress = job.advance(5.0)
        assert progress.finished and job.result.stages_run[0] == "propagate"
        assert [decl.name for decl in lpv.STAGE_LIST] == list(lpv.stage_list.STAGES)


def test_one_pass_on_numpy_input_matches_its_twin(gl_context):
    """A script's own VPLs (inside the cells: the RSM's lie on the box's walls, exactly on
    cell borders, where float32 and float64 may choose neighbouring cells)."""
    spec = lpv.GridSpec(origin=(-1.0, 0.5, -2.0), cell_size=0.25, resolution=8)
    vpls = random_vpls(1, spec, 300)
    switches = lpv.Corrections()
    grid = lpv.inject(vpls, spec, switches, ctx=gl_context)
    assert relative_error(grid, twin.inject(vpls, spec, switches)) < 1e-5
    steps = lpv.propagate(grid, switches, iterations=2, ctx=gl_context)
    twin_steps = twin.propagate(grid.astype(np.float64), switches, iterations=2)
    assert len(steps) == 3 and relative_error(steps[-1], twin_steps[-1]) < 1e-4


def test_a_script_injects_its_own_vpls_with_the_api_types_alone(gl_context):
    """An engineer's own VPLs, made with ``explorer.lpv.VplArrays`` and placed in an
    ``explorer.lpv.GridSpec``: one VPL in the middle of a cell injects its flux into that
    cell alone (corrected formulas: the grid's flux is the VPL's, docs/MODEL.md)."""
    spec = lpv.GridSpec(origin=(0.0, 0.0, 0.0), cell_size=1.0, resolution=4)
    vpl = lpv.VplArrays(positions=np.array([[1.5, 2.5, 0.5]]), normals=np.array([[0, 1.0, 0]]),
                        flux=np.array([[1.0, 2.0, 3.0]]), depth=np.array([2.0]),
                        texel_area=0.01)
    grid = lpv.inject(vpl, spec, lpv.PRESETS["corrected"], ctx=gl_context)
    lit = np.argwhere(np.abs(grid).sum(axis=(0, 4)) > 0)
    assert lit.tolist() == [[1, 2, 0]]
    assert np.allclose(twin.flux(grid), [1.0, 2.0, 3.0], rtol=1e-5)
