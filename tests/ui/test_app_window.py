"""The explorer in a real glfw window under Xvfb (pytest-xvfb starts it).

Panels are driven through the app state (``app.state`` changes + ``app.frame()``), never
by clicking pixels. Windows are small (800×600) and the LPV tiny (16³, RSM 64²).

Index: opening and drawing (``test_window_opens_and_draws_the_panels``), bad files and GL
(``test_corrupt_settings_file_falls_back_and_is_rewritten``), what re-runs, with a recording
pipeline (``RecordingPipeline``, ``RefusingPipeline``), the real pipeline's view
(``test_real_pipeline_view_reacts_to_the_switches_and_splits``), the run command, and the
panels fitting their column at 1280 px (``_content_fits_at_1280``)."""

from __future__ import annotations

import json
import os
import subprocess
import sys
import types

import numpy as np
import pytest
from window_cases import display_problem

import explorer.gl.window as window_module
from explorer.gl.context import GLUnavailableError
from explorer.lpv.settings import PRESETS, Settings
from explorer.ui.state import AppState

SMALL = dict(width=800, height=600, visible=False, vsync=False)
TINY = Settings(grid_size=16, iterations=4, rsm_size=64, width=256, height=192)


_PROBLEM = display_problem()
pytestmark = pytest.mark.skipif(_PROBLEM is not None, reason=str(_PROBLEM))


@pytest.fixture
def config_home(tmp_path, monkeypatch):
    monkeypatch.setenv("XDG_CONFIG_HOME", str(tmp_path / "config"))
    monkeypatch.setenv("XDG_CACHE_HOME", str(tmp_path.parent / "lpv-cache"))
    return tmp_path / "config" / "lpv-explorer"


def _app(state=None, **kwargs):
    from explorer.ui.app import App
    from explorer.ui.window_options import WindowOptions

    options = dict(SMALL, persist_settings=False)
    options.update(kwargs)
    return App(state or AppState(settings=TINY), WindowOptions(**options))


def test_window_opens_and_draws_the_panels(config_home):
    app = _app(pipeline_class=None)
    try:
        for _ in range(2):
            assert app.frame()
        assert app.frame(capture=True)
        pixels = app.last_pixels
        assert pixels.shape == (600, 800, 3)
        assert pixels.std() > 10, "the frame is blank"
        assert app.ctx.error == "GL_NO_ERROR"
        assert "no LPV pipeline" in app.state.runtime.frame.pipeline_error
        assert app.state.runtime.services.markdown_ready
        errors = [m.text for m in app.state.messages if m.level == "error"]
        assert errors == []
    finally:
        app.close()


def test_docked_panels_draw_no_background_of_their_own(config_home):
    """The frame's clear is the panels' colour, so a docked panel leaves its background
    to it (a layer of fill less on a software renderer) and looks as before."""
    from explorer.ui import theme

    assert theme.CLEAR_COLOUR == theme.WINDOW_BG and theme.DOCKED_WINDOW_BG[3] == 0.0
    app = _app(pipeline_class=None)
    try:
        for _ in range(3):
            assert app.frame()
        assert app.frame(capture=True)
        docked = [title for title, is_docked in app.panels.docked.items() if is_docked]
        assert "View" in docked and len(docked) >= 5
        # the View panel's empty space (no pipeline: no image, the middle column of the
        # default layout) shows the panel colour
        expected = np.round(np.array(theme.WINDOW_BG[:3]) * 255)
        empty = app.last_pixels[200, 440].astype(float)
        assert np.abs(empty - expected).max() <= 2, (empty, expected)
    finally:
        app.close()


def test_screenshot_writes_a_png_of_the_whole_window(config_home, tmp_path):
    from PIL import Image

    app = _app(pipeline_class=None)
    try:
        app.frame()
        path = app.screenshot(tmp_path / "shots" / "window.png")
        app.state.requests.screenshot = tmp_path / "requested.png"   # what F12 / the button do
        app.frame()
    finally:
        app.close()
    with Image.open(path) as image:
        assert image.size == (800, 600)
        assert np.asarray(image).std() > 10
    assert (tmp_path / "requested.png").is_file()


def test_corrupt_settings_file_falls_back_and_is_rewritten(config_home, capsys):
    from explorer.ui.app import App
    from explorer.ui.window_options import WindowOptions

    config_home.mkdir(parents=True)
    (config_home / "settings.json").write_text("{ this is not json")
    app = App(None, WindowOptions(**SMALL, pipeline_class=None))
    try:
        assert app.state.settings == Settings()
        warnings = [m.text for m in app.state.messages if m.level == "warning"]
        assert warnings and "default settings" in warnings[0]
        app.state.apply_preset("original")
        app.frame()
    finally:
        app.close()
    assert "could not read" in capsys.readouterr().err
    saved = json.loads((config_home / "settings.json").read_text())
    assert saved["settings"]["corrections"]["injection_pi"] is False
    assert (config_home / "imgui.ini").is_file()

    from explorer.ui.layout import PANELS

    # the next run reads it all back
    app = App(None, WindowOptions(**SMALL, pipeline_class=None))
    try:
        assert app.state.settings.corrections == PRESETS["original"]
        assert not app.panels.needs_layout, "a saved layout for the same panels is kept"
        assert app.state.layout_panels == [p.title for p in PANELS]
        assert app.state.window_size == (800, 600)
        assert not [m for m in app.state.messages if m.level != "info"]
    finally:
        app.close()


def test_a_gl_without_compute_shaders_gets_a_message_not_a_crash(config_home, monkeypatch,
                                                                 capsys):
    def no_compute(require=430):
        raise GLUnavailableError("the GL driver lacks what the LPV needs: compute shaders")

    monkeypatch.setattr(window_module, "wrap_current_context", no_compute)
    app = _app()
    try:
        assert app.frame(capture=True)
        assert "compute shaders" in app.state.runtime.services.gl_problem
        assert app.last_pixels.std() > 5
        assert app.state.runtime.frame.result is None
    finally:
        app.close()
    assert "compute shaders" in capsys.readouterr().err


def test_a_minimised_window_skips_rendering(config_home, monkeypatch):
    app = _app(pipeline_class=None)
    try:
        app.frame()
        drawn = app.state.runtime.frame.frame_index
        monkeypatch.setattr(type(app.window), "minimised", property(lambda self: True))
        assert app.frame()
        assert app.state.runtime.frame.frame_index == drawn
        assert app.ctx.error == "GL_NO_ERROR"
    finally:
        app.close()


class _FinishedJob:
    """A job that completes its frame on the first advance (the Job interface the
    window's controller drives)."""

    def __init__(self, result):
        from explorer.lpv.job import Progress

        self._result, self.done, self.cancelled = result, False, False
        self.progress = Progress("scene", 0, 1, False, ())

    def advance(self, budget_ms=None, finishing_ms=None, until=None):
        from explorer.lpv.job import Progress

        self.done = True
        self.progress = Progress(None, 0, 0, True, ("rsm", "propagate"))
        return self.progress

    @property
    def result(self):
        return self._result

    stage = None          # between stages (the Job interface)

    def next_unit_ms(self):
        return 0.0

    def preview(self, scale=1.0, injected=False):
        return False

    def preview_source(self):
        return None

    def next_unit_measured(self):
        return True

    def cancel(self):
        self.cancelled = True


class RecordingPipeline:
    """A test double with the Pipeline interface: counts the frames it starts, fails for
    "broken.obj", and holds linear direct light whose level depends on the corrections."""

    runs: list = []
    # the rest of explorer.ui.controller.PipelineLike: no units timed, no fog, no
    # previews, no scene of its own (the controller loads the scene's defaults)
    unit_ms: dict = {}
    unit_ms_at: dict = {}
    timings_ms: dict = {}
    fog_textures = None
    preview_textures = None
    base_scene = None

    def __init__(self, settings, ctx=None):
        self.ctx = ctx
        self.textures = None

    def view(self, name, **options):
        raise ValueError(f"the test pipeline has no view {name!r}")

    @property
    def linear_textures(self):
        return self.textures

    def start(self, settings, keep_steps=False, need_audit=True, progress=None):
        if settings.scene.endswith("broken.obj"):
            raise ValueError(f"{settings.scene}: no triangles")
        RecordingPipeline.runs.append(settings)
        level = 200 if settings.corrections.propagation_4pi else 40
        size = (settings.width, settings.height)
        if self.textures is None or self.textures[0].size != size:
            self.release()
            self.textures = tuple(self.ctx.texture(size, 4, dtype="f4") for _ in range(3))
        direct = np.zeros((settings.height, settings.width, 4), np.float32)
        direct[..., :3], direct[..., 3] = level / 255.0, 1.0
        self.textures[0].write(direct.tobytes())
        self.textures[1].write(np.zeros_like(direct).tobytes())
        self.textures[2].write(np.ones_like(direct).tobytes())
        data = np.full((settings.height, settings.width, 3), level / 255.0, np.float32)
        n, steps = settings.grid_size, settings.iterations + 1
        grid = np.zeros((3, n, n, n, 4), np.float32)
        audit = types.SimpleNamespace(
            rsm=np.ones(3), injected=np.ones(3), accumulated=np.ones(3) * 2,
            gathered=np.ones(3), per_step=np.ones((steps, 3)),
            border_loss=np.zeros((steps - 1, 3)), clamp_gain=np.zeros((steps - 1, 3)),
            occluded=np.zeros((steps - 1, 3)))
        rsm = np.zeros((8, 8, 4), np.float32)
        return _FinishedJob(types.SimpleNamespace(
            settings=settings, final_image=data, direct=data, indirect=data * 0,
            albedo=data * 0 + 1, rsm_position=rsm, rsm_normal=rsm, rsm_flux=rsm,
            accumulated=grid, steps=[grid] * steps if keep_steps else None,
            geometry_volume=None, audit=audit, timings_ms={"rsm": 1.0, "propagate": 2.0},
            stages_run=("rsm", "propagate"), warnings=[], display_scale=1.0, fog=None,
            timing_methods={}, gbuffer_position=None, gbuffer_normal=None, camera=None,
            scene_bounds=None, light_names=(), vpl_sets=[], vpls=None, received=None))

    def reload_shaders(self):
        return False

    programs = types.SimpleNamespace(errors={})

    def release(self):
        for texture in self.textures or ():
            texture.release()
        self.textures = None


def test_pipeline_reruns_only_on_change_and_a_broken_mesh_keeps_the_scene(config_home):
    RecordingPipeline.runs = []
    state = AppState(settings=TINY)
    state.follow_view_size = False
    app = _app(state, pipeline_class=RecordingPipeline)
    try:
        app.settle()      # a first picture at a reduced size, then the full size
        ran = len(RecordingPipeline.runs)
        assert ran == 2 and RecordingPipeline.runs[-1].width == TINY.width
        for _ in range(3):
            app.frame()
        assert len(RecordingPipeline.runs) == ran, "same settings must not re-run"
        app.state.set_corrections(propagation_4pi=False)
        app.frame()
        assert len(RecordingPipeline.runs) == ran + 1
        assert app.state.runtime.frame.result.settings.corrections.propagation_4pi is False

        app.window.dropped_paths.append(config_home / "broken.obj")   # drag and drop
        app.frame()
        app.frame()
        assert app.state.settings.scene == "cornell"
        errors = [m.text for m in app.state.messages if m.level == "error"]
        assert any("broken.obj" in e and "no triangles" in e for e in errors)

        for panel in ("inspect", "plots"):
            app.state.open_panels[panel.capitalize()] = True
        app.state.inspect.source = "propagation"
        app.state.view_mode = "split"
        app.frame()
        app.frame()
        assert app.state.runtime.frame.compare_result is not None
        assert app.state.runtime.frame.result.steps is not None
        errors = [m.text for m in app.state.messages if m.level == "error"
                  and "broken.obj" not in m.text]
        assert errors == []
    finally:
        app.close()


def _pipeline_available() -> bool:
    try:
        import explorer.lpv.pipeline  # noqa: F401
    except ModuleNotFoundError:
        return False
    return True


needs_pipeline = pytest.mark.skipif(not _pipeline_available(),
                                    reason="explorer.lpv.pipeline is not in this build")


def _view_pixels(app) -> np.ndarray:
    # The size is rounded on its own, so that one picture moved by a toolbar row (the split
    # view's extra checkbox) keeps its pixel count whatever the rounding of its edges.
    left, top, right, bottom = app.state.runtime.view.view_rect
    x0, y0 = int(round(left)), int(round(top))
    x1, y1 = x0 + int(round(right - left)), y0 + int(round(bottom - top))
    return app.last_pixels[y0 + 2:y1 - 2, x0 + 2:x1 - 2].astype(np.float32)


@needs_pipeline
def test_real_pipeline_view_reacts_to_the_switches_and_splits(config_home, monkeypatch):
    state = AppState(settings=TINY)
    state.follow_view_size = False
    app = _app(state)
    try:
        app.settle()
        app.frame(capture=True)
        assert app.state.runtime.frame.result is not None, app.state.runtime.frame.pipeline_error
        corrected = _view_pixels(app)
        assert corrected.std() > 5, "the 3D view is blank"
        assert app.ctx.error == "GL_NO_ERROR"

        app.state.set_corrections(propagation_4pi=False)        # the Corrections checkbox
        app.settle()
        app.frame(capture=True)
        flipped = _view_pixels(app)
        assert np.abs(flipped - corrected).mean() > 1.0, "flipping 1/(4π) changed nothing"

        app.state.apply_preset("corrected")
        app.state.compare_settings = app.state.compare_settings.with_changes(
            corrections="original")
        app.state.view_mode, app.state.split_position = "split", 0.5
        app.settle()
        app.frame(capture=True)
        split = _view_pixels(app)
        half = split.shape[1] // 2
        below = 36     # the rows under the A/B labels the split view overlays at the top
        left = np.abs(split[below:, :half - 4] - corrected[below:, :half - 4]).mean()
        right = np.abs(split[below:, half + 4:] - corrected[below:, half + 4:]).mean()
        assert left < 1.0 < right, (left, right)

        app.state.view_buffer = "indirect"                 # the view's buffer selector
        app.frame(capture=True)
        indirect = _view_pixels(app)
        assert indirect.std() > 1.0 and np.abs(indirect - split).mean() > 1.0
        app.state.view_buffer = "final"

        rt = app.state.runtime          # the display's auto exposure (on by default):
        shown = rt.frame
        assert shown.compare_result.display_scale != shown.result.display_scale   # their own,
        assert shown.displays["B"].scale == shown.displays["A"].scale   # but B is shown at A's
        app.state.expose_sides_separately = True           # each side on its own
        app.frame()
        assert rt.frame.displays["B"].scale == rt.frame.compare_result.display_scale
        assert rt.frame.displays["A"].scale == rt.frame.result.display_scale
        app.state.update(auto_exposure=False)              # a fixed display exposure: the
        for _ in range(3):                                 # sides get their exposures
            app.frame()
        exposure_a, exposure_b = app.state.runtime.frame.side_exposures
        assert exposure_a != exposure_b and (exposure_a, exposure_b) != (1.0, 1.0)
        assert rt.frame.displays["A"].exposure == exposure_a
        assert rt.frame.displays["B"].exposure == exposure_b
        assert rt.frame.displays["A"].scale == rt.frame.displays["B"].scale == 1.0
        app.state.expose_sides_separately = False
        app.state.update(auto_exposure=True, exposure=1.0)

        app.state.view_mode = "difference"
        app.state.inspect.source = "vpls"
        app.frame()
        app.state.inspect.source = "propagation"
        app.state.inspect.glyphs = True
        app.settle()
        app.frame(capture=True)
        assert _view_pixels(app).std() > 1.0
        assert app.state.runtime.frame.result.steps is not None
        errors = [m.text for m in app.state.messages if m.level == "error"]
        assert errors == []

        broken = config_home.parent.parent / "broken.obj"
        broken.write_text("v 0 0 0\nthis is not a mesh\n")
        app.state.requests.open_scene = str(broken)           # the path field's Open button
        app.settle()
        assert app.state.settings.scene == "cornell"
        errors = [m.text for m in app.state.messages if m.level == "error"]
        assert len(errors) == 1 and "broken.obj" in errors[0]

        # Shader hot reload: a compile error keeps the last good program and shows the log.
        from explorer.gl import program as program_module

        stamp = [program_module.ProgramCache.newest_change()]
        monkeypatch.setattr(program_module.ProgramCache, "newest_change",
                            staticmethod(lambda: stamp[0]))
        good_load = program_module.load_program

        def broken_load(ctx, name, defines=None, varyings=()):
            raise program_module.ShaderError(program_module.shader_dir() / name,
                                             "0:12(3): error: syntax error, unexpected ';'")

        monkeypatch.setattr(program_module, "load_program", broken_load)
        app.state.view_mode = "single"
        for bump in (0.0, 10.0):           # the first poll only records the time stamp
            stamp[0] += bump
            app.controller.poll_shaders(app.state)
            app.frame()
        shader_errors = app.state.runtime.services.shader_errors
        assert shader_errors and "syntax error" in next(iter(shader_errors.values()))
        app.state.set_corrections(propagation_4pi=False)   # still renders with the old ones
        app.settle()
        app.frame(capture=True)
        assert np.abs(_view_pixels(app) - flipped).mean() < 1.0
        assert app.state.runtime.frame.result.settings.corrections.propagation_4pi is False

        monkeypatch.setattr(program_module, "load_program", good_load)
        stamp[0] += 10.0
        app.controller.poll_shaders(app.state)
        app.frame()
        assert app.state.runtime.services.shader_errors == {}
        assert any(m.text.startswith("shaders reloaded") for m in app.state.messages)
    finally:
        app.close()


def test_run_command_writes_a_screenshot_and_rejects_bad_flags(config_home, tmp_path, capsys):
    from explorer.cli import main as cli_main

    shot = tmp_path / "run.png"
    assert cli_main(["run", "--no-persist", "--hidden", "--size", "800x600",
                     "--scene", "single-source", "--preset", "original",
                     "--screenshot", str(shot), "--frames", "4"]) == 0
    from PIL import Image

    with Image.open(shot) as image:
        assert image.size == (800, 600)
    assert not (config_home / "settings.json").exists(), "--no-persist wrote settings"
    assert cli_main(["run", "--frames", "0"]) == 2
    assert "--frames" in capsys.readouterr().err
    assert cli_main(["run", "--size", "huge"]) == 2
    assert "--size" in capsys.readouterr().err


def test_run_without_a_display_says_so():
    env = {k: v for k, v in os.environ.items() if k not in ("DISPLAY", "WAYLAND_DISPLAY")}
    proc = subprocess.run([sys.executable, "-m", "explorer", "run", "--no-persist"],
                          env=env, capture_output=True, text=True, timeout=60)
    assert proc.returncode == 1
    assert "display" in proc.stderr.lower()


def test_a_window_beside_the_headless_context_leaves_it_usable(ctx, config_home):
    """The session's EGL context is current when the window opens (as in the full suite);
    glXMakeCurrent would fail with BadAccess and Xlib would exit the process."""
    app = _app(pipeline_class=None)
    try:
        app.frame()
        assert app.frame(capture=True)
        assert app.last_pixels.std() > 10
    finally:
        app.close()
    buffer = ctx.buffer(np.arange(4, dtype=np.float32).tobytes())
    assert np.frombuffer(buffer.read(), np.float32).tolist() == [0.0, 1.0, 2.0, 3.0]
    buffer.release()


@needs_pipeline
def test_a_saved_scene_that_no_longer_opens_falls_back_to_the_default(config_home):
    state = AppState(settings=TINY.with_changes(scene=str(config_home / "gone.obj")))
    state.follow_view_size = False
    app = _app(state)
    try:
        app.settle()
        assert app.state.settings.scene == Settings().scene
        assert app.state.runtime.frame.result is not None
        assert any("gone.obj" in m.text for m in app.state.messages if m.level == "error")
    finally:
        app.close()


@needs_pipeline
def test_new_options_change_the_view_and_a_refused_combination_keeps_the_settings(
        config_home):
    """Offset, bounces and cascades reach the view; a combination Settings refuses (a
    second bounce without a geometry volume) is reported in the window, not raised."""
    state = AppState(settings=TINY)
    state.follow_view_size = False
    app = _app(state)
    try:
        app.settle()
        app.frame(capture=True)
        base = _view_pixels(app)
        assert app.state.runtime.frame.result is not None, app.state.runtime.frame.pipeline_error

        before = app.state.settings
        assert app.state.update(bounces=2) is False          # geometry volume is off
        assert app.state.settings == before
        assert "bounces" in app.state.messages[-1].text
        assert app.state.messages[-1].level == "error"

        assert app.state.update(injection_offset_cells=0.0)
        app.settle()
        app.frame(capture=True)
        offset_zero = _view_pixels(app)
        assert np.abs(offset_zero - base).mean() > 0.2, "the injection offset changed nothing"

        assert app.state.update(injection_offset_cells=0.5, geometry_volume="one-sided",
                                bounces=2)
        app.settle()
        app.frame(capture=True)
        assert app.state.runtime.frame.result.settings.bounces == 2
        assert np.abs(_view_pixels(app) - base).mean() > 0.2, "a second bounce changed nothing"

        assert app.state.update(bounces=1, geometry_volume="off", cascades=2)
        app.state.inspect.source = "grid-slice"
        app.state.inspect.cascade = 1
        app.settle()
        app.frame(capture=True)
        result = app.state.runtime.frame.result
        assert len(result.cascade_specs) == 2 and app.state.inspect.cascade == 1
        assert np.abs(_view_pixels(app) - base).mean() > 0.2, "two cascades changed nothing"
        assert app.ctx.error == "GL_NO_ERROR"
    finally:
        app.close()


_GOOD_SETTINGS = {"format": 1, "settings": TINY.to_dict()}
_BAD_STARTS = [
    ("settings.json", {**_GOOD_SETTINGS, "split_position": "abc"}, "split_position"),
    ("settings.json", {**_GOOD_SETTINGS, "render_scale": "big"}, "render_scale"),
    ("settings.json", {**_GOOD_SETTINGS, "render_scale": [1]}, "render_scale"),
    ("settings.json", {**_GOOD_SETTINGS, "settings": {"iterations": 1000000}},
     "settings.iterations"),
    ("settings.json", {**_GOOD_SETTINGS, "settings": {"grid_size": 100000, "rsm_size": 16384}},
     "settings.grid_size"),
    ("settings.json", {**_GOOD_SETTINGS, "inspect": {"slice_z": "abc"}}, "inspect.slice_z"),
    ("settings.json", {**_GOOD_SETTINGS, "inspect": {"source": "bogus"}}, "inspect.source"),
    ("settings.json", {**_GOOD_SETTINGS, "expose_sides_separately": "no"},
     "expose_sides_separately"),
    ("settings.json", {**_GOOD_SETTINGS, "settings": {"auto_exposure": "no"}},
     "settings.auto_exposure"),
    ("imgui.ini", "Parent=0x00000001 SizeRef=431,555", "no earlier line defines"),
    ("imgui.ini", "Size=-5,937 Split=X", "Size=-5,937"),
]


def _bad_layout(change: str) -> str:
    from test_app_settings import GOOD_LAYOUT

    if change.startswith("Parent="):
        return GOOD_LAYOUT.replace(change, change.replace("0x00000001", "0x0000BEEF"))
    return GOOD_LAYOUT.replace("Size=1600,937 Split=X", change)


@pytest.mark.parametrize("name, content, complaint", _BAD_STARTS,
                         ids=[f"{case[0]}:{case[2]}" for case in _BAD_STARTS])
def test_a_bad_file_stops_the_window_never_and_is_set_aside_once(config_home, capsys, name,
                                                                 content, complaint):
    """Each bad file (without its check it would end every launch with a traceback or an
    imgui assertion): the window opens, the file is set aside once with a one-line message in
    the window and on stderr, and the next launch is clean."""
    from explorer.ui.app import App
    from explorer.ui.window_options import WindowOptions

    config_home.mkdir(parents=True)
    (config_home / "settings.json").write_text(json.dumps(_GOOD_SETTINGS))
    bad = config_home / name
    bad.write_text(_bad_layout(content) if name == "imgui.ini" else json.dumps(content))
    app = App(None, WindowOptions(**SMALL, pipeline_class=None))
    try:
        assert app.frame()          # imgui reads the layout file in its first frame
        warnings = [m.text for m in app.state.messages if m.level == "warning"]
        assert len(warnings) == 1 and complaint in warnings[0] and "moved it to" in warnings[0]
        if name == "imgui.ini":
            assert app.state.settings == TINY       # the settings file was fine
    finally:
        app.close()
    err = capsys.readouterr().err
    assert complaint in err and "Traceback" not in err
    assert len(list(config_home.glob(f"{name}.bad-*"))) == 1
    app = App(None, WindowOptions(**SMALL, pipeline_class=None))      # the second launch is clean
    try:
        assert app.frame()
        assert [m for m in app.state.messages if m.level != "info"] == []
        assert not app.panels.needs_layout, "the layout saved by the first launch is used"
    finally:
        app.close()
    assert len(list(config_home.glob("*.bad-*"))) == 1
    assert "Traceback" not in capsys.readouterr().err


class RefusingPipeline(RecordingPipeline):
    """Refuses grid sizes above 16, as the real pipeline refuses what the driver lacks."""

    def start(self, settings, keep_steps=False, need_audit=True, progress=None):
        if settings.grid_size > 16:
            raise ValueError(f"grid_size {settings.grid_size} exceeds this driver's limit")
        return super().start(settings, keep_steps, need_audit, progress)


def test_settings_the_pipeline_refused_are_not_written_back(config_home):
    from explorer.ui.app import App
    from explorer.ui.window_options import WindowOptions

    state = AppState(settings=TINY)
    state.follow_view_size = False
    app = App(state, WindowOptions(**SMALL, persist_settings=True, pipeline_class=RefusingPipeline))
    try:
        app.settle()
        assert app.state.runtime.frame.result is not None
        app.state.update(grid_size=32, iterations=5)
        app.frame()
        assert "exceeds this driver's limit" in app.state.runtime.frame.pipeline_error
    finally:
        app.close()
    saved = json.loads((config_home / "settings.json").read_text())
    assert saved["settings"]["grid_size"] == 16 and saved["settings"]["iterations"] == 4


@needs_pipeline
def test_the_numeric_guards_warn_in_the_messages_once(config_home):
    """FrameResult.warnings arrive in the Messages panel when a result brings them, once:
    a display-only change keeps the warning and posts nothing new."""
    state = AppState(settings=TINY)
    state.follow_view_size = False
    app = _app(state)
    try:
        app.settle()
        assert app.state.runtime.frame.result.warnings == []
        app.state.set_corrections(injection_pi=False)   # the published injection alone
        app.settle()
        grows = [m for m in app.state.messages
                 if m.level == "warning" and m.text.startswith("the flux grows")]
        assert len(grows) == 1 and app.state.runtime.frame.result.warnings
        result = app.state.runtime.frame.result
        app.state.update(exposure=0.5)
        app.frame()
        assert app.state.runtime.frame.displays["A"].exposure == 0.5
        assert app.state.runtime.frame.result is result, "a display change runs no pass"
        assert sum(m.text.startswith("the flux grows") for m in app.state.messages) == 1
    finally:
        app.close()


def test_the_scene_panel_shows_every_section(config_home, tmp_path):
    """The Scene panel alone in its column, with the controls that only show sometimes
    (downsample factor, cascade options, fixed resolution): drawn without an error."""
    state = AppState(settings=TINY.with_changes(downsample="average", cascades=2,
                                                geometry_volume="one-sided", bounces=2))
    state.follow_view_size = False
    app = _app(state, pipeline_class=None)
    try:
        app.frame()
        for title in ("Lessons", "Corrections", "Compare"):
            app.state.open_panels[title] = False
        for _ in range(3):
            app.frame()
        app.screenshot(tmp_path / "scene.png")
        assert [m.text for m in app.state.messages if m.level == "error"] == []
    finally:
        app.close()


def test_several_panels_asked_forward_at_once_all_come_forward(config_home):
    """A lesson step may ask for panels in different dock nodes at once (lesson 12's
    cascades: Inspect and Error). A dock node selects the tab of the window holding the
    keyboard focus, so the app focuses them one a frame; each ends up the visible tab of
    its node, in place of the first tab the default layout shows (Show in scene, Plots)."""
    from imgui_bundle import imgui

    app = _app(pipeline_class=None, width=1280, height=720)
    try:
        for _ in range(2):         # the first frame docks the windows
            app.frame()

        def shown(title: str) -> bool:
            window = imgui.internal.find_window_by_name(title)
            return window is not None and not window.hidden

        assert shown("Show in scene") and not shown("Inspect") and not shown("Error")
        app.state.requests.focus_panel = ("Inspect", "Error")
        for _ in range(4):
            app.frame()
        assert shown("Inspect") and not shown("Show in scene")
        assert shown("Error") and not shown("Plots")
        assert app.state.requests.focus_panel is None
    finally:
        app.close()


def _content_fits_at_1280(title: str, state: AppState | None = None) -> None:
    """Panel ``title`` brought forward in a 1280×720 window: imgui's content width of the
    window (its widest item) stays within its inner width."""
    from imgui_bundle import imgui

    app = _app(state, pipeline_class=None, width=1280, height=720)
    try:
        for _ in range(2):         # the first frame docks the windows
            app.frame()
        app.state.requests.focus_panel = title
        for _ in range(4):
            app.frame()
        window = imgui.internal.find_window_by_name(title)
        assert not window.hidden
        inner = window.inner_rect.max.x - window.inner_rect.min.x
        assert 0 < window.content_size.x <= inner, (window.content_size.x, inner)
    finally:
        app.close()


def test_the_corrections_panel_fits_its_column_at_1280(config_home):
    """At 1280×720 the tool column is about 300 px wide: the Corrections panel's widest
    line (a consequence's formula and its '≈ value') wraps instead of running past the
    right edge."""
    _content_fits_at_1280("Corrections")


def test_the_scene_panel_fits_its_column_at_1280(config_home):
    """At 1280×720 the Scene panel's fields with long labels ("Shadow PCF [texels]",
    "Fog density σt [1/m]") are narrowed so that field and label end within the column,
    every sometimes-shown control included."""
    state = AppState(settings=TINY.with_changes(downsample="average", cascades=2, fog=True,
                                                glossy=True, fog_phase="henyey-greenstein"))
    state.follow_view_size = False
    _content_fits_at_1280("Scene", state)
