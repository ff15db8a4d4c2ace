"""Writing a lesson of one's own (docs/AUTHORING.md): the guide is what its registries
make and describes every key the loader reads; the lesson written from its example
alone loads, renders, checks and builds into a small site; ``lessons new`` starts one
and never replaces a file; every command reads the folder ``--lessons``/``--dir`` names;
``--check`` prints a failing claim with its numbers and ``--lint`` finds what the shipped
course is held to; errors name the line of their key; a lesson names a scene file beside
itself."""

from __future__ import annotations

import re
import subprocess
import sys
from pathlib import Path

import pytest

from explorer.cli import main
from explorer.lessons import LessonError, guide, load_lesson
from explorer.lessons.folder import load_course
from explorer.lessons.reader import format_keys
from explorer.lessons.where import line_of

ROOT = Path(__file__).resolve().parents[2]
GUIDE_TEXT = (ROOT / "docs" / "AUTHORING.md").read_text(encoding="utf-8")


def guide_example() -> str:
    """The guide's example lesson, as a reader copies it from the page."""
    match = re.search(r"<!-- generated: example -->\n```toml\n(.*?)```", GUIDE_TEXT, re.S)
    assert match, "docs/AUTHORING.md has no example lesson"
    return match.group(1)


@pytest.fixture
def folder(tmp_path) -> Path:
    """A teacher's folder holding the guide's example lesson."""
    mine = tmp_path / "my-lessons"
    mine.mkdir()
    (mine / "01-first-light.toml").write_text(guide_example(), encoding="utf-8")
    return mine


def test_the_guide_is_what_the_registries_make():
    assert not guide.stale(), f"docs/AUTHORING.md is stale: run {guide.REGENERATE}"
    stale = guide.render(GUIDE_TEXT.replace("| `audit.injected` |", "| `audit.nope` |"))
    assert stale != GUIDE_TEXT.replace("| `audit.injected` |", "| `audit.nope` |")
    with pytest.raises(ValueError, match="no place for"):
        guide.render(GUIDE_TEXT.replace("<!-- end: figure-kinds -->", ""))


GUIDE_SECTIONS = {"lesson": "## The lesson's keys", "steps": "## A step's keys",
                  "camera": "## A step's keys", "light": "## A step's keys",
                  "steps.try_this": "## Try this", "steps.try_this.predict": "### Predictions",
                  "steps.figures": "## Figures", "steps.marks": "## Marks",
                  "steps.checks": "## Checks", "glossary terms": "## The glossary"}
"""Where the guide describes each table of :func:`format_keys`."""


def guide_section(heading: str) -> str:
    """The guide's text under ``heading``, up to the next heading of any level."""
    parts = re.split(r"^(#{2,4} .*)$", GUIDE_TEXT, flags=re.M)
    return dict(zip(parts[1::2], parts[2::2]))[heading]


def test_the_guide_describes_every_key_and_name():
    from explorer.figure_params import FIGURE_KINDS, schema
    from explorer.lessons import live_values
    from explorer.lessons.model import TRY_COMPARES
    from explorer.lessons.text import MARKERS

    # each key in its own table's section: a row of its table, or (a camera's eye, a
    # light's position) named in the row of the key that holds it
    missing = [f"{table}: {key}" for table, keys in format_keys().items() for key in keys
               if f"`{key}`" not in guide_section(GUIDE_SECTIONS[table])]
    assert not missing, missing
    rows = [f"{table}: {key}" for table, keys in format_keys().items() for key in keys
            if table not in ("camera", "light")
            and f"| `{key}` |" not in guide_section(GUIDE_SECTIONS[table])]
    assert not rows, rows
    dialect = guide_section("## The prose dialect")
    assert not [name for name in MARKERS if "{{" + name not in dialect]
    assert all(f"`{mode}`" in guide_section("## Try this") for mode in TRY_COMPARES)
    names = [name for name in live_values.table() if f"`{name}`" not in GUIDE_TEXT]
    assert not names, names
    for kind in FIGURE_KINDS:
        assert f"#### `{kind.name}`" in GUIDE_TEXT
        assert all(f"| `{info.name}` |" in GUIDE_TEXT for info in schema(kind.params))


def test_the_guides_example_loads_renders_checks_and_builds_a_site(folder, ctx, tmp_path):
    import numpy as np

    from explorer.lessons import preview_settings, render_step
    from explorer.lessons.verify import verify_step
    from explorer.lpv.pipeline import Pipeline
    from explorer.ui.figures import declared_readouts

    lesson = load_lesson(folder / "01-first-light.toml")
    assert lesson.id == "first-light" and len(lesson.steps) == 2
    first, second = lesson.steps
    assert first.figures and first.marks and first.checks
    assert second.try_this and second.try_this[0].predict is not None
    outcomes = []
    with Pipeline(preview_settings(first), ctx=ctx) as pipeline:
        for step in lesson.steps:
            image, result = render_step(pipeline, step, preview_settings(step, size=48))
            assert image.shape[2] == 3 and np.isfinite(image).all() and image.max() > 0.05
            assert result.settings.grid_size == 16
            outcomes += verify_step(pipeline, step, figure_readouts=declared_readouts)
    assert len(outcomes) == 2 and all(o.holds for o in outcomes), [str(o) for o in outcomes]

    out = tmp_path / "class-site"
    done = subprocess.run([sys.executable, "-m", "explorer", "site", str(out), "--lessons",
                           str(folder), "--size", "96x64", "--figure-width", "240"],
                          cwd=ROOT, capture_output=True, text=True, timeout=600)
    assert done.returncode == 0, done.stdout + done.stderr
    page = (out / "01-first-light.html").read_text(encoding="utf-8")
    assert "One cell per step" in page and "The bounce of light" in page
    index = (out / "index.html").read_text(encoding="utf-8")
    assert "First light" in index and "overview" not in index   # the folder alone


def test_lessons_new_starts_a_lesson_and_never_replaces_one(tmp_path, capsys):
    mine = tmp_path / "mine"
    assert main(["lessons", "new", "First light", "--dir", str(mine)]) == 0
    path = mine / "01-first-light.toml"
    assert path.read_text(encoding="utf-8") == guide_example()   # the guide's example
    assert "run --lessons" in capsys.readouterr().out
    assert main(["lessons", "new", "Second", "--dir", str(mine)]) == 0
    assert load_lesson(mine / "02-second.toml").title == "Second"
    assert main(["lessons", "new", 'Über "it" \\', "--dir", str(mine)]) == 0
    odd = load_lesson(mine / "03-uber-it.toml")
    assert (odd.id, odd.title) == ("uber-it", 'Über "it" \\')
    (mine / "03-uber-it.toml").unlink()
    path.write_text("keep me")
    assert main(["lessons", "new", "First light", "--dir", str(mine)]) == 2
    assert "already" in capsys.readouterr().err and path.read_text() == "keep me"
    assert main(["lessons", "new", "!!!", "--dir", str(mine)]) == 2
    assert main(["lessons", "new", "--dir", str(mine)]) == 2
    assert sorted(p.name for p in mine.iterdir()) == ["01-first-light.toml", "02-second.toml"]


def test_every_lessons_verb_reads_the_folder(folder, tmp_path, capsys):
    assert main(["lessons", "--lessons", str(folder)]) == 0
    listed = capsys.readouterr().out
    assert "first-light" in listed and "overview" not in listed
    assert main(["lessons", "--dir", str(folder), "1"]) == 0
    assert "One cell per step" in capsys.readouterr().out
    assert main(["lessons", "--check", str(folder)]) == 0
    assert "2 of 2 checks hold on 2 steps" in capsys.readouterr().out
    assert main(["lessons", "first-light", "--dir", str(folder), "--check"]) == 0
    assert "2 of 2 checks hold" in capsys.readouterr().out
    png = tmp_path / "step.png"
    assert main(["lessons", "--dir", str(folder), "--export", "first-light", "--step", "2",
                 "--size", "640x400", "--out", str(png)]) == 0
    assert png.is_file() and "wrote" in capsys.readouterr().out
    # the folder and the shipped course do not mix
    assert main(["lessons", "--dir", str(folder), "--export", "overview"]) == 2
    assert "no lesson 'overview'" in capsys.readouterr().err
    for argv in (["lessons", "--dir", str(folder), "--lessons", str(tmp_path)],
                 ["lessons", "--check", str(folder), "--dir", str(tmp_path)],
                 ["lessons", "--check", str(tmp_path / "nowhere")],
                 ["run", "--lessons", str(tmp_path / "nowhere")],
                 ["run", "--no-shipped"],
                 ["run", "--lessons", str(folder), "--lesson", "nope"],
                 ["render", "--lessons", str(folder)]):
        assert main(argv) == 2, argv
        err = capsys.readouterr().err
        assert err.count("\n") == 1, (argv, err)


def test_render_draws_a_step_of_the_folder(folder, tmp_path, capsys):
    out = tmp_path / "step.png"
    assert main(["render", "--lesson", "first-light", "--step", "2", "--lessons", str(folder),
                 "--size", "64x48", "--rsm-size", "32", "--out", str(out)]) == 0
    assert "lesson first-light, step 2/2" in capsys.readouterr().out and out.is_file()


def test_check_prints_a_failing_claim_with_its_numbers(folder, capsys):
    path = folder / "01-first-light.toml"
    path.write_text(guide_example().replace("than = 0.1\n", "than = 1000\n"), encoding="utf-8")
    assert main(["lessons", "--check", str(folder)]) == 1
    out = capsys.readouterr().out
    failed = [line for line in out.splitlines() if "FAILS" in line]
    assert len(failed) == 1 and "mark.ceiling.irradiance > 1000" in failed[0], out
    assert re.search(r"measured \d+\.\d+", failed[0]), failed[0]
    assert "1 of 2 checks hold" in out


def test_lint_finds_what_the_course_is_held_to(folder, capsys):
    assert main(["lessons", "--lint", str(folder)]) == 0
    assert "0 findings in 1 lesson (2 steps, 1 figure)" in capsys.readouterr().out
    slips = guide_example().replace(
        "The view shows the indirect light alone.",
        r"The grid_size sets it, and \omega and audit.injected are words here.").replace(
        "at = [0.0, 0.99, -0.3]\nnormal = [0, -1, 0]\n[[steps.try_this]]",
        "at = [-0.34, -0.4, -0.32]\nnormal = [0, -1, 0]\n[[steps.try_this]]")
    (folder / "01-first-light.toml").write_text(slips, encoding="utf-8")
    assert main(["lessons", "--lint", str(folder)]) == 1
    found = capsys.readouterr().out.splitlines()
    words = [line for line in found if line.startswith("words: ")]
    assert any("raw TeX outside math: '\\\\omega'" in line for line in words), found
    assert any("live-quantity name shown as text: 'audit.injected'" in line for line in words)
    assert any("settings field names shown to the learner: grid_size" in line
               for line in words)
    marks = [line for line in found if line.startswith("mark: ")]
    assert marks == ["mark: 01-first-light.toml step 2: mark 'ceiling' is not in view of the "
                     "step's camera"], found


def test_an_error_names_the_line_of_its_key(folder):
    text = guide_example()
    lines = text.splitlines()
    assert line_of(text, None, "settings.grid_size") == lines.index("grid_size = 16") + 1
    assert line_of(text, 2, "try_this[0].value") == lines.index("value = 2") + 1
    assert line_of(text, 1, "figures[0].normal_deg") == lines.index("normal_deg = 30") + 1
    assert line_of(text, 2, "view") == lines.index('view = "indirect"') + 1
    assert line_of(text, 2, "checks[0].than") == lines.index("than = 1") + 1
    assert line_of(text, 1, "nothing") == lines.index("[[steps]]") + 1
    path = folder / "01-first-light.toml"
    path.write_text(text.replace('kind = "clamped-cosine"', 'kind = "nope"'), encoding="utf-8")
    with pytest.raises(LessonError) as caught:
        load_lesson(path)
    assert caught.value.line == lines.index('kind = "clamped-cosine"') + 1
    assert str(caught.value).startswith(f"{path}:{caught.value.line}, step 1")
    # a {{...}} the text gets wrong: the line of the text that holds it, not the key's
    for wrong, right in (("{{frame.cell_size:.3f}}", "{{frame.cellsize:.3f}}"),
                         ("{{try:1}}", "{{try:3}}"),
                         ("gets {{mark.ceiling", "gets {{mark.floor")):
        slip = text.replace(wrong, right)
        path.write_text(slip, encoding="utf-8")
        with pytest.raises(LessonError) as caught:
            load_lesson(path)
        assert caught.value.line == next(number for number, line in
                                         enumerate(slip.splitlines(), 1) if right in line)


SCENE = """builtin = "cornell"

[[lights]]
kind = "spot"
position = [0.0, 1.9, 0.0]
target = [0.0, 0.0, 0.0]
flux = 20.0
"""


def test_a_lesson_names_a_scene_file_beside_itself(folder):
    (folder / "scenes").mkdir()
    (folder / "scenes" / "box.toml").write_text(SCENE, encoding="utf-8")
    path = folder / "01-first-light.toml"
    path.write_text(guide_example().replace('scene = "cornell" ', 'scene = "scenes/box.toml"'),
                    encoding="utf-8")
    lesson = load_lesson(path)
    assert {step.scene for step in lesson.steps} == {str(folder / "scenes" / "box.toml")}
    assert lesson.steps[0].scene_name == "box"
    path.write_text(guide_example().replace('scene = "cornell" ', 'scene = "scenes/no.toml"'),
                    encoding="utf-8")
    with pytest.raises(LessonError, match=r"field 'scene': 'scenes/no.toml' is neither a "
                                          r"built-in scene .* missing"):
        load_lesson(path)


def test_the_window_lists_the_course_and_the_folder_side_by_side(folder):
    from explorer.ui.lesson_list import list_sections

    both = load_course(folder)
    sections = list_sections(both)
    assert [title for title, _ in sections] == ["Your lessons (my-lessons)", "The course"]
    assert [lesson.id for lesson in sections[0][1]] == ["first-light"]
    assert len(sections[1][1]) >= 10 and both.find("1").id == "first-light"
    assert both.find("overview").id == "overview"
    alone = load_course(folder, shipped=False)
    assert [title for title, _ in list_sections(alone)] == ["Your lessons (my-lessons)"]
    (folder / "02-copy.toml").write_text(guide_example().replace('id = "first-light"',
                                                                 'id = "overview"'))
    clash = load_course(folder)
    assert [error.field for error in clash.errors] == ["id"]
    assert "shipped lesson 01-overview.toml" in str(clash.errors[0])
    # a folder's broken lesson is listed under the folder (not below the whole course),
    # and the folder is not called empty while it holds one
    from explorer.ui.lesson_list import list_sections_with_errors

    (folder / "01-first-light.toml").write_text(guide_example().replace(
        'view = "indirect"', 'view = "indirec"'), encoding="utf-8")
    broken = load_course(folder)
    sections = list_sections_with_errors(broken)
    assert [(title, len(lessons), len(errors)) for title, lessons, errors in sections] == [
        ("Your lessons (my-lessons)", 0, 2), ("The course", len(sections[1][1]), 0)]


def _open_box_obj() -> str:
    """An open-fronted box room, 2 m each way, its five walls facing in, as OBJ text."""
    quads = [[(-1, 0, 1), (1, 0, 1), (1, 0, -1), (-1, 0, -1)],       # floor, up
             [(-1, 2, -1), (1, 2, -1), (1, 2, 1), (-1, 2, 1)],       # ceiling, down
             [(-1, 0, -1), (1, 0, -1), (1, 2, -1), (-1, 2, -1)],     # back, +z
             [(-1, 0, 1), (-1, 0, -1), (-1, 2, -1), (-1, 2, 1)],     # left, +x
             [(1, 0, -1), (1, 0, 1), (1, 2, 1), (1, 2, -1)]]         # right, -x
    lines = [f"v {x} {y} {z}" for quad in quads for x, y, z in quad]
    for k in range(len(quads)):
        a = 4 * k + 1
        lines += [f"f {a} {a + 1} {a + 2}", f"f {a} {a + 2} {a + 3}"]
    return "\n".join(lines) + "\n"


def test_a_folder_elsewhere_names_a_scene_file_and_a_mesh_beside_itself(tmp_path, capsys):
    """A teacher's project with lessons/, scenes/ and meshes/ side by side: each command
    reads the scene file and the mesh relative to the lesson (and the scene file's mesh
    relative to the scene file), and the site names the scene in a word, never by the
    teacher's own paths."""
    project = tmp_path / "project"
    for name in ("lessons", "scenes", "meshes"):
        (project / name).mkdir(parents=True)
    (project / "meshes" / "box.obj").write_text(_open_box_obj(), encoding="utf-8")
    (project / "scenes" / "room.toml").write_text(
        'name = "teacher room"\n[[meshes]]\npath = "../meshes/box.obj"\n', encoding="utf-8")
    lessons = project / "lessons"
    ceiling = ("at = [0.0, 0.99, -0.3]", "at = [0.0, 1.99, -0.3]")
    for number, scene in ((1, "../scenes/room.toml"), (2, "../meshes/box.obj")):
        (lessons / f"0{number}-room-{number}.toml").write_text(
            guide_example().replace('id = "first-light"', f'id = "room-{number}"')
            .replace('scene = "cornell" ', f'scene = "{scene}"').replace(*ceiling),
            encoding="utf-8")
    assert main(["lessons", "--check", str(lessons)]) == 0
    assert "4 of 4 checks hold on 4 steps" in capsys.readouterr().out
    png = tmp_path / "step.png"
    assert main(["render", "--lesson", "room-1", "--step", "2", "--lessons", str(lessons),
                 "--size", "64x48", "--rsm-size", "32", "--out", str(png)]) == 0
    assert png.is_file()
    out = tmp_path / "site"
    done = subprocess.run([sys.executable, "-m", "explorer", "site", str(out), "--lessons",
                           str(lessons), "--size", "96x64", "--figure-width", "240"],
                          cwd=ROOT, capture_output=True, text=True, timeout=600)
    assert done.returncode == 0, done.stdout + done.stderr
    pages = {path.name: path.read_text(encoding="utf-8") for path in out.glob("*.html")}
    assert sorted(pages) == ["01-room-1.html", "02-room-2.html", "index.html"]
    assert "of the room scene" in pages["01-room-1.html"]
    assert "of the box scene" in pages["02-room-2.html"]
    leaked = [name for name, page in pages.items() if str(tmp_path) in page]
    assert not leaked, leaked


def test_the_guides_window_and_web_variant_loads_with_both_sides(folder):
    from explorer.lessons.text import for_medium

    snippet = re.search(r"```toml\ntext = '''\n(.*?)'''\n```", guide_section("## Window and web"),
                        re.S)
    assert snippet, "the guide shows no variant"
    path = folder / "01-first-light.toml"
    path.write_text(guide_example().replace("{{figure:lobe}}\n'''",
                                            "{{figure:lobe}}\n\n" + snippet.group(1) + "'''"),
                    encoding="utf-8")
    text = load_lesson(path).steps[0].text
    window, web = for_medium(text, "window"), for_medium(text, "web")
    assert "Drag the normal in the figure" in window and "Move the slider" not in window
    assert "Move the slider under" in web and "Drag the normal" not in web
    path.write_text(guide_example().replace("{{figure:lobe}}\n'''", "{{figure:lobe}}\n\n"
                    + snippet.group(1).replace("{{fig:lobe}}", "{{fig:lob}}") + "'''"),
                    encoding="utf-8")
    with pytest.raises(LessonError, match=r"\{\{fig:lob\}\}: the step has no figure"):
        load_lesson(path)


def test_the_verbs_read_as_words_too(folder, tmp_path, capsys, monkeypatch):
    """What a teacher types, ``lessons list``, ``lessons check my-lessons``, is what the
    flags do."""
    assert main(["lessons", "list", "--dir", str(folder)]) == 0
    listed = capsys.readouterr().out
    assert "first-light" in listed and "overview" not in listed
    assert main(["lessons", "print", "1", "--lessons", str(folder)]) == 0
    assert "One cell per step" in capsys.readouterr().out
    assert main(["lessons", "check", str(folder)]) == 0
    assert "2 of 2 checks hold on 2 steps" in capsys.readouterr().out
    assert main(["lessons", "check", "first-light", "--dir", str(folder)]) == 0
    assert "2 of 2 checks hold" in capsys.readouterr().out
    monkeypatch.chdir(folder.parent)           # a folder named as the teacher sees it
    assert main(["lessons", "lint", folder.name]) == 0
    assert "0 findings in 1 lesson" in capsys.readouterr().out
    png = tmp_path / "step.png"
    assert main(["lessons", "export", "first-light", "--dir", str(folder), "--step", "2",
                 "--size", "640x400", "--out", str(png)]) == 0
    assert png.is_file()
    capsys.readouterr()
    for argv, says in ((["lessons", "list", "first-light"], "lessons print ID"),
                       (["lessons", "print"], "name the lesson"),
                       (["lessons", "export"], "name the lesson"),
                       (["lessons", "check", str(folder), "--lint"], "one verb at a time"),
                       (["lessons", "print", "a", "b"], "one lesson at a time"),
                       (["lessons", "lint", str(tmp_path / "nowhere")], "no such folder"),
                       (["lessons", "new", "List", "--dir", str(folder)], "is a verb")):
        assert main(argv) == 2, argv
        err = capsys.readouterr().err
        assert err.count("\n") == 1 and says in err, (argv, err)


def test_lint_reports_each_rule_from_a_lesson_that_breaks_it(tmp_path, capsys, monkeypatch):
    """One lesson per rule of ``--lint``, each finding naming its own lesson: an internal
    name (a module path, an array's name) in the prose, raw TeX outside math, a mark out
    of view, and a figure past the column (the column narrowed to 60 px: no figure's
    parameters make one wider than the real column, the figures adapt)."""
    import explorer.ui.lesson_lint as lesson_lint

    mine = tmp_path / "rules"
    mine.mkdir()
    prose = "The view shows the indirect light alone."
    slips = {"internal": ("The acc_N array of explorer.lpv.rsm holds it.", None),
             "tex": (r"It falls as \cos\theta with the angle.", None),
             "mark": (prose, ("at = [0.0, 0.99, -0.3]\nnormal = [0, -1, 0]\n[[steps.try_this]]",
                              "at = [-0.34, -0.4, -0.32]\nnormal = [0, -1, 0]\n"
                              "[[steps.try_this]]"))}
    for number, (name, (sentence, swap)) in enumerate(slips.items(), 1):
        text = guide_example().replace('id = "first-light"', f'id = "{name}"')
        text = text.replace(prose, sentence).replace(*(swap or ("", "")))
        (mine / f"0{number}-{name}.toml").write_text(text, encoding="utf-8")
    assert main(["lessons", "lint", str(mine)]) == 1
    found = capsys.readouterr().out.splitlines()
    assert found[-1] == "3 findings in 3 lessons (6 steps, 3 figures)", found
    assert ("words: 01-internal.toml step 2 text: internal identifiers shown to the learner: "
            "acc_N, explorer.lpv.rsm (say what they are in words)") in found, found
    assert any(line.startswith("words: 02-tex.toml step 2 text: raw TeX outside math: "
                               "'\\\\cos'") for line in found), found
    assert ("mark: 03-mark.toml step 2: mark 'ceiling' is not in view of the step's camera"
            in found), found
    monkeypatch.setattr(lesson_lint, "column_width", lambda window_width: 60.0)
    assert main(["lessons", "lint", "tex", "--dir", str(mine)]) == 1
    found = capsys.readouterr().out.splitlines()
    wide = [line for line in found if line.startswith("figure: tex/1/lobe (clamped-cosine) ")]
    assert len(wide) == 2 and all(" px past a 60 px column" in line for line in wide), found


def test_export_of_a_lesson_not_in_the_folder_says_so_before_anything(folder, capsys):
    for argv, said in ((["--export", "overview"], "no lesson 'overview'"),
                       (["--export", "first-light", "--step", "9"], "has steps 1..2, not 9"),
                       (["--export", "first-light", "--try", "7"], "not 7")):
        assert main(["lessons", "--dir", str(folder), *argv]) == 2, argv
        captured = capsys.readouterr()
        assert captured.out == "", (argv, captured.out)
        assert captured.err.count("\n") == 1 and said in captured.err, (argv, captured.err)


def test_check_and_lint_of_a_folder_of_broken_lessons_name_each_and_fail(tmp_path, capsys):
    (tmp_path / "01-a.toml").write_text(guide_example().replace('title = "', 'titel = "', 1),
                                        encoding="utf-8")
    (tmp_path / "02-b.toml").write_text('id = "b"\n[[steps]\n', encoding="utf-8")
    for verb in ("--check", "--lint"):
        assert main(["lessons", "--dir", str(tmp_path), verb]) == 1, verb
        captured = capsys.readouterr()
        assert "2 broken lessons not" in captured.out, captured.out
        broken = [line for line in captured.err.splitlines() if line.startswith("broken")]
        assert len(broken) == 2, captured.err
        assert "01-a.toml" in broken[0] and "'title'" in broken[0]
        assert "02-b.toml:2:" in broken[1]


def test_a_scene_path_that_is_a_symlink_loop_is_one_plain_line(folder, capsys):
    (folder / "loop.obj").symlink_to("loop.obj")
    path = folder / "01-first-light.toml"
    text = guide_example()
    assert 'scene = "cornell"' in text
    path.write_text(text.replace('scene = "cornell"', 'scene = "loop.obj"', 1),
                    encoding="utf-8")
    with pytest.raises(LessonError) as info:
        load_lesson(path)
    said = str(info.value)
    assert "\n" not in said and "Symlink loop" not in said, said
    assert "'loop.obj' is a symbolic link that leads nowhere (a loop" in said, said
    assert str(folder / "loop.obj") in said and f"{path}:" in said, said
    (folder / "02-loop.toml").symlink_to("02-loop.toml")
    assert main(["lessons", "--dir", str(folder)]) == 1
    err = capsys.readouterr().err
    assert "02-loop.toml: is a symbolic link that leads nowhere (a loop)" in err, err
    assert "Too many levels" not in err, err
