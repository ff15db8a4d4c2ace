"""The declared stage list (explorer/lpv/stage_list.py) is the only list of the frame's
stages: the execution order, the job's verbs, the timed passes, the stages a correction
may touch, the settings' stage names and the stage objects all derive from it, and no
other module spells out a list of stage names."""

from __future__ import annotations

import ast
import dataclasses
import inspect
import pkgutil
from pathlib import Path

import pytest

from explorer import schema
from explorer.lpv import cache_keys, corrections, job, stage_list, stages
from explorer.lpv.settings import Settings
from explorer.lpv.stage_list import STAGE_LIST, STAGES, StageDecl, execution_order
from explorer.lpv.stages.base import Stage

ROOT = Path(__file__).resolve().parents[2]


def test_every_other_stage_fact_is_derived_from_the_list():
    assert STAGES == tuple(decl.name for decl in STAGE_LIST)
    assert sorted(stage_list.EXECUTION_ORDER) == sorted(STAGES)
    assert cache_keys.EXECUTION_ORDER is stage_list.EXECUTION_ORDER
    assert job.VERBS is stage_list.VERBS and set(job.VERBS) == set(STAGES)   # fog too
    assert job.Progress("fog", 1, 3, False, ()).label == "marching the fog 1/3"
    assert corrections.STAGES == tuple(d.name for d in STAGE_LIST if d.corrections)
    assert cache_keys.PASSES == tuple(d.name for d in STAGE_LIST if d.gpu)
    assert not hasattr(schema, "STAGES")               # the schema knows no stage names
    every_field_stage = {s for spec in schema.specs(Settings).values() for s in spec.stages}
    assert every_field_stage <= set(STAGES)


def test_the_execution_order_runs_eager_stages_first_among_the_passes():
    assert stage_list.EXECUTION_ORDER.index("gbuffer") == 2       # after scene and grid
    for index, name in enumerate(stage_list.EXECUTION_ORDER):
        for up in stage_list.DECLARATIONS[name].all_upstream:
            assert stage_list.EXECUTION_ORDER.index(up) < index
    late = (StageDecl("b", ("a",), "b-ing", ""), StageDecl("a", (), "a-ing", ""))
    with pytest.raises(ValueError, match="stage b runs before its upstream stage"):
        execution_order(late)
    with pytest.raises(ValueError, match="unknown upstream"):
        execution_order((StageDecl("a", ("z",), "a-ing", ""),))


def test_each_declared_stage_has_its_module_and_no_module_is_undeclared():
    modules = {info.name for info in pkgutil.iter_modules(stages.__path__)}
    assert modules - {"base"} == set(STAGES)
    for name in STAGES:
        cls = stages.stage_class(name)
        assert issubclass(cls, Stage) and cls is not Stage
        assert cls.__module__ == f"explorer.lpv.stages.{name}"


def test_a_settings_field_declares_only_listed_stages():
    @dataclasses.dataclass(frozen=True)
    class Typo:
        x: int = schema.setting(1, kind="int", doc="x", stages=("gahter",))

    with pytest.raises(ValueError, match="field x: unknown stage"):
        schema.check_stages(Typo, STAGES)


def test_each_stage_params_read_only_the_fields_its_key_holds():
    """A stage's ``Params.of(settings)`` reads only Settings fields whose declaration
    names that stage: otherwise a change of the field would not re-run it."""
    class Recorder:
        def __init__(self):
            self.read = set()

        def __getattr__(self, name):
            self.read.add(name)
            return getattr(Settings(), name)

    derived = {"uses_camera_occluders": ("camera_occluders", "geometry_volume")}
    checked = []
    for name in STAGES:
        module = __import__(f"explorer.lpv.stages.{name}", fromlist=["Params"])
        params = getattr(module, "Params", None)
        if params is None:
            continue
        # one home and one shape: a dataclass of the stage's own module, made by ``of``
        assert dataclasses.is_dataclass(params) and params.__module__ == module.__name__, name
        recorder = Recorder()
        extra = {"eye": (0.0, 0.0, 2.0), "cascades": 1}     # what a stage adds itself
        names = list(inspect.signature(params.of).parameters)[1:]
        params.of(recorder, *[extra[n] for n in names])
        read = set()
        for field in recorder.read:
            read.update(derived.get(field, (field,)))
        allowed = set(schema.stages_reading(Settings, name))
        # a field of an upstream stage re-runs this one through the upstream's output key
        # (the display composes the fog when the fog stage has it on)
        upstream_inputs = {f for up in stage_list.DECLARATIONS[name].all_upstream
                           for f in schema.stages_reading(Settings, up)}
        assert read <= allowed | upstream_inputs, (name, read - allowed)
        checked.append(name)
    assert checked == ["inject", "geometry", "propagate", "gather", "fog", "display"]


def _stage_name_literals(path: Path) -> list[tuple[int, list[str]]]:
    """Tuple, list and set literals (and dict keys) of three or more stage names."""
    found = []
    for node in ast.walk(ast.parse(path.read_text(encoding="utf-8"))):
        items = node.elts if isinstance(node, (ast.Tuple, ast.List, ast.Set)) else \
            node.keys if isinstance(node, ast.Dict) else None
        if not items:
            continue
        names = [item.value for item in items
                 if isinstance(item, ast.Constant) and isinstance(item.value, str)]
        if len(names) >= 3 and len(names) == len(items) and set(names) <= set(STAGES):
            found.append((node.lineno, names))
    return found


def test_no_other_module_lists_the_stages():
    listed = [f"{path.relative_to(ROOT)}:{line} {names}"
              for package in ("explorer", "derivations")
              for path in sorted((ROOT / package).rglob("*.py"))
              if path.name != "stage_list.py"
              for line, names in _stage_name_literals(path)]
    assert listed == []


def test_a_frame_leaves_each_stage_its_typed_field(gl_context):
    """What the stages hand on is typed and complete once a frame is done; the fog's
    field is None while the fog is off and its images once it is on."""
    from explorer.lpv.frame_state import GBufferImages, RsmImages, VplImages
    from explorer.lpv.passes.fog import FogImages
    from explorer.lpv.passes.gather import GatherImages
    from explorer.lpv.pipeline import Pipeline

    small = Settings(grid_size=8, iterations=3, rsm_size=32, width=40, height=32)
    with Pipeline(small, ctx=gl_context) as pipeline:
        result = pipeline.run()
        state = pipeline.state
        assert isinstance(state.gbuffer, GBufferImages) and isinstance(state.rsm, RsmImages)
        assert isinstance(state.vpls, VplImages) and isinstance(state.gather, GatherImages)
        assert state.fog is None and len(state.cascades) == len(state.specs) == 1
        assert state.gbuffer.position.shape == (32, 40, 4)
        assert result.vpls is state.vpls.vpls and result.display_scale == state.display_scale
        assert {"scene", "rsm", "gbuffer", "gather", "fog"} <= set(state.warnings) <= set(
            STAGES)                        # the stages that check what they made said so
        pipeline.run(small.with_changes(fog=True))
        assert isinstance(pipeline.state.fog, FogImages)
