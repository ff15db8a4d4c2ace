"""Lesson checks (explorer/lessons/checks.py) and marks (explorer/lessons/marks.py): the
tables are validated as data, and every check of the shipped lessons holds on the
converged frame of its step (rendered headless at explorer.lessons.verify.CHECK_SIZE)."""

from __future__ import annotations

from dataclasses import replace

import pytest

from explorer.lessons import LessonError, load_all, load_lesson
from explorer.lessons.checks import CheckError, Outcome, evaluate, parse_check
from explorer.lessons.marks import MarkError, parse_mark


@pytest.fixture(scope="module")
def shipped():
    lessons, errors = load_all()
    assert not errors, errors
    return lessons


def _lookup(name: str):
    if name.startswith(("audit.", "frame.", "settings.", "figure.", "error.", "mark.")):
        return name
    raise KeyError(f"no live quantity {name!r}")


def _parse(**table):
    base = {"claim": "a claim", "value": "audit.clamp_gain", "op": ">", "than": 0}
    base.update(table)
    return parse_check({k: v for k, v in base.items() if v is not None}, _lookup,
                       try_count=1, has_compare=False, prefix="checks[0].")


@pytest.mark.parametrize("table, field, words", [
    ({"op": "~"}, "checks[0].op", "is not one of"),
    ({"op": "between", "than": [2, 1]}, "checks[0].than", "low < high"),
    ({"op": "<", "than": "zero"}, "checks[0].than", "finite number"),
    ({"value": "error.mitsuba_flux_ratio"}, "checks[0].value", "against Mitsuba"),
    ({"over": "error.reference_mitsuba_relative_l2"}, "checks[0].over", "against Mitsuba"),
    ({"over": "nothing.at_all"}, "checks[0].over", "no live quantity"),
    ({"after_try": 2}, "checks[0].after_try", "1..1"),
    ({"over_before_try": True}, "checks[0].over_before_try", "needs both"),
    ({"side": "compare"}, "checks[0].side", "no compare preset"),
    ({"claim": " "}, "checks[0].claim", "claim in words"),
    ({"code": "1+1"}, "checks[0].code", "unknown field"),
    ({"than": None}, "checks[0].than", "missing"),
])
def test_bad_check_tables_are_refused_with_the_field(table, field, words):
    with pytest.raises(CheckError) as caught:
        _parse(**table)
    assert caught.value.field == field and words in str(caught.value)


def test_a_figure_check_reads_the_steps_side():
    """A figure shows both sides of a comparison (a_*, b_*): its check is read on the
    step's side; the error and figure numbers are accepted otherwise."""
    def parse(**table):
        base = {"claim": "a claim", "value": "figure.audit.a_injected", "op": ">", "than": 0}
        return parse_check({**base, **table}, _lookup, try_count=1, has_compare=True)

    assert parse().value == "figure.audit.a_injected"
    assert parse(value="error.flux_ratio", side="compare").side == "compare"
    with pytest.raises(CheckError) as caught:
        parse(side="compare")
    assert caught.value.field == "side" and "both sides" in str(caught.value)


def test_evaluate_compares_ratios_and_reads_before_the_press():
    values = {("audit.a", False): 2.0, ("audit.a", True): 5.0, ("audit.b", False): 4.0,
              ("audit.b", True): 10.0}

    def read(name, after):
        return values[(name, after)]

    assert evaluate(_parse(value="audit.a", over="audit.b", op="between", than=[0.4, 0.6]),
                    read).holds
    check = _parse(value="audit.a", over="audit.b", after_try=1, over_before_try=True,
                   op=">", than=1.2)
    outcome = evaluate(check, read)
    assert outcome.holds and outcome.measured == pytest.approx(1.25)   # 5 after / 4 before
    assert not evaluate(replace(check, than=1.3), read).holds
    assert not evaluate(_parse(value="audit.a", op="<", than=2), read).holds
    missing = evaluate(_parse(value="audit.a", after_try=1), lambda n, a: (_ for _ in ()).throw(
        LookupError("no frame")))
    assert not missing.holds and "no frame" in missing.reason
    assert "FAILS" in str(missing)


def test_a_check_on_a_word():
    def read(name, after):
        return "no"
    assert evaluate(_parse(value="frame.gbuffer_ran", op="==", than="no"), read).holds
    assert not evaluate(_parse(value="frame.gbuffer_ran", op=">", than=0), read).holds


@pytest.mark.parametrize("table, field", [
    ({"id": "Dark", "label": "x", "at": [0, 0, 0]}, "marks[0].id"),
    ({"id": "dark", "label": "", "at": [0, 0, 0]}, "marks[0].label"),
    ({"id": "dark", "at": [0, 0, 0]}, "marks[0].label"),          # neither drawn nor measuring
    ({"id": "dark", "label": "x", "at": [0, 0]}, "marks[0].at"),
    ({"id": "dark", "label": "x", "at": [0, 9, 0]}, "marks[0].at"),      # outside the box
    ({"id": "dark", "label": "x", "at": [0, 0, 0], "normal": [0, 0, 0]}, "marks[0].normal"),
    ({"id": "dark", "label": "x"}, "marks[0].at"),
])
def test_bad_marks_are_refused(table, field):
    with pytest.raises(MarkError) as caught:
        parse_mark(table, ((-1, 0, -1), (1, 2, 1)), "marks[0].")
    assert caught.value.field == field


LESSON = '''
id = "probe"
title = "t"
summary = "s"
scene = "cornell"
[[steps]]
title = "one"
text = "The floor gets {{mark.floor.irradiance:.3g}} W/m²."
[[steps.marks]]
id = "floor"
label = "floor"
at = [0.0, 0.01, 0.0]
normal = [0, 1, 0]
[[steps.checks]]
claim = "the floor receives indirect light"
value = "mark.floor.irradiance"
op = ">"
than = 0
'''


def test_a_lesson_file_with_marks_and_checks_loads_and_errors_name_the_step(tmp_path):
    path = tmp_path / "01-probe.toml"
    path.write_text(LESSON)
    step = load_lesson(path).steps[0]
    assert step.mark_ids == ("floor",) and step.checks[0].value == "mark.floor.irradiance"
    path.write_text(LESSON.replace('value = "mark.floor.irradiance"',
                                   'value = "mark.wall.irradiance"'))
    with pytest.raises(LessonError) as caught:
        load_lesson(path)
    assert "step 1" in str(caught.value) and "checks[0].value" in str(caught.value)
    assert "no mark with id 'wall'" in str(caught.value)
    path.write_text(LESSON.replace("normal = [0, 1, 0]\n", ""))
    with pytest.raises(LessonError, match="text"):   # the text quotes a mark that measures
        load_lesson(path)


def test_every_lesson_checks_its_claims(shipped):
    """Every lesson declares checks; the course as a whole checks many of its steps."""
    checked = [(lesson.id, step.number) for lesson in shipped for step in lesson.steps
               if step.checks]
    for lesson in shipped:
        assert any(step.checks for step in lesson.steps), f"lesson {lesson.id} checks nothing"
    assert len(checked) >= 60, len(checked)


def test_every_check_holds_on_its_converged_frame(shipped, ctx):
    """Each checked step rendered headless at CHECK_SIZE (and after its try-this, or on its
    compare side, where a check reads there) to convergence, its figures read as it
    declares them and the error against the reference measured where a check names it;
    every claim holds (test_a_false_claim_fails: the same frames with the operator
    reversed fail, so a check that could never fail is caught)."""
    from explorer.lessons import preview_settings
    from explorer.lessons.verify import FrameCache, verify_step
    from explorer.lpv.pipeline import Pipeline
    from explorer.ui.figures import declared_readouts

    failures: list[str] = []
    count = 0
    cache = FrameCache()           # steps that render the same settings share the frame
    with Pipeline(preview_settings(shipped[0].steps[0]), ctx=ctx) as pipeline:
        for lesson in shipped:
            for step in lesson.steps:
                if not step.checks:
                    continue
                for outcome in verify_step(pipeline, step, figure_readouts=declared_readouts,
                                           cache=cache):
                    count += 1
                    if not outcome.holds:
                        failures.append(f"{lesson.path.name} step {step.number}: {outcome}")
    assert not failures, "\n".join(failures)
    assert count >= 140


def test_a_false_claim_fails(shipped, ctx):
    """A check that contradicts the frame fails with its claim and measured value."""
    from explorer.lessons import find_lesson, preview_settings
    from explorer.lessons.verify import verify_step
    from explorer.lpv.pipeline import Pipeline

    step = find_lesson("overview", shipped).steps[2]
    assert step.checks
    flipped = {">": "<=", ">=": "<", "<": ">=", "<=": ">"}
    reversed_checks = tuple(replace(c, op=flipped[c.op]) for c in step.checks
                            if c.op in flipped)
    assert reversed_checks
    with Pipeline(preview_settings(step), ctx=ctx) as pipeline:
        outcomes: list[Outcome] = verify_step(pipeline, replace(step, checks=reversed_checks))
    assert outcomes and not any(o.holds for o in outcomes)
    assert "FAILS" in str(outcomes[0]) and "measured" in str(outcomes[0])


FIGURE_AND_ERROR = '''
id = "probe"
title = "t"
summary = "s"
scene = "single-source"
[[steps]]
title = "one"
text = "L1 gives {{figure.lobe.l1_at_normal:.2f}} along the normal; error {{error.flux_ratio}}."
[steps.settings]
grid_size = 8
iterations = 4
[[steps.figures]]
kind = "clamped-cosine"
id = "lobe"
normal_deg = 40
[[steps.checks]]
claim = "L1 reads 3/4 along the normal, wherever the figure's normal points"
value = "figure.lobe.l1_at_normal"
op = "between"
than = [0.7499, 0.7501]
[[steps.checks]]
claim = "the figure opens at its declared normal"
value = "figure.lobe.normal_deg"
op = "=="
than = 40
[[steps.checks]]
claim = "the LPV puts some light on screen, as the reference does"
value = "error.flux_ratio"
op = ">"
than = 0
'''


def test_figure_and_error_checks_read_the_declared_figure_and_the_reference(tmp_path, ctx):
    """A figure check reads the figure as the step declares it, through the readouts
    handed in (without them it fails saying so, and renders nothing); an error check
    measures the step against the one-bounce reference, and only then."""
    from explorer.lessons import preview_settings
    from explorer.lessons.verify import verify_step
    from explorer.lpv.pipeline import Pipeline
    from explorer.ui.figures import declared_readouts

    path = tmp_path / "01-probe.toml"
    path.write_text(FIGURE_AND_ERROR)
    step = load_lesson(path).steps[0]
    with Pipeline(preview_settings(step), ctx=ctx) as pipeline:
        outcomes = verify_step(pipeline, step, figure_readouts=declared_readouts)
        assert all(o.holds for o in outcomes), [str(o) for o in outcomes]
        assert outcomes[2].measured > 0
        runs = []
        original = pipeline.run
        pipeline.run = lambda *a, **k: runs.append(a) or original(*a, **k)
        try:
            figures_only = replace(step, checks=step.checks[:2])
            assert all(o.holds for o in verify_step(pipeline, figures_only,
                                                    figure_readouts=declared_readouts))
            missing = verify_step(pipeline, figures_only)
        finally:
            del pipeline.run
        assert runs == []                      # the math figure needs no frame
        assert not missing[0].holds and "figure_readouts" in missing[0].reason
        unknown = replace(step, checks=(replace(step.checks[0],
                                                value="figure.lobe.nothing"),))
        [outcome] = verify_step(pipeline, unknown, figure_readouts=declared_readouts)
        assert not outcome.holds and "l1_at_normal" in outcome.reason


def test_the_lessons_command_verifies_the_checks(capsys):
    from explorer.cli import main

    assert main(["lessons", "overview", "--check"]) == 0
    out = capsys.readouterr().out
    assert "holds:" in out and "FAILS" not in out



def test_a_mark_measures_what_the_gather_computes_and_lands_on_its_pixel(shipped, ctx):
    """A mark placed on the surface seen at a pixel measures the irradiance the GPU's
    final gather computed there (indirect radiance = albedo·E/π), and the view draws it
    at that pixel with its label inside the image; a mark behind a wall is drawn faded."""
    import numpy as np

    from explorer.lessons import find_lesson, preview_settings
    from explorer.lessons.marks import Mark, irradiance
    from explorer.lpv.pipeline import Pipeline
    from explorer.ui.overlays.marks import placements

    step = find_lesson("overview", shipped).steps[0]
    settings = preview_settings(step, size=96, max_grid=16, rsm_size=32)
    with Pipeline(settings, ctx=ctx) as pipeline:
        result = pipeline.run(settings)
    x, y = 48, 40
    position = result.gbuffer_position[y, x]
    normal = result.gbuffer_normal[y, x, :3]
    assert position[3] > 0.5
    mark = Mark("probe", "probe", tuple(map(float, position[:3])),
                tuple(map(float, normal / np.linalg.norm(normal))))
    albedo = result.albedo[y, x]
    gathered = float(np.sum(result.indirect[y, x] * np.pi / np.maximum(albedo, 1e-6)))
    assert irradiance(mark, result) == pytest.approx(gathered, rel=0.03)
    from explorer.lessons.marks import readout

    shares = [readout(mark, result, f"{c}_share") for c in ("red", "green", "blue")]
    assert sum(shares) == pytest.approx(1.0) and all(0.0 <= v <= 1.0 for v in shares)

    origin, end = (100.0, 50.0), (100.0 + 2 * 96, 50.0 + 2 * 96)    # drawn at twice size
    [placed] = placements(result, [mark], origin, end, lambda text: (8.0 * len(text), 14.0))
    assert placed.point == pytest.approx((100 + 2 * (x + 0.5), 50 + 2 * (y + 0.5)), abs=2.5)
    assert placed.visible
    x0, y0, x1, y1 = placed.box
    assert origin[0] <= x0 < x1 <= end[0] and origin[1] <= y0 < y1 <= end[1]
    behind = Mark("behind", "behind the back wall", (0.0, 0.0, -1.2), None)
    [hidden] = placements(result, [behind], origin, end, lambda text: (8.0 * len(text), 14.0))
    assert not hidden.visible
    assert placements(result, [Mark("probe", "", mark.at, mark.normal)], origin, end,
                      lambda text: (1.0, 1.0)) == []          # a measuring mark is not drawn


def test_a_marks_reference_is_the_error_panels_reference_at_its_pixel(shipped, ctx):
    """``over_reference``: the LPV's irradiance at a mark over the one-bounce reference's
    there; the reference at the point is the GPU reference image's at the pixel that sees
    it (irradiance = radiance·π/albedo, shadow rays, the 1/r² clamp at half a cell), and
    the numpy sum of one pixel (``numpy_reference_irradiance``) to rounding."""
    import numpy as np

    from explorer.lessons import find_lesson, preview_settings
    from explorer.lessons.marks import Mark, irradiance_rgb, readout, reference_irradiance_rgb
    from explorer.lpv.pipeline import Pipeline
    from explorer.truth.gbuffer import scene_for, scene_triangles
    from explorer.truth.reference import GBuffer, numpy_reference_irradiance
    from explorer.truth.render import lit_vpls, reference_for_frame

    step = find_lesson("how-far", shipped).steps[0]
    settings = preview_settings(step, size=64, max_grid=16, rsm_size=16)
    with Pipeline(settings, ctx=ctx) as pipeline:
        result = pipeline.run(settings)
    x, y = 40, 30
    position, normal = result.gbuffer_position[y, x], result.gbuffer_normal[y, x, :3]
    assert position[3] > 0.5
    mark = Mark("probe", "", tuple(map(float, position[:3])),
                tuple(map(float, normal / np.linalg.norm(normal))))
    truth = reference_irradiance_rgb(mark, result)
    image, gbuffer = reference_for_frame(result, True, ctx=ctx)
    gpu = image[y, x] * np.pi / np.asarray(gbuffer.albedo)[y, x]
    np.testing.assert_allclose(truth, gpu, rtol=2e-3)
    one = GBuffer(np.array([[mark.at]]), np.array([[mark.normal]]), np.ones((1, 1, 3)),
                  np.ones((1, 1), bool))
    triangles = scene_triangles(scene_for(result.settings))
    numpy_sum = numpy_reference_irradiance(one, lit_vpls(result.vpls),
                                           0.5 * result.grid_spec.cell_size, triangles,
                                           True, ray_offset=None)[0, 0]
    np.testing.assert_allclose(truth, numpy_sum, rtol=1e-10)
    lpv = irradiance_rgb(mark, result)
    assert readout(mark, result, "over_reference") == pytest.approx(lpv.sum() / truth.sum())
    assert readout(mark, result, "green_over_reference") == pytest.approx(lpv[1] / truth[1])
    assert truth.min() > 0 and lpv.min() > 0


def test_a_try_this_may_reframe_the_camera(tmp_path):
    """``camera`` in a try-this moves the camera with the change (the reframe a new grid
    needs); with ``split`` it is refused (both sides share the step's camera)."""
    text = LESSON.replace('''[[steps.checks]]''', '''[[steps.try_this]]
control = "grid_size"
value = 8
camera = { eye = [0.0, 1.0, 4.0], target = [0.0, 0.0, 0.0] }
prompt = "Coarser."
[[steps.checks]]''', 1)
    path = tmp_path / "01-probe.toml"
    path.write_text(text)
    step = load_lesson(path).steps[0]
    after = step.try_this[0].apply(step.settings())
    assert after.grid_size == 8 and after.camera == ((0.0, 1.0, 4.0), (0.0, 0.0, 0.0))
    path.write_text(text.replace('prompt = "Coarser."', 'prompt = "Coarser."\nsplit = true'))
    with pytest.raises(LessonError, match="try_this\\[0\\].camera"):
        load_lesson(path)


def test_glyph_peaks_are_the_largest_value_over_the_mesh():
    import numpy as np

    from explorer.lpv.twin.light_grid import cosine_lobe
    from explorer.ui.overlays.glyphs import glyph_peaks
    from explorer.ui.overlays.quantities import glyph_directions

    directions, _ = glyph_directions()
    lobe = np.zeros((1, 9))
    lobe[0, :4] = cosine_lobe(np.array([0.0, 1.0, 0.0]))      # straight up: a mesh pole
    assert glyph_peaks(lobe, directions)[0] == pytest.approx(0.75)   # 1/4 + 1/2 along n


def test_the_readers_mode_shows_the_panels_a_step_uses(shipped):
    """Reader's mode: the article and the view always; the plot, Inspect, Show in scene,
    Error and Corrections panels only for the steps that use them; nothing is hidden in
    the explorer mode or outside a lesson."""
    from types import SimpleNamespace

    from explorer.lessons import find_lesson
    from explorer.ui.lesson_panel import LessonSession, hidden_panels, step_panels

    lessons = shipped
    overview = find_lesson("overview", lessons)
    assert step_panels(overview.steps[0]) == {"View", "Lesson"}
    assert "Plots" in step_panels(find_lesson("radiometry", lessons).steps[0])
    limits = find_lesson("limits", lessons)
    cascades = next(step for step in limits.steps if step.view == "cascade-weights")
    assert "Error" in step_panels(limits.steps[0]) and "Inspect" in step_panels(cascades)
    assert "Show in scene" in step_panels(find_lesson("solid-angles", lessons).steps[0])
    assert "Corrections" in step_panels(find_lesson("propagation", lessons).steps[2])

    session = LessonSession(lessons=lessons)
    session.open("overview")
    session.saved = object()                    # a step's configuration is on screen
    from explorer.ui.layout import PANELS

    titles = [panel.title for panel in PANELS]
    state = SimpleNamespace(reader_mode=True, lesson_session=session)
    hidden = hidden_panels(state, titles)
    assert "Corrections" in hidden and "Plots" in hidden
    assert "View" not in hidden and "Lesson" not in hidden
    state.reader_mode = False
    assert hidden_panels(state, titles) == frozenset()
    state.reader_mode, session.saved = True, None   # left the lesson
    assert hidden_panels(state, titles) == frozenset()


def test_predict_then_press_is_validated_and_needs_a_check(tmp_path):
    """A prediction names its question, two to four choices and the right one, and the
    step must check its answer after that try-this (so CI verifies it)."""
    from explorer.ui.article_try import verdict

    try_this = '''[[steps.try_this]]
control = "iterations"
value = 4
predict = { question = "Brighter or darker?", choices = ["brighter", "darker"], answer = 2 }
prompt = "Darker."
'''
    check = '''[[steps.checks]]
claim = "fewer steps: the floor darkens"
value = "mark.floor.irradiance"
after_try = 1
over = "mark.floor.irradiance"
over_before_try = true
op = "<"
than = 1
'''
    path = tmp_path / "01-probe.toml"
    path.write_text(LESSON + try_this + check)
    item = load_lesson(path).steps[0].try_this[0]
    assert item.predict.choices == ("brighter", "darker") and item.predict.answer == 2
    assert "right" in verdict(item.predict, 2) and "the answer is darker" in \
        verdict(item.predict, 1)
    path.write_text(LESSON + try_this)
    with pytest.raises(LessonError, match="needs a check of its answer"):
        load_lesson(path)
    path.write_text(LESSON + try_this.replace("answer = 2", "answer = 3") + check)
    with pytest.raises(LessonError, match="predict.answer"):
        load_lesson(path)


def test_small_multiples_vary_one_thing_on_one_scale():
    """The small-multiples figure: values checked per kind of variation; more steps
    accumulate more light (the lingering lesson 07 shows), the published formulas less,
    and L1 and L2 carry about the same flux."""
    from explorer.figure_params import FigureParamError, make_figure
    from explorer.ui.figures.small_multiples import State, panels, readouts

    steps = make_figure("small-multiples", values="4, 8, 16").params
    r = readouts(steps, State())
    assert r["flux_1"] < r["flux_2"] < r["flux_3"]
    assert r["flux_1"] == pytest.approx(15.0, rel=0.2)     # about (4 + 1) × 3 W injected
    assert [p.title for p in panels(steps)] == ["4 steps", "8 steps", "16 steps"]
    formulas = make_figure("small-multiples", vary="corrections",
                           values="corrected, original").params
    assert readouts(formulas, State())["last_over_first"] < 0.5
    orders = make_figure("small-multiples", vary="sh_order", values="1, 2").params
    assert readouts(orders, State())["last_over_first"] == pytest.approx(1.0, abs=0.1)
    for bad in ({"values": "4"}, {"values": "4, 4"}, {"values": "4, 99"},
                {"vary": "sh_order", "values": "1, 3"},
                {"vary": "corrections", "values": "corrected, nonsense"}):
        with pytest.raises(FigureParamError, match="values"):
            make_figure("small-multiples", **bad)


def test_every_labelled_mark_is_in_view_in_its_step(shipped, ctx):
    """The step's own camera shows what its marks point at: each labelled mark projects
    into the image and no surface hides it (tiny frames: only the camera matters)."""
    from explorer.lessons import preview_settings
    from explorer.lpv.pipeline import Pipeline
    from explorer.ui.lesson_lint import hidden_marks

    with Pipeline(preview_settings(shipped[0].steps[0]), ctx=ctx) as pipeline:
        assert not hidden_marks(pipeline, shipped)
