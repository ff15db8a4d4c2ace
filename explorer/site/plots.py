"""The audit figures as SVG: the flux in flight per propagation step (lines) and the
energy audit (bars), with axes, tick labels, axis titles and a legend, each data point
carrying a ``<title>`` so the browser shows its value on hover.

They plot the same numbers as the window's figures (explorer/ui/figures/flux_per_step.py
``flux_per_step``, energy_audit.py ``audit_values``) from the step's converged frames, and
choose linear or log axes the same way (explorer/ui/figures/plotting.py ``choose_scale``).
"""

from __future__ import annotations

import html
import math
from collections.abc import Sequence
from dataclasses import dataclass

import numpy as np

SIDE_COLOURS = ("#2f6fdf", "#e0702f")
"""Configuration A, B (the window's blue and orange)."""
WIDTH, HEIGHT = 560, 300


def _num(value: float) -> str:
    magnitude = abs(value)
    text = format(value, ".3g" if value == 0 or 1e-3 <= magnitude < 1e4 else ".2e")
    return text.replace("-", "−")


def watts(value: float) -> str:
    return f"{_num(value)} W"


def share(value: float, reference: float) -> str:
    """``value`` relative to ``reference``: a percentage, or ``3.2×`` from twice on."""
    if reference == 0 or not math.isfinite(reference):
        return "–"
    ratio = value / reference
    return f"{_num(ratio)}×" if abs(ratio) >= 2 else f"{100 * ratio:.1f} %"


def share_words(value: float, reference: float) -> str:
    """The share in a sentence: "106.0 % of the injected flux", "16× the injected flux"."""
    text = share(value, reference)
    return f"{text} the injected flux" if text.endswith("×") else f"{text} of the injected flux"


class Axis:
    """A value axis, linear (from 0 or the most negative value) or log (whole decades)."""

    def __init__(self, values: Sequence[float], scale: str, length: float) -> None:
        data = np.asarray([v for v in values if math.isfinite(v)], np.float64)
        self.scale, self.length = scale, float(length)
        if scale == "log":
            positive = data[data > 0]
            positive = positive if positive.size else np.array([1.0])
            self.low = 10.0 ** math.floor(math.log10(positive.min()))
            self.high = 10.0 ** math.ceil(math.log10(positive.max()))
            if self.high <= self.low:
                self.high = self.low * 10
        else:
            self.low = min(0.0, float(data.min()) if data.size else 0.0)
            top = float(data.max()) if data.size else 1.0
            self.high = top * 1.08 if top > 0 else 1.0

    def at(self, value: float) -> float:
        """Distance along the axis (0 at ``low``) of ``value``."""
        if self.scale == "log":
            value = max(value, self.low)
            return self.length * (math.log10(value) - math.log10(self.low)) / (
                math.log10(self.high) - math.log10(self.low))
        return self.length * (value - self.low) / (self.high - self.low)

    def ticks(self) -> list[float]:
        if self.scale == "log":
            decades = range(round(math.log10(self.low)), round(math.log10(self.high)) + 1)
            every = max(1, math.ceil(len(decades) / 7))
            return [10.0 ** d for d in decades if (d - decades[0]) % every == 0]
        span = self.high - self.low
        step = 10 ** math.floor(math.log10(span / 5))
        for factor in (1, 2, 2.5, 5, 10):
            if span / (step * factor) <= 6:
                step *= factor
                break
        first = math.ceil(self.low / step) * step
        return [first + i * step for i in range(int((self.high - first) / step) + 1)]

    def label(self, value: float) -> str:
        """The tick's SVG text content: a decade as 10 with a raised exponent."""
        if self.scale == "log":
            exponent = round(math.log10(value))
            if exponent == 0:
                return "1"
            power = str(exponent).replace("-", "−")
            return f'10<tspan dy="-5" font-size="9">{power}</tspan>'
        return _num(round(value, 12))


@dataclass(frozen=True)
class Box:
    """A plot's size and the margins around its axes rectangle (pixels)."""

    width: float = WIDTH
    height: float = HEIGHT
    left: float = 72
    right: float = 110
    top: float = 34
    bottom: float = 46

    @property
    def inner(self) -> tuple[float, float]:
        return (self.width - self.left - self.right, self.height - self.top - self.bottom)


def _frame(box: Box, title: str, x_label: str, y_label: str) -> list[str]:
    w, h = box.inner
    out = [f'<svg xmlns="http://www.w3.org/2000/svg" class="plot" viewBox="0 0 {box.width:g} '
           f'{box.height:g}" role="img" aria-label="{html.escape(title)}">',
           f"<title>{html.escape(title)}</title>",
           f'<text class="axis-title" x="{box.left + w / 2:.1f}" y="{box.height - 8:g}" '
           f'text-anchor="middle">{html.escape(x_label)}</text>']
    if y_label:
        out.append(f'<text class="axis-title" transform="translate(14 {box.top + h / 2:.1f}) '
                   f'rotate(-90)" text-anchor="middle">{html.escape(y_label)}</text>')
    return out


def _legend(box: Box, labels: Sequence[str]) -> list[str]:
    out = []
    x = box.left
    for i, label in enumerate(labels):
        out.append(f'<rect x="{x:g}" y="8" width="12" height="12" fill="{SIDE_COLOURS[i % 2]}"/>'
                   f'<text class="legend" x="{x + 17:g}" y="18">{html.escape(label)}</text>')
        x += 30 + 6.5 * len(label)
    return out


def _value_ticks(box: Box, axis: Axis, horizontal: bool = False) -> list[str]:
    out = []
    w, h = box.inner
    for tick in axis.ticks():
        if horizontal:
            x = box.left + axis.at(tick)
            out.append(f'<line class="grid" x1="{x:.1f}" x2="{x:.1f}" y1="{box.top:g}" '
                       f'y2="{box.top + h:g}"/><text class="tick" x="{x:.1f}" '
                       f'y="{box.top + h + 16:g}" text-anchor="middle">'
                       f"{axis.label(tick)}</text>")
        else:
            y = box.top + h - axis.at(tick)
            out.append(f'<line class="grid" x1="{box.left:g}" x2="{box.left + w:g}" '
                       f'y1="{y:.1f}" y2="{y:.1f}"/><text class="tick" '
                       f'x="{box.left - 6:g}" y="{y + 4:.1f}" text-anchor="end">'
                       f"{axis.label(tick)}</text>")
    return out


def flux_per_step_svg(series: Sequence[tuple[str, np.ndarray]], scale: str = "log",
                      relative: bool = False) -> str:
    """Lines of flux in flight against the step t, one per (label, values) series;
    ``relative``: each as a percentage of its own injected flux (t = 0)."""
    shown = [(label, 100.0 * v / v[0] if relative and v[0] else np.asarray(v, np.float64))
             for label, v in series]
    unit = "%" if relative else "W"
    every = np.concatenate([v for _, v in shown]) if shown else np.zeros(1)
    box = Box()
    w, h = box.inner
    axis = Axis(every, scale, h)
    steps = max(len(v) for _, v in shown) - 1 if shown else 1
    x_of = lambda t: box.left + w * t / max(steps, 1)  # noqa: E731
    out = _frame(box, "Flux in flight per propagation step", "step t",
                 f"flux in flight [{unit}]" + (" (log)" if axis.scale == "log" else ""))
    out += _value_ticks(box, axis)
    every_t = max(1, math.ceil(steps / 8))
    for t in range(0, steps + 1, every_t):
        out.append(f'<text class="tick" x="{x_of(t):.1f}" y="{box.top + h + 16:g}" '
                   f'text-anchor="middle">{t}</text>')
    out.append(f'<rect class="axes" x="{box.left:g}" y="{box.top:g}" width="{w:g}" '
               f'height="{h:g}"/>')
    for i, (label, values) in enumerate(shown):
        colour = SIDE_COLOURS[i % 2]
        points = [(x_of(t), box.top + h - axis.at(float(v))) for t, v in enumerate(values)]
        out.append(f'<polyline fill="none" stroke="{colour}" stroke-width="2" points="'
                   + " ".join(f"{x:.1f},{y:.1f}" for x, y in points) + '"/>')
        raw = series[i][1]
        for t, ((x, y), v) in enumerate(zip(points, values)):
            text = (f"{label}: step {t}: " + (f"{v:.3g} % of the injected flux" if relative
                                              else f"{watts(float(v))} in flight ("
                                                   f"{share_words(float(raw[t]), float(raw[0]))}"
                                                   ")"))
            out.append(f'<circle class="point" cx="{x:.1f}" cy="{y:.1f}" r="4" fill="{colour}">'
                       f"<title>{html.escape(text)}</title></circle>")
        last_x, last_y = points[-1]
        end = f"{values[-1]:.3g} %" if relative else watts(float(values[-1]))
        out.append(f'<text class="end-label" x="{last_x + 8:.1f}" y="{last_y + 4 + 14 * i:.1f}" '
                   f'fill="{colour}">{html.escape(end)}</text>')
    out += _legend(box, [label for label, _ in shown])
    out.append("</svg>")
    return "\n".join(out)


def audit_svg(rows: Sequence[str], sides: Sequence[tuple[str, np.ndarray, float]],
              scale: str = "linear", relative: bool = False) -> str:
    """Horizontal bars, one row per audit term and one bar per side ((label, values,
    injected flux)); each labelled with its value and its share of that side's injected
    flux."""
    shown = [(label, (v / injected if relative and injected else v), v, injected)
             for label, v, injected in sides]
    every = np.concatenate([np.abs(v) for _, v, _, _ in shown]) if shown else np.zeros(1)
    bar = 12
    row = bar * max(len(shown), 1) + 10
    box = Box(height=34 + 46 + len(rows) * row, left=170, right=120)
    w, h = box.inner
    axis = Axis(every, scale, w)
    unit = "share of injected" if relative else "W"
    out = _frame(box, "Energy audit",
                 f"flux [{unit}]" + (" (log)" if axis.scale == "log" else ""), "")
    out += _value_ticks(box, axis, horizontal=True)
    for r, name in enumerate(rows):
        y0 = box.top + r * row + 5
        out.append(f'<text class="tick" x="{box.left - 8:g}" '
                   f'y="{y0 + bar * len(shown) / 2 + 3:.1f}" text-anchor="end">'
                   f"{html.escape(name)}</text>")
        for i, (label, values, watts_values, injected) in enumerate(shown):
            value = float(values[r])
            length = 0.0 if not math.isfinite(value) else axis.at(abs(value))
            y = y0 + i * bar
            text = (f"{label}: {name}: {watts(float(watts_values[r]))} "
                    f"({share_words(float(watts_values[r]), injected)})")
            out.append(f'<rect class="bar" x="{box.left:g}" y="{y:g}" width="{length:.1f}" '
                       f'height="{bar - 2}" fill="{SIDE_COLOURS[i % 2]}"><title>'
                       f"{html.escape(text)}</title></rect>")
            out.append(f'<text class="end-label" x="{box.left + length + 4:.1f}" '
                       f'y="{y + bar - 3:g}">{html.escape(watts(float(watts_values[r])))}'
                       f" ({html.escape(share(float(watts_values[r]), injected))})</text>")
    out.append(f'<line class="axis" x1="{box.left:g}" x2="{box.left:g}" y1="{box.top:g}" '
               f'y2="{box.top + h:g}"/>')
    out += _legend(box, [label for label, *_ in shown])
    out.append("</svg>")
    return "\n".join(out)
