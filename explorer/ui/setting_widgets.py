"""imgui widgets drawn from settings specs (explorer/schema.py).

A field that declares ``widget`` is edited here generically: its label, its range (a
slider stops at ``widget_high``, Ctrl+click types any allowed value), its choices or
suggested values, and a tooltip made of its documentation and what it allows. The caller
applies the value through the schema, which refuses what the spec does not allow.
"""

from __future__ import annotations

from typing import Any

from imgui_bundle import imgui

from explorer.lessons.words import for_reader
from explorer.schema import Spec


def label_of(spec: Spec, name: str) -> str:
    """The widget's label: the spec's label (or the field name) and its unit."""
    text = spec.label or name.replace("_", " ")
    return f"{text} [{spec.unit}]" if spec.unit else text


def tooltip_of(spec: Spec) -> str:
    """The documentation and the allowed values (``None`` shown as 0 by an input)."""
    text = f"{for_reader(spec.doc)}\nAllowed: {spec.allowed()}."
    if spec.optional and spec.widget == "input":
        text += " 0 = automatic (None)."
    return text


def combo_options(spec: Spec, value: Any) -> list:
    """What a combo offers: the choices, or the suggested values and the current one."""
    if spec.kind == "choice":
        return list(spec.choices)
    return sorted(set(spec.suggested) | {value})


def slider_range(spec: Spec) -> tuple[float, float]:
    """(low, high) of a slider: the allowed range, cut at ``widget_high``."""
    high = spec.widget_high if spec.widget_high is not None else spec.high
    return spec.low, high


def draw_setting(name: str, spec: Spec, value: Any) -> tuple[bool, Any]:
    """Draw the widget ``spec`` declares for ``value``; (changed, new value). The new
    value is what the user set, not yet checked: apply it through the schema."""
    label = label_of(spec, name)
    if spec.widget == "combo":
        options = combo_options(spec, value)
        index = options.index(value) if value in options else 0
        changed, index = imgui.combo(label, index, [str(option) for option in options])
        result = changed, options[index]
    elif spec.widget == "slider":
        low, high = slider_range(spec)
        if spec.kind == "int":
            result = imgui.slider_int(label, int(value), int(low), int(high))
        else:
            changed, number = imgui.slider_float(label, float(value), low, high, "%.2f")
            result = changed, round(float(number), 3)
    elif spec.widget == "checkbox":
        result = imgui.checkbox(label, bool(value))
    elif spec.widget == "input":
        changed, number = imgui.input_float(label, float(value or 0.0), 0.0, 0.0, "%.3g")
        result = changed, (None if spec.optional and number == 0.0 else float(number))
    else:
        raise ValueError(f"{name} declares no widget")
    if imgui.is_item_hovered():
        imgui.set_tooltip(tooltip_of(spec))
    return result
