"""Whether a glfw window can open here (the window tests skip, saying why, when not)."""

from __future__ import annotations


def display_problem() -> str | None:
    try:
        # isort: off
        import imgui_bundle  # noqa: F401
        import glfw
        # isort: on
    except ImportError as exc:  # pragma: no cover
        return f"glfw/imgui_bundle missing: {exc}"
    import os
    import time
    import warnings

    # a display that is busy for a moment (two workers' Xvfb starting) gets a few tries;
    # no display at all gets one
    tries = 3 if os.environ.get("DISPLAY") else 1
    for attempt in range(tries):
        if attempt:
            time.sleep(0.5 * attempt)
        with warnings.catch_warnings(record=True) as caught:
            warnings.simplefilter("always")
            started = glfw.init()
        if started:
            glfw.terminate()
            return None
    said = "; ".join(str(w.message) for w in caught) or "no message"
    return (f"no X server could be started (install Xvfb, or pytest-xvfb's xvfb): "
            f"DISPLAY={os.environ.get('DISPLAY')!r}, glfw said: {said}")


def run_child(args: list[str], tmp_path, timeout: float = 600, env: dict | None = None):
    """Run ``python ARGS`` from the repository root in a child process (a GLX window
    cannot become current where the tests' EGL context was; an imgui assert aborts the
    child only), its settings and caches in ``tmp_path``; the CompletedProcess."""
    import os
    import subprocess
    import sys
    from pathlib import Path

    base = dict(os.environ if env is None else env)
    base.update(XDG_CONFIG_HOME=str(tmp_path / "config"),
                XDG_CACHE_HOME=str(tmp_path / "cache"))
    return subprocess.run([sys.executable, *args], cwd=Path(__file__).resolve().parent.parent,
                          env=base, capture_output=True, text=True, errors="replace",
                          timeout=timeout)
