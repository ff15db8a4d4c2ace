"""``lpv-explorer site``: a CI-sized build of two lessons (small pictures), read as files
and in a real browser (Debian's chromium headless, driven by selenium and chromedriver).

The build runs once per session as a user runs it (``python -m explorer site``;
tests/site/conftest.py). The browser checks skip with the reason printed when chromium
or chromedriver is missing.
"""

from __future__ import annotations

import html
import os
import re
import subprocess
import sys
import time
from pathlib import Path

import pytest
from sitebuild import LESSONS, ROOT, SIZE

from explorer.lessons import live_values, load_all
from explorer.site.build import PLOT_OF_PANEL
from explorer.site.controls import reader_text

WIDTHS = (375, 1280)
SCREENSHOTS = Path(os.environ.get("LPV_SITE_SCREENSHOTS", "")) if os.environ.get(
    "LPV_SITE_SCREENSHOTS") else None
"""Set to a folder to keep the browser's screenshots of every page at both widths."""


def page_of(site: Path, lesson) -> Path:
    return site / f"{lesson.number:02d}-{lesson.id}.html"


def sections(text: str) -> dict[int, str]:
    """Step number -> the HTML of its <section>."""
    found = re.findall(r'<section class="step" id="step-(\d+)">(.*?)</section>', text, re.S)
    return {int(number): body for number, body in found}


# --- the files -------------------------------------------------------------------------

def test_every_step_is_on_its_page_with_all_its_figures(site, lessons):
    index = (site / "index.html").read_text()
    for lesson in lessons:
        assert f'href="{page_of(site, lesson).name}"' in index
        text = page_of(site, lesson).read_text()
        found = sections(text)
        assert sorted(found) == [step.number for step in lesson.steps]
        for step in lesson.steps:
            body = found[step.number]
            assert html.escape(step.title) in body
            assert body.count('<figure class="view" ') == 1
            figures = re.findall(r'data-figure="([^"]+)"', body)
            assert sorted(figures) == sorted(step.figure_ids), (lesson.id, step.number)
            panel = PLOT_OF_PANEL.get(step.plot or "")
            drawn = panel is not None and panel not in [f.kind for f in step.figures]
            assert (f'data-plot="{panel}"' in body) == drawn, (lesson.id, step.number)
            assert len(re.findall(r'class="try" id=', body)) == len(step.try_this)
            assert body.count("data-swipe") == len(step.try_this)
            command = f"lpv-explorer run --lesson {lesson.id} --step {step.number}"
            assert command in body
    for image in re.findall(r'src="([^"]+)"', index + "".join(
            page_of(site, lesson).read_text() for lesson in lessons)):
        assert (site / image).is_file(), image


def test_the_open_command_opens_that_step():
    """The command each step shows is one ``run`` accepts (checked before any window)."""
    from explorer.cli import build_parser

    args = build_parser().parse_args(["run", "--lesson", "solid-angles", "--step", "2"])
    assert (args.lesson, args.step) == ("solid-angles", 2)


_LIVE = re.compile(r'class="live" data-q="([^"]+)" data-fmt="([^"]*)"[^>]*>([^<]*)<')


def _context(ctx, step, settings, texts):
    """The live numbers' context of ``settings`` rendered afresh (the step's figures'
    readouts from the figure code itself)."""
    from explorer.lpv.pipeline import Pipeline
    from explorer.site.frames import uses_error
    from explorer.ui.figures.host import FigureContext
    from explorer.ui.figures.registry import FIGURES

    settings = settings.with_changes(width=SIZE[0], height=SIZE[1])
    pipeline = Pipeline(settings, ctx=ctx)
    try:
        result = pipeline.run(settings, need_audit="full")
    finally:
        pipeline.release()
    figures = {}
    for spec in step.figures:
        kind = FIGURES[spec.kind]
        figures[spec.instance_id] = kind.readouts(spec.params, kind.make_state(spec.params),
                                                  FigureContext(results=(result,)))
    error = _error(ctx, settings) if uses_error(texts) else None
    from explorer.site.values import context_marks

    return live_values.LiveContext(settings=settings, result=result, error=error,
                                   figures=figures, renderer=ctx.info["GL_RENDERER"],
                                   **context_marks(step))


def _check(numbers, context, step, where) -> int:
    for name, fmt, shown in numbers:
        expected = live_values.render(html.unescape(name), html.unescape(fmt), context,
                                      step.figure_ids)
        assert html.unescape(shown) == expected, (where, name)
        assert expected != live_values.PENDING, (where, name)
    return len(numbers)


def test_baked_numbers_equal_the_converged_frames_live_values(site, lessons, gl_context):
    """Each number of a step's prose equals what the window's article shows for the
    step's frame, rendered here again at the site's size; each number of a try-this
    prompt what it shows after the change (and, beside a measured one, before it)."""
    from explorer.ui.figures.registry import USES_RESULTS

    checked = 0
    for lesson in lessons:
        found = sections(page_of(site, lesson).read_text())
        for step in lesson.steps:
            body = found[step.number]
            prose = body.split('<div class="prose">', 1)[1].split('<div class="try"', 1)[0]
            cards = re.findall(r'<div class="try" id="[^"]+"[^>]*>(.*?)</div>\s*'
                               r'(?=<div class="try"|<p class="open">)', body, re.S)
            assert len(cards) == len(step.try_this)
            texts = [step.text] + [t.prompt for t in step.try_this]
            if step.plot == "error":            # the page shows the Error panel's numbers
                texts.append("{{error.flux_ratio}}")
            before = _context(gl_context, step, step.settings(), texts)
            results_figures = any(spec.kind in USES_RESULTS for spec in step.figures)
            numbers = [n for n in _LIVE.findall(prose)
                       if not (results_figures and n[0].startswith("figure."))]
            checked += _check(numbers, before, step, f"{lesson.id} step {step.number}")
            for index, (item, card) in enumerate(zip(step.try_this, cards), 1):
                prompt = card.split('<p class="prompt">', 1)[1]
                was = re.findall(r'<span class="was-note">\(before: (<span [^>]*>[^<]*</span>)',
                                 prompt)
                after = [n for n in _LIVE.findall(re.sub(r'<span class="was-note">.*?</span>'
                                                         r"</span>\)?", "", prompt))]
                if not after:
                    continue
                context = _context(gl_context, step, item.apply(step.settings()),
                                   [item.prompt])
                where = f"{lesson.id} step {step.number} try {index}"
                checked += _check(after, context, step, where)
                checked += _check([_LIVE.search(w.replace('class="live was"', 'class="live"'))
                                   .groups() for w in was], before, step, where + " before")
    assert checked >= 10


def _error(ctx, settings):
    from explorer.lpv.pipeline import Pipeline
    from explorer.truth.progressive import ErrorJob, Measurement

    measured = settings.with_changes(exposure=1.0, indirect_only=False)
    job = ErrorJob(measured, Measurement(), settings.width / settings.height)
    pipeline = Pipeline(job.settings, ctx=ctx)
    try:
        while not job.advance(ctx, pipeline, 30.0):
            pass
        return job.result.stats
    finally:
        job.release()
        pipeline.release()


def test_no_raw_tex_in_the_output(site):
    pages = sorted(site.glob("*.html"))
    assert len(pages) >= 1 + len(LESSONS)
    for page in pages:
        text = reader_text(page.read_text())
        for mark in ("\\", "$", "{{", "}}"):
            assert mark not in text, (page.name, mark, text[max(text.find(mark) - 80, 0):
                                                              text.find(mark) + 80])
        assert "<math" in page.read_text() or page.name == "index.html"


def test_the_site_needs_no_network(site):
    for path in site.rglob("*"):
        if path.suffix in (".html", ".css", ".js"):
            text = path.read_text()
            assert not re.search(r"""(src|href)=["']?(https?:)?//""", text), path.name
            assert "url(http" not in text and "@import" not in text, path.name


# --- in the browser ---------------------------------------------------------------------

def _open(driver, page: Path, width: int) -> None:
    driver.set_window_size(width, 900)
    driver.execute_cdp_cmd("Emulation.setDeviceMetricsOverride", {
        "width": width, "height": 900, "deviceScaleFactor": 1, "mobile": width < 600})
    driver.get(page.as_uri())
    # every picture now: the lazy ones and a sequence's frames (fetched on first use)
    driver.execute_script(
        "document.querySelectorAll('img[loading=lazy]').forEach(i => i.loading = 'eager');"
        "document.querySelectorAll('img[data-src]').forEach(i => {"
        " if (i.dataset.srcset) { i.srcset = i.dataset.srcset; }"
        " i.src = i.dataset.src; i.removeAttribute('data-src'); });")
    driver.execute_async_script(
        "const done = arguments[arguments.length - 1];"
        "Promise.all([document.fonts.ready, ...Array.from(document.images, i => i.decode()"
        ".catch(() => null))]).then(() => done(true));")


def _picture(driver, element) -> bytes:
    driver.execute_script("arguments[0].scrollIntoView({block: 'center'})", element)
    return element.screenshot_as_png


@pytest.mark.parametrize("width", WIDTHS)
def test_pages_in_chromium(site, browser, width):
    """Every page loads without a console message of level SEVERE or WARNING, every
    image and font loads, nothing is wider than the window."""
    browser.get_log("browser")                          # drop what came before
    for page in sorted(site.glob("*.html")):
        _open(browser, page, width)
        logs = [entry for entry in browser.get_log("browser")
                if entry["level"] in ("SEVERE", "WARNING")]
        assert logs == [], (page.name, logs)
        broken = browser.execute_script(
            "return Array.from(document.images).filter(i => !i.complete || i.naturalWidth"
            " === 0).map(i => i.getAttribute('src'))")
        assert broken == [], (page.name, broken)
        fonts = browser.execute_script(
            "return Array.from(document.fonts).map(f => [f.family, f.status])")
        assert all(status != "error" for _, status in fonts), (page.name, fonts)
        if browser.execute_script("return document.querySelector('math') !== null"):
            assert ['"Latin Modern Math"', "loaded"] in [list(f) for f in fonts] or \
                ["Latin Modern Math", "loaded"] in [list(f) for f in fonts], fonts
        overflow = browser.execute_script(
            "const d = document.documentElement; return [d.scrollWidth, d.clientWidth]")
        assert overflow[0] <= overflow[1], (page.name, width, overflow)
        if SCREENSHOTS is not None:
            SCREENSHOTS.mkdir(parents=True, exist_ok=True)
            height = browser.execute_script("return document.documentElement.scrollHeight")
            shot = browser.execute_cdp_cmd("Page.captureScreenshot", {
                "format": "png", "captureBeyondViewport": True,
                "clip": {"x": 0, "y": 0, "width": width, "height": min(height, 6000),
                         "scale": 1}})
            import base64

            (SCREENSHOTS / f"{page.stem}-{width}.png").write_bytes(
                base64.b64decode(shot["data"]))


def test_every_slider_changes_the_picture(site, browser, lessons):
    """Each swipe and each image sequence, moved from the keyboard as a reader would,
    shows another picture; Play moves a sequence on by itself."""
    from selenium.webdriver.common.keys import Keys

    moved = plays = 0
    for lesson in lessons:
        _open(browser, page_of(site, lesson), 1280)
        for card in browser.find_elements("css selector", "[data-predict]"):
            _predict(browser, card)
        for widget in browser.find_elements(
                "css selector", "[data-swipe], [data-sequence]:not(.is-live)"):
            picture = widget if widget.get_attribute("data-swipe") is not None else \
                widget.find_element("css selector", ".frames")
            slider = widget.find_element("css selector", "input[type=range]")
            before = _picture(browser, picture)
            start = int(slider.get_attribute("value"))
            key = Keys.HOME if start > int(slider.get_attribute("min")) else Keys.END
            browser.execute_script("arguments[0].focus()", slider)
            slider.send_keys(key)
            assert slider.get_attribute("value") != str(start)
            after = _picture(browser, picture)
            assert after != before, (lesson.id, widget.get_attribute("outerHTML")[:200])
            moved += 1
            play = widget.find_elements("css selector", "button.play")
            if play:
                slider.send_keys(Keys.HOME)
                still = _picture(browser, picture)
                play[0].click()
                time.sleep(1.2)
                assert int(slider.get_attribute("value")) > 0
                assert _picture(browser, picture) != still
                plays += 1
    expected = sum(len(step.try_this) for lesson in lessons for step in lesson.steps)
    assert moved >= expected and plays >= 1


def _predict(browser, card) -> None:
    """Pick the first choice of a predict-then-press: the verdict and the change show."""
    reveal = card.find_element("css selector", ".reveal")
    assert not reveal.is_displayed()
    choice = card.find_element("css selector", "button.choice")
    browser.execute_script("arguments[0].scrollIntoView({block: 'center'})", choice)
    choice.click()
    verdict = card.find_element("css selector", ".verdict").text
    assert verdict.startswith("You predicted " + choice.text)
    assert reveal.is_displayed()


def test_numbers_show_what_they_measure(site, browser, lessons):
    """A live number shows its tooltip on a tap (touch screens show no title)."""
    _open(browser, page_of(site, lessons[0]), 375)
    number = browser.find_element("css selector", ".prose .live")
    browser.execute_script("arguments[0].scrollIntoView({block: 'center'})", number)
    number.click()
    tip = browser.find_element("css selector", ".tip")
    assert tip.is_displayed() and len(tip.text) > 10


# --- without a build --------------------------------------------------------------------

def test_every_formula_of_the_course_typesets_as_mathml():
    """All the LaTeX the lessons hold (prose, display math, derivation results), with
    their live numbers in place, converts; nothing of the TeX is left outside the
    annotation."""
    from explorer import derived
    from explorer.lessons import text as lesson_text
    from explorer.site.mathml import strip_annotations, to_mathml

    found, errors = load_all()
    assert not errors
    latex = []
    for lesson in found:
        for step in lesson.steps:
            texts = [step.text] + [t.prompt for t in step.try_this] + [
                f.caption for f in step.figures]
            for text in texts:
                blocks = lesson_text.parse(text)
                latex += [b.latex for b in blocks if isinstance(b, lesson_text.DisplayMath)]
                latex += [derived.get(b.name).latex for b in blocks
                          if isinstance(b, lesson_text.FormulaRef)]
                latex += [r.latex for r in lesson_text.all_runs(blocks)
                          if isinstance(r, lesson_text.Math)]
            latex += [derived.get(name).latex for name in step.formulas]
    assert len(latex) > 100
    for formula in latex:
        filled = lesson_text.substitute(formula, lambda name, fmt: "1.5")
        for display in (False, True):
            markup = strip_annotations(to_mathml(filled, display))
            assert "\\" not in markup and "{" not in markup, (formula, markup)
            assert markup.count("<math") == 1


def test_a_folder_that_is_not_a_site_is_refused_and_kept(tmp_path):
    """OUT holding other files: one line, exit 2, the files untouched."""
    out = tmp_path / "mine"
    out.mkdir()
    (out / "notes.txt").write_text("keep me")
    done = subprocess.run([sys.executable, "-m", "explorer", "site", str(out), "--only",
                           "1"], cwd=ROOT, capture_output=True, text=True, timeout=120)
    assert done.returncode == 2
    assert done.stderr.count("\n") == 1 and "not empty" in done.stderr
    assert (out / "notes.txt").read_text() == "keep me"
    assert sorted(p.name for p in tmp_path.iterdir()) == ["mine"]


def test_an_unknown_lesson_is_one_line(tmp_path):
    done = subprocess.run([sys.executable, "-m", "explorer", "site", str(tmp_path / "s"),
                           "--only", "1,nope"], cwd=ROOT, capture_output=True, text=True,
                          timeout=120)
    assert done.returncode == 2 and done.stderr.count("\n") == 1, done.stderr
    assert "nope" in done.stderr and not (tmp_path / "s").exists()


def test_plots_have_axes_labels_and_a_value_per_point():
    import numpy as np

    from explorer.site.plots import audit_svg, flux_per_step_svg

    svg = flux_per_step_svg([("A: corrected", np.array([3.0, 3.1, 3.18])),
                             ("B: original", np.array([9.0, 0.7, 0.05]))], "log")
    assert "step t" in svg and "flux in flight [W] (log)" in svg
    titles = re.findall(r"<circle[^>]*><title>([^<]*)</title>", svg)
    assert len(titles) == 6
    assert titles[2] == "A: corrected: step 2: 3.18 W in flight (106.0 % of the injected flux)"
    assert '10<tspan dy="-5" font-size="9">−2</tspan>' in svg       # a decade below 0.05
    bars = audit_svg(["RSM", "injected"], [("A", np.array([2.0, 1.0]), 1.0)], "linear")
    assert re.findall(r"<rect[^>]*><title>([^<]*)</title>", bars) == [
        "A: RSM: 2 W (2× the injected flux)", "A: injected: 1 W (100.0 % of the injected flux)"]


def test_a_plot_point_shows_its_value_on_a_tap(site, browser, lessons):
    _open(browser, page_of(site, lessons[0]), 375)
    point = browser.find_element("css selector", "svg.plot .point")
    browser.execute_script("arguments[0].scrollIntoView({block: 'center'})", point)
    title = browser.execute_script("return arguments[0].querySelector('title').textContent",
                                   point)
    point.click()
    assert browser.find_element("css selector", ".tip").text == title


def test_marks_sit_where_the_window_puts_them():
    """A mark's dot is at its pixel and its label in percent of the picture, so both
    scale with the image; a hidden mark is faded."""
    from explorer.site.pages import marks_overlay

    markup = marks_overlay(640, 400, [("dark side", (320.0, 200.0), (160.0, 100.0),
                                       (200.0, 110.0), True),
                                      ("behind", (10.0, 20.0), (60.0, 40.0), (40.0, 30.0),
                                       False)])
    assert 'viewBox="0 0 640 400"' in markup
    assert '<circle cx="320.0" cy="200.0"' in markup
    assert 'style="left: 25.00%; top: 25.00%">dark side</span>' in markup
    assert markup.count("hidden-mark") == 2 and marks_overlay(640, 400, []) == ""


def test_a_prediction_hides_nothing_without_the_script():
    from types import SimpleNamespace

    from explorer.site.pages import try_card

    card = try_card(2, "step-1-try-2", "Iterations: 4", "<div>pair</div>", "It darkens.",
                    SimpleNamespace(question="Brighter or darker?",
                                    choices=("brighter", "darker"), answer=2))
    assert 'data-answer="2"' in card and card.count('class="choice secondary"') == 2
    assert "<noscript>The answer: darker.</noscript>" in card
    assert '<div class="reveal"><div>pair</div><p class="prompt">It darkens.</p>' in card
    assert " hidden" not in card            # the script hides the reveal, the page does not
