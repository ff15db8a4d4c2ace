"""The site as a reader meets it: text written for the page (no window-only instruction,
no build-machine timing, figures by number, terms and sources), a page that works from
the keyboard and passes an accessibility engine, reads without the script, and weighs
what the build says (the session's small build, tests/site/conftest.py)."""

from __future__ import annotations

import html
import json
import re
from pathlib import Path

import pytest

from explorer.site.controls import CONTROLS, Control, desktop_phrases, reader_text, register
from explorer.site.weight import BUDGET, FONT, first_files, median_first, page_weight

CODE_ID = re.compile(r"\b(?:audit|settings|sh|frame|derived|corrections|error|figure)\.[a-z_]")


def _pages(site: Path) -> list[Path]:
    return sorted(site.glob("*.html"))


def _lesson_pages(site: Path) -> list[Path]:
    return [page for page in _pages(site) if page.name != "index.html"]


# --- the text ---------------------------------------------------------------------------

def test_no_page_tells_the_reader_to_use_a_control_it_does_not_have(site):
    for page in _pages(site):
        assert desktop_phrases(page.read_text()) == [], page.name


def test_the_phrase_rule_admits_a_control_once_the_page_has_it():
    markup = '<p>Drag the normal and watch the table.</p><p>The main view shows it.</p>'
    assert [found.split(":")[0] for found in desktop_phrases(markup)] == ["drag", "main view"]
    live = '<div data-control="swipe"></div>' + markup
    assert [found.split(":")[0] for found in desktop_phrases(live)] == ["main view"]
    with pytest.raises(ValueError, match="unknown phrases"):
        register(Control("lobe", "a live lobe", ("drag-the-lobe",)))
    register(Control("test-lobe", "a live cosine lobe: drag n", ("drag",)))
    try:
        assert desktop_phrases('<div data-control="test-lobe"></div><p>Drag n.</p>') == []
    finally:
        del CONTROLS["test-lobe"]


def test_no_timing_template_plural_or_code_name_reaches_the_reader(site):
    for page in _pages(site):
        markup = page.read_text()
        assert 'data-q="frame.time' not in markup, page.name
        text = reader_text(markup)
        assert "(s)" not in text, page.name
        assert not CODE_ID.search(text), (page.name, CODE_ID.search(text))


def test_figures_are_numbered_referred_to_by_number_and_captioned_per_step(site):
    for page in _lesson_pages(site):
        markup = page.read_text()
        numbers = [int(n) for n in re.findall(r'<figure [^>]*id="fig-(\d+)"', markup)]
        assert numbers == list(range(1, len(numbers) + 1)), page.name
        captions = re.findall(r'<span class="fig-no">Figure (\d+)\.</span>(.*?)</figcaption>',
                              markup, re.S)
        assert [int(n) for n, _ in captions] == numbers, page.name
        texts = [reader_text(text) for _, text in captions]
        assert len(set(texts)) == len(texts), page.name           # no caption repeated
        refs = re.findall(r'<a class="fig-ref" href="#fig-(\d+)">Figure (\d+)</a>', markup)
        assert refs and all(a == b and int(a) in numbers for a, b in refs), page.name
        looks = re.findall(r'<p class="look">(.*?)</p>', markup)
        assert len(looks) == markup.count('<section class="step"'), page.name
        assert all(look.startswith("Look at ") for look in looks)


def test_terms_link_to_their_definitions_and_sources_are_cited_in_full(site):
    from explorer.lessons.glossary import load_glossary

    meanings = {term.term: term.meaning for term in load_glossary()}
    for page in _lesson_pages(site):
        markup = page.read_text()
        links = re.findall(r'<a class="term" data-control="term" href="#([^"]+)" '
                           r'aria-describedby="([^"]+)">', markup)
        assert links, page.name
        for anchor, described in links:
            assert f'<dt id="{anchor}">' in markup and described == f"{anchor}-def"
        defined = re.findall(r'<dt id="[^"]+"><dfn>([^<]+)</dfn></dt><dd id="[^"]+">([^<]+)'
                             r"</dd>", markup)
        assert defined and all(meanings[html.unescape(term)] == html.unescape(meaning)
                               for term, meaning in defined)
        references = markup.split('<section class="references"', 1)[1]
        assert "Cascaded Light Propagation Volumes for Real-Time Indirect Illumination" \
            in references and "Light Propagation Volumes in CryEngine 3" in references


# --- weight -----------------------------------------------------------------------------

def test_the_build_reports_each_pages_bytes_and_keeps_the_median_in_budget(site):
    from fontTools.ttLib import TTFont

    from explorer.ui.fonts import SYMBOL_FONT, fonts_dir

    report = json.loads((site / "lpv-site.json").read_text())["weights"]
    assert sorted(report) == sorted(page.name for page in _pages(site))
    for name, weight in report.items():
        assert weight == page_weight(site, name)
        assert weight["first"] == weight["html"] + weight["assets"] + weight["pictures"]
    assert median_first(report) <= BUDGET
    font = site / "assets" / FONT
    assert font.read_bytes()[:4] == b"wOF2"
    assert font.stat().st_size < (fonts_dir() / SYMBOL_FONT).stat().st_size / 10
    assert "MATH" in TTFont(str(font))
    assert not (site / "assets" / "latinmodern-math.otf").exists()
    for page in _lesson_pages(site):
        markup = page.read_text()
        images = re.findall(r"<img [^>]*>", markup)
        assert sum('loading="lazy"' not in tag and "data-src" not in tag
                   for tag in images) <= 1, page.name        # one picture before the fold
        assert any("data-src=" in tag for tag in images), page.name   # frames on first use


# --- in the browser ---------------------------------------------------------------------

def _open(driver, page: Path, width: int, script: bool = True) -> None:
    driver.set_window_size(width, 900)
    driver.execute_cdp_cmd("Emulation.setDeviceMetricsOverride", {
        "width": width, "height": 900, "deviceScaleFactor": 1, "mobile": width < 600})
    driver.execute_cdp_cmd("Emulation.setScriptExecutionDisabled", {"value": not script})
    driver.get(page.as_uri())


CONTROLS_JS = """return Array.from(document.querySelectorAll(
  'a[href], button, input, summary, [tabindex]')).filter(e => !e.disabled &&
  e.getClientRects().length && getComputedStyle(e).visibility !== 'hidden' &&
  e.tabIndex >= 0)"""


@pytest.fixture(scope="module")
def served(site):
    """The site over HTTP on localhost (Chromium records what it fetches from there)."""
    import functools
    import http.server
    import threading

    class Quiet(http.server.SimpleHTTPRequestHandler):
        def log_message(self, *args) -> None:
            pass

    server = http.server.ThreadingHTTPServer(
        ("127.0.0.1", 0), functools.partial(Quiet, directory=str(site)))
    thread = threading.Thread(target=server.serve_forever, daemon=True)
    thread.start()
    yield f"http://127.0.0.1:{server.server_address[1]}"
    server.shutdown()
    thread.join()


@pytest.mark.parametrize("width", (375, 1280))
def test_before_interaction_the_browser_fetches_only_what_the_build_counted(
        site, browser, served, width):
    """Loaded and left alone, a lesson page fetches no file the build's count leaves out
    (a phone-size copy counts as its full-size picture)."""
    import time

    missed = []
    for page in _lesson_pages(site):
        _open(browser, page, width)
        browser.get(f"{served}/{page.name}")
        browser.execute_async_script(
            "const done = arguments[arguments.length - 1];"
            "document.fonts.ready.then(() => setTimeout(() => done(true), 300))")
        time.sleep(0.5)
        names = browser.execute_script(
            "return [location.href, ...performance.getEntriesByType('resource')"
            ".map(e => e.name)]")
        fetched = {name[len(served) + 1:].split("#")[0] for name in names
                   if name.startswith(served)}
        fetched = {re.sub(r"-small(\.\w+)$", r"\1", name) for name in fetched}
        extra = fetched - first_files(site, page.name)
        if extra:
            missed.append((page.name, sorted(extra)))
        assert any(name.startswith("img/") for name in fetched)
    assert missed == [], width


def test_a_keyboard_reader_reaches_and_works_every_control(site, browser):
    """Tab from the top reaches every focusable control of the page once, in order,
    each with a visible focus ring; Enter on a prediction reveals it, the arrow keys move
    a slider (its value spoken in words), Enter plays a sequence and opens the lesson menu
    (its entries at least 44 px tall), a term shows its meaning on focus. Live numbers
    are no tab stops."""
    from selenium.webdriver.common.keys import Keys

    page = _lesson_pages(site)[0]
    _open(browser, page, 1280)
    browser.execute_script("document.querySelectorAll('details').forEach(d => d.open = true)")
    wanted = browser.execute_script(CONTROLS_JS)
    assert browser.find_elements("css selector", ".live") and not browser.execute_script(
        "return Array.from(document.querySelectorAll('.live')).some(e => e.tabIndex >= 0)")
    from selenium.webdriver.common.action_chains import ActionChains

    reached, rings = [], []
    for _ in range(len(wanted) + 5):
        ActionChains(browser).send_keys(Keys.TAB).perform()
        active = browser.switch_to.active_element
        if reached and active == reached[0]:
            break
        reached.append(active)
        rings.append(browser.execute_script(
            "const e = arguments[0], s = getComputedStyle(e), p = e.closest('.swipe');"
            "const w = p ? getComputedStyle(p) : s;"
            "return (s.outlineStyle !== 'none' && parseFloat(s.outlineWidth) >= 2) ||"
            " (w.outlineStyle !== 'none' && parseFloat(w.outlineWidth) >= 2)", active))
        if len(reached) >= len(wanted):
            break
    assert [e.id for e in reached] == [e.id for e in wanted[:len(reached)]]
    assert set(reached) == set(wanted)
    assert all(rings), [r.get_attribute("outerHTML")[:80] for r, ok in zip(reached, rings)
                        if not ok]
    choice = browser.find_element("css selector", "[data-predict] button.choice")
    browser.execute_script("arguments[0].focus()", choice)
    choice.send_keys(Keys.ENTER)
    card = choice.find_element("xpath", "ancestor::*[@data-predict]")
    assert card.find_element("css selector", ".reveal").is_displayed()
    slider = browser.find_element("css selector", "[data-swipe] input[type=range]")
    browser.execute_script("arguments[0].focus()", slider)
    slider.send_keys(Keys.ARROW_RIGHT)
    assert slider.get_attribute("value") == "51"
    assert "51 %" in slider.get_attribute("aria-valuetext")
    sequence = browser.find_element("css selector", "[data-sequence]")
    scrub = sequence.find_element("css selector", "input[type=range]")
    browser.execute_script("arguments[0].focus()", scrub)
    scrub.send_keys(Keys.HOME)
    assert scrub.get_attribute("aria-valuetext") == sequence.find_element(
        "css selector", "output").text
    play = sequence.find_element("css selector", "button.play")
    browser.execute_script("arguments[0].focus()", play)
    play.send_keys(Keys.ENTER)
    import time

    time.sleep(1.2)
    assert int(scrub.get_attribute("value")) > 0
    menu = browser.find_element("css selector", "details.lessons")
    browser.execute_script("arguments[0].open = false", menu)
    summary = menu.find_element("css selector", "summary")
    browser.execute_script("arguments[0].focus()", summary)
    summary.send_keys(Keys.ENTER)
    assert menu.get_attribute("open") is not None
    links = menu.find_elements("css selector", "li a")
    assert all(link.size["height"] >= 44 for link in links)
    term = browser.find_element("css selector", "a.term")
    browser.execute_script("arguments[0].focus()", term)
    tip = browser.find_element("css selector", ".tip")
    assert tip.is_displayed() and term.text in tip.text and len(tip.text) > len(term.text) + 20


def test_without_the_script_nothing_is_dead(site, browser):
    """No Play button, a swipe's two pictures side by side, every picture loaded."""
    page = _lesson_pages(site)[0]
    _open(browser, page, 375, script=False)
    try:
        assert browser.execute_script("return document.documentElement.className") == "no-js"
        plays = browser.find_elements("css selector", "button.play")
        assert plays and not any(play.is_displayed() for play in plays)
        swipe = browser.find_element("css selector", "[data-swipe]")
        before, after = (swipe.find_element("css selector", f"img.{side}")
                         for side in ("before", "after"))
        assert before.rect["x"] + before.rect["width"] <= after.rect["x"] + 1
        assert after.rect["width"] > 0.4 * swipe.rect["width"]
    finally:
        browser.execute_cdp_cmd("Emulation.setScriptExecutionDisabled", {"value": False})


@pytest.mark.parametrize("width", (375, 1280))
def test_an_accessibility_engine_finds_nothing_serious(site, browser, width):
    """axe-core (shipped in axe-selenium-python) on every page: no serious or critical
    violation."""
    axe = pytest.importorskip("axe_selenium_python", reason="axe-selenium-python is missing")
    source = (Path(axe.__file__).parent / "node_modules" / "axe-core" / "axe.min.js").read_text()
    for page in _pages(site):
        _open(browser, page, width)
        browser.execute_script(source)
        result = browser.execute_async_script(
            "const done = arguments[arguments.length - 1];"
            "axe.run(document).then(r => done(r.violations.map(v => [v.id, v.impact,"
            " v.nodes.length, v.nodes[0].html.slice(0, 120)])))")
        serious = [v for v in result if v[1] in ("serious", "critical")]
        assert serious == [], (page.name, width, serious)


def test_display_math_fits_a_phone_or_scrolls_with_a_cue(site, browser):
    wide = []
    for page in _lesson_pages(site):
        _open(browser, page, 375)
        wide += browser.execute_script(
            "return Array.from(document.querySelectorAll('.display-math')).filter("
            "b => b.scrollWidth > b.clientWidth + 1).map(b => [getComputedStyle(b).overflowX,"
            " getComputedStyle(b).backgroundImage, b.tabIndex])")
    assert wide                                  # the course has formulas wider than a phone
    for overflow, background, tab in wide:
        assert overflow == "auto" and "radial-gradient" in background and tab == 0
