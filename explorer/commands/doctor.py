"""``lpv-explorer doctor``: what this machine's OpenGL offers and what the LPV needs.

Opens a headless EGL context (``explorer.gl.context``) without insisting on GL 4.3, so a
too-old driver is reported rather than refused, and lists vendor, renderer, GL version,
compute shader support and the largest 3D texture. Then checks whether a window can be
opened (``DISPLAY``/``WAYLAND_DISPLAY`` set and glfw initialises). Exit status 0 when the
headless renderer works (a missing display only disables the window), 1 when it does not;
each problem comes with what to install or set.
"""

from __future__ import annotations

import argparse
import json
import os
import platform
import sys
from dataclasses import asdict, dataclass, field

PROBE_GL = 330
"""Lowest core version asked for, so older drivers still report what they have."""
LARGEST_GRID = 128

_HEADLESS_HELP = (
    "Headless rendering needs EGL and Mesa (or a GPU driver). On Debian/Ubuntu: "
    "sudo apt-get install -y libegl1 libegl-mesa0 libgl1-mesa-dri ; on Fedora: "
    "sudo dnf install mesa-libEGL mesa-dri-drivers. Mesa's llvmpipe software renderer "
    "gives OpenGL 4.5 without a GPU."
)
_VERSION_HELP = (
    "The LPV passes need OpenGL 4.3 core (compute shaders, image load/store). Update the "
    "GPU driver, or use Mesa's llvmpipe (Mesa >= 20 offers 4.5): "
    "LIBGL_ALWAYS_SOFTWARE=1 selects it."
)
_DISPLAY_HELP = (
    "No window can be opened, so `lpv-explorer run` will not start; the headless commands "
    "(render, bench, compare, constants, lessons) still work. For a virtual display: "
    "xvfb-run -a lpv-explorer run"
)


@dataclass
class Report:
    """Everything doctor found (``--json`` prints it)."""

    python: str = platform.python_version()
    moderngl: str | None = None
    headless_ok: bool = False
    headless_error: str | None = None
    vendor: str | None = None
    renderer: str | None = None
    gl_version: str | None = None
    gl_version_code: int | None = None
    compute_shaders: bool | None = None
    max_3d_texture_size: int | None = None
    max_draw_buffers: int | None = None
    missing: list[str] = field(default_factory=list)
    software_renderer: bool | None = None
    display_variable: str | None = None
    glfw_ok: bool = False
    glfw_error: str | None = None
    advice: list[str] = field(default_factory=list)

    @property
    def ok(self) -> bool:
        return self.headless_ok and not self.missing


def add_arguments(parser: argparse.ArgumentParser) -> None:
    parser.add_argument("--json", action="store_true", help="print the findings as JSON")
    parser.add_argument("--no-window-check", action="store_true",
                        help="skip the glfw/display check (e.g. over ssh)")


def _open_context():
    """The context factory (tests replace it); raises ``GLUnavailableError``."""
    from explorer.gl.context import create_headless_context

    return create_headless_context(require=PROBE_GL, check=False)


def check_headless(report: Report) -> None:
    from explorer.gl.context import GLUnavailableError, probe, release_headless_context

    try:
        import moderngl

        report.moderngl = moderngl.__version__
    except ImportError as exc:  # pragma: no cover - a broken install
        report.headless_error = f"moderngl cannot be imported: {exc}"
        report.advice.append("pip install moderngl (or reinstall lpv-explorer)")
        return
    try:
        ctx = _open_context()
    except GLUnavailableError as exc:
        report.headless_error = str(exc)
        report.advice.append(_HEADLESS_HELP)
        return
    try:
        caps = probe(ctx)
    finally:
        release_headless_context(ctx)
    report.headless_ok = True
    report.vendor, report.renderer = caps.vendor, caps.renderer
    report.gl_version, report.gl_version_code = caps.version, caps.version_code
    report.compute_shaders = caps.compute_shaders
    report.max_3d_texture_size = caps.max_3d_texture_size
    report.max_draw_buffers = caps.max_draw_buffers
    report.missing = list(caps.missing)
    from explorer.lpv.timing import SOFTWARE_RENDERERS

    report.software_renderer = any(word in caps.renderer.lower()
                                   for word in SOFTWARE_RENDERERS)
    if report.missing:
        report.advice.append(_VERSION_HELP)
    if 0 < caps.max_3d_texture_size < LARGEST_GRID:
        report.advice.append(f"3D textures are limited to {caps.max_3d_texture_size}³: keep "
                             f"grid_size at or below that.")


def check_window(report: Report) -> None:
    for variable in ("WAYLAND_DISPLAY", "DISPLAY"):
        if os.environ.get(variable):
            report.display_variable = f"{variable}={os.environ[variable]}"
            break
    if report.display_variable is None:
        report.glfw_error = "neither DISPLAY nor WAYLAND_DISPLAY is set"
        report.advice.append(_DISPLAY_HELP)
        return
    try:
        # isort: off
        import imgui_bundle  # noqa: F401  (points pyglfw at the GLFW it bundles)
        import glfw
        # isort: on
    except ImportError as exc:
        report.glfw_error = f"glfw cannot be imported: {exc}"
        report.advice.append("pip install glfw imgui-bundle (or reinstall lpv-explorer)")
        return
    previous = getattr(glfw, "ERROR_REPORTING", None)
    glfw.ERROR_REPORTING = "ignore"
    try:
        report.glfw_ok = bool(glfw.init())
        if report.glfw_ok:
            glfw.terminate()
        else:
            report.glfw_error = f"glfw could not connect to {report.display_variable}"
            report.advice.append(_DISPLAY_HELP)
    finally:
        if previous is not None:
            glfw.ERROR_REPORTING = previous


def _yes_no(flag: bool | None) -> str:
    return "?" if flag is None else ("yes" if flag else "NO")


def render_text(report: Report) -> str:
    lines = [f"Python {report.python}, moderngl {report.moderngl or '?'}", ""]
    lines.append("Headless OpenGL (EGL):")
    if not report.headless_ok:
        lines.append(f"  NOT AVAILABLE: {report.headless_error}")
    else:
        lines += [
            f"  vendor:             {report.vendor}",
            f"  renderer:           {report.renderer}"
            + ("  (software)" if report.software_renderer else ""),
            f"  GL version:         {report.gl_version}",
            f"  compute shaders:    {_yes_no(report.compute_shaders)}",
            f"  max 3D texture:     {report.max_3d_texture_size}",
            f"  max draw buffers:   {report.max_draw_buffers}",
        ]
        if report.missing:
            lines.append("  MISSING: " + "; ".join(report.missing))
        else:
            lines.append("  everything the LPV needs is there")
    lines += ["", "Window (glfw):"]
    if report.glfw_ok:
        lines.append(f"  available ({report.display_variable})")
    elif report.glfw_error is None:
        lines.append("  not checked")
    else:
        lines.append(f"  not available: {report.glfw_error}")
    if report.advice:
        lines += ["", "What to do:"] + [f"  - {advice}" for advice in report.advice]
    lines += ["", "Result: " + ("OK" if report.ok else "the LPV cannot run on this machine")]
    return "\n".join(lines)


def main(args: argparse.Namespace) -> int:
    report = Report()
    check_headless(report)
    if not getattr(args, "no_window_check", False):
        check_window(report)
    if getattr(args, "json", False):
        data = asdict(report)
        data["ok"] = report.ok
        print(json.dumps(data, indent=2))
    else:
        print(render_text(report))
    sys.stdout.flush()
    return 0 if report.ok else 1
