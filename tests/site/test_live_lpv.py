"""The live LPV of a lesson step in its web page (explorer/site/live_lpv.py and
explorer/site/assets/lpv/): one small site of one live step, built once for the module as
a user builds it, served over HTTP and driven in headless Chromium (WebGL2 through
SwiftShader).

* the page's JavaScript twin on VPLs made here, run by the page's Workers (the colour
  channels split among them and added up), equals explorer/lpv/twin/light_grid.py: the flux per
  step, the audit terms and the accumulated grid to a relative 1e-9, for every correction
  switch, both presets, both geometry volumes and a propagation continued from fewer
  iterations;
* the page's WebGL2 gather of its grid against ``Pipeline.run`` (what ``render`` runs) at
  the same size: the indirect radiance within a mean relative 1e-5 and a max relative 1e-4
  over the lit surface pixels (float32 textures on both sides, the page's grid a float64
  propagation rounded to float32 once, the window's propagated in float32; both filter in
  float32 from eight texel fetches), the shown bytes within 2 of 255 (the sRGB power in
  float32 on different libraries);
* over 26 neighbours the page's twin equals the numpy twin's 26-neighbour step on an odd
  grid to a relative 1e-12 (float64 on both sides; measured about 1e-15), and its
  Neighbours control gives the window's 26-neighbour frame;
* toggling each correction (and each preset, the light, the grid size, the iterations,
  the geometry volume) in the page changes its numbers as the twin does on the baked
  VPLs (relative 1e-9), as the window's GPU frame does (flux per step, relative 1e-4), and
  its picture changes exactly when the window's does.

The browser checks skip with the reason printed when chromium or chromedriver is missing.
"""

from __future__ import annotations

import functools
import http.server
import json
import re
import subprocess
import sys
import threading
from dataclasses import replace
from pathlib import Path

import numpy as np
import pytest
from browser_cases import start_chromium
from lpv_cases import random_vpls

from explorer.lpv.corrections import CORRECTIONS, PRESETS, Corrections
from explorer.lpv.grid import GridSpec
from explorer.lpv.twin import light_grid as twin
from explorer.lpv.vpl import VplArrays

ROOT = Path(__file__).resolve().parents[2]
SIZE = (96, 64)
LESSON = '''id = "live"
title = "A live LPV"
summary = "One step whose LPV runs in the page."
scene = "cornell"

[[steps]]
title = "The Cornell box, live"
text = "The LPV of the Cornell box at {{settings.grid_size}}³ cells."
view = "final"
live_lpv = true
[steps.settings]
grid_size = 8
iterations = 4
rsm_size = 32
'''
TWIN_TOLERANCE = 1e-9
TWIN_26_TOLERANCE = 1e-12
"""The 26-neighbour port against the numpy twin: float64 both, sums in other orders."""
GPU_FLUX_TOLERANCE = 1e-4
INDIRECT_MEAN, INDIRECT_MAX = 1e-5, 1e-4
BYTE_TOLERANCE = 2


@pytest.fixture(scope="module")
def lessons_dir(tmp_path_factory) -> Path:
    folder = tmp_path_factory.mktemp("lessons")
    (folder / "01-live.toml").write_text(LESSON, encoding="utf-8")
    return folder


@pytest.fixture(scope="module")
def site(tmp_path_factory, lessons_dir) -> Path:
    out = tmp_path_factory.mktemp("site") / "live"
    done = subprocess.run(
        [sys.executable, "-m", "explorer", "site", str(out), "--dir", str(lessons_dir),
         "--size", f"{SIZE[0]}x{SIZE[1]}"], cwd=ROOT, capture_output=True, text=True,
        timeout=600)
    assert done.returncode == 0, done.stderr + done.stdout
    return out


@pytest.fixture(scope="module")
def step(lessons_dir):
    from explorer.lessons import load_all

    lessons, errors = load_all(lessons_dir)
    assert not errors
    return lessons[0].steps[0]


def description(site: Path) -> dict:
    text = (site / "01-live.html").read_text(encoding="utf-8")
    found = re.search(r'<script type="application/json" class="live-description">(.*?)'
                      r"</script>", text, re.S)
    assert found, "no live LPV description in the page"
    return json.loads(found.group(1))


def baked_vpls(site: Path, light: int = 0) -> VplArrays:
    """The VPLs the page reads for a light choice, as the twin reads them."""
    d = description(site)
    entry = d["lights"][light]
    assert len(entry["views"]) == 1, "the Cornell box's spot has one RSM view"
    floats = np.fromfile(site / entry["url"], "<f4").astype(np.float64)
    view = entry["views"][0]

    def part(name, columns):
        start, count = view[name]
        return floats[start:start + count].reshape(-1, columns) if columns else \
            floats[start:start + count]

    return VplArrays(part("positions", 3), part("normals", 3), part("flux", 3),
                     part("depth", 0), view["texelArea"], view["projection"])


def spec_of(entry: dict) -> GridSpec:
    return GridSpec(tuple(entry["origin"]), entry["cellSize"], entry["resolution"])


def relative(a, b) -> float:
    a, b = np.asarray(a, np.float64), np.asarray(b, np.float64)
    scale = float(np.max(np.abs(b))) if b.size else 0.0
    return float(np.max(np.abs(a - b)) / scale) if scale > 0 else float(np.max(np.abs(a)))


# --- the files -------------------------------------------------------------------------

def test_the_build_writes_the_arrays_the_description_names(site, step):
    d = description(site)
    assert (d["width"], d["height"]) == SIZE
    pixels = SIZE[0] * SIZE[1]
    gbuffer = d["gbuffer"]
    assert (site / gbuffer["url"]).stat().st_size == gbuffer["bytes"]
    assert {name: place[1] for name, place in gbuffer["arrays"].items()} == {
        "position": 4 * pixels, "normal": 4 * pixels, "albedo": 3 * pixels}
    assert len(d["lights"]) >= 2 and d["lights"][0]["light"] != d["lights"][1]["light"]
    for entry in d["lights"]:
        assert (site / entry["url"]).stat().st_size == entry["bytes"]
        assert entry["direct"][1] == 3 * pixels
    assert str(step.settings().grid_size) in d["grids"]
    assert [entry["name"] for entry in d["corrections"]] == [c.name for c in CORRECTIONS]
    settings = step.settings()
    for size, entry in d["grids"].items():
        from explorer.lpv.cascades import frame_specs
        from explorer.scene.loader import load_scene

        expected = frame_specs(settings.with_changes(grid_size=int(size)),
                               load_scene(settings.scene))[0]
        assert spec_of(entry) == expected


def test_a_step_the_page_cannot_run_is_refused_by_name(tmp_path, lessons_dir):
    lesson = LESSON.replace("rsm_size = 32", "rsm_size = 32\ncascades = 2")
    (tmp_path / "lessons").mkdir()
    (tmp_path / "lessons" / "01-live.toml").write_text(lesson, encoding="utf-8")
    done = subprocess.run(
        [sys.executable, "-m", "explorer", "site", str(tmp_path / "out"), "--dir",
         str(tmp_path / "lessons"), "--size", "64x64"], cwd=ROOT, capture_output=True,
        text=True, timeout=600)
    assert done.returncode != 0
    assert "cascades = 2" in done.stderr and "live_lpv" in done.stderr
    assert len(done.stderr.strip().splitlines()) == 1


# --- in the browser --------------------------------------------------------------------

@pytest.fixture(scope="module")
def served(site):
    class Quiet(http.server.SimpleHTTPRequestHandler):
        def log_message(self, *args) -> None:
            pass

    handler = functools.partial(Quiet, directory=str(site))
    server = http.server.ThreadingHTTPServer(("127.0.0.1", 0), handler)
    thread = threading.Thread(target=server.serve_forever, daemon=True)
    thread.start()
    yield f"http://127.0.0.1:{server.server_port}"
    server.shutdown()
    thread.join()


@pytest.fixture(scope="module")
def page(served):
    driver = start_chromium(("--enable-unsafe-swiftshader", "--use-angle=swiftshader"))
    driver.set_script_timeout(120)
    driver.set_window_size(1280, 900)
    driver.get(f"{served}/01-live.html")
    ready = driver.execute_async_script(
        "const done = arguments[arguments.length - 1];"
        "const wait = () => { const r = document.querySelector('[data-live-lpv]');"
        "  if (r && r.lpvLive) { done(r.lpvLive.unsupported || 'ready'); }"
        "  else { setTimeout(wait, 50); } }; wait();")
    if ready != "ready":
        driver.quit()
        print(f"\nskipped: {ready}")
        pytest.skip(ready)
    yield driver
    errors = [entry for entry in driver.get_log("browser") if entry["level"] == "SEVERE"
              and "favicon" not in entry["message"]]
    driver.quit()
    assert not errors, errors


RESULT = """
const r = live.result;
return {per_step: r.audit.per_step, injected: r.audit.injected, border_loss: r.audit.border_loss,
        clamp_gain: r.audit.clamp_gain, occluded: r.audit.occluded,
        accumulated: r.audit.accumulated, gathered: r.gathered, ms: r.ms,
        request: r.request, bytes: Array.from(r.bytes), indirect: Array.from(r.indirect)};
"""


def changed(driver, action: str = "") -> dict:
    """Run ``action`` (JavaScript with ``live``, ``root`` and ``q(selector)``), let the
    page compute and show, and return its result."""
    return driver.execute_async_script(
        "const done = arguments[arguments.length - 1];"
        "const root = document.querySelector('[data-live-lpv]'); const live = root.lpvLive;"
        "const q = (s) => root.querySelector(s);"
        f"{action};"
        "if (live.result === null && !live.busy) { live.changed(); }"
        "live.settled().then(() => { if (live.failed) { done({error: String(live.failed)}); }"
        f"  else {{ done((() => {{ {RESULT} }})()); }} }});")


def click(driver, selector: str) -> dict:
    return changed(driver, f"q('{selector}').click()")


def choose(driver, control: str, value) -> dict:
    return changed(driver, f"const s = q('[data-control={control}]'); s.value = '{value}';"
                           "s.dispatchEvent(new Event(s.type === 'range' ? 'input' : "
                           "'change'))")


def page_twin(driver, vpls: VplArrays, spec: GridSpec, corrections: Corrections,
              iterations: int, geometry: str = "off", offset: float = 0.5,
              neighbours: int = 6) -> dict:
    """The page's worker run on ``vpls``."""
    view = {"count": vpls.count, "texelArea": vpls.texel_area, "projection": vpls.projection,
            **{name: np.asarray(getattr(vpls, name), np.float64).ravel().tolist()
               for name in ("positions", "normals", "flux", "depth")}}
    request = {"views": [view], "corrections": {c.name: bool(getattr(corrections, c.name))
                                                for c in CORRECTIONS},
               "spec": {"origin": list(spec.origin), "cellSize": spec.cell_size,
                        "resolution": spec.resolution},
               "iterations": iterations, "offset": offset, "geometry": geometry,
               "neighbours": neighbours}
    return driver.execute_async_script(
        "const done = arguments[arguments.length - 1];"
        "const live = document.querySelector('[data-live-lpv]').lpvLive;"
        "live.twin(arguments[0]).then((a) => done({audit: a.audit, continued: a.continued,"
        " accumulated: Array.from(a.accumulated)}), (e) => done({error: String(e)}));",
        request)


def python_twin(vpls: VplArrays, spec: GridSpec, corrections: Corrections, iterations: int,
                geometry: str = "off", offset: float = 0.5, neighbours: int = 6):
    grid = twin.inject(vpls, spec, corrections, offset_cells=offset)
    volume = None if geometry == "off" else twin.inject_geometry(vpls, spec, corrections,
                                                                 geometry)
    return twin.propagate_audited(grid, corrections, iterations, volume,
                                  neighbours=neighbours)


def assert_audit_equal(audit: dict, expected, where: str,
                       tolerance: float = TWIN_TOLERANCE) -> None:
    checks = {"per_step": expected.per_step, "injected": expected.injected,
              "accumulated": expected.accumulated, "border_loss": expected.border_loss,
              "clamp_gain": expected.clamp_gain, "occluded": expected.occluded}
    for name, value in checks.items():
        got = np.asarray(audit[name], np.float64).reshape(np.shape(value))
        assert relative(got, value) < tolerance, (where, name, relative(got, value))


TWIN_CASES = [("corrected", PRESETS["corrected"], "off"),
              ("original", PRESETS["original"], "off"),
              *[(f"{entry.name} off", Corrections(**{entry.name: False}), "off")
                for entry in CORRECTIONS],
              ("one-sided geometry", PRESETS["corrected"], "one-sided"),
              ("double-sided geometry", PRESETS["corrected"], "double-sided"),
              ("linear surfel area", Corrections(surfel_area_squared=False), "one-sided"),
              ("original with geometry", PRESETS["original"], "one-sided")]


def test_the_page_twin_equals_the_numpy_twin_on_the_tests_vpls(page):
    spec = GridSpec((0.5, -1.0, 2.0), 0.25, 6)
    vpls = random_vpls(29, spec, 160, outside=4)
    for where, corrections, geometry in TWIN_CASES:
        answer = page_twin(page, vpls, spec, corrections, 3, geometry)
        assert "error" not in answer, (where, answer)
        _, accumulated, audit = python_twin(vpls, spec, corrections, 3, geometry)
        assert_audit_equal(answer["audit"], audit, where)
        got = np.asarray(answer["accumulated"]).reshape(accumulated.shape)
        assert relative(got, accumulated) < TWIN_TOLERANCE, where
    # more iterations of the same request continue from the last grid: the same numbers
    page_twin(page, vpls, spec, PRESETS["corrected"], 2)
    answer = page_twin(page, vpls, spec, PRESETS["corrected"], 5)
    assert answer["continued"]
    assert_audit_equal(answer["audit"], python_twin(vpls, spec, PRESETS["corrected"], 5)[2],
                       "continued")


NEEDED_BY_26 = ("ping_pong", "side_faces", "model_face_weights")
TWIN_26_CASES = [("corrected", PRESETS["corrected"], "off"),
                 *[(f"{entry.name} off", Corrections(**{entry.name: False}), "off")
                   for entry in CORRECTIONS if entry.name not in NEEDED_BY_26],
                 ("one-sided geometry", PRESETS["corrected"], "one-sided"),
                 ("double-sided geometry", PRESETS["corrected"], "double-sided"),
                 ("clamp off with geometry", Corrections(clamp_front_face=False), "one-sided")]


def test_the_page_twin_over_26_neighbours_equals_the_numpy_twin_on_an_odd_grid(page):
    """docs/MODEL.md "26 neighbours": every switch the step has a form for, both geometry
    volumes, on 5³ cells (odd: no cell is the grid's centre by symmetry of an even one);
    the switches it has no form for are refused with the twin's one line."""
    spec = GridSpec((0.5, -1.0, 2.0), 0.25, 5)
    vpls = random_vpls(31, spec, 160, outside=4)
    for where, corrections, geometry in TWIN_26_CASES:
        answer = page_twin(page, vpls, spec, corrections, 3, geometry, neighbours=26)
        assert "error" not in answer, (where, answer)
        _, accumulated, audit = python_twin(vpls, spec, corrections, 3, geometry,
                                            neighbours=26)
        assert_audit_equal(answer["audit"], audit, where, TWIN_26_TOLERANCE)
        got = np.asarray(answer["accumulated"]).reshape(accumulated.shape)
        assert relative(got, accumulated) < TWIN_26_TOLERANCE, where
        six = python_twin(vpls, spec, corrections, 3, geometry)[1]
        assert relative(got, six) > 1e-3, where      # not the six-neighbour step
    for name in NEEDED_BY_26:
        answer = page_twin(page, vpls, spec, Corrections(**{name: False}), 1, neighbours=26)
        with pytest.raises(ValueError) as numpy_error:
            python_twin(vpls, spec, Corrections(**{name: False}), 1, neighbours=26)
        assert answer["error"].endswith(str(numpy_error.value)), (name, answer)
        assert "\n" not in answer["error"]


def test_the_neighbours_control_gives_the_windows_26_neighbour_frame(page, frames, site):
    d = description(site)
    base = frames.base
    spec = spec_of(d["grids"][str(base.grid_size)])
    start = changed(page)
    answer = choose(page, "neighbours", 26)
    assert answer["request"]["neighbours"] == 26
    assert_audit_equal(answer, python_twin(baked_vpls(site), spec, base.corrections,
                                           base.iterations, neighbours=26)[2],
                       "26 neighbours", TWIN_26_TOLERANCE)
    assert_like_the_window(answer, frames(neighbours=26), "26 neighbours")
    assert _picture_changed(start, answer)
    back = choose(page, "neighbours", 6)
    assert back["bytes"] == start["bytes"]


def test_the_page_refuses_a_bad_request_with_one_line(page):
    spec = GridSpec((0.0, 0.0, 0.0), 1.0, 4)
    vpls = random_vpls(3, spec, 5)
    answer = page_twin(page, vpls, spec, PRESETS["corrected"], 1, offset=-1.0)
    assert "injection offset" in answer["error"] and "\n" not in answer["error"]


@pytest.fixture(scope="module")
def frames(gl_context, step):
    """The window's GPU frame of the step at the page's size, with changes."""
    from explorer.lpv.pipeline import Pipeline

    gl_context.__enter__()
    base = step.settings().with_changes(width=SIZE[0], height=SIZE[1])
    pipeline = Pipeline(base, ctx=gl_context)

    def frame(**changes):
        return pipeline.run(base.with_changes(**changes), need_audit="full")

    frame.base = base
    yield frame
    pipeline.release()


def shown_bytes(result) -> np.ndarray:
    from explorer.lpv.twin.tonemap import display_encode
    from explorer.site.frames import to_bytes

    s = result.settings
    return to_bytes(display_encode(result.final_image, result.display_scale, s.tone_map))


def assert_like_the_window(answer: dict, result, where: str) -> None:
    """The page's numbers against the window's GPU frame of the same settings."""
    page_steps = np.asarray(answer["per_step"]).sum(axis=1)
    gpu_steps = np.asarray(result.audit.per_step).sum(axis=1)
    assert page_steps.shape == gpu_steps.shape, where
    assert relative(page_steps, gpu_steps) < GPU_FLUX_TOLERANCE, (where, page_steps,
                                                                   gpu_steps)


def test_the_page_picture_matches_the_window_frame(page, frames, site):
    answer = changed(page)
    assert "error" not in answer, answer
    result = frames()
    assert_like_the_window(answer, result, "the step")
    gathered = float(np.sum(result.audit.gathered))
    assert abs(answer["gathered"] - gathered) < 1e-4 * gathered, (answer["gathered"], gathered)
    assert relative(description(site)["window_per_step"],
                    np.asarray(result.audit.per_step).sum(axis=1)) < 1e-6   # the plot's line
    indirect = np.asarray(answer["indirect"], np.float64).reshape(SIZE[1], SIZE[0], 4)[..., :3]
    expected = np.asarray(result.indirect, np.float64)[..., :3]
    lit = expected > 1e-3 * expected.max()
    error = np.abs(indirect - expected)[lit] / expected[lit]
    print(f"\nindirect against the window: mean relative {error.mean():.2e}, max "
          f"{error.max():.2e} over {lit.sum()} lit channels; page timings "
          f"{answer['ms']}")
    assert error.mean() < INDIRECT_MEAN and error.max() < INDIRECT_MAX
    assert np.all(indirect[~lit] <= 2e-3 * expected.max())
    shown = np.asarray(answer["bytes"], np.int64).reshape(SIZE[1], SIZE[0], 4)[..., :3]
    difference = np.abs(shown - shown_bytes(result).astype(np.int64))
    print(f"shown bytes: max difference {difference.max()}, "
          f"{(difference > 0).mean():.1%} of the channels differ")
    assert difference.max() <= BYTE_TOLERANCE
    # and the twin's numbers of the baked VPLs
    d = description(site)
    spec = spec_of(d["grids"][str(frames.base.grid_size)])
    assert_audit_equal(answer, python_twin(baked_vpls(site), spec, frames.base.corrections,
                                           frames.base.iterations)[2], "the step")


def _picture_changed(before: dict, after: dict) -> bool:
    return before["bytes"] != after["bytes"]


def test_toggling_each_correction_changes_the_page_as_the_window(page, frames, site):
    d = description(site)
    base = frames.base
    spec = spec_of(d["grids"][str(base.grid_size)])
    vpls = baked_vpls(site)
    before = changed(page)
    window_before = frames()
    for geometry in ("off", "one-sided"):
        if geometry != "off":
            before = choose(page, "geometry", geometry)
            window_before = frames(geometry_volume=geometry)
        for entry in CORRECTIONS:
            corrections = replace(base.corrections, **{entry.name: False})
            where = f"{entry.name} off, geometry {geometry}"
            answer = click(page, f"[data-correction={entry.name}]")
            assert "error" not in answer, (where, answer)
            assert_audit_equal(answer, python_twin(vpls, spec, corrections, base.iterations,
                                                   geometry)[2], where)
            window = frames(corrections=corrections, geometry_volume=geometry)
            if entry.name == "ping_pong":
                # In place, the GPU's pass races (explorer/lpv/twin/light_grid.py: it reads some
                # neighbours already updated, by invocation order); the page computes the
                # twin's race-free reading. Both count light again: the flux grows.
                for steps in (answer["per_step"], window.audit.per_step):
                    flux = np.asarray(steps).sum(axis=1)
                    assert np.all(flux[2:] > np.asarray(before["per_step"]).sum(1)[2:]), where
            else:
                assert_like_the_window(answer, window, where)
            window_changed = not np.array_equal(shown_bytes(window), shown_bytes(window_before))
            assert _picture_changed(before, answer) == window_changed, where
            back = click(page, f"[data-correction={entry.name}]")   # on again
            assert back["bytes"] == before["bytes"], where
    choose(page, "geometry", "off")


def test_presets_lights_sizes_and_iterations_follow_the_twin(page, frames, site):
    d = description(site)
    base = frames.base
    vpls = baked_vpls(site)
    spec = spec_of(d["grids"][str(base.grid_size)])
    start = changed(page)
    published = click(page, "[data-preset=original]")
    assert_audit_equal(published, python_twin(vpls, spec, PRESETS["original"],
                                              base.iterations)[2], "original preset")
    assert_like_the_window(published, frames(corrections=PRESETS["original"]),
                           "original preset")
    assert _picture_changed(start, published)
    corrected = click(page, "[data-preset=corrected]")
    assert corrected["bytes"] == start["bytes"]
    answer = choose(page, "iterations", 2)
    assert len(answer["per_step"]) == 3
    assert_like_the_window(answer, frames(iterations=2), "iterations 2")
    answer = choose(page, "iterations", base.iterations)
    assert answer["bytes"] == start["bytes"]
    answer = choose(page, "grid", 16)
    assert answer["request"]["spec"]["resolution"] == 16
    assert_like_the_window(answer, frames(grid_size=16), "grid 16")
    choose(page, "grid", base.grid_size)
    answer = choose(page, "light", 1)
    light = tuple(tuple(v) for v in d["lights"][1]["light"])
    assert_audit_equal(answer, python_twin(baked_vpls(site, 1), spec, base.corrections,
                                           base.iterations)[2], "light 1")
    assert_like_the_window(answer, frames(light=light), "light 1")
    assert _picture_changed(start, answer)
    back = choose(page, "light", 0)
    assert back["bytes"] == start["bytes"]


def test_the_controls_work_from_the_keyboard(page, frames):
    """Space on a switch, an arrow on the iterations slider, Enter on a preset: each a
    new run, with the focus drawn."""
    from selenium.webdriver.common.keys import Keys

    start = changed(page)
    steps = len(start["per_step"])
    for selector, key, check in (
            ("[data-correction=injection_pi]", Keys.SPACE,
             lambda a: a["per_step"][0] != start["per_step"][0]),
            ("[data-preset=corrected]", Keys.ENTER,
             lambda a: a["per_step"] == start["per_step"]),
            ("[data-control=iterations]", Keys.ARROW_RIGHT,
             lambda a: len(a["per_step"]) == steps + 1),
            ("[data-control=iterations]", Keys.ARROW_LEFT,
             lambda a: a["bytes"] == start["bytes"])):
        control = page.find_element("css selector", f"[data-live-lpv] {selector}")
        control.send_keys(key)
        outline = page.execute_script(
            "return getComputedStyle(document.activeElement).outlineStyle")
        answer = changed(page)
        assert check(answer), selector
        assert outline != "none", selector


def test_screenshots_at_desktop_and_phone_width(page, tmp_path):
    """The live figure laid out at 1280 and 375 px: every control inside the column."""
    import os

    keep = os.environ.get("LPV_SITE_SCREENSHOTS")
    for width in (1280, 375):
        page.set_window_size(width, 900)
        overflow = page.execute_script(
            "const r = document.querySelector('[data-live-lpv]');"
            "r.scrollIntoView(); const box = r.getBoundingClientRect();"
            "return Array.from(r.querySelectorAll('input, select, button, canvas'))"
            ".filter(e => { const b = e.getBoundingClientRect();"
            "  return b.width > 0 && (b.left < box.left - 1 || b.right > box.right + 1); })"
            ".map(e => e.outerHTML.slice(0, 80));")
        assert not overflow, (width, overflow)
        if keep:
            page.save_screenshot(str(Path(keep) / f"live-lpv-{width}.png"))


def test_opened_as_a_file_the_page_keeps_the_baked_picture_and_says_why(page, site):
    page.get((site / "01-live.html").as_uri())
    state = page.execute_script(
        "const r = document.querySelector('[data-live-lpv]');"
        "return [r.lpvLive === undefined, r.querySelector('img.live-baked').hidden,"
        " r.querySelector('.live-status').textContent];")
    assert state[0] and not state[1]
    assert "served over HTTP" in state[2]
    errors = [e for e in page.get_log("browser") if e["level"] in ("SEVERE", "WARNING")
              and "favicon" not in e["message"]]
    assert errors == [], errors


def test_without_webgl_the_page_keeps_the_baked_picture_and_says_why(served):
    driver = start_chromium(("--disable-webgl", "--disable-3d-apis"))
    try:
        driver.get(f"{served}/01-live.html")
        state = driver.execute_async_script(
            "const done = arguments[arguments.length - 1];"
            "const wait = () => { const r = document.querySelector('[data-live-lpv]');"
            "  if (!r.lpvLive) { setTimeout(wait, 50); return; }"
            "  done([r.lpvLive.unsupported, r.querySelector('img.live-baked').hidden,"
            "        r.querySelector('canvas.live-canvas').hidden,"
            "        Array.from(r.querySelectorAll('.live-controls input')).every("
            "          (e) => e.disabled), r.querySelector('.live-status').textContent]); };"
            "wait();")
    finally:
        driver.quit()
    reason, baked_hidden, canvas_hidden, disabled, status = state
    assert "WebGL2" in reason and not baked_hidden and canvas_hidden and disabled
    assert "baked" in status
