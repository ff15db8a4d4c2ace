"""The site's live figures: the figure kinds the page computes itself in JavaScript
(``explorer/site/assets/figures/``, ES modules that import only the generated constants,
``assets/generated/constants.js``), mounted over the baked picture, which stays the
picture without JavaScript.

:func:`with_live` adds a figure's mount (its kind and parameters as JSON, the numbers a
kind cannot compute in the page, such as the pipeline's frame, baked in) to the HTML the
build wrote for it; :func:`copy_assets` ships the modules and writes
``assets/lpv-modules.js``, the loader (``assets/live-loader.js``) with every module's
source packed in, because a page read from ``file://`` may not fetch modules;
:func:`loader_tag` is the script tag a page with a live figure needs.
"""

from __future__ import annotations

import dataclasses
import json
import shutil
from collections.abc import Mapping
from importlib.resources import files
from pathlib import Path
from typing import Any

import numpy as np

from explorer.site.pages import esc

LIVE_KINDS = ("clamped-cosine", "cell-faces", "rsm-texel", "pipeline", "propagation-stepper")
"""The figure kinds drawn live in the page (assets/figures/live.js names their modules)."""
MODULE_FOLDERS = ("generated", "figures")
"""The folders of ES modules under assets/, imported as ``lpv/<folder>/<file>``."""
LOADER = "lpv-modules.js"
STYLE = "live-figures.css"
MOUNT = 'class="live-figure"'
HEAT_SAMPLES = 101
"""Samples of the window's heat map the stepper interpolates (its knots among them)."""


def _extras(kind: str, readouts: Mapping[str, float]) -> dict[str, Any]:
    """What a kind's module needs beyond the figure's parameters."""
    if kind == "rsm-texel":
        from explorer.figure_params import MAX_TILT

        return {"max_tilt": MAX_TILT}
    if kind == "pipeline":
        from explorer.figure_params import PIPELINE_STAGES

        return {"readouts": dict(readouts), "stages": [list(stage) for stage in PIPELINE_STAGES]}
    if kind == "propagation-stepper":
        from explorer.figure_params import STEPPER_CORRECTIONS
        from explorer.ui.figures.propagation_stepper import (
            PLAY_RATE,
            SOURCE_FLUX,
            corrections_named,
        )
        from explorer.ui.glyphs import SAMPLES
        from explorer.ui.legend import describe_corrections
        from explorer.ui.textures import heat

        switches = {name: dataclasses.asdict(corrections_named(name))
                    for name in STEPPER_CORRECTIONS}
        return {"choices": list(STEPPER_CORRECTIONS), "switches": switches,
                "labels": {name: describe_corrections(corrections_named(name)).capitalize()
                           for name in STEPPER_CORRECTIONS},
                "heat": [[round(float(v), 4) for v in colour] for colour in heat(
                    np.linspace(0.0, 1.0, HEAT_SAMPLES))],
                "rate": PLAY_RATE, "source_flux": SOURCE_FLUX, "glyph_samples": SAMPLES}
    return {}


def figure_params(spec, readouts: Mapping[str, float]) -> dict[str, Any]:
    """The JSON a live figure starts from: the lesson's parameters and the extras."""
    return {**dataclasses.asdict(spec.params), **_extras(spec.kind, readouts)}


def with_live(spec, readouts: Mapping[str, float], caption_html: str, html: str) -> str:
    """``html`` (a ``<figure>`` the build wrote) with a live mount before its baked
    content, which moves into ``<div class="baked">``; unchanged for a kind that is not
    live. A figure whose caption sits inside its baked part (the stepper's sequence)
    gets the caption in its mount too."""
    if spec.kind not in LIVE_KINDS:
        return html
    start = html.index(">", html.index("<figure")) + 1
    end = html.rfind("<figcaption>")
    own_caption = end >= 0
    if not own_caption:
        end = html.rindex("</figure>")
    data = json.dumps(figure_params(spec, readouts), separators=(",", ":"), sort_keys=True)
    caption = "" if own_caption else caption_html.replace("<figcaption>", '<p class="caption">') \
        .replace("</figcaption>", "</p>")
    mount = (f'<div {MOUNT} data-live-kind="{esc(spec.kind)}" data-params="{esc(data)}" '
             f'hidden><div class="live-mount"></div>{caption}</div>')
    return f'{html[:start]}{mount}<div class="baked">{html[start:end]}</div>{html[end:]}'


def module_sources() -> dict[str, str]:
    """``<folder>/<file>`` -> source of every shipped ES module."""
    assets = files("explorer.site") / "assets"
    found = {}
    for folder in MODULE_FOLDERS:
        for item in sorted((assets / folder).iterdir(), key=lambda entry: entry.name):
            if item.name.endswith(".js"):
                found[f"{folder}/{item.name}"] = item.read_text(encoding="utf-8")
    return found


def copy_assets(folder: Path) -> None:
    """The modules, their stylesheet and the loader into the site's ``assets/``."""
    assets = files("explorer.site") / "assets"
    sources = module_sources()
    for name, text in sources.items():
        (folder / name).parent.mkdir(parents=True, exist_ok=True)
        (folder / name).write_text(text, encoding="utf-8")
    with (assets / STYLE).open("rb") as source, (folder / STYLE).open("wb") as target:
        shutil.copyfileobj(source, target)
    packed = json.dumps(sources, ensure_ascii=True).replace("</", "<\\/")
    loader = (assets / "live-loader.js").read_text(encoding="utf-8")
    (folder / LOADER).write_text(f"// The live figures' ES modules, packed by the site build "
                                 f"(explorer/site/live_figures.py).\nvar LPV_MODULES = "
                                 f"{packed};\n{loader}", encoding="utf-8")


def loader_tag(body: str) -> str:
    """The loader's script tag for a page whose ``body`` holds a live figure, else ""."""
    return f'<script src="assets/{LOADER}"></script>' if MOUNT in body else ""
