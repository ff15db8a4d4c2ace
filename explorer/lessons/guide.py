"""The generated parts of docs/AUTHORING.md, the lesson authors' guide: the live value
names, the figure kinds and their parameters, the ``[steps.show]`` and ``[settings]``
fields, the scenes, views, plots, presets and operators, and the example lesson (the one
``lpv-explorer lessons new`` writes), each read from its registry so the guide cannot
drift from what the loader accepts::

    python -m explorer.lessons.guide            # rewrite the generated parts
    python -m explorer.lessons.guide --check    # exit 1 when docs/AUTHORING.md is stale

A generated part sits between ``<!-- generated: NAME -->`` and ``<!-- end: NAME -->``;
the prose around it is written by hand.
"""

from __future__ import annotations

import argparse
import re
import sys
from collections.abc import Callable
from pathlib import Path

GUIDE = Path(__file__).resolve().parents[2] / "docs" / "AUTHORING.md"
"""The guide in a checkout."""
REGENERATE = "python -m explorer.lessons.guide"
_BLOCK = re.compile(r"(<!-- generated: ([a-z-]+) -->\n)(.*?)(<!-- end: \2 -->)", re.S)


def _cell(text: object) -> str:
    """``text`` fit for a markdown table cell (one line, pipes escaped)."""
    return " ".join(str(text).split()).replace("|", "\\|")


def _toml(value: object) -> str:
    """``value`` as a lesson file writes it (true, "text", [1, 2])."""
    if isinstance(value, bool):
        return "true" if value else "false"
    if isinstance(value, str):
        return '"' + value.replace("\\", "\\\\").replace('"', '\\"') + '"'
    if isinstance(value, (tuple, list)):
        return "[" + ", ".join(_toml(item) for item in value) + "]"
    return "(none)" if value is None else f"{value:g}" if isinstance(value, float) \
        else str(value)


def _allowed(spec) -> str:
    text = spec.allowed()
    return text.removesuffix(" or None") + (" (leave it out: the default)"
                                            if spec.optional else "")


def live_values() -> str:
    """Every live value name a lesson may quote, by source."""
    from explorer.lessons import live_values as values
    from explorer.lessons.marks import READOUTS

    table = values.table()
    lines = ["| name | unit | what it is |", "|---|---|---|"]
    for name, quantity in table.items():
        if name.startswith(("settings.", "corrections.")):
            continue
        lines.append(f"| `{name}` | {_cell(quantity.unit)} | {_cell(quantity.doc)} |")
    settings = sorted(name for name in table if name.startswith("settings."))
    switches = sorted(name for name in table if name.startswith("corrections."))
    lines += ["", "Configuration (the settings on screen): "
              + ", ".join(f"`{name}`" for name in settings) + ".", "",
              "Correction switches (on or off): " + ", ".join(f"`{name}`" for name in switches)
              + ".", "", "At a mark with a normal, `mark.<id>.<readout>`:", "",
              "| readout | unit | what it is |", "|---|---|---|"]
    lines += [f"| `{name}` | {_cell(unit)} | {_cell(doc)} |"
              for name, (doc, unit) in READOUTS.items()]
    return "\n".join(lines)


def figure_kinds() -> str:
    """Every figure kind, its title and its parameters."""
    from explorer.figure_params import FIGURE_KINDS, schema

    parts = []
    for kind in FIGURE_KINDS:
        plots = " It plots the frames on screen (A, and B while the step compares)." \
            if kind.results else ""
        parts += [f"#### `{kind.name}`: {kind.title}", "", f"Parameters:{plots}", "",
                  "| key | allowed | default | what it sets |", "|---|---|---|---|"]
        parts += [f"| `{info.name}` | {_cell(_allowed(info.spec))} | "
                  f"`{_cell(_toml(info.default))}` | {_cell(info.doc)} |"
                  for info in schema(kind.params)]
        parts.append("")
    return "\n".join(parts).rstrip()


def _spec_table(fields: dict, skip: tuple[str, ...] = ()) -> str:
    lines = ["| key | allowed | what it sets |", "|---|---|---|"]
    lines += [f"| `{name}` | {_cell(_allowed(spec))} | {_cell(spec.doc)} |"
              for name, spec in fields.items() if name not in skip]
    return "\n".join(lines)


def show_fields() -> str:
    """The ``[steps.show]`` keys (the overlays' declarations)."""
    from explorer.overlay_params import READER_FIELDS, OverlayState
    from explorer.schema import specs

    return _spec_table(specs(OverlayState), READER_FIELDS)


def settings_fields() -> str:
    """The ``[settings]`` keys (the Settings declarations, less those a lesson sets with
    keys of its own)."""
    from explorer.lessons.reader import OWN_KEYS
    from explorer.lpv.settings import Settings
    from explorer.schema import specs

    return _spec_table(specs(Settings), (*OWN_KEYS, "corrections"))


def choices() -> str:
    """Scenes, views, plots, presets, try-this modes, check operators."""
    from explorer.lessons.checks import OPERATORS
    from explorer.lessons.model import STEP_VIEWS, TRY_COMPARES
    from explorer.lpv.corrections import CORRECTIONS
    from explorer.lpv.settings import PLOTS, PRESETS
    from explorer.scene.builtin import BUILTIN_SCENES

    def names(items) -> str:
        return ", ".join(f"`{item}`" for item in items)

    lines = [f"* `scene`: a built-in scene, {names(BUILTIN_SCENES)}, or a path;",
             f"* `view`: {names(STEP_VIEWS)};",
             f"* `plot`: {names(PLOTS)};",
             f"* `corrections` and `compare` presets: {names(PRESETS)};",
             "* correction switches (`corrections = {preset = ..., <switch> = false}`, a "
             f"try-this's `corrections.<switch>`): {names(e.name for e in CORRECTIONS)};",
             f"* a try-this's `compare`: {names(TRY_COMPARES)};",
             f"* a check's `op`: {names(OPERATORS)}."]
    return "\n".join(lines)


def example() -> str:
    """The lesson ``lessons new "First light"`` writes, as a TOML block."""
    from explorer.lessons.template import new_lesson

    return "```toml\n" + new_lesson("First light")[1] + "```"


SECTIONS: dict[str, Callable[[], str]] = {
    "example": example, "choices": choices, "live-values": live_values,
    "figure-kinds": figure_kinds, "show-fields": show_fields,
    "settings-fields": settings_fields,
}


def render(text: str) -> str:
    """``text`` (the guide) with every generated part made anew; a part the guide lacks
    is an error (the prose must say where it goes)."""
    found = {match.group(2) for match in _BLOCK.finditer(text)}
    missing = [name for name in SECTIONS if name not in found]
    if missing:
        raise ValueError(f"the guide has no place for {missing} (<!-- generated: NAME --> "
                         "... <!-- end: NAME -->)")

    def fill(match: re.Match) -> str:
        name = match.group(2)
        if name not in SECTIONS:
            raise ValueError(f"the guide names an unknown generated part {name!r}")
        return f"{match.group(1)}{SECTIONS[name]()}\n{match.group(4)}"

    return _BLOCK.sub(fill, text)


def stale(path: Path = GUIDE) -> bool:
    """Whether the guide at ``path`` differs from what :func:`render` makes of it."""
    text = path.read_text(encoding="utf-8")
    return render(text) != text


def main(argv: list[str] | None = None) -> int:
    parser = argparse.ArgumentParser(prog=REGENERATE, description=__doc__.split("\n\n")[0])
    parser.add_argument("--check", action="store_true",
                        help="exit 1 when docs/AUTHORING.md is not what the registries make")
    args = parser.parse_args(argv)
    text = GUIDE.read_text(encoding="utf-8")
    fresh = render(text)
    if args.check:
        if fresh != text:
            print(f"{GUIDE} is stale: run {REGENERATE}", file=sys.stderr)
            return 1
        print(f"{GUIDE} is up to date")
        return 0
    if fresh != text:
        GUIDE.write_text(fresh, encoding="utf-8")
        print(f"wrote {GUIDE}")
    else:
        print(f"{GUIDE} is up to date")
    return 0


if __name__ == "__main__":  # pragma: no cover
    raise SystemExit(main())
