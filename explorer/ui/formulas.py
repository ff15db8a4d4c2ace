"""Typeset LaTeX formulas as textures (imgui_microtex), with a text fallback.

The LaTeX comes from the derivation table generated at codegen time
(``explorer.derived``): typesetting a formula never runs sympy.

MicroTeX builds a C++ ``std::locale("en_US.UTF-8")``; systems that lack that locale make
it throw. We then compile the locale once with ``localedef`` into the user's cache dir and
point glibc at it with ``LOCPATH`` (read when a locale is created, so setting it from
Python before the first formula is enough). If that fails too, formulas are shown as
their LaTeX source: :attr:`FormulaCache.error` says why.
"""

from __future__ import annotations

import os
import shutil
import subprocess
from dataclasses import dataclass
from pathlib import Path

import numpy as np

LOCALE = "en_US.UTF-8"


def cache_dir() -> Path:
    base = os.environ.get("XDG_CACHE_HOME") or str(Path.home() / ".cache")
    return Path(base) / "lpv-explorer"


def ensure_utf8_locale() -> str | None:
    """Make ``en_US.UTF-8`` loadable; returns None when it is, else the reason."""
    import locale

    try:
        saved = locale.setlocale(locale.LC_CTYPE)
        locale.setlocale(locale.LC_CTYPE, LOCALE)
        locale.setlocale(locale.LC_CTYPE, saved)
        return None
    except locale.Error:
        pass
    target = cache_dir() / "locale"
    if not (target / LOCALE).is_dir():
        localedef = shutil.which("localedef")
        if localedef is None:
            return f"the {LOCALE} locale is missing and localedef is not installed"
        target.mkdir(parents=True, exist_ok=True)
        # built beside its place and renamed into it: another process starting at the
        # same moment (a second window, the test workers) sees the whole locale or none
        import tempfile

        with tempfile.TemporaryDirectory(dir=target, prefix=".build-") as building:
            proc = subprocess.run([localedef, "-i", "en_US", "-f", "UTF-8",
                                   str(Path(building) / LOCALE)],
                                  capture_output=True, text=True, timeout=60)
            try:
                os.rename(Path(building) / LOCALE, target / LOCALE)
            except OSError:
                pass         # not built (said below), or another process was first
        if not (target / LOCALE).is_dir():
            return f"localedef could not build {LOCALE}: {proc.stderr.strip()[:200]}"
    os.environ["LOCPATH"] = str(target)
    return None


@dataclass
class Formula:
    texture_id: int      # 0 = not typeset, show ``latex`` as text
    width: int
    height: int
    latex: str
    baseline: int = 0    # pixels from the image's top to the formula's baseline


MAX_CACHED_FORMULAS = 1024
"""Typeset formulas kept as textures at once; the least recently used go first. The whole
course has a few hundred (a 30-minute soak through every step settled near 400 UI
textures), so a reader never waits for one twice, and a long session stays bounded."""


class FormulaCache:
    """LaTeX → texture, rendered once per (formula, size) and kept while among the
    :data:`MAX_CACHED_FORMULAS` most recently used. Textures belong to the UI."""

    def __init__(self, textures, font_size: float = 18.0) -> None:
        self.textures = textures          # explorer.ui.textures.UiTextures
        self.font_size = font_size
        self.error: str | None = None
        self._cache: dict[tuple[str, float], Formula] = {}
        self._ready = False
        self._tried = False

    def _init(self) -> None:
        self._tried = True
        self.error = init_microtex()
        self._ready = self.error is None

    @property
    def available(self) -> bool:
        if not self._tried:
            self._init()
        return self._ready

    def get(self, latex: str, scale: float = 1.0, inline: bool = False) -> Formula:
        """``latex`` typeset at ``scale`` × the cache's font size, in TeX's display style
        (formula blocks) or its text style (``inline``: math within a line of prose)."""
        size = round(self.font_size * scale, 1)
        key = (latex, size, inline)
        if key in self._cache:
            self._cache[key] = self._cache.pop(key)      # most recently used last
            return self._cache[key]
        while len(self._cache) >= MAX_CACHED_FORMULAS:
            oldest = next(iter(self._cache))
            del self._cache[oldest]
            self.textures.discard(_texture_key(oldest))
        formula = Formula(0, 0, 0, latex)
        if self.available:
            try:
                rendered, pixels = typeset(latex, size, inline)
                if pixels.size:
                    tex = self.textures.upload(_texture_key(key), pixels,
                                               version=key, nearest=False)
                    formula = Formula(tex, pixels.shape[1], pixels.shape[0], latex,
                                      int(rendered.baseline_y))
            except Exception as exc:  # noqa: BLE001 - a formula MicroTeX cannot parse
                self.error = f"could not typeset {latex!r}: {exc}"
        self._cache[key] = formula
        return formula


def _texture_key(key: tuple[str, float, bool]) -> str:
    """The UI texture name of a cached formula (latex, size, inline)."""
    latex, size, inline = key
    return f"formula:{latex}:{size}:{inline}"


def typeset(latex: str, size: float, inline: bool = False):
    """(MicroTeX's RenderedFormula, its RGBA pixels as an (H, W, 4) array) of ``latex``
    in white; needs :func:`init_microtex` first. No GL involved (tests use it too)."""
    from imgui_bundle import imgui_microtex

    style = imgui_microtex.TexStyle.text if inline else imgui_microtex.TexStyle.display
    rendered = imgui_microtex.render(latex, size, 0xFFFFFFFF, style)
    return rendered, np.array(rendered.pixels_as_array(), copy=True)


def init_microtex() -> str | None:
    """Load MicroTeX's fonts (once); None when it works, else why it cannot."""
    problem = ensure_utf8_locale()
    if problem:
        return problem
    try:
        import imgui_bundle
        from imgui_bundle import imgui_microtex

        fonts = Path(imgui_bundle.__file__).parent / "assets" / "fonts" / "latex"
        imgui_microtex.init(str(fonts / "latinmodern-math.clm1"),
                            str(fonts / "latinmodern-math.otf"))
        imgui_microtex.render("x", 10.0, 0xFFFFFFFF)  # fails here if the locale is bad
    except Exception as exc:  # noqa: BLE001 - any failure means "show the source"
        return f"imgui_microtex unavailable: {exc}"
    return None
