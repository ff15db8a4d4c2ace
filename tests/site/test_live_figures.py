"""The live figures in the page (explorer/site/live_figures.py, assets/figures/*.js):
built once for a one-step lesson that holds every live kind (tests/site/live_lessons/, a
160×100 view), read from ``file://`` in headless chromium. Each figure is dragged or
driven from the keyboard, and the numbers it then shows (each readout's full double, its
``data-value``) must equal what the window's figure code computes in Python for that
state (``readouts`` of explorer/ui/figures/<kind>.py): relative 1e-9 (1e-12 absolute near
0). The cosine lobe's L1/L2 values differ from the window's by ~1e-13 (its projection is
a quadrature, the page's the closed form); the rest agree to a few ulps.
"""

from __future__ import annotations

import base64
import json
import math
import os
import subprocess
import sys
import time
from pathlib import Path

import pytest

from explorer.figure_params import (
    MAX_TILT,
    PIPELINE_STAGES,
    CellFacesParams,
    ClampedCosineParams,
    PropagationStepperParams,
)

ROOT = Path(__file__).resolve().parents[2]
LESSONS = Path(__file__).resolve().parent / "live_lessons"
PAGE = "01-live-figures.html"
REL, ABS = 1e-9, 1e-12
SCREENSHOTS = Path(os.environ["LPV_SITE_SCREENSHOTS"]) if os.environ.get(
    "LPV_SITE_SCREENSHOTS") else None
"""Set to a folder to keep the page's screenshots at 1280 and 375 px."""


@pytest.fixture(scope="module")
def site(tmp_path_factory) -> Path:
    out = tmp_path_factory.mktemp("live") / "site"
    start = time.monotonic()
    done = subprocess.run([sys.executable, "-m", "explorer", "site", str(out), "--dir",
                           str(LESSONS), "--size", "160x100", "--figure-width", "480"],
                          cwd=ROOT, capture_output=True, text=True, timeout=600)
    assert done.returncode == 0, done.stderr + done.stdout
    print(f"\n{done.stdout.strip()}\n(build {time.monotonic() - start:.0f} s)")
    return out


def _load(driver, site: Path, width: int = 1280, url: str | None = None) -> None:
    driver.set_window_size(width, 900)
    driver.execute_cdp_cmd("Emulation.setDeviceMetricsOverride", {
        "width": width, "height": 900, "deviceScaleFactor": 1, "mobile": width < 600})
    driver.get_log("browser")
    driver.get(url or (site / PAGE).as_uri())
    for _ in range(100):
        if driver.execute_script("return document.querySelectorAll('figure.is-live').length"
                                 " === document.querySelectorAll('[data-live-kind]').length"):
            return
        time.sleep(0.1)
    raise AssertionError(f"the live figures did not start: {driver.get_log('browser')}")


def _figure(driver, figure_id: str):
    figure = driver.find_element("css selector", f'[data-figure="{figure_id}"]')
    driver.execute_script("arguments[0].scrollIntoView({block: 'center'})", figure)
    return figure


def _readouts(driver, figure) -> dict[str, float]:
    return driver.execute_script(
        "return Object.fromEntries(Array.from(arguments[0].querySelectorAll('[data-readout]'),"
        " e => [e.dataset.readout, Number(e.dataset.value)]))", figure)


def _agree(shown: dict[str, float], expected: dict[str, float], what: str) -> int:
    """Every number the window's readouts() gives that the page shows is equal; returns
    how many were compared."""
    compared = 0
    for name, value in expected.items():
        if name in shown:
            assert math.isclose(shown[name], value, rel_tol=REL, abs_tol=ABS), \
                (what, name, shown[name], value)
            compared += 1
    return compared


def _drag(driver, handle, dx: int, dy: int) -> None:
    from selenium.webdriver import ActionChains

    ActionChains(driver).move_to_element(handle).click_and_hold().move_by_offset(
        dx // 2, dy // 2).move_by_offset(dx - dx // 2, dy - dy // 2).release().perform()


def _press(driver, element, key, times: int = 1) -> None:
    """Focus ``element`` and press ``key``; each further press goes where focus is then."""
    driver.execute_script("arguments[0].focus()", element)
    element.send_keys(key)
    for _ in range(times - 1):
        driver.switch_to.active_element.send_keys(key)


def test_without_javascript_each_live_figure_keeps_its_baked_picture(site):
    text = (site / PAGE).read_text()
    mounts = text.count('class="live-figure"')
    assert mounts == 5 and text.count('class="baked"') == 5
    for chunk in text.split('class="live-figure"')[1:]:
        assert chunk.split(">", 1)[0].rstrip().endswith("hidden")     # shown by the script
        baked = chunk.split('class="baked">', 1)[1]
        # a picture (as a link to its full size) or, inside the stepper's sequence, its
        # title, frames and controls
        assert baked.lstrip().startswith(('<a class="enlarge"', "<h3>")), baked[:80]
        assert "<img" in baked.split("</figure>", 1)[0], baked[:80]
    assert 'src="assets/lpv-modules.js"' in text
    for name in ("generated/constants.js", "figures/live.js", "figures/common.js",
                 "live-figures.css", "lpv-modules.js"):
        assert (site / "assets" / name).is_file(), name
    assert "http" not in (site / "assets" / "lpv-modules.js").read_text().split(
        "LPV_MODULES")[0]


@pytest.mark.parametrize("width", (1280, 375))
def test_the_live_figures_start_at_both_widths(site, browser, width):
    _load(browser, site, width)
    logs = [e for e in browser.get_log("browser") if e["level"] in ("SEVERE", "WARNING")]
    assert logs == []
    assert browser.execute_script("return document.querySelectorAll('.baked').length") == 0
    overflow = browser.execute_script(
        "const d = document.documentElement; return [d.scrollWidth, d.clientWidth]")
    assert overflow[0] <= overflow[1], overflow
    for slider in browser.find_elements("css selector", ".live-figure input[type=range]"):
        assert slider.get_attribute("aria-valuetext"), slider.get_attribute("outerHTML")
    if SCREENSHOTS is not None:
        SCREENSHOTS.mkdir(parents=True, exist_ok=True)
        height = browser.execute_script("return document.documentElement.scrollHeight")
        shot = browser.execute_cdp_cmd("Page.captureScreenshot", {
            "format": "png", "captureBeyondViewport": True,
            "clip": {"x": 0, "y": 0, "width": width, "height": min(height, 8000), "scale": 1}})
        (SCREENSHOTS / f"live-figures-{width}.png").write_bytes(base64.b64decode(shot["data"]))


def test_dragging_the_cosine_lobe_gives_the_windows_numbers(site, browser):
    from selenium.webdriver.common.keys import Keys

    from explorer.ui.figures import clamped_cosine

    _load(browser, site)
    figure = _figure(browser, "cosine")
    params = ClampedCosineParams(normal_deg=30.0)
    shown = _readouts(browser, figure)
    states = [(shown["normal_deg"], shown["probe_deg"])]
    assert states[0] == (30.0, 180.0)
    _drag(browser, figure.find_element("css selector", '[data-handle="n"]'), -150, 40)
    _drag(browser, figure.find_element("css selector", '[data-handle="ω"]'), 90, -60)
    after = _readouts(browser, figure)
    assert after["normal_deg"] != 30.0 and after["probe_deg"] != 180.0
    sliders = figure.find_elements("css selector", "input[type=range]")
    _press(browser, sliders[0], Keys.ARROW_RIGHT, 3)
    keyed = _readouts(browser, figure)
    assert keyed["normal_deg"] == round(after["normal_deg"]) + 3
    assert "n at" in sliders[0].get_attribute("aria-valuetext")
    solid = figure.find_element("css selector", "svg.solid")        # the 3D view turns
    before = browser.execute_script("return arguments[0].innerHTML", solid)
    _press(browser, solid, Keys.ARROW_LEFT, 2)
    assert browser.execute_script("return arguments[0].innerHTML", solid) != before
    for shown in (after, keyed):
        state = clamped_cosine.State(shown["normal_deg"], shown["probe_deg"])
        expected = clamped_cosine.readouts(params, state)
        assert _agree(shown, expected, "cosine") >= 20
        assert shown["rest_energy"] == pytest.approx(
            1.0 - sum(expected[f"band{b}_energy"] for b in range(3)), abs=1e-12)


def test_each_face_shows_the_windows_solid_angles(site, browser):
    from selenium.webdriver import ActionChains
    from selenium.webdriver.common.keys import Keys

    from explorer.ui.figures import cell_faces

    _load(browser, site)
    figure = _figure(browser, "faces")
    figure.find_element("css selector", 'button[data-direction="-y"]').click()
    face = figure.find_element("css selector", 'svg polygon[data-face="3"]')
    ActionChains(browser).move_to_element(face).perform()          # hover
    checked = []
    shown = _readouts(browser, figure)
    checked.append(("-y", 3, shown))
    figure.find_element("css selector", 'button.face-row[data-face="0"]').click()   # a tap
    checked.append(("-y", 0, _readouts(browser, figure)))
    row = figure.find_element("css selector", 'button.face-row[data-face="0"]')
    _press(browser, row, Keys.ARROW_DOWN, 2)
    checked.append(("-y", 2, _readouts(browser, figure)))
    assert browser.execute_script("return document.activeElement.dataset.face") == "2"
    for direction, highlighted, values in checked:
        expected = cell_faces.readouts(CellFacesParams(direction=direction),
                                       cell_faces.State(highlighted))
        assert "highlighted" in values
        assert _agree(values, expected, f"faces {direction} {highlighted}") == len(expected)
        assert values["front_share"] == pytest.approx(expected["front"] / (4 * math.pi),
                                                      rel=1e-15)


def test_tilting_the_texel_gives_the_windows_footprint(site, browser):
    from selenium.webdriver.common.keys import Keys

    from explorer.ui.figures import rsm_texel

    _load(browser, site)
    figure = _figure(browser, "texel")
    _drag(browser, figure.find_element("css selector", '[data-handle="tilt"]'), -20, 60)
    dragged = _readouts(browser, figure)
    assert dragged["theta_deg"] > 30.0
    slider = figure.find_element("css selector", "input[type=range]")
    _press(browser, slider, Keys.END)
    ends = _readouts(browser, figure)
    assert ends["theta_deg"] == MAX_TILT
    _press(browser, slider, Keys.ARROW_LEFT, 5)
    keyed = _readouts(browser, figure)
    for values in (dragged, ends, keyed):
        expected = rsm_texel.readouts(None, rsm_texel.State(values["theta_deg"]))
        assert _agree(values, expected, "texel") == 4
        assert values["flux"] == pytest.approx(1.0, rel=1e-12)       # E·A = Φ0 at any tilt
    assert slider.get_attribute("aria-valuetext") == "θ = 80°"


def test_the_pipeline_shows_its_frames_numbers_and_what_each_stage_does(site, browser):
    from selenium.webdriver import ActionChains
    from selenium.webdriver.common.keys import Keys

    from explorer.ui.figures.pipeline_overview import _lines

    _load(browser, site)
    figure = _figure(browser, "pipeline")
    root = figure.find_element("css selector", "[data-live-kind]")
    values = json.loads(root.get_attribute("data-params"))["readouts"]
    assert values["rsm_flux"] > 0 and values["cells"] > 0
    expected = _lines(values)
    text = figure.find_element("css selector", ".pipeline-text")
    for key, title, doc in PIPELINE_STAGES:
        box = figure.find_element("css selector", f'button[data-stage="{key}"]')
        lines = [line.text for line in box.find_elements("css selector", ".line")]
        assert lines == [line for line in expected[key]], key
        ActionChains(browser).move_to_element(box).perform()
        assert text.text == f"{title}: {doc}"
    first = figure.find_element("css selector", 'button[data-stage="light"]')
    _press(browser, first, Keys.ARROW_RIGHT, 2)
    assert browser.execute_script("return document.activeElement.dataset.stage") == "inject"


def test_the_stepper_propagates_as_the_twin_does(site, browser):
    from selenium.webdriver.common.keys import Keys
    from selenium.webdriver.support.ui import Select

    from explorer.ui.figures import propagation_stepper

    _load(browser, site)
    figure = _figure(browser, "stepper")
    slider = figure.find_element("css selector", "input[type=range]")
    play = figure.find_element("css selector", "button.play")
    canvas = figure.find_element("css selector", "canvas")
    still = canvas.screenshot_as_png
    play.click()
    time.sleep(1.0)
    assert int(slider.get_attribute("value")) > 0 and canvas.screenshot_as_png != still
    play.click()                                              # pause
    formulas = Select(figure.find_element("css selector", "select"))
    checked = 0
    for name in ("corrected", "original", "ping_pong off", "clamp_front_face off"):
        formulas.select_by_value(name)
        for key, step in ((Keys.HOME, 0), (Keys.ARROW_RIGHT, 1), (Keys.END, 6)):
            _press(browser, slider, key)
            shown = _readouts(browser, figure)
            assert shown["step"] == step
            params = PropagationStepperParams(iterations=6, corrections=name)
            state = propagation_stepper.State(step, False, "auto", "arrow")
            expected = propagation_stepper.readouts(params, state)
            checked += _agree(shown, expected, f"stepper {name} t={step}")
    assert checked == 4 * 3 * 8
    arrows = canvas.screenshot_as_png
    Select(figure.find_elements("css selector", "select")[1]).select_by_value("lobe")
    assert canvas.screenshot_as_png != arrows                # each cell's lobe instead
    assert slider.get_attribute("aria-valuetext") == "step t = 6 of 6"


def test_numbers_read_as_the_window_prints_them(site, browser):
    """The page's number formats (assets/figures/common.js) print what the window's
    (explorer/ui/figures/style.py) print, over magnitudes from 1e-7 to 1e5 and both
    signs."""
    from explorer.ui.figures import style

    _load(browser, site)
    values = [0.0, 1.0, -1.0, 3.0, 0.999999, 1e-7, -2.5e-5, 0.00099951, 0.001, 0.0123456,
              0.5, 12.3456, 999.5, 9999.4, 1e4, -123456.7, 0.875, 127 / 128, 1 / 3]
    printed = browser.execute_async_script(
        "const done = arguments[arguments.length - 1];"
        "import('lpv/figures/common.js').then(m => done(arguments[0].map(v => ["
        "m.watts(v), m.percent(v, 1), m.percent(v, 2), m.fixed(v, 3), m.general(v, 3),"
        " m.shareOf(v, 0.5)])));", values)
    for value, page in zip(values, printed):
        window = [style.watts(value), style.percent(value, 1), style.percent(value, 2),
                  style.num(value, ".3f"), style.num(value, ".3g"), style.share_of(value, 0.5)]
        assert page == window, value


def test_from_a_web_server_the_module_files_themselves_load(site, browser):
    """Served over HTTP the import map points at assets/ and the browser fetches the
    module files (from file:// it imports the packed copies)."""
    import functools
    import http.server
    import threading

    class Quiet(http.server.SimpleHTTPRequestHandler):
        def log_message(self, *args) -> None:
            pass

    handler = functools.partial(Quiet, directory=str(site))
    server = http.server.ThreadingHTTPServer(("127.0.0.1", 0), handler)
    thread = threading.Thread(target=server.serve_forever, daemon=True)
    thread.start()
    try:
        _load(browser, site, url=f"http://127.0.0.1:{server.server_port}/{PAGE}")
        fetched = browser.execute_script(
            "return performance.getEntriesByType('resource').map(e => e.name)")
        for name in ("assets/figures/live.js", "assets/figures/stepper.js",
                     "assets/generated/constants.js"):
            assert any(url.endswith(name) for url in fetched), (name, fetched)
        errors = [e for e in browser.get_log("browser") if e["level"] == "SEVERE"
                  and "favicon.ico" not in e["message"]]    # the browser's own request
        assert errors == []
    finally:
        server.shutdown()
        server.server_close()
        thread.join(5)


def test_a_touch_drag_turns_the_normal(site, browser):
    """A finger on the handle (touch events, as a phone sends them) drags n as a mouse
    does: pointer events serve both."""
    from explorer.ui.figures import clamped_cosine

    _load(browser, site, 375)
    figure = _figure(browser, "cosine")
    handle = figure.find_element("css selector", '[data-handle="n"]')
    box = browser.execute_script("arguments[0].scrollIntoView({block: 'center'});"
                                 "const r = arguments[0].getBoundingClientRect();"
                                 "return [r.x + r.width / 2, r.y + r.height / 2]", handle)
    browser.execute_cdp_cmd("Emulation.setTouchEmulationEnabled", {"enabled": True,
                                                                   "maxTouchPoints": 1})
    path = [box, [box[0] - 40, box[1] + 30], [box[0] - 80, box[1] + 70]]
    for kind, (x, y) in zip(("touchStart", "touchMove", "touchMove"), path):
        browser.execute_cdp_cmd("Input.dispatchTouchEvent", {
            "type": kind, "touchPoints": [{"x": x, "y": y}]})
        time.sleep(0.05)                                # one frame per move
    browser.execute_cdp_cmd("Input.dispatchTouchEvent", {"type": "touchEnd", "touchPoints": []})
    browser.execute_cdp_cmd("Emulation.setTouchEmulationEnabled", {"enabled": False})
    shown = _readouts(browser, figure)
    assert shown["normal_deg"] < 0.0                   # turned past up, toward −x
    expected = clamped_cosine.readouts(ClampedCosineParams(normal_deg=30.0), clamped_cosine.State(
        shown["normal_deg"], shown["probe_deg"]))
    assert _agree(shown, expected, "cosine by touch") >= 20


def test_every_live_control_is_reached_by_tab_and_shows_its_focus(site, browser):
    """Tab walks through each figure's controls (sliders, buttons, selects); the one that
    has the focus draws a visible outline."""
    from selenium.webdriver.common.keys import Keys

    _load(browser, site)
    query = ".live-figure input, .live-figure button, .live-figure select"
    controls = browser.execute_script(f"return document.querySelectorAll('{query}').length")
    first = browser.find_element("css selector", query)
    browser.execute_script("arguments[0].focus()", first)
    seen = {0}
    for _ in range(3 * controls):
        browser.switch_to.active_element.send_keys(Keys.TAB)
        index, style, width = browser.execute_script(
            f"const e = document.activeElement, s = getComputedStyle(e);"
            f" return [Array.from(document.querySelectorAll('{query}')).indexOf(e),"
            " s.outlineStyle, parseFloat(s.outlineWidth)]")
        if index < 0:
            continue                            # a link of the page between the figures
        assert style != "none" and width >= 2, index
        seen.add(index)
        if index == controls - 1:
            break
    assert seen == set(range(controls))         # every control, by Tab alone
