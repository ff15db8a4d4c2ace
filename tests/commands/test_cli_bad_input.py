"""Every subcommand driven with bad input: the exit code, one line on stderr naming what
is wrong, no traceback, nothing left on disk. In-process through ``explorer.cli.main``
(each case fails before any GL work), and a few as child processes to prove that no
traceback reaches a terminal; Ctrl-C as a real SIGINT to a child process."""

from __future__ import annotations

import signal
import subprocess
import sys
import time
from pathlib import Path

import pytest
from command_cases import StandInPipeline

from explorer.cli import main
from explorer.commands.options import Outputs, Progress, settings_from_args
from explorer.lpv.settings import PRESETS, Corrections, Settings
from explorer.schema import specs

ROOT = Path(__file__).resolve().parents[2]

BAD = [
    # render: sizes and counts out of the schema's range, bad numbers, bad combinations
    ("render --iterations 1000000", 2, "iterations must be a whole number in [0, 1024]"),
    ("render --iterations 1000000 --grid 8", 2, "got 1000000"),
    ("render --rsm-size 8192", 2, "rsm_size must be a whole number in [1, 4096]"),
    ("render --rsm-size 16384", 2, "rsm_size must be"),
    ("render --size 16384x16384", 2, "width must be a whole number in [1, 8192]"),
    ("render --size 64", 2, "size must look like 512x512"),
    ("render --grid 100000", 2, "grid_size must be a whole number in [1, 256]"),
    ("render --grid x", 2, "grid_size must be a whole number in [1, 256], got 'x'"),
    ("render --iterations 1.5", 2, "got '1.5'"),
    ("render --exposure nan", 2, "exposure must be a finite number in (0, 1000000]"),
    ("render --exposure -1", 2, "exposure must be a finite number"),
    ("render --exposure inf", 2, "got inf"),
    ("render --cascade-extent inf", 2, "cascade_extent must be a finite number"),
    ("render --cascade-extent 1e-30", 2, "cascade_extent must be a finite number in [1e-06"),
    ("render --sh-order 3", 2, "sh_order must be one of 1, 2, got 3"),
    ("render --cone-angles 60,30", 2, "spot_cone_degrees must be two numbers [first, second] "
                                      "with 0 <= first <= second <= 80, second > 0"),
    ("render --cone-angles 30", 2, "spot_cone_degrees must be two numbers"),
    ("render --cone-angles 0,0", 2, "second > 0 or None, got (0.0, 0.0)"),
    ("render --cone-angles 10,90", 2, "second <= 80"),
    ("render --shadow-kernel 10", 2, "shadow_kernel must be a whole number in [1, 9]"),
    ("render --tone-map sepia", 2, "tone_map must be one of 'linear-clip', 'filmic'"),
    ("compare --cone-angles 50,nan", 2, "spot_cone_degrees must be two numbers"),
    ("render --bounces 2", 2, "needs geometry_volume 'one-sided' or 'double-sided'"),
    ("render --preset nope", 2, "invalid choice: 'nope'"),
    ("render --scene nosuch", 2, "no built-in scene or mesh file named 'nosuch'"),
    ("render --slice 99 --view grid-slice --grid 8", 2, "--slice must be a z index in [0, 7]"),
    ("render --view grid-slice --coefficient 5", 2,
     "--coefficient must be in [0, 3] with --sh-order 1"),
    ("render --view grid-slice --cascade 2", 2, "--cascade must be in [0, 0]"),
    ("render --step 2", 2, "--step needs --lesson"),
    ("render --lesson nosuch", 2, "no lesson 'nosuch'"),
    ("render --lesson 4 --step 99", 2, "has steps 1..6, not 99"),
    ("render --bogus", 2, "unrecognized arguments: --bogus"),
    # render: output paths checked before the work
    ("render --out {tmp}/adir", 2, "is a folder"),
    ("render --out {tmp}/adir/", 2, "is a folder"),
    ("render --out {tmp}/noext", 2, "has no suffix; end the name in .png"),
    ("render --out {tmp}/x.xyz", 2, "not '.xyz'"),
    ("render --out {tmp}/afile/x.png", 2, "cannot make the folder"),
    # compare
    ("compare --grid-size 1000", 2, "grid_size must be a whole number in [1, 256]"),
    ("compare --size 100000x256", 2, "width must be a whole number in [1, 8192]"),
    ("compare --width 100000", 2, "width must be a whole number in [1, 8192], got 100000"),
    ("compare --rsm-size 100000", 2, "rsm_size must be a whole number in [1, 4096]"),
    ("compare --min-distance inf", 2, "min_distance must be a finite number"),
    ("compare --min-distance -1", 2, "min_distance must be a finite number in [0,"),
    ("compare --region 10,10,5,5", 2, "need 0 <= X0 < X1 and 0 <= Y0 < Y1"),
    ("compare --region 1,2,3", 2, "expected four integers"),
    ("compare --region 0,0,300,10", 2, "leaves the 256×256 image"),
    ("compare --region-mask nope", 2, "--region-mask: scene 'cornell' has no surface "
                                      "named 'nope'; its surfaces are: floor, ceiling"),
    ("compare --scene atrium --region-mask curtains", 2, "its surfaces are: floor, north "
                                                        "columns, north arcade walls"),
    ("compare --error-scale 0", 2, "error_scale must be a finite number in (0,"),
    ("compare --iterations 2,x", 2, "got 'x'"),
    ("compare --cascades 9", 2, "cascades must be a whole number in [1, 4]"),
    ("compare --size 8192x8192 --rsm-size 4096", 2, "the reference would gather"),
    ("compare --scene nosuch --out {tmp}/cmp", 2, "no built-in scene or mesh file"),
    ("compare --out {tmp}/afile", 2, "is a file, not a folder"),
    ("compare --out {tmp}/afile/sub", 2, "cannot make the folder"),
    # bench
    ("bench --grids 1000", 2, "grid_size must be a whole number in [1, 256]"),
    ("bench --grids 8,x", 2, "got 'x'"),
    ("bench --repeat 0", 2, "repeat must be a whole number in [1, 1000]"),
    ("bench --peak-gbs nan", 2, "peak_gbs must be a finite number"),
    ("bench --format rgba8", 2, "grid_format must be one of 'rgba32f', 'rgba16f'"),
    ("bench --variants sparkle", 2, "variants must be 'none' or a comma list"),
    ("bench --json {tmp}/adir", 2, "is a folder"),
    ("bench --json {tmp}/x.txt", 2, "this command writes .json, not '.txt'"),
    ("bench --json {tmp}/afile/x.json", 2, "cannot make the folder"),
    # run: refused before any window opens
    ("run --lesson nosuch", 2, "no lesson 'nosuch'"),
    ("run --scene nosuch", 2, "no built-in scene or mesh file named 'nosuch'"),
    ("run --scene {tmp}/corrupt.glb", 2, "corrupt.glb: not a GLB file (no glTF magic)"),
    ("run --size 100000x100000", 2, "window size must be [width, height], whole numbers in "
                                    "[150, 8192]"),
    ("run --size huge", 2, "size must look like 512x512"),
    ("run --frames 0", 2, "frames must be a whole number in [1,"),
    ("run --compare quad", 2, "invalid choice: 'quad'"),
    ("run --screenshot {tmp}/adir", 2, "is a folder"),
    ("run --screenshot {tmp}/x.xyz", 2, "not '.xyz'"),
    ("run --screenshot {tmp}/afile/x.png", 2, "cannot make the folder"),
    # lessons, constants, doctor
    ("lessons --dir /nonexistent", 2, "--dir /nonexistent: no such folder"),
    ("lessons --dir {tmp}/adir", 1, "no lessons (*.toml files) in"),
    ("lessons nosuch", 2, "no lesson 'nosuch'"),
    ("constants --name nosuch", 2, "no derivation result named 'nosuch'"),
    ("doctor --bogus", 2, "unrecognized arguments: --bogus"),
    ("no-such-command", 2, "invalid choice: 'no-such-command'"),
]


@pytest.fixture
def places(tmp_path):
    (tmp_path / "afile").write_text("a file where a folder is expected")
    (tmp_path / "adir").mkdir()
    (tmp_path / "corrupt.glb").write_bytes(b"not a glb file at all")
    return tmp_path


def _one_error_line(err: str, command: str) -> str:
    lines = [line for line in err.splitlines() if line.strip()]
    assert len(lines) == 1, f"expected one line on stderr, got:\n{err}"
    assert "Traceback" not in err
    prefix = "lpv-explorer" if command not in ("render", "compare", "bench", "run", "lessons",
                                               "constants", "doctor") else \
        f"lpv-explorer {command}"
    assert lines[0].startswith(f"{prefix}: error: "), lines[0]
    return lines[0]


@pytest.mark.parametrize("command, code, message", BAD, ids=[case[0] for case in BAD])
def test_bad_input_is_one_line_and_an_exit_code(places, capsys, command, code, message):
    before = sorted(places.rglob("*"))
    args = command.format(tmp=places).split()
    assert main(args) == code
    captured = capsys.readouterr()
    line = _one_error_line(captured.err, args[0])
    assert message in line
    assert sorted(places.rglob("*")) == before, "a refused command left files behind"


def test_a_broken_lesson_is_reported_with_its_own_error(tmp_path, capsys, monkeypatch):
    good = next(iter(sorted((ROOT / "lessons").glob("*.toml"))))
    (tmp_path / good.name).write_text(good.read_text(encoding="utf-8"), encoding="utf-8")
    (tmp_path / "40-broken.toml").write_text('id = "broken"\ntitle = "t"\nsummary = "s"\n'
                                             '[[steps]]\ntitle = "a"\ntext = "b"\n'
                                             '[steps.settings]\ngrid_size = 100000\n')
    monkeypatch.setattr("explorer.lessons.reader.lesson_dir", lambda: tmp_path)
    for command in (["render", "--lesson", "broken"], ["run", "--lesson", "40"],
                    ["lessons", "40-broken"]):
        assert main(command) == 2
        line = _one_error_line(capsys.readouterr().err, command[0])
        assert "lesson" in line and "is broken" in line and "40-broken.toml" in line
        assert "grid_size must be a whole number in [1, 256], got 100000" in line


@pytest.mark.parametrize("command, message", [
    ("render --iterations 1000000 --grid 8", "iterations must be a whole number"),
    ("compare --min-distance inf", "min_distance must be a finite number"),
    ("run --size 100000x100000", "whole numbers in [150, 8192]"),
    ("lessons --dir /nonexistent", "no such folder"),
    ("constants --name nosuch", "no derivation result named 'nosuch'"),
])
def test_no_traceback_reaches_the_terminal(command, message):
    done = subprocess.run([sys.executable, "-m", "explorer", *command.split()], cwd=ROOT,
                          capture_output=True, text=True, timeout=120)
    assert done.returncode == 2
    assert message in _one_error_line(done.stderr, command.split()[0])


def test_ctrl_c_ends_with_130_one_line_and_no_partial_output(tmp_path):
    """A real SIGINT during a long compare (the largest reference the bound allows): exit
    130, one line, and the output folder made at the start is removed again."""
    out = tmp_path / "cmp"
    child = subprocess.Popen(
        [sys.executable, "-m", "explorer", "compare", "--size", "1024x1024", "--rsm-size",
         "128", "--grid", "8", "--iterations", "2", "--out", str(out)],
        cwd=ROOT, stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True)
    deadline = time.monotonic() + 120
    while not out.exists() and child.poll() is None and time.monotonic() < deadline:
        time.sleep(0.05)
    assert out.is_dir(), "the output folder is made before the work starts"
    time.sleep(1.0)
    child.send_signal(signal.SIGINT)
    _, err = child.communicate(timeout=120)
    assert child.returncode == 130
    assert err.strip() == "lpv-explorer compare: interrupted"
    assert not out.exists()


def test_an_interrupted_render_removes_the_views_it_wrote(tmp_path, capsys, monkeypatch):
    def interrupt():
        raise KeyboardInterrupt

    monkeypatch.setattr(StandInPipeline, "on_second_view", staticmethod(interrupt))
    monkeypatch.setattr("explorer.lpv.pipeline.Pipeline", StandInPipeline)
    out = tmp_path / "new" / "frame.png"
    assert main(["render", "--out", str(out), "--view", "final", "--view", "direct"]) == 130
    captured = capsys.readouterr()
    assert "wrote" in captured.out                    # the first view was written ...
    assert captured.err.strip() == "lpv-explorer render: interrupted"
    assert not (tmp_path / "new").exists()            # ... and removed with its folder


def test_outputs_write_whole_files_and_clean_up_on_failure(tmp_path):
    with pytest.raises(RuntimeError):
        with Outputs() as outputs:
            folder = outputs.folder(tmp_path / "a" / "b")
            outputs.write(folder / "one.txt", lambda p: p.write_text("1"))
            assert not (folder / "one.txt").exists()      # renamed in when all is done

            def half(path):
                path.write_text("half")
                raise RuntimeError("disk full")

            outputs.write(folder / "two.txt", half)
    assert list(tmp_path.iterdir()) == [], "written files, partials and made folders remain"
    with Outputs() as outputs:
        kept = outputs.write(outputs.file(tmp_path / "x.png"), lambda p: p.write_bytes(b"png"))
    assert kept.read_bytes() == b"png" and sorted(p.name for p in tmp_path.iterdir()) == [
        "x.png"]


class _Terminal:
    def __init__(self, tty: bool) -> None:
        self.tty, self.text = tty, ""

    def isatty(self) -> bool:
        return self.tty

    def write(self, text: str) -> None:
        self.text += text

    def flush(self) -> None:
        pass


def test_progress_draws_a_bar_on_a_terminal_and_nothing_when_piped():
    clock = [0.0]
    terminal = _Terminal(tty=True)
    progress = Progress("render", terminal, clock=lambda: clock[0], width=10)
    # the pipeline's callback: progress(stage, done, total), propagation steps included
    progress("rsm", 0, 1)
    assert terminal.text.endswith("render: rsm [..........]   0% (0/1)")
    clock[0] = 0.01
    progress("rsm", 0, 1)
    progress("propagate", 3, 16)          # a new stage: drawn at once
    assert terminal.text.endswith("render: propagate [#.........]  18% (3/16)")
    clock[0] = 0.02
    progress("propagate", 5, 16)          # within the interval: not redrawn
    assert "(5/16)" not in terminal.text
    clock[0] = 0.5
    progress("propagate", 8, 16)
    assert terminal.text.endswith("render: propagate [#####.....]  50% (8/16)")
    progress("propagate", 16, 16)         # the end of a stage is always drawn
    assert terminal.text.endswith("[##########] 100% (16/16)")
    assert progress.fraction("reference")(0.25) is True
    assert "reference [##........]  25%" in terminal.text   # a new stage: drawn at once
    progress.close()
    assert terminal.text.endswith("\r")
    last = terminal.text.rsplit("\r", 2)[-2]
    assert last.strip() == "", "close() blanks the bar's line"

    piped = _Terminal(tty=False)
    with Progress("render", piped) as quiet:
        quiet("propagate", 1, 2)
        quiet.fraction("reference")(0.5)
    assert piped.text == ""


def test_run_pipeline_draws_the_stages_and_prints_each_warning_once(gl_context):
    """options.run_pipeline hands the bar to Pipeline.run (progress per stage) and prints
    FrameResult.warnings on stderr, piped or not, each text once per command."""
    from explorer.commands.options import run_pipeline
    from explorer.lpv.pipeline import Pipeline

    # the published injection alone: the flux grows ×π per step (a numeric guard warns)
    growing = Settings(grid_size=8, iterations=4, rsm_size=16, width=24, height=16,
                       corrections=Corrections(injection_pi=False))
    terminal, piped = _Terminal(tty=True), _Terminal(tty=False)
    with Pipeline(growing, ctx=gl_context) as pipeline:
        bar = Progress("render", terminal, interval=0.0)
        result = run_pipeline(pipeline, growing, bar)
        assert any(w.startswith("the flux grows") for w in result.warnings)
        for stage in ("rsm", "inject", "propagate", "gather", "display"):
            assert f"render: {stage} [" in terminal.text
        assert terminal.text.count("lpv-explorer render: warning: the flux grows") == 1
        run_pipeline(pipeline, growing, bar)                # the same warning: not again
        assert terminal.text.count("lpv-explorer render: warning: the flux grows") == 1
        quiet = Progress("compare", piped)
        run_pipeline(pipeline, growing.with_changes(iterations=5), quiet)
    # piped: no bar, but the warnings
    lines = piped.text.splitlines()
    assert lines and all(line.startswith("lpv-explorer compare: warning: ") for line in lines)
    assert any("the flux grows" in line for line in lines)


def test_every_flagged_setting_is_an_option_and_reaches_the_settings():
    from explorer.cli import build_parser

    parser = build_parser()
    args = parser.parse_args(
        ["render", "--grid", "16", "--iterations", "0", "--rsm-size", "64", "--downsample",
         "average", "--downsample-factor", "4", "--injection-mode", "compute",
         "--geometry-volume", "one-sided", "--grid-format", "rgba16f", "--sh-order", "2",
         "--cascades", "2", "--cascade-extent", "2.5", "--cascade-focus", "0.5",
         "--cascade-iterations", "same-distance", "--exposure", "2", "--indirect-only",
         "--debug-nan", "--injection-offset", "0", "--gather-damping", "--bounces", "2",
         "--scene", "room", "--size", "64x32", "--preset", "original", "--spot-cone",
         "--cone-angles", "30,60", "--shadow-kernel", "5", "--tone-map", "linear-clip",
         "--no-auto-exposure"])
    expected = Settings(grid_size=16, iterations=0, rsm_size=64, downsample="average",
                        downsample_factor=4, injection_mode="compute",
                        geometry_volume="one-sided", grid_format="rgba16f", sh_order=2,
                        cascades=2, cascade_extent=2.5, cascade_focus=0.5,
                        cascade_iterations="same-distance", exposure=2.0, indirect_only=True,
                        debug_nan=True, injection_offset_cells=0.0, gather_damping=True,
                        bounces=2, scene="room", width=64, height=32,
                        corrections=PRESETS["original"], spot_cone=True,
                        spot_cone_degrees=(30.0, 60.0), shadow_kernel=5,
                        tone_map="linear-clip", auto_exposure=False)
    assert settings_from_args(args) == expected
    flagged = {spec.flag for spec in specs(Settings).values() if spec.flag}
    help_text = parser.command_parsers["render"].format_help()
    for flag in flagged:
        assert flag in help_text
    assert "a whole number in [1, 256]" in help_text          # ranges come from the specs
    assert settings_from_args(parser.parse_args(["render"])) == Settings()


def test_gl_refusing_a_framebuffer_is_one_line_and_exit_1(tmp_path, capsys, monkeypatch):
    """A driver with less memory than the schema's largest sizes assume: moderngl's own
    error (e.g. an incomplete framebuffer) ends the command in one line, exit 1."""
    import moderngl

    class Refusing(StandInPipeline):
        def run(self, settings=None, **options):
            raise moderngl.Error("framebuffer is not complete")

    monkeypatch.setattr("explorer.lpv.pipeline.Pipeline", Refusing)
    out = tmp_path / "big" / "frame.png"
    assert main(["render", "--size", "8192x8192", "--out", str(out)]) == 1
    line = _one_error_line(capsys.readouterr().err, "render")
    assert line == "lpv-explorer render: error: framebuffer is not complete"
    assert not (tmp_path / "big").exists()
