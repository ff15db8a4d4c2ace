"""Settings and window layout between runs: ``$XDG_CONFIG_HOME/lpv-explorer/``.

``settings.json`` holds the fields of :class:`~explorer.ui.state.AppState` declared with
the settings schema (the two configurations, the view choices, the Inspect panel's
state...): JSON only, never pickle, read back through :func:`explorer.schema.from_dict`
so every value is type- and range-checked. ``imgui.ini`` next to it holds the dock
layout; :func:`check_layout` reads it before imgui does.

A file that fails is set aside, renamed ``<name>.bad-YYYYmmdd-HHMMSS``, and the defaults
are used: the problem is reported once, with where the file went, and the next launch
starts clean.
"""

from __future__ import annotations

import json
import os
from datetime import datetime
from pathlib import Path
from typing import Any

from explorer.safe_files import UserFileError, parse_json, read_text, write_atomically
from explorer.schema import SettingError, from_dict, specs, to_dict
from explorer.ui.layout_file import LayoutFileError, check_layout
from explorer.ui.state import AppState

FORMAT_VERSION = 1
RENAMED = {"auto_exposure": "expose_sides_separately"}
"""Old name -> new name of fields renamed since files of this format were written (the
per-side exposure of the compare views was ``auto_exposure`` before ``Settings`` got an
auto exposure of its own); read under the new name."""


def config_dir() -> Path:
    """``$XDG_CONFIG_HOME/lpv-explorer`` (``~/.config/lpv-explorer`` when unset)."""
    base = os.environ.get("XDG_CONFIG_HOME") or str(Path.home() / ".config")
    return Path(base) / "lpv-explorer"


def writable_config_dir() -> str | None:
    """Make the config folder; None when it is there and writable, else why not (its
    parent is a file, a read-only file system, no permission): the window then runs
    without saving settings or layout, says so once, and does not fail to start."""
    folder = config_dir()
    try:
        folder.mkdir(parents=True, exist_ok=True)
        probe = write_atomically(folder / ".write-probe", b"")
        probe.unlink()
    except OSError as exc:
        return (f"cannot write the settings folder {folder} ({exc.strerror or exc}); "
                f"running without saving settings")
    return None


def settings_path() -> Path:
    return config_dir() / "settings.json"


def layout_path() -> Path:
    return config_dir() / "imgui.ini"


class SettingsFileError(ValueError):
    """The settings file exists but is not a valid lpv-explorer settings file."""


def state_to_dict(state: AppState) -> dict:
    """What the settings file holds: the format version and every declared field."""
    return {"format": FORMAT_VERSION, **to_dict(state, declared_only=True)}


def apply_dict(state: AppState, data: Any) -> None:
    """Fill ``state``'s declared fields from a settings file's content (all or none);
    raises SettingsFileError naming the field, the value and what is allowed."""
    if not isinstance(data, dict):
        raise SettingsFileError("the file must hold a JSON object")
    if data.get("format") != FORMAT_VERSION:
        raise SettingsFileError(
            f"unsupported format {data.get('format')!r} (this version writes {FORMAT_VERSION})")
    fields = {RENAMED.get(key, key) if RENAMED.get(key) not in data else key: value
              for key, value in data.items() if key != "format"}
    try:
        loaded = from_dict(AppState, fields, AppState(), declared_only=True)
    except SettingError as exc:
        raise SettingsFileError(str(exc)) from None
    for name in specs(AppState):
        setattr(state, name, getattr(loaded, name))


def set_aside(path: Path) -> Path:
    """Rename a file that failed to ``<name>.bad-YYYYmmdd-HHMMSS`` (kept for the user to
    look at, never read again); returns the new path."""
    stamp = datetime.now().strftime("%Y%m%d-%H%M%S")
    target = path.with_name(f"{path.name}.bad-{stamp}")
    number = 1
    while target.exists():
        number += 1
        target = path.with_name(f"{path.name}.bad-{stamp}-{number}")
    os.replace(path, target)
    return target


def _setting_aside(path: Path, problem: str, what: str, failed: str = "could not read"
                   ) -> str:
    """The message for a file that failed: where it went, and that defaults are used."""
    # a UserFileError names the file already ("PATH: ..." or "PATH:LINE:COL: ...")
    said = f"{failed} {problem}" if problem.startswith(f"{path}:") else \
        f"{failed} {path}: {problem}"
    try:
        moved = set_aside(path)
    except OSError as exc:
        return f"{said}; could not move it aside ({exc}); using the default {what}"
    return f"{said}; moved it to {moved.name}; using the default {what}"


def load_state(state: AppState, path: Path | None = None) -> str | None:
    """Load the settings file into ``state``. Returns None on success or when there is no
    file yet; otherwise the file is set aside, the defaults stay and the returned text
    says what was wrong and where the file went."""
    path = path or settings_path()
    if not os.path.lexists(path):
        return None
    try:
        data = parse_json(read_text(path, "settings file"), path)
        apply_dict(state, data)
    except (UserFileError, SettingsFileError) as exc:
        return _setting_aside(path, str(exc), "settings")
    problem = over_budget(state)
    if problem:
        apply_dict(state, state_to_dict(AppState()))
        return _setting_aside(path, problem, "settings", "cannot use")
    return None


def over_budget(state: AppState) -> str | None:
    """Why the configurations of ``state`` cannot run, each field valid but together more
    than the memory budget (explorer/lpv/limits.py) or the cascades allow; None when
    they fit. Checked when the file is read, so a saved combination that cannot run is
    one line at start and the defaults, not a failed first frame."""
    from explorer.lpv.cascades import check_limits
    from explorer.lpv.limits import DEFAULT_MEMORY_BUDGET, check_memory

    for side, settings in (("A", state.settings), ("B", state.compare_settings)):
        try:
            check_limits(settings.grid_shape, settings.cascades, settings.grid_format,
                         settings.geometry_volume != "off", 0, 0)
            check_memory(settings, DEFAULT_MEMORY_BUDGET)
        except ValueError as exc:
            return f"configuration {side}: {exc}"
    return None


def load_layout(path: Path | None = None) -> tuple[str | None, str | None]:
    """(the dock layout's text for imgui, the problem) from one read of the file, checked
    before imgui loads it (imgui asserts, and the process ends, on a layout it cannot
    use). (None, None) when there is no file; a file that fails is set aside and the
    problem says why and where (the default layout is then built)."""
    path = path or layout_path()
    if not os.path.lexists(path):
        return None, None
    try:
        text = read_text(path, "layout file")
        check_layout(text)
    except (UserFileError, LayoutFileError) as exc:
        return None, _setting_aside(path, str(exc), "layout")
    return text, None


def check_layout_file(path: Path | None = None) -> str | None:
    """:func:`load_layout`'s problem alone: None when the layout file is fine or absent."""
    return load_layout(path)[1]


def save_layout(text: str, path: Path | None = None) -> None:
    """Write the dock layout atomically, with a temporary of this process's own."""
    path = path or layout_path()
    path.parent.mkdir(parents=True, exist_ok=True)
    write_atomically(path, text)


def save_state(state: AppState, path: Path | None = None) -> None:
    """Write the settings file atomically (a crash never leaves half a file; two windows
    saving at once each write their own temporary, so neither sees an empty file)."""
    path = path or settings_path()
    path.parent.mkdir(parents=True, exist_ok=True)
    write_atomically(path, json.dumps(state_to_dict(state), indent=2))
