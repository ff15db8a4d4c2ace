"""``App`` takes its state and one :class:`WindowOptions`: a new way to open a window is a
field of the options (with a default, read by the app), never another constructor
parameter."""

from __future__ import annotations

import ast
import dataclasses
import inspect
from pathlib import Path

from explorer.ui.app import App
from explorer.ui.window_options import WindowOptions

APP_SOURCE = Path(inspect.getfile(App))


def test_app_takes_a_state_and_an_options_object():
    parameters = list(inspect.signature(App.__init__).parameters.values())
    assert [p.name for p in parameters] == ["self", "state", "options"]
    assert "WindowOptions" in str(parameters[2].annotation)
    assert parameters[2].default is None            # App(): the interactive explorer


def _attributes_of(name: str, tree: ast.AST) -> set[str]:
    """Every ``<name>.<attribute>`` the code reads."""
    return {node.attr for node in ast.walk(tree) if isinstance(node, ast.Attribute)
            and isinstance(node.value, ast.Name) and node.value.id == name}


def test_every_option_has_a_default_and_is_read_by_the_app():
    fields = dataclasses.fields(WindowOptions)
    assert all(f.default is not dataclasses.MISSING for f in fields)
    read = _attributes_of("options", ast.parse(APP_SOURCE.read_text(encoding="utf-8")))
    for name, value in vars(WindowOptions).items():     # read through a property
        if isinstance(value, property) and name in read:
            source = inspect.getsource(value.fget)
            read |= _attributes_of("self", ast.parse(inspect.cleandoc("\n" + source)))
    unread = sorted(f.name for f in fields if f.name not in read)
    assert not unread, f"options App never reads: {unread}"
