"""``lpv-explorer doctor``: a working driver, no EGL, and a too-old driver."""

from __future__ import annotations

import json
import sys
import types

from explorer.cli import main
from explorer.commands import doctor
from explorer.gl.context import GLUnavailableError


class _OldDriver:
    """Looks like a moderngl context on a GL 3.3 driver without compute shaders."""

    version_code = 330
    extensions: set[str] = set()
    info = {"GL_VENDOR": "Old Vendor", "GL_RENDERER": "Old GPU", "GL_VERSION": "3.3 Core",
            "GL_MAX_3D_TEXTURE_SIZE": 64, "GL_MAX_DRAW_BUFFERS": 8}
    released = False

    def release(self) -> None:
        self.released = True


def test_reports_the_real_driver(capsys, gl_context):
    # No window check here: glfw.terminate() would close windows other tests hold open.
    assert main(["doctor", "--json", "--no-window-check"]) == 0
    report = json.loads(capsys.readouterr().out)
    assert report["ok"] and report["headless_ok"] and report["compute_shaders"]
    assert report["gl_version_code"] >= 430 and report["max_3d_texture_size"] >= 128
    assert report["renderer"]


def test_missing_egl_is_explained_not_raised(monkeypatch, capsys):
    def no_egl():
        raise GLUnavailableError("could not open a headless OpenGL context through EGL")

    monkeypatch.setattr(doctor, "_open_context", no_egl)
    assert main(["doctor", "--no-window-check"]) == 1
    out = capsys.readouterr().out
    assert "NOT AVAILABLE" in out and "libegl1" in out and "Traceback" not in out


def test_old_driver_lists_what_is_missing(monkeypatch, capsys):
    old = _OldDriver()
    monkeypatch.setattr(doctor, "_open_context", lambda: old)
    assert main(["doctor", "--no-window-check"]) == 1
    out = capsys.readouterr().out
    assert "Old GPU" in out and "OpenGL 4.3" in out and "compute shaders" in out
    assert "limited to 64" in out and old.released


def test_no_display_is_advice_not_failure(monkeypatch, capsys):
    monkeypatch.delenv("DISPLAY", raising=False)
    monkeypatch.delenv("WAYLAND_DISPLAY", raising=False)
    report = doctor.Report()
    doctor.check_window(report)
    assert not report.glfw_ok and "xvfb-run" in report.advice[0]


def test_display_that_glfw_cannot_open(monkeypatch):
    fake_glfw = types.SimpleNamespace(init=lambda: False, terminate=lambda: None,
                                      ERROR_REPORTING="warn")
    monkeypatch.setitem(sys.modules, "glfw", fake_glfw)
    monkeypatch.setenv("DISPLAY", ":99")
    report = doctor.Report()
    doctor.check_window(report)
    assert not report.glfw_ok and "DISPLAY=:99" in report.glfw_error
    assert fake_glfw.ERROR_REPORTING == "warn"
    assert "not available: glfw could not connect" in doctor.render_text(report)
