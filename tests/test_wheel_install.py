"""Install as users install: build the wheel, install it into a fresh venv (no
``--system-site-packages``: its dependencies come from the package index, as a user's do),
and from outside the checkout (so shaders and lessons must come from the installed
package) render headless and open the window under the display pytest-xvfb provides,
checking that neither picture is blank.

Slow (a wheel build, a venv, the dependencies downloaded once per session: about 1.5
minutes on the 2-core VM, most of it pip): marked ``install``, ``-m "not install"`` leaves
it out of a quick local run. It skips, saying why, when the package index cannot be
reached."""

from __future__ import annotations

import os
import shutil
import subprocess
import sys
import venv
from pathlib import Path

import numpy as np
import pytest
from PIL import Image
from window_cases import display_problem

ROOT = Path(__file__).resolve().parents[1]
SOURCE_FILES = ("pyproject.toml", "setup.py", "README.md", "explorer", "derivations",
                "shaders", "lessons")
"""What the wheel is built from (the package's sources and the files setup reads)."""
pytestmark = pytest.mark.install


def _run(command: list[str], cwd: Path, env: dict, timeout: float) -> subprocess.CompletedProcess:
    proc = subprocess.run(command, cwd=cwd, env=env, capture_output=True, text=True,
                          timeout=timeout)
    assert proc.returncode == 0, f"{command[:3]}... failed:\n{proc.stdout}\n{proc.stderr}"
    return proc


OFFLINE = ("No matching distribution", "Could not find a version", "Failed to establish",
           "Temporary failure in name resolution")
"""What pip prints when the package index cannot be reached."""


def _skip_when_offline(proc: subprocess.CompletedProcess, what: str) -> None:
    if proc.returncode != 0 and any(text in proc.stderr + proc.stdout for text in OFFLINE):
        pytest.skip(f"{what} could not be fetched from the package index: "
                    f"{proc.stderr.strip()[-200:]}")


@pytest.fixture(scope="module")
def installed(tmp_path_factory):
    """``(venv bin folder, a folder outside the checkout, environment)`` with the wheel of
    this checkout installed into a fresh venv."""
    base = tmp_path_factory.mktemp("wheel")
    (base / "source").mkdir()
    # PYGLFW_LIBRARY: explorer.gl.window points pyGLFW at this venv's imgui_bundle glfw
    # once imported in this process; the fresh venv must load its own (two glfw libraries
    # in one process: imgui's backend sees no window and draws nothing)
    env = {k: v for k, v in os.environ.items()
           if not k.startswith(("PYTHON", "VIRTUAL_ENV", "PYGLFW_"))}
    env["PIP_CACHE_DIR"] = str(base / "pip-cache")
    # build from a copy of what a source distribution holds: setuptools writes build/ and
    # *.egg-info next to the sources, which must not litter the checkout
    source = base / "source"
    for name in SOURCE_FILES:
        shutil.copy2(ROOT / name, source / name) if (ROOT / name).is_file() else \
            shutil.copytree(ROOT / name, source / name,
                            ignore=shutil.ignore_patterns("__pycache__", "*.pyc"))
    wheels = base / "dist"
    built = subprocess.run([sys.executable, "-m", "pip", "wheel", str(source), "--no-deps",
                            "-w", str(wheels), "-q"], env=env, capture_output=True, text=True,
                           timeout=600)
    _skip_when_offline(built, "the build backend (setuptools, wheel)")
    assert built.returncode == 0, built.stderr
    wheel, = wheels.glob("lpv_explorer-*.whl")
    target = base / "venv"
    venv.EnvBuilder(with_pip=False).create(target)       # pip runs from outside it
    python = target / "bin" / "python"
    # --no-compile: no bytecode written ahead for the ~2 900 modules of the dependencies
    # (sympy alone 1 500): about 10 s of this file's 32 s of CPU time on the 2-core VM;
    # what the tests import is compiled as it is imported (pip's compile step fails no
    # install anyway, so it checks nothing)
    proc = subprocess.run([sys.executable, "-m", "pip", "--python", str(python), "install",
                           "-q", "--no-compile", str(wheel)], env=env, capture_output=True,
                          text=True, timeout=900)
    _skip_when_offline(proc, "the dependencies")
    assert proc.returncode == 0, proc.stderr
    outside = base / "elsewhere"
    outside.mkdir()
    env["XDG_CONFIG_HOME"] = str(base / "config")
    env["XDG_CACHE_HOME"] = str(base / "cache")
    return target / "bin", outside, env


def test_the_wheel_holds_every_package_and_resource(installed):
    bin_folder, outside, env = installed
    proc = _run([str(bin_folder / "python"), "-c",
                 "import explorer, explorer.resources as r, pkgutil;"
                 "print(explorer.__file__); print(r.shader_dir()); print(r.lesson_dir());"
                 "print(len([m for m in pkgutil.walk_packages(explorer.__path__, 'explorer.')"
                 " if m.ispkg]))"], outside, env, 120)
    module, shaders, lessons, packages = proc.stdout.split()
    assert "site-packages" in module and str(ROOT) not in module
    assert Path(shaders, "gather.glsl").is_file() and Path(shaders, "generated",
                                                            "constants.glsl").is_file()
    assert sorted(p.name for p in Path(lessons).glob("*.toml")) == sorted(
        p.name for p in (ROOT / "lessons").glob("*.toml"))
    ours = [p for p in (ROOT / "explorer").rglob("__init__.py") if "__pycache__" not in p.parts]
    assert int(packages) >= len(ours) - 1        # every package of explorer/ but itself
    _run([str(bin_folder / "python"), "-c", "import explorer.ui.overlays, derivations.porting"],
         outside, env, 120)
    # the site's assets, the generated ES module of constants included
    proc = _run([str(bin_folder / "python"), "-c",
                 "from importlib.resources import files; a = files('explorer.site') / 'assets';"
                 "print(*sorted(p.relative_to(a).as_posix() for p in __import__('pathlib')"
                 ".Path(str(a)).rglob('*.js')))"], outside, env, 120)
    shipped = sorted(p.relative_to(ROOT / "explorer" / "site" / "assets").as_posix()
                     for p in (ROOT / "explorer" / "site" / "assets").rglob("*.js"))
    assert "generated/constants.js" in shipped and proc.stdout.split() == shipped


def test_installed_render_is_lit(installed):
    bin_folder, outside, env = installed
    out = outside / "render.png"
    _run([str(bin_folder / "lpv-explorer"), "render", "--scene", "cornell", "--size", "64x48",
          "--rsm-size", "16", "--grid", "8", "--iterations", "2", "--out", str(out)],
         outside, env, 300)
    pixels = np.asarray(Image.open(out).convert("RGB"), np.float64)
    assert pixels.mean() > 20 and pixels.std() > 5           # lit, not a blank picture


def test_installed_window_opens_and_draws(installed):
    problem = display_problem()
    if problem:
        pytest.skip(problem)
    bin_folder, outside, env = installed
    shot = outside / "window.png"
    proc = _run([str(bin_folder / "lpv-explorer"), "run", "--no-persist", "--size",
                 "800x600", "--scene", "cornell",
                 "--screenshot", str(shot), "--frames", "4"], outside, env, 300)
    image = np.asarray(Image.open(shot).convert("RGB"), np.float64)
    assert image.shape == (600, 800, 3)
    assert image.std() > 10, proc.stdout + proc.stderr        # panels and a picture
    assert len(np.unique(image.reshape(-1, 3), axis=0)) > 200  # not a flat fill
