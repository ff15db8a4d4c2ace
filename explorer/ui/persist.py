"""Settings and window layout between runs: ``$XDG_CONFIG_HOME/lpv-explorer/``.

``settings.json`` holds the two configurations and the view choices (JSON only, never
pickle: the file is read back as plain data and every value is validated by
:class:`~explorer.lpv.settings.Settings`). ``imgui.ini`` next to it holds the dock layout.
A file that cannot be read falls back to the defaults and says why.
"""

from __future__ import annotations

import dataclasses
import json
import os
from pathlib import Path
from typing import Any

from explorer.lpv.settings import Corrections, Settings
from explorer.ui.state import VIEW_BUFFERS, VIEW_MODES, AppState, InspectState

FORMAT_VERSION = 1


def config_dir() -> Path:
    """``$XDG_CONFIG_HOME/lpv-explorer`` (``~/.config/lpv-explorer`` when unset)."""
    base = os.environ.get("XDG_CONFIG_HOME") or str(Path.home() / ".config")
    return Path(base) / "lpv-explorer"


def settings_path() -> Path:
    return config_dir() / "settings.json"


def layout_path() -> Path:
    return config_dir() / "imgui.ini"


class SettingsFileError(ValueError):
    """The settings file exists but is not a valid lpv-explorer settings file."""


def settings_from_dict(data: Any) -> Settings:
    """A :class:`Settings` from its :meth:`Settings.to_dict` form, with clear errors."""
    if not isinstance(data, dict):
        raise SettingsFileError(f"settings must be a JSON object, got {type(data).__name__}")
    known = {f.name for f in dataclasses.fields(Settings)}
    unknown = sorted(set(data) - known)
    if unknown:
        raise SettingsFileError(f"unknown settings field(s): {', '.join(unknown)}")
    values = dict(data)
    if "corrections" in values:
        corr = values["corrections"]
        if not isinstance(corr, dict):
            raise SettingsFileError("corrections must be an object of true/false switches")
        bad = sorted(set(corr) - set(Corrections.names()))
        if bad:
            raise SettingsFileError(f"unknown correction(s): {', '.join(bad)}")
        for name, value in corr.items():
            if not isinstance(value, bool):
                raise SettingsFileError(f"correction {name} must be true or false")
        values["corrections"] = Corrections(**corr)
    for name in ("camera", "light"):
        if values.get(name) is not None:
            values[name] = _pair_of_points(name, values[name])
    if values.get("spot_cone_degrees") is not None:
        values["spot_cone_degrees"] = _two_numbers("spot_cone_degrees",
                                                   values["spot_cone_degrees"])
    defaults = Settings()
    for f in dataclasses.fields(Settings):
        if f.name in values and f.name not in _STRUCTURED:
            expected = type(getattr(defaults, f.name))
            value = values[f.name]
            if getattr(defaults, f.name) is None:  # optional numbers (light_flux)
                if value is not None and (isinstance(value, bool)
                                          or not isinstance(value, (int, float))):
                    raise SettingsFileError(f"{f.name} must be a number or null")
                continue
            if expected is float and isinstance(value, int) and not isinstance(value, bool):
                values[f.name] = float(value)
            elif getattr(defaults, f.name) is not None and not isinstance(value, expected):
                raise SettingsFileError(
                    f"{f.name} must be {expected.__name__}, got {value!r}")
    try:
        return Settings(**values)
    except (TypeError, ValueError) as exc:
        raise SettingsFileError(str(exc)) from exc


_STRUCTURED = ("corrections", "camera", "light", "spot_cone_degrees")
"""Fields read above, not by the per-type check."""


def _two_numbers(name: str, value: Any) -> tuple[float, float]:
    try:
        first, second = value
        if any(isinstance(v, bool) for v in (first, second)):
            raise TypeError
        return float(first), float(second)
    except (TypeError, ValueError):
        raise SettingsFileError(f"{name} must be two numbers [inner, outer] or null") from None


def _pair_of_points(name: str, value: Any) -> tuple:
    try:
        first, second = value
        pair = (tuple(float(v) for v in first), tuple(float(v) for v in second))
    except (TypeError, ValueError):
        raise SettingsFileError(f"{name} must be two points [[x, y, z], [x, y, z]]") from None
    if any(len(p) != 3 for p in pair):
        raise SettingsFileError(f"{name} must be two points [[x, y, z], [x, y, z]]")
    return pair


def state_to_dict(state: AppState) -> dict:
    return {
        "format": FORMAT_VERSION,
        "settings": state.settings.to_dict(),
        "compare_settings": state.compare_settings.to_dict(),
        "view_mode": state.view_mode,
        "view_buffer": state.view_buffer,
        "split_position": state.split_position,
        "auto_exposure": state.auto_exposure,
        "render_scale": state.render_scale,
        "mesh_path": state.mesh_path,
        "window_size": list(state.window_size),
        "inspect": dataclasses.asdict(state.inspect),
        "open_panels": dict(state.open_panels),
        "layout_panels": list(state.layout_panels),
    }


def apply_dict(state: AppState, data: Any) -> None:
    """Fill ``state`` from a settings file's content; raises SettingsFileError."""
    if not isinstance(data, dict):
        raise SettingsFileError("the file must hold a JSON object")
    if data.get("format") != FORMAT_VERSION:
        raise SettingsFileError(
            f"unsupported format {data.get('format')!r} (this version writes {FORMAT_VERSION})")
    settings = settings_from_dict(data.get("settings", {}))
    compare = settings_from_dict(data.get("compare_settings", {}))
    view_mode = data.get("view_mode", "single")
    if view_mode not in VIEW_MODES:
        raise SettingsFileError(f"view_mode must be one of {VIEW_MODES}, got {view_mode!r}")
    view_buffer = data.get("view_buffer", "final")
    if view_buffer not in VIEW_BUFFERS:
        raise SettingsFileError(f"view_buffer must be one of {VIEW_BUFFERS}, got {view_buffer!r}")
    inspect_data = data.get("inspect", {})
    try:
        inspect = InspectState(**inspect_data)
    except TypeError as exc:
        raise SettingsFileError(f"inspect: {exc}") from None
    panels = data.get("open_panels", {})
    if not isinstance(panels, dict) or not all(isinstance(v, bool) for v in panels.values()):
        raise SettingsFileError("open_panels must map panel titles to true/false")
    state.settings, state.compare_settings = settings, compare
    state.view_mode = view_mode
    state.view_buffer = view_buffer
    state.split_position = min(max(float(data.get("split_position", 0.5)), 0.05), 0.95)
    state.auto_exposure = bool(data.get("auto_exposure", False))
    state.render_scale = min(max(float(data.get("render_scale", 1.0)), 0.25), 2.0)
    state.mesh_path = str(data.get("mesh_path", ""))
    size = data.get("window_size", [1600, 960])
    if (not isinstance(size, list) or len(size) != 2
            or not all(isinstance(v, int) and 200 <= v <= 16384 for v in size)):
        raise SettingsFileError(f"window_size must be [width, height] in pixels, got {size!r}")
    state.window_size = (size[0], size[1])
    state.inspect = inspect
    state.open_panels = dict(panels)
    layout_panels = data.get("layout_panels", [])
    if not isinstance(layout_panels, list) or not all(isinstance(t, str)
                                                      for t in layout_panels):
        raise SettingsFileError("layout_panels must be a list of panel titles")
    state.layout_panels = layout_panels


def load_state(state: AppState, path: Path | None = None) -> str | None:
    """Load the settings file into ``state``. Returns None on success or when there is no
    file yet; otherwise the defaults stay and the returned text says what was wrong."""
    path = path or settings_path()
    if not path.exists():
        return None
    try:
        data = json.loads(path.read_text(encoding="utf-8"))
        apply_dict(state, data)
    except (OSError, UnicodeDecodeError, json.JSONDecodeError, SettingsFileError) as exc:
        return f"could not read {path}: {exc}; using the default settings"
    return None


def save_state(state: AppState, path: Path | None = None) -> None:
    """Write the settings file atomically (a crash never leaves half a file)."""
    path = path or settings_path()
    path.parent.mkdir(parents=True, exist_ok=True)
    tmp = path.with_suffix(".json.tmp")
    tmp.write_text(json.dumps(state_to_dict(state), indent=2), encoding="utf-8")
    os.replace(tmp, path)
