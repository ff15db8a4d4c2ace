"""The import graph of every package (``explorer/`` and ``derivations/``): no circles,
arrows only downwards, no private names borrowed across modules. Read from the source with
:mod:`ast` (imports inside functions count too: a lazy import is still a dependency)."""

from __future__ import annotations

import ast
from functools import cache
from pathlib import Path

ROOT = Path(__file__).resolve().parent.parent
PACKAGES = ("explorer", "derivations")
LAYERS = (
    ("derivations",),
    ("explorer.resources", "explorer.safe_files", "explorer.stop_signals", "explorer.schema",
     "explorer.derived", "explorer.derived_table"),
    ("explorer.gl",),
    ("explorer.scene",),
    ("explorer.lpv",),
    ("explorer.truth", "explorer.lessons", "explorer.figure_params", "explorer.overlay_params",
     "explorer.exchange"),
    ("explorer.ui",),
    ("explorer.site",),
    ("explorer.commands",),
    ("explorer.cli", "explorer.__main__", "explorer"),
)
"""Bottom to top: a module may import its own package and the layers below it. Plain data
first (the generated derivation table, the corrections registry), which the derivations
read and check; the derivations feed the constants (the code generator never imports the
LPV); the scene is data the LPV passes read; truth (the reference) and lessons read both;
the window, the web site (which renders what the window shows) and the commands sit on
top."""


@cache
def _tree(path: Path) -> ast.Module:
    """The parsed source of ``path``, once per run (every check reads every module)."""
    return ast.parse(path.read_text(encoding="utf-8"))


def _modules() -> dict[str, Path]:
    found = {}
    for path in (path for package in PACKAGES for path in (ROOT / package).rglob("*.py")):
        parts = path.relative_to(ROOT).with_suffix("").parts
        name = ".".join(parts[:-1] if parts[-1] == "__init__" else parts)
        found[name] = path
    return found


def _imports(path: Path, known: dict[str, Path]) -> list[tuple[str, list[str], int]]:
    """(module imported, names taken from it, line) for every import of ``path``."""
    result = []
    for node in ast.walk(_tree(path)):
        if isinstance(node, ast.Import):
            result += [(alias.name, [], node.lineno) for alias in node.names]
        elif isinstance(node, ast.ImportFrom) and node.module and node.level == 0:
            names = [alias.name for alias in node.names]
            submodules = [f"{node.module}.{n}" for n in names if f"{node.module}.{n}" in known]
            plain = [n for n in names if f"{node.module}.{n}" not in known]
            if plain:    # `from explorer import lessons` takes a module, not the package
                result.append((node.module, plain, node.lineno))
            result += [(module, [], node.lineno) for module in submodules]
    return result


@cache
def _graph() -> dict[str, set[str]]:
    """Module -> the modules it imports (built once: the checks only read it)."""
    known = _modules()
    return {name: {target for target, _, _ in _imports(path, known)
                   if target in known and target != name}
            for name, path in known.items()}


def _layer(module: str) -> int:
    best, rank = -1, None
    for index, prefixes in enumerate(LAYERS):
        for prefix in prefixes:
            if (module == prefix or module.startswith(prefix + ".")) and len(prefix) > best:
                best, rank = len(prefix), index
    assert rank is not None, f"{module} is in no layer of LAYERS"
    return rank


def _package(module: str) -> str:
    """``explorer.<package>`` (or the top-level module), or ``derivations``."""
    parts = module.split(".")
    return ".".join(parts[:2]) if parts[0] == "explorer" else parts[0]


def test_no_package_has_an_import_circle():
    graph = _graph()
    state: dict[str, str] = {}
    circles = []

    def visit(node: str, trail: list[str]) -> None:
        state[node] = "open"
        for target in sorted(graph[node]):
            if state.get(target) == "open":
                circles.append(trail[trail.index(target):] + [target])
            elif target not in state:
                visit(target, trail + [target])
        state[node] = "done"

    for module in sorted(graph):
        if module not in state:
            visit(module, [module])
    assert circles == [], "import circles: " + "; ".join(" -> ".join(c) for c in circles)


def test_every_import_points_down_the_layers():
    graph = _graph()
    upward = [f"{a} -> {b}" for a, targets in sorted(graph.items()) for b in sorted(targets)
              if _package(a) != _package(b) and _layer(b) > _layer(a)]
    assert upward == []


LPV_PARTS = {
    "explorer.lpv.twin": ("explorer.lpv.twin",),
    "explorer.lpv.passes": ("explorer.lpv.passes", "explorer.lpv.twin"),
}
"""Inside explorer/lpv/: what each part may import of the package besides the shared data
at its top (settings, corrections, grid, cascades, vpl, audit, frame_state...). The numpy
twin is written independently of the GPU passes, so it imports none; the passes import no
frame machinery (the stage list, the stages, the cache keys, the job, the pipeline)."""

FRAME_MACHINERY = ("explorer.lpv.stage_list", "explorer.lpv.stages", "explorer.lpv.cache_keys",
                   "explorer.lpv.job", "explorer.lpv.pipeline", "explorer.lpv.frame")


def _under(module: str, prefix: str) -> bool:
    return module == prefix or module.startswith(prefix + ".")


def test_the_lpv_parts_hold_their_order():
    graph = _graph()
    wrong = []
    for part, allowed in LPV_PARTS.items():
        for module in (m for m in sorted(graph) if _under(m, part)):
            for target in sorted(graph[module]):
                inside = [p for p in ("explorer.lpv.twin", "explorer.lpv.passes")
                          if _under(target, p)]
                if (inside and not any(_under(target, a) for a in allowed)) or any(
                        _under(target, f) for f in FRAME_MACHINERY):
                    wrong.append(f"{module} -> {target}")
    assert wrong == []
    assert "explorer.lpv.grid" in graph["explorer.lpv.twin.light_grid"]   # the reader sees it


def test_no_private_name_is_imported_from_another_module():
    known = _modules()
    borrowed = [f"{path.relative_to(ROOT)}:{line} imports {name} from {module}"
                for module_name, path in known.items()
                for module, names, line in _imports(path, known)
                for name in names
                if module.split(".")[0] in PACKAGES and module != module_name
                and name.startswith("_")]
    assert borrowed == []


def test_the_checks_see_the_arrows_they_judge():
    """The graph reader finds lazy imports inside functions (the kind the circles were
    made of) and the layers rank what they should."""
    graph = _graph()
    assert "explorer.lpv.pipeline" in graph["explorer.commands.render"]   # inside main()
    assert "explorer.scene" in graph["explorer.lpv.pipeline"]
    assert _layer("explorer.scene.lights") < _layer("explorer.lpv.constants")
    assert _layer("explorer.ui.app") < _layer("explorer.commands.run")
    assert "derivations.correction_registry" in graph["derivations.codegen"]
    assert "derivations.names" in graph["explorer.derived"]
    assert _layer("derivations.codegen") < _layer("explorer.lpv.corrections")


def test_the_code_generator_reads_no_lpv_module():
    """It writes explorer/lpv/constants.py, so it must run whatever state the LPV package
    is in (a stale or missing generated file included)."""
    graph = _graph()
    reached, todo = set(), ["derivations.codegen"]
    while todo:
        module = todo.pop()
        for target in graph[module] - reached:
            reached.add(target)
            todo.append(target)
    assert sorted(m for m in reached if m.startswith("explorer.lpv")) == []


def test_the_architecture_page_draws_these_layers():
    """docs/ARCHITECTURE.md's layer table lists exactly LAYERS, row by row: the picture a
    reader trusts is the one this test enforces."""
    import re

    text = (ROOT / "docs" / "ARCHITECTURE.md").read_text(encoding="utf-8")
    rows = re.findall(r"^\| (\d+) \| (.+?) \| .+ \|$", text, re.M)
    drawn = [tuple(re.findall(r"`([\w.]+)`", modules)) for _, modules in rows]
    assert [int(number) for number, _ in rows] == list(range(len(LAYERS)))
    assert drawn == [tuple(layer) for layer in LAYERS], (
        "docs/ARCHITECTURE.md's layer table differs from LAYERS")


BORROWED_PRIVATE = {
    ("explorer/scene/meshes.py", "mesh._cache"):
        "trimesh keeps a file's own vertex normals only in its cache; asking for them "
        "would compute smoothed ones",
    ("explorer/commands/overhead_bench.py", "Job._run_unit"):
        "the overhead benchmark wraps a job's unit to time its Python side, and puts it back",
    ("explorer/commands/units_driver.py", "Job._run_unit"):
        "the unit benchmark wraps one job's units to time each with its GL work finished",
    ("explorer/ui/drawn_lists.py", "draw_list._owner_name"):
        "imgui's ImDrawList has no public name: its _OwnerName, the window's name, is what "
        "matches one frame's list with the next frame's",
}
"""The only reads of another object's private attribute, each with its reason."""


def _own(value: ast.expr) -> bool:
    """``self``, ``cls`` or ``super()``: the object itself."""
    if isinstance(value, ast.Name):
        return value.id in ("self", "cls")
    return isinstance(value, ast.Call) and isinstance(value.func, ast.Name) \
        and value.func.id == "super"


def test_no_module_reaches_into_another_objects_private_state():
    """``x._name`` only on ``self``/``cls``: a window module (or any other) that needs
    another object's state asks through a public member, so the state's owner can see
    who depends on it."""
    found = []
    for _name, path in _modules().items():
        for node in ast.walk(_tree(path)):
            if isinstance(node, ast.Attribute) and node.attr.startswith("_") \
                    and not node.attr.startswith("__") \
                    and not _own(node.value):
                found.append((path.relative_to(ROOT).as_posix(), ast.unparse(node), node.lineno))
    wrong = [f"{where}:{line}: {what}" for where, what, line in found
             if (where, what) not in BORROWED_PRIVATE]
    assert not wrong, "private state read from outside its object:\n" + "\n".join(wrong)
    assert {(where, what) for where, what, _ in found} == set(BORROWED_PRIVATE)


def test_the_derivations_import_nothing_of_the_explorer():
    """The bottom layer: what the code generator needs about the corrections is its own
    (derivations/correction_registry.py), so the derivations run with no explorer code."""
    graph = _graph()
    upward = sorted(f"{a} -> {b}" for a, targets in graph.items() if a.startswith("derivations")
                    for b in targets if b.startswith("explorer"))
    assert upward == []
