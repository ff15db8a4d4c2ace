"""The window's pipeline controller without a window (explorer/ui/controller.py), on the
headless context: which stages a change runs (counted where the pipeline starts them),
progressive pictures (reduced, and fewer for a short job) that end on the one-shot frame
at full size, cancellation mid-propagation, both sides of the split view advancing, the
quiet frame's longer budget that input cuts back, the view composer's single draw
per display change (explorer/ui/view_composer.py), a side refused with A's settings
(``test_a_side_that_cannot_run_with_a_is_refused_in_one_message``) and a side no longer
shown releasing what it made (``test_a_side_no_longer_shown_gives_back_what_it_made``).
Helpers: ``_state`` (a small AppState), ``_settle`` (update until idle),
``_live_textures``."""

from __future__ import annotations

import dataclasses
from collections import Counter

import numpy as np
import pytest

from explorer.lpv.passes.gather import reduced_size
from explorer.lpv.pipeline import Pipeline
from explorer.lpv.settings import Settings
from explorer.lpv.stage_list import VERBS
from explorer.ui import frame_budget
from explorer.ui import previews as preview_pacing
from explorer.ui.controller import CAMERA_STAGES, PINNED_DISPLAY, PipelineController
from explorer.ui.frame_budget import DRAG_SCALES, QUIET_AFTER_S, QUIET_BUDGET_MS
from explorer.ui.previews import FIRST_PREVIEW_SCALE, PREVIEW_SCALE
from explorer.ui.state import AppState
from explorer.ui.view_composer import ViewComposer

SMALL = Settings(scene="cornell", grid_size=8, iterations=6, rsm_size=32, width=48,
                 height=36)
BUDGET_MS = 0.01
"""A budget smaller than any unit (an 8³ propagation step takes about 0.1 ms): each update
does one unit per side."""


class CountingPipeline(Pipeline):
    """A real pipeline that counts the stages it begins (``stage_work`` is called once
    per stage a job runs, not for the stages that are up to date)."""

    def __init__(self, settings, ctx=None):
        super().__init__(settings, ctx=ctx)
        self.began: Counter = Counter()

    def stage_work(self, stage, job):
        self.began[stage] += 1
        return super().stage_work(stage, job)


@pytest.fixture
def controller(gl_context, ctx):
    control = PipelineController(gl_context, CountingPipeline)
    yield control
    control.release()


def _state(**changes) -> AppState:
    state = AppState(settings=SMALL.with_changes(**changes))
    state.follow_view_size = False
    return state


def _settle(controller, state, budget_ms=50.0, limit=2000, **options) -> list:
    """Update until a frame finds nothing to do; returns every status."""
    statuses = []
    for _ in range(limit):
        status = controller.update(state, budget_ms, **options)
        statuses.append(status)
        if not status.active:
            return statuses
    raise AssertionError("the controller never settled")


def _counts(controller) -> dict[str, Counter]:
    return {name: Counter(side.pipeline.began) for name, side in controller.sides.items()
            if side.pipeline is not None}


def _ran_since(controller, before: dict[str, Counter]) -> dict[str, set[str]]:
    now = _counts(controller)
    return {name: {stage for stage, count in (now[name] - before.get(name, Counter())).items()
                   if count} for name in now}


def test_display_only_changes_run_no_stage_and_draw_once(controller, gl_context):
    state = _state()
    state.view_mode = "split"
    _settle(controller, state)
    composer = ViewComposer(gl_context, controller.programs)
    try:
        def shown():
            for side in ("A", "B"):
                composer.side_image(side, state.runtime.frame.pictures[side],
                                    controller.side_display(state, side), state.view_buffer)
            pictures = state.runtime.frame.pictures
            composer.difference(pictures["A"], pictures["B"],
                                controller.side_display(state, "A"),
                                controller.side_display(state, "B"), state.view_buffer,
                                state.difference_scale, state.difference_colour_map)
            return composer.read("A").copy()

        first = shown()
        before, draws = _counts(controller), composer.draws
        assert shown().tolist() == first.tolist() and composer.draws == draws, \
            "an unchanged view draws nothing"
        changes = [("exposure", lambda: state.update(exposure=3.0)),
                   ("tone map", lambda: state.update(tone_map="linear-clip")),
                   ("indirect only", lambda: state.update(indirect_only=True)),
                   ("auto exposure", lambda: state.update(auto_exposure=False)),
                   ("buffer", lambda: setattr(state, "view_buffer", "direct")),
                   ("difference scale", lambda: setattr(state, "difference_scale", 0.5)),
                   ("colour map", lambda: setattr(state, "difference_colour_map",
                                                  "diverging")),
                   ("divider", lambda: setattr(state, "split_position", 0.3)),
                   ("sides exposed apart", lambda: setattr(state, "expose_sides_separately",
                                                           True))]
        for name, change in changes:
            change()
            status = controller.update(state, 50.0)
            assert not status.active, name
            draws = composer.draws
            shown()
            assert composer.draws - draws <= 3, name     # A, B and the difference at most
        assert _ran_since(controller, before) == {"A": set(), "B": set()}
        assert composer.draws > 0
        # what the pipelines ran has the display stage's fields pinned
        result = state.runtime.frame.result
        assert all(getattr(result.settings, name) == value
                   for name, value in PINNED_DISPLAY.items())
    finally:
        composer.release()


def test_a_before_after_split_of_a_display_field_shows_it_on_side_b(controller, gl_context):
    """A lesson's try-this "indirect light alone, beside the full image" overrides
    indirect_only for B only: B's side shows the indirect light alone (what its pipeline's
    display stage would show at A's display scale), A the full image."""
    state = _state(auto_exposure=False, exposure=2.0)
    state.view_mode = "split"
    state.compare_settings = state.compare_settings.with_changes(
        corrections=state.settings.corrections)
    state.compare_overrides = (("indirect_only", True),)
    _settle(controller, state)
    display_a = controller.side_display(state, "A")
    display_b = controller.side_display(state, "B")
    assert not display_a.indirect_only and display_b.indirect_only
    assert display_b.scale == display_a.scale, "B is shown at A's display scale"
    composer = ViewComposer(gl_context, controller.programs)
    try:
        images = {}
        for side, display in (("A", display_a), ("B", display_b)):
            composer.side_image(side, state.runtime.frame.pictures[side], display, "final")
            images[side] = composer.read(side)[..., :3].astype(int)
        # the same frame on both sides: only the display differs; the direct light is gone
        # on B, so B is darker everywhere and much darker where the spot shines
        assert (images["B"] <= images["A"] + 1).all()
        assert (images["A"] - images["B"]).max() > 100
        with Pipeline(SMALL.with_changes(indirect_only=True, auto_exposure=False,
                                         exposure=2.0), ctx=gl_context) as once:
            once.run(need_audit=False)
            width, height = once.final_texture.size
            alone = np.frombuffer(once.final_texture.read(), np.uint8).reshape(
                height, width, 4)[::-1, :, :3].astype(int)
        assert np.abs(images["B"] - alone).max() <= 1
    finally:
        composer.release()


def test_a_camera_change_runs_only_the_camera_stages(controller):
    state = _state()
    _settle(controller, state)
    camera = state.runtime.scene_facts.camera_default
    eye = tuple(c + 0.3 for c in camera[0])
    before = _counts(controller)
    state.update(camera=(eye, camera[1]))
    _settle(controller, state)
    ran = _ran_since(controller, before)["A"]
    assert ran and ran <= CAMERA_STAGES and "gather" in ran and "propagate" not in ran
    assert set(state.runtime.frame.result.stages_run) <= CAMERA_STAGES


def test_a_toggle_shows_growing_pictures_that_end_on_the_one_shot_frame(controller,
                                                                         gl_context):
    state = _state()
    _settle(controller, state)
    controller.preview_interval_s = 0.0     # a picture after every step
    state.set_corrections(propagation_4pi=False)
    steps, finals = [], 0
    for _ in range(500):
        status = controller.update(state, BUDGET_MS)
        picture = state.runtime.frame.pictures["A"]
        if status.published and not picture.stamp.final:
            steps.append(picture.stamp.done)
        finals += bool(status.published and picture.stamp.final)
        if not status.active:
            break
    assert len(steps) >= 2 and steps == sorted(set(steps)), steps   # strictly increasing
    assert finals == 1 and state.runtime.frame.pictures["A"].stamp.final
    result = state.runtime.frame.result
    with Pipeline(result.settings, ctx=gl_context) as once:
        expected = once.run(result.settings, need_audit=False)
    for name in ("direct", "indirect"):
        got, want = getattr(result, name), getattr(expected, name)
        assert np.abs(got - want).max() <= 1e-6 * max(np.abs(want).max(), 1e-30), name
    direct, indirect, mask = state.runtime.frame.pictures["A"].read()   # what the view shows
    np.testing.assert_allclose(indirect, expected.indirect, rtol=0, atol=1e-6 * max(
        float(np.abs(expected.indirect).max()), 1e-30))
    np.testing.assert_allclose(direct, expected.direct, rtol=0, atol=1e-6 * max(
        float(np.abs(expected.direct).max()), 1e-30))
    assert mask.any()


def test_a_change_mid_propagation_cancels_and_restarts(controller, gl_context):
    state = _state()
    _settle(controller, state)
    state.set_corrections(propagation_4pi=False)
    side = controller.sides["A"]
    for _ in range(500):
        controller.update(state, BUDGET_MS)
        progress = side.progress
        if progress is not None and progress.stage == "propagate" and \
                0 < progress.done < progress.total:
            break
    else:
        raise AssertionError("never caught the propagation in the middle")
    job = side.job
    before = _counts(controller)
    state.set_corrections(clamp_front_face=False)        # a switch of the propagation
    controller.update(state, BUDGET_MS)
    assert job.cancelled and side.job is not job
    _settle(controller, state)
    ran = _ran_since(controller, before)["A"]
    assert "propagate" in ran and not ran & {"rsm", "inject", "downsample"}
    result = state.runtime.frame.result
    assert result.settings.corrections == state.settings.corrections
    with Pipeline(result.settings, ctx=gl_context) as once:
        expected = once.run(result.settings, need_audit=False)
    assert np.abs(result.indirect - expected.indirect).max() <= 1e-6 * max(
        float(np.abs(expected.indirect).max()), 1e-30)


def test_split_view_advances_both_sides_in_turn(controller):
    state = _state()
    state.view_mode = "split"
    _settle(controller, state)
    state.update(iterations=5)          # both sides propagate again
    statuses = _settle(controller, state, budget_ms=BUDGET_MS)
    busy = [status for status in statuses if len(status.labels) == 2]
    assert len(busy) >= 4
    # while both have work, every frame advances both
    for status in busy[:4]:
        assert {unit.side for unit in status.work} >= {"A", "B"}, status.work
    assert state.runtime.frame.result.settings.iterations == 5
    assert state.runtime.frame.compare_result.settings.iterations == 5


def test_a_drag_renders_smaller_and_the_rest_refines(controller):
    state = _state()
    _settle(controller, state)
    full = state.runtime.frame.result.direct.shape[:2]
    camera = state.runtime.scene_facts.camera_default
    for step in (1, 2, 3):    # a drag whose frames cannot fit: the scale falls to the least
        state.update(camera=(tuple(c + 0.1 * step for c in camera[0]), camera[1]))
        _settle(controller, state, interacting=True, drag_budget_ms=1e-3)
    dragged = state.runtime.frame.result.direct.shape[:2]
    assert controller.drag_scale == DRAG_SCALES[-1]
    assert dragged[0] < full[0] and dragged[1] < full[1]
    assert dragged[1] / dragged[0] == pytest.approx(full[1] / full[0], rel=0.1)
    before = _counts(controller)
    _settle(controller, state)          # the drag ended: full size, camera stages only
    assert state.runtime.frame.result.direct.shape[:2] == full
    assert _ran_since(controller, before)["A"] <= CAMERA_STAGES


def test_a_request_that_fails_keeps_the_last_good_picture(controller):
    state = _state()
    _settle(controller, state)
    good = state.runtime.frame.result
    picture = state.runtime.frame.pictures["A"].stamp
    controller.sides["A"].pipeline.memory_budget_bytes = 1    # refuses any frame
    state.update(grid_size=16)
    statuses = _settle(controller, state)
    assert sum(status.failures for status in statuses) == 1
    assert state.runtime.frame.result is good and state.runtime.frame.pictures["A"].stamp == picture
    assert "pipeline A failed" in state.runtime.frame.pipeline_error
    assert [m.level for m in state.messages].count("error") == 1
    assert controller.failed_settings == state.settings


@pytest.mark.parametrize("indirect_only", [False, True], ids=["final", "indirect-only"])
def test_the_view_shows_a_frame_with_fog_as_the_display_stage_does(controller, gl_context,
                                                                   indirect_only):
    """The picture keeps a finished frame's fog and the view pass composes it as the
    display stage does (one fog_compose.glsl): the view's image equals a one-shot
    pipeline's display texture to a step of 8 bits, and differs from the frame without
    fog."""
    state = _state(fog=True, fog_density=1.5, fog_steps=8, indirect_only=indirect_only)
    _settle(controller, state)
    picture = state.runtime.frame.pictures["A"]
    assert picture.stamp.final and picture.has_fog
    composer = ViewComposer(gl_context, controller.programs)
    try:
        def shown():
            composer.side_image("A", state.runtime.frame.pictures["A"],
                                controller.side_display(state, "A"), "final")
            return composer.read("A")[..., :3].astype(int)

        with_fog = shown()
        with Pipeline(state.settings, ctx=gl_context) as once:
            once.run(state.settings, need_audit=False)
            width, height = once.final_texture.size
            display = np.frombuffer(once.final_texture.read(), np.uint8).reshape(
                height, width, 4)[::-1, :, :3].astype(int)
        assert np.abs(with_fog - display).max() <= 1
        state.update(fog=False)
        _settle(controller, state)
        assert not state.runtime.frame.pictures["A"].has_fog
        assert np.abs(shown() - with_fog).max() > 20      # the fog showed
    finally:
        composer.release()


def _toggle_pictures(controller, state, budget_ms=BUDGET_MS, **options) -> list:
    """Toggle a propagation switch and update until settled: the (stamp, size) of every
    picture published on the way."""
    state.set_corrections(propagation_4pi=not state.settings.corrections.propagation_4pi)
    shown = []
    for _ in range(2000):
        status = controller.update(state, budget_ms, **options)
        picture = state.runtime.frame.pictures["A"]
        if status.published:
            shown.append((picture.stamp, picture.size))
        if not status.active:
            return shown
    raise AssertionError("the controller never settled")


def test_previews_come_reduced_and_the_finished_frame_at_full_size(controller, gl_context):
    state = _state()
    _settle(controller, state)
    full = (SMALL.width, SMALL.height)
    controller.preview_interval_s = 0.0     # a picture after every step
    shown = _toggle_pictures(controller, state)
    previews = [size for stamp, size in shown if not stamp.final]
    assert len(previews) >= 2
    # the job's first preview is coarse (the quickest changed picture), the others half size
    assert previews[0] == reduced_size(full, FIRST_PREVIEW_SCALE), previews
    assert set(previews[1:]) == {reduced_size(full, PREVIEW_SCALE)}, previews
    assert shown[-1][0].final and shown[-1][1] == full
    result = state.runtime.frame.result
    with Pipeline(result.settings, ctx=gl_context) as once:
        expected = once.run(result.settings, need_audit=False)
    direct, indirect, mask = state.runtime.frame.pictures["A"].read()
    for got, want in ((direct, expected.direct), (indirect, expected.indirect)):
        np.testing.assert_allclose(got, want, rtol=0, atol=1e-6 * max(
            float(np.abs(want).max()), 1e-30))
    assert mask.any()


def test_a_reduced_preview_is_the_full_preview_at_the_texels_below(gl_context):
    """The preview at half of each edge holds, at each pixel, what the full-size preview
    of the same accumulation holds at the G-buffer texel below it (gather.glsl's and
    view_snapshot.glsl's mapping); direct light and albedo as the G-buffer gives them."""
    settings = SMALL.with_changes(width=50, height=37)      # odd sizes: rounding
    with Pipeline(settings, ctx=gl_context) as pipeline:
        pipeline.run(settings, need_audit=False)
        job = pipeline.start(settings.with_changes(iterations=settings.iterations + 3),
                             need_audit=False)
        while not (job.progress.stage == "propagate" and job.progress.done >= 2):
            job.advance(0.0)
        assert job.preview(1.0)
        full = [_texture_array(t) for t in pipeline.preview_textures]
        assert job.preview(PREVIEW_SCALE)
        small = [_texture_array(t) for t in pipeline.preview_textures[:2]]
        job.cancel()
    size = reduced_size((settings.width, settings.height), PREVIEW_SCALE)
    assert small[0].shape[:2] == (size[1], size[0])
    rows = np.arange(size[1]) * settings.height // size[1]
    cols = np.arange(size[0]) * settings.width // size[0]
    below = [array[rows][:, cols] for array in full]
    assert below[0][..., 3].any() and np.abs(below[1][..., :3]).max() > 0.0
    for got, want in zip(small, below[:2]):
        np.testing.assert_allclose(got, want, rtol=0, atol=1e-6 * max(
            float(np.abs(want).max()), 1e-30))


def _texture_array(texture) -> np.ndarray:
    """An rgba32f or rgba16f texture as (H, W, 4) float32, row 0 at the bottom."""
    dtype = np.float16 if texture.dtype == "f2" else np.float32
    width, height = texture.size
    return np.frombuffer(texture.read(), dtype).reshape(height, width, 4).astype(np.float32)


def test_a_short_job_shows_one_preview_and_then_the_finished_frame(controller, monkeypatch):
    """After the first preview, none while the finished frame is due within FINISH_SOON_S
    (set here beyond any job; then to 0, when every step shows one)."""
    state = _state(iterations=40)
    _settle(controller, state)
    controller.preview_interval_s = 1e-9     # due after every step ...
    monkeypatch.setattr(preview_pacing, "PREVIEW_SHARE", 1e9)   # ... whatever it costs
    monkeypatch.setattr(preview_pacing, "FINISH_SOON_S", 1e9)
    shown = _toggle_pictures(controller, state)
    assert [stamp.final for stamp, _ in shown] == [False, True]
    monkeypatch.setattr(preview_pacing, "FINISH_SOON_S", 0.0)
    shown = _toggle_pictures(controller, state)
    steps = [stamp.done for stamp, _ in shown if not stamp.final]
    assert len(steps) >= 3 and shown[-1][0].final, steps


def test_a_quiet_frame_gets_the_longer_budget_and_input_cuts_it_back(controller):
    state = _state(iterations=40)
    _settle(controller, state)
    state.set_corrections(propagation_4pi=False)
    controller.update(state, BUDGET_MS, quiet_s=0.0)     # the click: the frame budget
    assert controller.budget_used_ms == BUDGET_MS
    while not controller.sides["A"].previews:      # the job's first picture (its frame is
        controller.update(state, BUDGET_MS, quiet_s=0.0)    # drawn: the frame budget)

    def units(status) -> int:
        return sum(unit.side == "A" and unit.what.startswith("propagating")
                   for unit in status.work)

    status = controller.update(state, BUDGET_MS, quiet_s=QUIET_AFTER_S)   # left alone
    assert units(status) > 1
    # ... until the job reaches the stages after the propagation: its finished frame is
    # near and is drawn, so that frame keeps to the frame budget
    last = status.work[-1].what
    finishing = last == "done" or last.startswith(
        tuple(VERBS[stage] for stage in frame_budget.FINISHING_STAGES))
    assert controller.budget_used_ms == (BUDGET_MS if finishing else QUIET_BUDGET_MS)
    state.set_corrections(propagation_4pi=True)          # a job that starts afresh
    asked = []

    def input_pending() -> bool:
        asked.append(True)
        return True
    status = controller.update(state, BUDGET_MS, quiet_s=1.0, input_pending=input_pending)
    assert asked and controller.budget_used_ms == BUDGET_MS and units(status) == 1
    status = controller.update(state, BUDGET_MS, quiet_s=1.0, interacting=True)
    assert controller.budget_used_ms < QUIET_BUDGET_MS     # a drag keeps its own budget


def test_the_shown_plot_chooses_the_audit_the_propagation_measures(controller):
    """The Plots panel's tab asks for the audit it needs (explorer/ui/panels/plots.py
    AUDIT_OF_TAB, through runtime.want_audit as the window's frame does): the flux-per-step
    tab gets the flux per step from the minimal kernel, the Energy audit tab reruns only
    the propagation for every term, and going back to flux or to no audit runs nothing."""
    from explorer.ui.panels.plots import AUDIT_OF_TAB

    state = _state()

    def show(tab: str | None) -> dict[str, set[str]]:
        before = _counts(controller)
        state.runtime.audit_wanted = "off"          # as the window's frame starts
        if tab is not None:
            state.runtime.want_audit(AUDIT_OF_TAB[tab])
        _settle(controller, state, need_audit=state.runtime.audit_wanted)
        return _ran_since(controller, before)

    show(None)
    audit = state.runtime.frame.result.audit
    assert audit.mode == "off" and np.isnan(audit.per_step[1:]).all()
    assert show("flux-per-step") == {"A": {"propagate"}}
    audit = state.runtime.frame.result.audit
    assert audit.mode == "flux" and np.isfinite(audit.per_step).all()
    assert audit.border_loss is None and state.runtime.frame.result.cascades[0].cell_records is None
    flux = audit.per_step.copy()
    assert show("audit") == {"A": {"propagate"}}
    audit = state.runtime.frame.result.audit
    assert audit.mode == "full" and audit.border_loss is not None
    assert np.allclose(audit.per_step, flux, rtol=1e-6)
    assert show("flux-per-step") == {"A": set()}           # the full audit covers it
    assert show("timings") == {"A": set()}
    state.runtime.want_audit("full")
    state.runtime.want_audit("flux")           # a picked cell and the flux plot at once
    assert state.runtime.audit_wanted == "full", "want_audit keeps the most asked for"


def test_the_picked_sides_audit_only(controller):
    """The picked cell's records are read on the picked side only (explorer/ui/panels/
    picked.py asks runtime.want_audit("full", side=...)): that side measures every term
    and keeps its per-cell records, the other measures what the rest asks (84 MiB of
    records a side at 64³ with two cascades, issue #31); picked on the other side, that
    one reruns its propagation (the first keeps its full audit: it covers the flux)."""
    state = _state()
    state.view_mode = "split"

    def frame_wants(picked_side: str) -> None:
        state.runtime.ask_again()                     # as the window's frame starts
        state.runtime.want_audit("flux")              # a plot of every side
        state.runtime.want_audit("full", side=picked_side)
        _settle(controller, state, need_audit=state.runtime.audit_of_sides(("A", "B")))

    frame_wants("B")
    shown, compared = state.runtime.frame.result, state.runtime.frame.compare_result
    assert compared.audit.mode == "full" and compared.cascades[0].cell_records is not None
    assert shown.audit.mode == "flux" and shown.cascades[0].cell_records is None
    before = _counts(controller)
    frame_wants("A")
    assert _ran_since(controller, before) == {"A": {"propagate"}, "B": set()}
    shown = state.runtime.frame.result
    assert shown.audit.mode == "full" and shown.cascades[0].cell_records is not None
    assert state.runtime.audit_of_sides(("A", "C")) == {"A": "full", "C": "flux"}
    state.runtime.ask_again()
    assert state.runtime.audit_of_sides(("A",)) == {"A": "off"}


@pytest.mark.parametrize("change", [{"corrections": "propagation_4pi"},
                                    {"corrections": "irradiance_gather"}])
def test_a_change_shows_a_labelled_coarse_picture_before_the_converged_one(controller,
                                                                          change):
    """After a change the first new picture is a coarse preview (a job's first, at
    FIRST_PREVIEW_SCALE), which the view labels, then the converged frame at full size;
    a change only the gather sees (no propagation to watch) gets one too."""
    from explorer.ui.panels.view import progress_label

    state = _state()
    _settle(controller, state)
    name = change["corrections"]
    state.set_corrections(**{name: not getattr(state.settings.corrections, name)})
    full = (SMALL.width, SMALL.height)
    shown = []
    for _ in range(2000):
        status = controller.update(state, BUDGET_MS)
        picture = state.runtime.frame.pictures["A"]
        if status.published:
            shown.append((picture.stamp.final, picture.size,
                          progress_label(status.labels.get("A"), picture)))
        if not status.active:
            break
    first_final, first_size, first_label = shown[0]
    assert not first_final and first_size == reduced_size(full, FIRST_PREVIEW_SCALE)
    width, height = first_size
    assert first_label.startswith(f"preview {width}×{height} · ")
    assert shown[-1][:2] == (True, full) and shown[-1][2] == ""


def test_an_unchanged_frame_reuses_its_request_and_any_change_makes_a_new_one():
    """The request of a side is made once per change of what it is made of (making it
    validates every Settings field and a new one compares the Settings by value)."""
    control = PipelineController(None, None)
    state = _state()
    first = control.request_for(state, "A", "flux", False)
    assert control.request_for(state, "A", "flux", False) is first
    state.set_corrections(side_faces=False)
    toggled = control.request_for(state, "A", "flux", False)
    assert toggled is not first and not toggled.settings.corrections.side_faces
    assert control.request_for(state, "A", "full", False).need_audit == "full"
    assert control.request_for(state, "A", "flux", True).interactive
    b = control.request_for(state, "B", "flux", False)
    ping_pong = state.compare_settings.corrections.ping_pong
    state.compare_settings = state.compare_settings.with_changes(
        corrections={"ping_pong": not ping_pong})
    changed = control.request_for(state, "B", "flux", False)
    assert changed != b and changed.settings.corrections.ping_pong != ping_pong
    again = control.request_for(state, "A", "flux", False)     # one request kept a side
    assert again == toggled and control.request_for(state, "A", "flux", False) is again


def test_a_frame_without_the_comparison_makes_no_settings_for_side_b(controller):
    """Side B's Settings (a validated copy of A's) are made only when B is shown: the
    sides' own exposures ask for them only when the sides are exposed separately."""
    state = _state()
    _settle(controller, state)
    made = Counter()
    settings_for = controller.settings_for

    def counted(state, side):
        made[side] += 1
        return settings_for(state, side)

    controller.settings_for = counted
    for _ in range(5):
        controller.update(state, BUDGET_MS)
    assert made["B"] == 0


def test_a_side_that_cannot_run_with_a_is_refused_in_one_message(controller):
    """A at 26 neighbours beside B propagating in place (which 26 neighbours refuse):
    the frame goes on, A converges, B runs nothing and the window says why once; a
    correction switch that would make such an A is not applied (the soak found A's
    toggle raising out of the frame)."""
    state = _state(neighbours=26)
    state.view_mode = "split"
    state.compare_settings = state.compare_settings.with_changes(
        corrections={"ping_pong": False})
    _settle(controller, state)
    _settle(controller, state)
    assert controller.sides["A"].result is not None
    assert controller.sides["B"].result is None
    refused = [m.text for m in state.messages if "cannot run with A's settings" in m.text]
    assert len(refused) == 1 and "ping_pong" in refused[0]
    assert controller.settings_for(state, "B") is state.settings     # shown as A's
    before = state.settings
    assert not state.set_corrections(ping_pong=False)
    assert state.settings is before
    b_before = state.compare_settings
    in_place = dataclasses.replace(b_before.corrections, ping_pong=False)
    assert not state.set_compare_corrections(in_place)    # the Compare panel's switch
    assert state.compare_settings is b_before
    assert sum("not applied" in m.text for m in state.messages) == 2
    state.update(neighbours=6)                  # now B can run beside A
    assert state.apply_preset("original", compare=True)
    state.compare_settings = state.compare_settings.with_changes(
        corrections={"ping_pong": False})
    _settle(controller, state)
    assert controller.sides["B"].result is not None


def test_a_side_no_longer_shown_gives_back_what_it_made(controller, gl_context):
    """Split view, then the single view for longer than ``idle_release_s``: B's pipeline,
    picture and frame are released (GL objects back to A's alone) and B, shown again,
    converges anew; a side shown again within the time keeps what it made."""
    state = _state()
    _settle(controller, state)
    alone = _live_textures(gl_context)
    state.view_mode = "split"
    _settle(controller, state)
    b = controller.sides["B"]
    assert b.pipeline is not None and b.result is not None
    assert _live_textures(gl_context) > alone
    state.view_mode = "single"
    _settle(controller, state)
    assert controller.sides["B"] is b, "within the time B keeps its pipeline"
    controller.idle_release_s = 0.0
    _settle(controller, state)
    fresh = controller.sides["B"]
    assert fresh.pipeline is None and fresh.picture is None and fresh.result is None
    assert _live_textures(gl_context) == alone
    state.view_mode = "split"
    _settle(controller, state)
    assert controller.sides["B"].result is not None



def _live_textures(gl_context) -> int:
    """Textures and framebuffers alive in the context now (the soak's own count)."""
    from explorer.commands.interaction import gl_objects

    gl_context.gc()
    counts = gl_objects(limit=4096)
    return counts["Texture"] + counts["Framebuffer"]


class _UnitClock:
    """A clock that stands still except while a unit of work runs: a unit of a per-pixel
    stage takes ``ms_per_pixel`` times the image's pixels, any other unit 0.01 ms, so
    that what a frame fits is decided by the units' sizes and not by the machine."""

    def __init__(self, ms_per_pixel: float) -> None:
        self.now_s, self.ms_per_pixel = 1000.0, ms_per_pixel
        self.units: list[tuple[int, str, int]] = []
        """(frame, stage, pixels) of every unit run."""
        self.frame = 0

    def __call__(self) -> float:
        return self.now_s

    def timed(self, stage: str, job, work):
        from explorer.lpv.stage_list import PIXEL_STAGES

        pixels = job.settings.width * job.settings.height
        cost_ms = self.ms_per_pixel * pixels if stage in PIXEL_STAGES else 0.01
        try:
            while True:
                self.now_s += cost_ms / 1e3
                self.units.append((self.frame, stage, pixels))
                try:
                    value = next(work)
                except StopIteration as stop:
                    return stop.value
                yield value
        finally:
            work.close()


def test_the_full_size_frame_after_a_drag_is_sized_by_full_size_units(gl_context, ctx,
                                                                         monkeypatch):
    """A drag's reduced frames measure small units; the full-size frame after the release
    must not be sized by them (it ran the full-size G-buffer and a gather band in one frame
    of a 30 ms budget): each frame of the release runs only what fits, as measured at the
    full size, and the G-buffer's units come in frames of their own."""
    import time as time_module

    full_unit_ms = 20.0
    clock = _UnitClock(full_unit_ms / (SMALL.width * SMALL.height))

    class TimedPipeline(CountingPipeline):
        def stage_work(self, stage, job):
            return clock.timed(stage, job, super().stage_work(stage, job))

    control = PipelineController(gl_context, TimedPipeline)
    monkeypatch.setattr(time_module, "perf_counter", clock)
    try:
        state = _state()
        _settle(control, state)                 # the first small picture, then full size
        camera = state.runtime.scene_facts.camera_default
        for step in (1, 2):                     # a drag: reduced frames
            state.update(camera=(tuple(c + 0.1 * step for c in camera[0]), camera[1]))
            _settle(control, state, interacting=True, drag_budget_ms=30.0)
        assert state.runtime.frame.result.direct.shape[1] < SMALL.width
        released = len(clock.units)
        budget_ms = 30.0
        for frame in range(1, 200):             # released: the full size follows
            clock.frame = frame
            status = control.update(state, budget_ms)
            if not status.active:
                break
        units = [(frame, stage) for frame, stage, pixels in clock.units[released:]
                 if pixels == SMALL.width * SMALL.height]
        pixel_units = Counter(frame for frame, stage in units
                              if stage in ("gbuffer", "gather", "display"))
        assert pixel_units, "the release ran no full-size work"
        # two 20 ms units never share a 30 ms frame (the first unit of a frame always runs)
        assert max(pixel_units.values()) == 1, pixel_units
        assert len({frame for frame, stage in units if stage == "gbuffer"}) >= 2
    finally:
        control.release()


def test_the_full_size_frame_after_a_drag_shows_no_preview(controller):
    """The full-size frame after a drag's reduced ones shows no progressive preview: it
    would show the camera's picture already on screen, at no larger a size."""
    state = _state()
    _settle(controller, state)
    camera = state.runtime.scene_facts.camera_default
    for step in (1, 2):
        state.update(camera=(tuple(c + 0.1 * step for c in camera[0]), camera[1]))
        _settle(controller, state, BUDGET_MS, interacting=True, drag_budget_ms=1e-3)
    assert state.runtime.frame.result.direct.shape[1] < SMALL.width
    statuses = _settle(controller, state, BUDGET_MS)
    assert state.runtime.frame.result.direct.shape[1] == SMALL.width
    previews = [unit.what for status in statuses for unit in status.work
                if unit.what.startswith("preview")]
    assert previews == []
    # a change the gather sees on the same size still gets its coarse first picture
    state.set_corrections(irradiance_gather=not state.settings.corrections.irradiance_gather)
    statuses = _settle(controller, state, BUDGET_MS)
    assert any(unit.what.startswith("preview") for status in statuses
               for unit in status.work)
