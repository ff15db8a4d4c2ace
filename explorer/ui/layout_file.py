"""The dock layout file (``imgui.ini``) checked before imgui reads it.

imgui trusts its ini file: a ``[Docking][Data]`` node whose ``Parent=`` does not exist
ends the process with ``IM_ASSERT(ancestor_node->Size.x > 0 ...)``, and a duplicated node
id or a split node with one child crashes it (measured with imgui-bundle's imgui 1.92).
:func:`check_layout` parses that section as imgui does (``DockSettingsHandler_ReadLine``
in imgui.cpp: ``DockSpace``/``DockNode`` lines of ``key=value`` fields) and refuses what
imgui cannot use; the app then sets the file aside and builds its default layout.
"""

from __future__ import annotations

import re
from dataclasses import dataclass, field

SHORT = (-32768, 32767)
"""imgui stores node positions and sizes as 16-bit integers (ImVec2ih)."""
_SECTION = re.compile(r"^\[([^\]]*)\]\[(.*)\]$")
_HEX = re.compile(r"^0x[0-9A-Fa-f]{1,8}$")


class LayoutFileError(ValueError):
    """The layout file has something imgui cannot load; the message names the line."""


@dataclass
class DockNode:
    """One ``DockSpace``/``DockNode`` line of the ``[Docking][Data]`` section."""

    id: int
    line: int
    parent: int | None = None
    split: str | None = None
    children: list[int] = field(default_factory=list)


def check_layout(text: str) -> dict[int, DockNode]:
    """The dock nodes of an ``imgui.ini``; :class:`LayoutFileError` when a line is
    malformed or the nodes do not form trees imgui can rebuild: ids unique, every parent
    defined before its children, a split node with exactly two children (and only a split
    node with children), positive sizes within imgui's 16-bit range."""
    nodes: dict[int, DockNode] = {}
    section = None
    for number, raw in enumerate(text.splitlines(), start=1):
        line = raw.strip()
        if not line or line.startswith(";"):
            continue
        match = _SECTION.match(line)
        if match:
            section = match.groups()
            continue
        if section == ("Docking", "Data"):
            node = _parse_node(line, number)
            if node.id in nodes:
                raise LayoutFileError(f"line {number}: dock node id {node.id:#010x} is used "
                                      f"twice (first on line {nodes[node.id].line})")
            if node.parent is not None:
                parent = nodes.get(node.parent)
                if parent is None:
                    raise LayoutFileError(f"line {number}: dock node {node.id:#010x} names "
                                          f"Parent={node.parent:#010x}, which no earlier line "
                                          f"defines")
                parent.children.append(node.id)
            nodes[node.id] = node
    for node in nodes.values():
        if (node.split is None) != (not node.children) or len(node.children) not in (0, 2):
            raise LayoutFileError(
                f"line {node.line}: dock node {node.id:#010x} has {len(node.children)} "
                f"child node(s) and {'Split=' + node.split if node.split else 'no Split'}; "
                f"a split node has exactly two children, any other node none")
    return nodes


def _parse_node(line: str, number: int) -> DockNode:
    kind, _, rest = line.partition(" ")
    if kind not in ("DockSpace", "DockNode"):
        raise LayoutFileError(f"line {number}: expected DockSpace or DockNode, got {kind!r}")
    values: dict[str, str] = {}
    for token in rest.split():
        key, sep, value = token.partition("=")
        if not sep or not value:
            raise LayoutFileError(f"line {number}: expected key=value, got {token!r}")
        values[key] = value
    node = DockNode(_hex(values, "ID", number), number)
    if "Parent" in values:
        node.parent = _hex(values, "Parent", number)
    else:   # a root: imgui reads its position and size
        for key in ("Pos", "Size"):
            if key not in values:
                raise LayoutFileError(f"line {number}: a root dock node needs {key}=x,y")
        _pair(values, "Pos", number, positive=False)
        _pair(values, "Size", number, positive=True)
    if "SizeRef" in values:
        _pair(values, "SizeRef", number, positive=False)
    if "Split" in values:
        node.split = values["Split"][:1]
        if node.split not in ("X", "Y"):
            raise LayoutFileError(f"line {number}: Split must be X or Y, got "
                                  f"{values['Split']!r}")
    return node


def _hex(values: dict[str, str], key: str, number: int) -> int:
    text = values.get(key)
    if text is None or not _HEX.match(text) or int(text, 16) == 0:
        raise LayoutFileError(f"line {number}: {key} must be a non-zero id like 0x0000000A, "
                              f"got {text!r}")
    return int(text, 16)


def _pair(values: dict[str, str], key: str, number: int, positive: bool) -> tuple[int, int]:
    try:
        x, y = (int(part) for part in values[key].split(","))
    except ValueError:
        raise LayoutFileError(f"line {number}: {key} must be two integers x,y, got "
                              f"{values[key]!r}") from None
    low = 1 if positive else (SHORT[0] if key == "Pos" else 0)
    if not all(low <= v <= SHORT[1] for v in (x, y)):
        raise LayoutFileError(f"line {number}: {key}={x},{y} must be in [{low}, {SHORT[1]}]")
    return x, y
