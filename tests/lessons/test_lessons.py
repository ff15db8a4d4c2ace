"""Lessons: every shipped lesson validates, names real formulas and controls, renders;
broken files give errors that name the file, the step and the field.

Index: the shipped lessons (``test_every_shipped_lesson_validates`` to
``test_find_lesson_by_id_number_and_stem``), broken input (``_error``), the command line
(``test_cli_lists_and_prints``), every step rendered (``test_every_step_renders_headlessly``),
the panel's session (``test_panel_session_navigates_applies_and_restores``) and the
steps' words (``test_panel_step_caption_says_where_to_look``)."""

from __future__ import annotations

import os
import re
import shutil
from pathlib import Path

import pytest

from explorer.cli import main as cli_main
from explorer.lessons import (
    COMPARE_VIEWS,
    LESSON_DEFAULTS,
    LessonError,
    Step,
    find_lesson,
    load_all,
    load_lesson,
    valid_controls,
)
from explorer.lpv.settings import PRESETS, Settings
from explorer.resources import lesson_dir


def _structure_only(name: str) -> None:
    """A formula check that accepts every name (for tests about everything else)."""


@pytest.fixture(scope="module")
def shipped():
    lessons, errors = load_all(check_formula=_structure_only)
    return lessons, errors


def test_every_shipped_lesson_validates(shipped):
    lessons, errors = shipped
    assert errors == [], "\n".join(str(e) for e in errors)
    assert len(lessons) >= 14
    assert lessons[0].id == "overview" and lessons[-1].id == "beyond-diffuse"
    for lesson in lessons:
        assert 3 <= len(lesson.steps) <= 6, lesson.id
        assert lesson.path.name.startswith(f"{lesson.number:02d}-")
    assert not (lesson_dir() / ".keep").exists()


def test_every_formula_name_resolves(shipped):
    registry = pytest.importorskip("derivations.registry")
    lessons, _ = shipped
    names = {name for lesson in lessons for step in lesson.steps for name in step.formulas}
    assert names, "the lessons typeset no formula at all"
    for name in sorted(names):
        assert registry.get(name) is not None, name
    # and the loader's own check (the default) accepts every shipped lesson
    assert load_all()[1] == []


def test_every_try_this_names_a_real_control(shipped):
    lessons, _ = shipped
    controls = set(valid_controls())
    assert {"grid_size", "corrections.injection_pi", "corrections"} <= controls
    prompts = 0
    for lesson in lessons:
        for step in lesson.steps:
            for item in step.try_this:
                assert item.control in controls, (lesson.id, step.number, item.control)
                assert len(item.prompt) > 30, (lesson.id, step.number)
                prompts += 1
    assert prompts >= 20


def test_steps_apply_on_top_of_a_base(shipped):
    lessons, _ = shipped
    base = Settings(width=300, height=200, exposure=2.0, corrections=PRESETS["original"])
    for lesson in lessons:
        for step in lesson.steps:
            settings = step.settings(base)
            assert settings.scene == step.scene
            assert settings.corrections == step.corrections
            for name, value in step.overrides:
                assert getattr(settings, name) == value
            if "width" not in dict(step.overrides):
                assert settings.width == 300
            # the published square frustum and a fixed exposure, unless the step asks
            for name, value in LESSON_DEFAULTS.items():
                assert getattr(settings, name) == dict(step.overrides).get(name, value)
            if step.view in COMPARE_VIEWS:
                other = step.compare_settings(base)
                assert other.corrections == step.compare
                assert other.corrections != settings.corrections, (lesson.id, step.number)
            else:
                assert step.compare_settings(base) is None


def test_lessons_cover_the_topics(shipped):
    lessons, _ = shipped
    text = " ".join(" ".join([step.title, step.text] + [t.prompt for t in step.try_this])
                    for lesson in lessons for step in lesson.steps)
    text = " ".join(text.lower().split())
    for topic in ("radiance", "solid angle", "spherical harmonic", "reflective shadow map",
                  "injection", "side face", "reprojection", "geometry volume",
                  "final gather", "in place", "leak", "cascade", "reference",
                  # the lesson on LPV in practice
                  "snapped", "flicker", "depth and normal buffer", "several lights",
                  "memory", "voxel cone tracing", "ddgi", "screen-space gi",
                  # beyond diffuse
                  "depth and normal buffer", "transmittance", "henyey–greenstein",
                  "phase function", "glossy", "what it gets wrong"):
        assert topic in text, topic
    used_views = {step.view for lesson in lessons for step in lesson.steps}
    used_plots = {step.plot for lesson in lessons for step in lesson.steps}
    assert {"split", "difference"} <= used_views
    assert {"flux-per-step", "error"} <= used_plots
    used_scenes = {step.scene for lesson in lessons for step in lesson.steps}
    assert used_scenes == {"cornell", "single-source", "room", "two-rooms"}


def test_find_lesson_by_id_number_and_stem(shipped):
    lessons, _ = shipped
    first = lessons[0]
    assert find_lesson(first.id, lessons) is first
    assert find_lesson(str(first.number), lessons) is first
    assert find_lesson(first.path.stem, lessons) is first
    with pytest.raises(KeyError, match="no lesson 'nope'"):
        find_lesson("nope", lessons)
    with pytest.raises(IndexError, match="steps 1.."):
        first.step(len(first.steps) + 1)
    assert isinstance(first.step(1), Step)


# --- broken input -----------------------------------------------------------------------

GOOD = '''
id = "tiny"
title = "A tiny lesson"
summary = "Used by the tests."

[[steps]]
title = "First"
text = "One."
scene = "single-source"

[[steps]]
title = "Second"
text = "Two."
view = "split"
compare = "original"
[steps.settings]
grid_size = 8
[[steps.try_this]]
control = "corrections.side_faces"
value = false
prompt = "Switch the side faces off and watch the cross-shaped pattern appear."
'''


def _write(folder: Path, name: str, text: str) -> Path:
    path = folder / name
    path.write_text(text, encoding="utf-8")
    return path


def _error(tmp_path: Path, text: str, **kwargs) -> LessonError:
    path = _write(tmp_path, "50-broken.toml", text)
    with pytest.raises(LessonError) as info:
        load_lesson(path, **kwargs)
    assert "50-broken.toml" in str(info.value)
    return info.value


def test_a_good_file_loads(tmp_path):
    lesson = load_lesson(_write(tmp_path, "07-tiny.toml", GOOD), check_formula=None)
    assert lesson.id == "tiny" and lesson.number == 7 and len(lesson.steps) == 2
    second = lesson.step(2)
    assert second.settings().grid_size == 8
    assert second.compare_settings().corrections == PRESETS["original"]
    assert lesson.step(1).settings().scene == "single-source"


def test_syntax_error_names_the_line(tmp_path):
    broken = GOOD.replace('title = "Second"', 'title = "Second')
    error = _error(tmp_path, broken, check_formula=None)
    line = broken.splitlines().index('title = "Second') + 1
    assert error.line == line
    assert f"50-broken.toml:{line}" in str(error) and "TOML syntax error" in str(error)


def test_an_error_quoting_several_lines_of_the_file_is_one_line(tmp_path):
    """A {{...}} whose format spans lines (found by tests/test_fuzz_readers.py) is named in
    one line, its line breaks shown as \\n."""
    quoted = "{{derived.propagation.step_flux_factor_original:.v 1\nv 2\n4f}}"
    broken = GOOD.replace('text = "One."', f"text = '''{quoted} One.'''", 1)
    assert broken != GOOD
    error = _error(tmp_path, broken, check_formula=None)
    assert "\n" not in str(error) and "\\n" in str(error) and "format" in str(error)


def test_unknown_field_names_step_and_field(tmp_path):
    error = _error(tmp_path, GOOD.replace("grid_size = 8", "grid_sise = 8"), check_formula=None)
    assert error.step == 2 and error.field == "settings.grid_sise"
    assert "step 2 ('Second')" in str(error) and "unknown field" in str(error)
    error = _error(tmp_path, GOOD.replace('text = "One."', 'text = "One."\ncolour = 1'),
                   check_formula=None)
    assert (error.step, error.field) == (1, "colour")


def test_a_text_broken_only_on_the_web_side_is_a_lesson_error(tmp_path):
    """The page's side of a variant is read too, and its error is the lesson's one line."""
    text = GOOD.replace('text = "One."', 'text = "One {{window}}fine{{web}}tr{{{{uth{{end}}."')
    error = _error(tmp_path, text, check_formula=None)
    assert (error.step, error.field) == (1, "text") and "web page" in str(error)


def test_wrong_type_and_bad_values(tmp_path):
    error = _error(tmp_path, GOOD.replace("grid_size = 8", 'grid_size = "8"'),
                   check_formula=None)
    assert error.field == "settings.grid_size"
    assert "grid_size must be a whole number in [1, 256], got '8'" in str(error)
    error = _error(tmp_path, GOOD.replace("grid_size = 8", "grid_size = 0"), check_formula=None)
    assert "grid_size must be a whole number in [1, 256], got 0" in str(error) and error.step == 2
    error = _error(tmp_path, GOOD.replace("grid_size = 8", "iterations = true"),
                   check_formula=None)
    assert error.field == "settings.iterations"
    error = _error(tmp_path, GOOD.replace("grid_size = 8", "spot_cone_degrees = [30, 'x']"),
                   check_formula=None)
    assert error.field == "settings.spot_cone_degrees" and "two numbers" in str(error)
    error = _error(tmp_path, GOOD.replace("grid_size = 8", "spot_cone_degrees = [50, 20]"),
                   check_formula=None)
    assert "spot_cone_degrees must be two numbers [first, second] with 0 <= first <= second" \
        in str(error)
    cone = _write(tmp_path, "51-cone.toml", GOOD.replace(
        "grid_size = 8", "spot_cone = true\nspot_cone_degrees = [30, 60]\nauto_exposure = true"))
    step = load_lesson(cone, check_formula=None).step(2)
    assert step.settings().spot_cone_degrees == (30.0, 60.0)
    assert step.settings().spot_cone and step.settings().auto_exposure
    error = _error(tmp_path, GOOD.replace('compare = "original"', 'compare = "fixed"'),
                   check_formula=None)
    assert error.field == "compare"
    assert "compare must be one of 'original', 'corrected'" in str(error)
    error = _error(tmp_path, GOOD.replace('compare = "original"\n', ""), check_formula=None)
    assert error.field == "compare" and "needs a compare preset" in str(error)


def test_unknown_scene_view_plot_control(tmp_path):
    error = _error(tmp_path, GOOD.replace('"single-source"', '"sponza"'), check_formula=None)
    assert (error.step, error.field) == (1, "scene")
    assert "'sponza' is neither a built-in scene (cornell, single-source, room, two-rooms, " \
        "atrium) nor a file" in str(error)
    error = _error(tmp_path, GOOD.replace('view = "split"', 'view = "sideways"'),
                   check_formula=None)
    assert error.field == "view" and "view must be one of 'final'" in str(error)
    error = _error(tmp_path, GOOD.replace('view = "split"', 'view = "split"\nplot = "pie"'),
                   check_formula=None)
    assert error.field == "plot"
    error = _error(tmp_path, GOOD.replace("corrections.side_faces", "corrections.magic"),
                   check_formula=None)
    assert error.field == "try_this[0].control" and "control must be one of" in str(error)


def test_unknown_formula_names_step_and_index(tmp_path):
    def registry(name):
        if name != "known":
            raise KeyError(f"no derivation named {name!r}")

    text = GOOD.replace('text = "Two."', 'text = "Two."\nformulas = ["known", "made.up"]')
    error = _error(tmp_path, text, check_formula=registry)
    assert (error.step, error.field) == (2, "formulas[1]")
    assert "unknown formula 'made.up'" in str(error)


def test_one_broken_lesson_does_not_stop_the_others(tmp_path):
    for path in sorted(lesson_dir().glob("*.toml"))[:3]:
        shutil.copy(path, tmp_path / path.name)
    _write(tmp_path, "90-broken.toml", GOOD.replace('"single-source"', '"sponza"'))
    _write(tmp_path, "91-syntax.toml", "id = \n")
    lessons, errors = load_all(tmp_path, check_formula=_structure_only)
    assert len(lessons) == 3
    assert sorted(e.path.name for e in errors) == ["90-broken.toml", "91-syntax.toml"]


def test_duplicate_ids_are_reported(tmp_path):
    _write(tmp_path, "01-a.toml", GOOD)
    _write(tmp_path, "02-b.toml", GOOD)
    lessons, errors = load_all(tmp_path, check_formula=None)
    assert [lesson.path.name for lesson in lessons] == ["01-a.toml"]
    assert len(errors) == 1 and "already used" in str(errors[0])


# --- CLI ---------------------------------------------------------------------------------

def test_cli_lists_and_prints(capsys, shipped):
    lessons, _ = shipped
    assert cli_main(["lessons"]) == 0
    out = capsys.readouterr().out
    for lesson in lessons:
        assert lesson.id in out and lesson.title in out
    assert f"({len(lessons[0].steps)} steps)" in out
    assert cli_main(["lessons", lessons[0].id]) == 0
    out = capsys.readouterr().out
    assert lessons[0].steps[-1].title in out and "try this" in out
    # the export options alone export nothing: refused, not silently ignored
    assert cli_main(["lessons", "--step", "2"]) == 2
    assert "--step needs --export ID" in capsys.readouterr().err
    assert cli_main(["lessons", lessons[0].id, "--try", "1", "--no-overlays"]) == 2
    assert "--try, --no-overlays need --export ID" in capsys.readouterr().err


def test_cli_reports_broken_lessons(tmp_path, capsys):
    _write(tmp_path, "01-tiny.toml", GOOD)
    _write(tmp_path, "02-broken.toml", GOOD.replace('id = "tiny"', 'id = "other"')
           .replace("grid_size = 8", "grid_sise = 8"))
    assert cli_main(["lessons", "--dir", str(tmp_path)]) == 1
    captured = capsys.readouterr()
    assert "tiny" in captured.out
    assert "02-broken.toml" in captured.err and "settings.grid_sise" in captured.err
    assert cli_main(["lessons", "--dir", str(tmp_path), "missing"]) == 2
    assert "no lesson 'missing'" in capsys.readouterr().err
    assert cli_main(["lessons", "--dir", str(tmp_path), "02"]) == 2   # the broken one
    err = capsys.readouterr().err
    assert "lesson '02' is broken" in err and "settings.grid_sise" in err


# --- rendering every step ----------------------------------------------------------------

def test_every_step_renders_headlessly(shipped, ctx, tmp_path):
    """Each step at a tiny size (64², grid <= 16³, RSM 32², <= 8 iterations) in one shared
    Pipeline, showing the step's own view (split/difference included). The PNGs go to
    $LPV_LESSON_RENDERS when set (CI keeps them), else to a temporary folder."""
    pipeline_module = pytest.importorskip("explorer.lpv.pipeline")
    import numpy as np

    from explorer.lessons import preview_settings, render_step

    lessons, _ = shipped
    out = Path(os.environ["LPV_LESSON_RENDERS"]) if os.environ.get("LPV_LESSON_RENDERS") \
        else tmp_path
    out.mkdir(parents=True, exist_ok=True)
    with pipeline_module.Pipeline(preview_settings(lessons[0].steps[0]), ctx=ctx) as pipeline:
        for lesson in lessons:
            for step in lesson.steps:
                image, result = render_step(pipeline, step, preview_settings(step))
                assert result.settings.corrections == step.corrections
                assert result.final_image.shape == (64, 64, 3)
                assert np.isfinite(image).all() and image.min() >= 0.0 and image.max() <= 1.0
                assert image.max() > 0.0, (lesson.id, step.number, "renders black")
                _save(out / f"{lesson.path.stem}-step{step.number}.png", image)


def _save(path: Path, image) -> None:
    import numpy as np
    from PIL import Image

    Image.fromarray((np.clip(image, 0.0, 1.0) * 255.0 + 0.5).astype(np.uint8)).save(path)


# --- lesson panel (pure navigation and state; no window) -----------------------------------

def test_panel_session_navigates_applies_and_restores(shipped):
    from explorer.ui.lesson_panel import LessonSession, Screen

    lessons, _ = shipped
    session = LessonSession(lessons=lessons)
    own = Screen(settings=Settings(width=320, height=240, exposure=3.0),
                 compare_settings=Settings(corrections=PRESETS["original"]),
                 view_mode="single")
    lesson = session.open("reprojection")
    assert session.step_number == 1 and session.step is lesson.steps[0]
    assert not session.previous() and session.step_number == 1
    first = session.apply(own)
    assert session.applied and session.saved is own
    assert first.settings.scene == lesson.steps[0].scene
    assert (first.settings.width, first.settings.exposure) == (320, 3.0)
    assert first.plot == lesson.steps[0].plot
    # the split step: B gets the compare preset, the view mode follows the step
    assert session.next() and session.step_number == 2
    split = session.apply(first)          # a second apply keeps the first saved screen
    assert session.saved is own
    assert split.view_mode == "split"
    assert split.compare_settings.corrections == lesson.steps[1].compare
    assert split.settings.corrections == lesson.steps[1].corrections
    assert session.go(99) and session.step_number == len(lesson.steps)
    assert not session.next()
    assert session.leave() is own and not session.applied and session.left
    back = session.apply(own)
    assert back.settings.corrections == lesson.steps[-1].corrections and not session.left
    assert session.close() is own and session.lesson is None


def test_panel_screen_maps_views(shipped):
    from explorer.ui.lesson_panel import Screen, step_screen

    lessons, _ = shipped
    own = Screen(settings=Settings(), compare_settings=Settings(), view_mode="difference")
    for lesson in lessons:
        for step in lesson.steps:
            screen = step_screen(step, own)
            if step.view in ("split", "difference"):
                assert screen.view_mode == step.view
            else:
                assert screen.view_mode == "single"
            if step.view in ("final", "direct", "indirect", "albedo"):
                assert screen.view_buffer == step.view
            else:
                assert screen.view_buffer == "final"
            if step.view.startswith("rsm-") or step.view in ("grid-slice", "geometry-volume"):
                assert screen.inspect_source == step.view


def test_render_command_renders_a_lesson_step(tmp_path):
    """`render --lesson ID --step K`, run as a child process: a CLI render opens and
    releases its own EGL context, which leaves this process's shared test context no
    longer current (later GPU tests would then fail with GL_INVALID_VALUE)."""
    import subprocess
    import sys

    import numpy as np
    from PIL import Image

    root = Path(__file__).resolve().parents[2]

    def render(*args: str) -> subprocess.CompletedProcess:
        return subprocess.run([sys.executable, "-m", "explorer", "render", *args], cwd=root,
                              capture_output=True, text=True, timeout=300)

    out = tmp_path / "step.png"
    small = ["--size", "48x48", "--grid", "8", "--iterations", "3", "--rsm-size", "32"]
    done = render("--lesson", "reference", "--step", "2", "--out", str(out), *small)
    assert done.returncode == 0, done.stderr
    assert "lesson reference, step 2/" in done.stdout
    assert "split against original" in done.stdout
    image = np.asarray(Image.open(out), dtype=np.float64)
    assert image.shape == (48, 48, 3)
    left, right = image[:, :23], image[:, 25:]
    assert left.mean() > right.mean()   # the original preset is much dimmer
    # every option of a plain render also overrides the step (cascades, SH order, leaks)
    done = render("--lesson", "injection", "--step", "1", "--out", str(out), *small,
                  "--cascades", "2", "--sh-order", "2", "--injection-offset", "0",
                  "--audit")
    assert done.returncode == 0, done.stderr
    assert "cascade 1" in done.stdout
    done = render("--lesson", "injection", "--step", "1", "--out", str(out),
                  "--injection-offset", "3")
    assert done.returncode == 2 and "injection_offset_cells" in done.stderr
    done = render("--lesson", "nope", "--out", str(out))
    assert done.returncode == 2 and "no lesson 'nope'" in done.stderr
    done = render("--lesson", "reference", "--step", "99", "--out", str(out))
    assert done.returncode == 2 and "steps 1.." in done.stderr


def test_inline_math_reads_as_plain_text(shipped):
    """The terminal form of a lesson (``lpv-explorer lessons ID``): math as text, derived
    numbers filled in, live ones named, markers spelled out."""
    from explorer.commands.lessons import _plain
    from explorer.lessons import MATH_COMMANDS, math_to_text

    assert math_to_text(r"$\Phi = \int_{S^2} I(\omega)\,d\omega$") == "Φ = ∫_S² I(ω) dω"
    assert math_to_text(r"$\frac{\Delta\omega_f}{4\pi}$ and $c_1 = \sqrt{3}/(2\sqrt{\pi})$") \
        == "Δω_f/(4π) and c_1 = √3/(2√π)"
    assert math_to_text(r"$\langle n, \omega\rangle$") == "<n, ω>"
    assert math_to_text(r"$(x^2 + 9)^{-3/2}$, $87.5\%$, $\{\pm x\}$") \
        == "(x² + 9)^(-3/2), 87.5%, {± x}"
    # nested braces and sizing commands (lesson 06's injection formula)
    assert math_to_text(r"$f \mathrel{+}= k\,\left(\frac{\sqrt{\pi}}{2},\; "
                        r"-\sqrt{\pi/3}\,n_y\right)$") == "f += k (√π/2, -√(π/3) n_y)"
    assert math_to_text(r"$\frac{1}{2\sqrt{\pi}}$, $\alpha\,\sigma_t$") == "1/(2√π), α σ_t"
    assert _plain(r"$c_0 = {{derived.sh.c0:.4f}}$ and {{audit.injected:.3g}} W {{try:1}}") \
        == "c_0 = 0.2821 and [flux injected into the grid (before any step)] W [try 1]"
    lessons, _ = shipped
    for lesson in lessons:
        for step in lesson.steps:
            plain = _plain(step.text)
            assert "$" not in plain and "\\" not in plain and "{{" not in plain, \
                (lesson.id, step.number)
            # every command the lessons' math uses is one the text form knows (an unknown
            # one would leave its name in the text: "left(frac√π2")
            texts = (step.text, *(item.prompt for item in step.try_this))
            for math in re.findall(r"\$+([^$]+)\$+", "\n".join(texts)):
                for command in re.findall(r"\\[A-Za-z]+", math):
                    assert command in MATH_COMMANDS, (lesson.id, step.number, command)


_WINDOW_SCRIPT = """
from explorer.lpv.settings import Settings
from explorer.ui.app import App
from explorer.ui.window_options import WindowOptions
from explorer.ui.lesson_panel import current_screen, show_screen
from explorer.ui.state import AppState

own = Settings(grid_size=16, iterations=4, rsm_size=64, width=256, height=192, exposure=2.0)
app = App(AppState(settings=own, lesson_id="reprojection"),
          WindowOptions(width=900, height=640, visible=False, vsync=False,
                        persist_settings=False, pipeline_class=None))
try:
    for _ in range(2):
        assert app.frame()
    state = app.state
    session = state.lesson_session
    lesson = session.lesson
    assert lesson.id == "reprojection" and session.applied
    assert state.settings.scene == lesson.steps[0].scene
    assert state.settings.corrections == lesson.steps[0].corrections
    assert state.settings.exposure == 2.0
    assert state.view_buffer == "final"      # step 1 shows a grid slice (Inspect panel)
    session.next()                       # what the "next" arrow does
    show_screen(state, session.apply(current_screen(state)))
    assert app.frame(capture=True)
    assert state.view_mode == "split"
    assert state.compare_settings.corrections == lesson.steps[1].compare
    assert app.last_pixels.std() > 10
    show_screen(state, session.leave())  # "Leave lesson settings"
    app.frame()
    assert state.settings == own and state.view_mode == "single"
    assert state.view_buffer == "final"
    assert [m.text for m in state.messages if m.level == "error"] == []
finally:
    app.close()
print("window ok")
"""


def test_lesson_panel_in_the_window(tmp_path):
    """`run --lesson ID` sets state.lesson_id; the Lessons panel applies step 1, steps on,
    and gives the reader's own settings back, in a real window (Xvfb). It runs in a child
    process: a GLX window cannot become current in a process that already made the
    tests' EGL context current (Xlib aborts the process with BadAccess)."""
    import subprocess
    import sys

    # imgui_bundle first: it points pyglfw at the GLFW it bundles; a pyglfw imported
    # before it loads another GLFW, and this process's later windows fail (EGL surface)
    pytest.importorskip("imgui_bundle")
    glfw = pytest.importorskip("glfw")
    if not os.environ.get("DISPLAY") or not glfw.init():
        pytest.skip("no X server for a window")
    glfw.terminate()
    env = dict(os.environ, XDG_CONFIG_HOME=str(tmp_path / "config"),
               XDG_CACHE_HOME=str(tmp_path / "cache"))
    root = Path(__file__).resolve().parents[2]
    proc = subprocess.run([sys.executable, "-c", _WINDOW_SCRIPT], cwd=root, env=env,
                          capture_output=True, text=True, timeout=300)
    assert proc.returncode == 0 and "window ok" in proc.stdout, proc.stdout + proc.stderr


def test_panel_step_caption_says_where_to_look(shipped):
    from dataclasses import replace

    from explorer.ui.lesson_panel import step_caption

    lessons, _ = shipped
    steps = [step for lesson in lessons for step in lesson.steps]
    captions = {step_caption(step) for step in steps}
    # a step that draws in the scene points at the main view, not at the Inspect panel
    shown = [step for step in steps if step.overlays().any_shown]
    assert shown and all(step_caption(s).startswith("Look at the main view (") for s in shown)
    grid_step = next(s for s in shown if s.view == "grid-slice")
    assert "slice through the grid" in step_caption(grid_step)
    assert step_caption(replace(grid_step, show=())) == \
        "Look at the grid-slice view in the Inspect panel."
    assert any("split view: this step against the original preset" in c for c in captions)
    assert any(c.endswith("and the flux-per-step plot.") for c in captions)


def test_a_step_naming_the_cascade_weights_brings_the_inspect_panel(shipped):
    """The cascades step draws the cascade boxes in the scene and its text reads the
    cascade-weights view: no overlay shows the weights, so the caption names the Inspect
    panel too and showing the step brings that panel (not Show in scene) forward."""
    from explorer.ui.lesson_panel import Screen, show_screen, step_caption, step_screen
    from explorer.ui.state import AppState

    lessons, _ = shipped
    step = next(s for lesson in lessons if lesson.id == "limits" for s in lesson.steps
                if s.view == "cascade-weights")
    assert "the cascade-weights view in the Inspect panel" in step_caption(step)
    assert step_caption(step).startswith("Look at the main view (")
    own = Screen(settings=Settings(), compare_settings=Settings(), view_mode="single")
    state = AppState()
    show_screen(state, step_screen(step, own))
    assert state.inspect.source == "cascade-weights"
    assert "Inspect" in state.requests.focus_panel
    assert "Show in scene" not in state.requests.focus_panel


def test_the_leak_steps_look_at_the_dark_side_of_the_orange_wall(shipped):
    """Lesson 12 step 1 asks for the light on the dark side of the room's thin orange
    wall: its camera sees that face (the +x side, away from the sun) well off grazing;
    the room's own camera looks along the wall and sees it edge-on."""
    import numpy as np

    from explorer.scene import load_scene

    lesson = find_lesson("limits", *shipped)
    room = load_scene("room")
    wall = next(o for o in room.objects if o.name == "thin wall")
    normals = room.normals[wall.first:wall.first + wall.count]
    positions = room.positions[wall.first:wall.first + wall.count]
    dark = normals[:, 0] > 0.99                       # the face turned away from the sun
    centre = positions[dark].mean(axis=0)
    assert room.light.position[0] < centre[0], "the sun lights the -x side"

    def facing(eye) -> float:
        to_eye = np.asarray(eye, float) - centre
        return float(to_eye[0] / np.linalg.norm(to_eye))   # cosine against +x

    assert abs(facing(room.camera.eye)) < 0.2               # the default view: edge-on
    for step in lesson.steps[:1]:
        assert step.camera is not None, step.number
        assert facing(step.camera[0]) > 0.4, step.number
