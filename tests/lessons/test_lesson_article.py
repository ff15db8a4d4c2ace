"""Lessons as articles: every number is live or derived, every placeholder resolves on a
real frame, every try-this applies and is undone, every view, plot and panel a lesson
names exists, and no step shows raw LaTeX, a stray ``$`` or a glyph the fonts lack."""

from __future__ import annotations

import re

import numpy as np
import pytest

from explorer.lessons import COMPARE_VIEWS, load_all, preview_settings
from explorer.lessons import live_values as lv
from explorer.lessons import text as lt
from explorer.lpv.settings import PLOTS, PRESETS, VIEWS, Settings
from explorer.truth.mitsuba_render import mitsuba_available

MITSUBA = mitsuba_available()
"""None when Mitsuba 3 is installed (the error.mitsuba_* numbers then resolve), else why
not."""


@pytest.fixture(scope="module")
def shipped():
    lessons, errors = load_all()
    assert errors == [], "\n".join(str(e) for e in errors)
    return lessons


def texts_of(lesson):
    """(where, text, kind) for everything a lesson shows: kind "markdown" (parsed by
    explorer.lessons.text) or "plain" (drawn as it is)."""
    yield "summary", lesson.summary, "plain"
    yield "title", lesson.title, "plain"
    for step in lesson.steps:
        where = f"{lesson.id} step {step.number}"
        yield f"{where} title", step.title, "plain"
        yield f"{where} text", step.text, "markdown"
        for index, item in enumerate(step.try_this):
            yield f"{where} try_this[{index}].prompt", item.prompt, "markdown"
            yield f"{where} try_this[{index}].label", item.label, "markdown"
        for index, spec in enumerate(step.figures):
            yield f"{where} figures[{index}].caption", spec.caption, "markdown"


# --- numbers ----------------------------------------------------------------------------

_FIELD = re.compile(r"\{\{[^{}]*\}\}")
_CODE = re.compile(r"`[^`]*`")
_MEASURED_LOOKING = re.compile(r"(?<![\w.])\d+\.\d+(?![\w.])|\d+(?:\.\d+)?\s*\\?%"
                               r"|\d\s*\\times\s*10\^")


def test_no_measured_number_is_typed_into_a_lesson(shipped):
    """No decimal number, percentage or power-of-ten number is typed into lesson prose
    (math included): each such number is a ``{{...}}`` placeholder, so it names the one
    quantity it shows. The placeholder's source is what tells a derived constant quoted
    as an illustration from a measurement: ``derived.<result>`` is an exact value of the
    derivation registry (the same on every machine); ``audit``, ``frame``, ``error`` and
    ``figure`` quantities are read from what is on screen. Whole numbers (counts, grid
    sizes, iteration counts, years) and command lines in code spans may be typed."""
    found = []
    for lesson in shipped:
        for where, text, _ in texts_of(lesson):
            bare = _CODE.sub(" ", _FIELD.sub(" ", text))
            found += [(where, token) for token in _MEASURED_LOOKING.findall(bare)]
    assert found == []


def test_lessons_quote_live_and_derived_numbers(shipped):
    sources = {}
    for lesson in shipped:
        for _, text, _ in texts_of(lesson):
            for name, _ in lt.placeholders(text):
                sources.setdefault(name.split(".", 1)[0], set()).add(name)
    assert {"derived", "audit", "frame", "error", "settings", "figure"} <= set(sources)
    assert len(sources["derived"]) >= 20 and len(sources["error"]) >= 4


def _small(settings: Settings) -> Settings:
    """A try-this's settings at the preview size of its step."""
    return settings.with_changes(width=64, height=64, rsm_size=min(settings.rsm_size, 32),
                                 grid_size=min(settings.grid_size, 16),
                                 iterations=min(settings.iterations, 8))


@pytest.fixture(scope="module")
def measured(shipped, gl_context):
    """For every step and try-this: the settings, a FrameResult at preview size and, when
    its text quotes errors, an error measurement (16 px, RSM 16², no shadow rays)."""
    from explorer.lpv.pipeline import Pipeline
    from explorer.truth.progressive import ErrorJob, Measurement

    gl_context.__enter__()
    out = {}
    with Pipeline(preview_settings(shipped[0].steps[0]), ctx=gl_context) as pipeline:
        def measure(settings, texts):
            result = pipeline.run(settings)
            error = None
            if any(name.startswith("error.") for text in texts
                   for name, _ in lt.placeholders(text)):
                job = ErrorJob(settings, Measurement(size=16, rsm_size=16,
                                                     reference="unoccluded"))
                while not job.advance(gl_context, pipeline, 1.0):
                    pass
                job.release()
                error = job.result.stats
                if MITSUBA is None and any(
                        name.startswith(TRUTH_NAMES) for text in texts
                        for name, _ in lt.placeholders(text)):
                    error = _against_mitsuba(job.result)
            return settings, result, error

        for lesson in shipped:
            for step in lesson.steps:
                base = preview_settings(step)
                texts = [step.text] + [spec.caption for spec in step.figures]
                out[(lesson.id, step.number, 0)] = measure(base, texts)
                for index, item in enumerate(step.try_this, start=1):
                    after = _small(item.apply(base))
                    out[(lesson.id, step.number, index)] = measure(after, [item.prompt])
    return out


TRUTH_NAMES = ("error.mitsuba_", "error.reference_mitsuba_")


def _against_mitsuba(result):
    """The error measurement held against a tiny Mitsuba render (4 spp per seed)."""
    from explorer.truth.gbuffer import scene_for
    from explorer.truth.mitsuba_job import ErrorReadout, TruthStats
    from explorer.truth.mitsuba_render import render_truth

    s = result.settings
    truth = render_truth(scene_for(s), s.width, s.height, spp=4)
    return ErrorReadout(result.stats, TruthStats(result.lpv, result.reference, result.valid,
                                                 truth))


def _figure_readouts(step, result):
    from explorer.ui.figures import FIGURES, FigureContext

    context = FigureContext(results=(result,))
    return {spec.instance_id: FIGURES[spec.kind].readouts(
        spec.params, FIGURES[spec.kind].make_state(spec.params), context)
        for spec in step.figures}


def test_every_placeholder_resolves_for_every_step(shipped, measured):
    """Each step's text and captions on the step's own frame, each try-this's prompt on
    the frame of the configuration its button sets: no placeholder stays pending."""
    checked = 0
    for lesson in shipped:
        for step in lesson.steps:
            for index in range(len(step.try_this) + 1):
                settings, result, error = measured[(lesson.id, step.number, index)]
                context = lv.LiveContext(settings=settings, result=result, error=error,
                                         figures=_figure_readouts(step, result),
                                         renderer="llvmpipe",
                                         marks={m.id: m for m in step.marks})
                texts = ([step.text] + [s.caption for s in step.figures] if index == 0
                         else [step.try_this[index - 1].prompt])
                for text in texts:
                    for name, fmt in lt.placeholders(text):
                        shown = lv.render(name, fmt, context, step.figure_ids)
                        if MITSUBA is not None and name.startswith(TRUTH_NAMES):
                            continue     # pending without Mitsuba, as in the window
                        assert shown != lv.PENDING and shown, \
                            (lesson.id, step.number, index, name)
                        assert "nan" not in shown.lower(), (lesson.id, step.number, name)
                        checked += 1
    assert checked > 150


def test_a_try_this_prompt_reads_the_configuration_its_button_sets(shipped, measured):
    """The numbers in a prompt are the button's configuration, not the step's: e.g. the
    prompt of "corrections: original" in the radiometry lesson reads π times the RSM flux
    injected, where the step itself injects exactly the RSM flux."""
    lesson = next(x for x in shipped if x.id == "radiometry")
    step = lesson.steps[-1]
    index = next(i for i, t in enumerate(step.try_this, start=1)
                 if t.control == "corrections" and t.value == "original")
    _, step_frame, _ = measured[(lesson.id, step.number, 0)]
    _, try_frame, _ = measured[(lesson.id, step.number, index)]

    def ratio(frame):
        return lv.lookup("audit.injected_over_rsm").value(lv.LiveContext(result=frame))

    assert ratio(step_frame) == pytest.approx(1.0, rel=1e-4)
    assert ratio(try_frame) == pytest.approx(np.pi, rel=1e-4)


# --- try this -----------------------------------------------------------------------------

def test_every_try_this_applies_and_is_undone_on_leaving(shipped):
    from explorer.ui.lesson_panel import LessonSession, Screen

    own = Screen(settings=Settings(width=300, height=200, exposure=2.0, grid_size=20,
                                   corrections=PRESETS["original"]),
                 compare_settings=Settings(corrections=PRESETS["original"]),
                 view_mode="difference")
    count = 0
    for lesson in shipped:
        for step in lesson.steps:
            for index, item in enumerate(step.try_this, start=1):
                session = LessonSession(lessons=shipped)
                session.open(lesson.id)
                session.go(step.number)
                shown = session.apply(own)
                tried = session.toggle_try(index, shown)
                wanted = item.apply(shown.settings)
                where = (lesson.id, step.number, index)
                assert wanted != shown.settings, where
                if item.compares:   # A: the step (before), B: the change (after)
                    assert tried.view_mode == item.compare, where
                    assert tried.settings == shown.settings, where
                    b = tried.settings.with_changes(
                        corrections=tried.compare_settings.corrections,
                        **dict(tried.compare_overrides))
                    assert b == wanted, where
                    further = [tried.settings.with_changes(**dict(v))
                               for v in tried.compare_variants]   # small multiples' C, D
                    assert further == [item.apply(shown.settings, value)
                                       for value in item.variants[1:]], where
                else:
                    assert tried.settings == wanted, where
                assert session.tried == index
                assert session.toggle_try(index, tried) == shown, where   # undo
                session.toggle_try(index, shown)
                assert session.leave() is own and session.tried is None
                count += 1
    assert count >= 60


# --- views, plots, panels ----------------------------------------------------------------

def test_every_view_plot_and_panel_a_lesson_names_exists(shipped):
    from explorer.ui.layout import PANELS
    from explorer.ui.lesson_panel import INSPECT_VIEWS, MAIN_VIEW_BUFFERS
    from explorer.ui.panels.plots import TABS
    from explorer.ui.state import INSPECT_SOURCES, VIEW_BUFFERS, VIEW_MODES

    titles = {panel.title for panel in PANELS}
    assert set(MAIN_VIEW_BUFFERS) <= set(VIEW_BUFFERS)
    assert set(INSPECT_VIEWS) <= set(INSPECT_SOURCES)
    assert set(VIEWS) <= set(MAIN_VIEW_BUFFERS) | set(INSPECT_VIEWS)    # every view shows
    assert set(PLOTS) == set(TABS) | {"error"} and "Error" in titles
    named_views = set(VIEWS) | set(COMPARE_VIEWS) | set(VIEW_MODES)
    for lesson in shipped:
        for step in lesson.steps:
            assert step.view in MAIN_VIEW_BUFFERS + INSPECT_VIEWS + COMPARE_VIEWS
            assert step.plot is None or step.plot in PLOTS
            # a step quoting the error shows the Error panel, which then measures
            quoted = [name for text in [step.text] + [t.prompt for t in step.try_this]
                      for name, _ in lt.placeholders(text)]
            if any(name.startswith("error.") for name in quoted):
                assert step.plot == "error", (lesson.id, step.number)
        for where, text, _ in texts_of(lesson):
            for panel in re.findall(r"\b([A-Z][a-z]+) panel\b", text):
                assert panel in titles, (where, panel)
            # "the X plot" names a plot; "the cascade-weights view" (a hyphenated name)
            # names a view, while "the light's view" or "the 3D view" is plain English
            for name in re.findall(r"\bthe ([\w-]+) plot\b", text):
                assert name in PLOTS, (where, f"{name} plot")
            for name in re.findall(r"\b([\w-]+) view\b", text):
                if "-" in name or name in named_views:
                    assert name in named_views, (where, f"{name} view")


# --- what the text shows ----------------------------------------------------------------

def _sample(name: str, fmt: str) -> str:
    """A stand-in for a live number in typesetting checks: the derived value itself,
    else 1.25 (or 16 for a setting) formatted as the lesson asks."""
    if name.startswith("derived."):
        return lv.render(name, fmt, lv.LiveContext())
    if name.startswith(("settings.", "corrections.")):
        return "16"
    return lv.format_value(1.25, fmt or ".3g")


def test_no_step_shows_raw_latex_a_dollar_or_a_missing_glyph(shipped):
    from explorer.ui import fonts

    for lesson in shipped:
        for where, text, kind in texts_of(lesson):
            if kind == "plain":
                assert "$" not in text and "\\" not in text and "{{" not in text, where
                assert fonts.missing(text, "bold" if "title" in where else "regular") \
                    == set(), where
                continue
            for run in lt.all_runs(lt.parse(text)):
                if isinstance(run, lt.Text):
                    for bad in ("$", "\\", "{{", "}}"):
                        assert bad not in run.text, (where, run.text)
                    assert fonts.missing(run.text, run.style) == set(), (where, run.text)
                elif isinstance(run, lt.Value):
                    shown = lv.PENDING + lv.format_value(-1.5, ".2f") + "∞"
                    assert fonts.missing(shown, run.style) == set()
    # what a button, a status line or a live number adds
    assert fonts.missing("Undo: ×²³°→≈θπΦ−…·", "regular") == set()


def _formulas(shipped):
    """Every LaTeX a lesson typesets: (where, latex, display?) with live numbers filled."""
    from explorer import derived

    for lesson in shipped:
        for where, text, kind in texts_of(lesson):
            if kind != "markdown":
                continue
            blocks = lt.parse(text)
            for block in blocks:
                if isinstance(block, lt.DisplayMath):
                    yield where, lt.substitute(block.latex, _sample), True
                elif isinstance(block, lt.FormulaRef):
                    yield where, derived.get(block.name).latex, True
            for run in lt.all_runs(blocks):
                if isinstance(run, lt.Math):
                    yield where, lt.substitute(run.latex, _sample), False
        for step in lesson.steps:
            for name in step.formulas:
                yield f"{lesson.id} step {step.number} formulas", derived.get(name).latex, True


def test_every_formula_typesets_and_states_its_left_hand_side(shipped):
    from explorer.ui.formulas import init_microtex, typeset

    problem = init_microtex()
    if problem:
        pytest.skip(problem)
    count = 0
    for where, latex, display in _formulas(shipped):
        if display:
            assert "=" in latex, (where, latex)     # never a bare right-hand side
        rendered, pixels = typeset(latex, 17.0, inline=not display)
        assert pixels.size and pixels[..., 3].max() > 0, (where, latex)
        assert 0 < rendered.baseline_y <= pixels.shape[0], (where, latex)
        count += 1
    assert count > 150


def test_every_derivation_result_has_a_left_hand_side():
    from explorer import derived

    registry = pytest.importorskip("derivations.registry")
    from derivations.symbols import SYMBOLS
    from explorer.ui import fonts

    assert set(SYMBOLS) <= set(registry.names())
    for name in derived.names():
        result = derived.get(name)
        assert "=" in result.latex, name
        # statements are drawn under formulas and in tooltips, in the window's fonts
        assert fonts.missing(result.statement, "italic") == set(), name


def test_the_printed_pi_is_typeset_as_pi():
    """The DX11 sample's PI macro is the number pi as printed: its left-hand side is the
    Greek letter with the printed mark (lesson 11 step 1), not the macro's name."""
    from explorer import derived

    lhs = derived.get("errata.dx11.pi").latex.split("=")[0].strip()
    assert lhs == r"\pi^{\mathrm{printed}}"


def test_figures_of_the_lessons_parse_and_each_is_placed(shipped):
    """Figures are drawn where the text places them ({{figure:ID}}); the kinds used
    cover the registry's."""
    from explorer.ui.figures import FIGURES

    kinds = set()
    for lesson in shipped:
        for step in lesson.steps:
            placed = {b.id for b in lt.parse(step.text) if isinstance(b, lt.FigureRef)}
            assert placed == set(step.figure_ids), (lesson.id, step.number)
            kinds |= {spec.kind for spec in step.figures}
    assert kinds == set(FIGURES)


def _introduction(text: str, figure_id: str) -> str:
    """The paragraph that places figure ``figure_id`` in ``text``, up to the figure, or the
    block just before it when the figure stands between blocks."""
    before = text.split("{{figure:" + figure_id + "}}", 1)[0]
    blocks = [b for b in re.split(r"\n\s*\n", before) if b.strip()]
    return blocks[-1] if blocks else ""


def test_every_figure_is_introduced_before_it_appears(shipped):
    """A figure is named in the words just before it, in the window and on the site. A
    figure that draws a toy of its own (a diagram or a small synthetic grid, not the frame
    on screen) is also set against the main view there, so the reader knows it is not
    the scene beside the text."""
    from explorer.figure_params import FIGURE_KINDS

    plots_frames = {decl.name for decl in FIGURE_KINDS if decl.results}
    view = re.compile(r"\{\{fig:view\}\}|\bmain view\b|\b3D view\b", re.I)
    missing = []
    for lesson in shipped:
        for step in lesson.steps:
            for spec in step.figures:
                ident = re.escape(spec.instance_id)
                named = re.compile(r"\{\{fig:" + ident + r"\}\}|\bfigures?\b", re.I)
                for medium in lt.MEDIA:
                    words = _introduction(lt.for_medium(step.text, medium), spec.instance_id)
                    where = f"{lesson.id} step {step.number} figure {spec.instance_id} ({medium})"
                    if not named.search(words):
                        missing.append(f"{where}: not named before it appears")
                    elif spec.kind not in plots_frames and not view.search(words):
                        missing.append(f"{where}: a toy figure not set against the main view")
    assert missing == [], "\n".join(missing)


def test_a_step_with_an_unknown_placeholder_is_refused(tmp_path):
    from explorer.lessons import LessonError, load_lesson

    text = '''
id = "tiny"
title = "T"
summary = "S"
[[steps]]
title = "One"
text = "The flux is {{audit.injectd:.3g}} W."
'''
    path = tmp_path / "05-tiny.toml"
    path.write_text(text, encoding="utf-8")
    with pytest.raises(LessonError) as info:
        load_lesson(path)
    error = info.value
    assert (error.step, error.field) == (1, "text")
    assert "did you mean audit.injected" in str(error) and "05-tiny.toml" in str(error)
    path.write_text(text.replace("audit.injectd:.3g", "audit.injected:.3q"), encoding="utf-8")
    with pytest.raises(LessonError, match="does not apply"):
        load_lesson(path)
    bad_try = text.replace('W."', 'W."\n[[steps.try_this]]\ncontrol = "grid_size"\n'
                                  'value = 0\nprompt = "Fewer cells {{frame.cells}}."')
    path.write_text(bad_try.replace("audit.injectd:.3g", "audit.injected"), encoding="utf-8")
    with pytest.raises(LessonError) as info:
        load_lesson(path)
    assert info.value.field == "try_this[0].value" and "grid_size" in str(info.value)
    same = bad_try.replace("value = 0", "value = 32").replace("audit.injectd:.3g",
                                                               "audit.injected")
    path.write_text(same, encoding="utf-8")
    with pytest.raises(LessonError, match="already 32"):
        load_lesson(path)


def test_a_try_this_says_what_its_pending_numbers_wait_for():
    """A "…" in a prompt is explained under it: before the press, the number is read once
    the button is pressed; after it, an error number waits for the Error panel and a frame
    number for the frame; a prompt whose numbers all have values gets no note."""
    from explorer.ui.article_try import pending_note

    empty = lv.LiveContext(settings=Settings())
    frame_prompt = "One step keeps {{audit.step_ratio:.4f}} of the flux."
    error_prompt = "Relative L2 {{error.relative_l2:.3f}}, {{audit.gathered:.3g}} W."
    assert "press the button" in pending_note(frame_prompt, empty, active=False)
    assert "next frame" in pending_note(frame_prompt, empty, active=True)
    assert "Error panel" in pending_note(error_prompt, empty, active=True)
    assert pending_note("{{settings.iterations}} steps", empty, active=False) == ""
