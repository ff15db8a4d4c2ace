"""The named exact results of every derivation module.

Each module in :data:`MODULES` exposes ``results() -> list[Result]``; the registry
collects them once (cached) under dotted names ``"<module>.<item>"``. The codegen, the
``lpv-explorer constants`` command and the app read the results only from here.

Examples
--------
>>> from derivations.registry import get
>>> get("solid_angles.front_face").expr
4*atan(sqrt(11)/33)
>>> get("propagation.step_flux_factor_corrected").expr
1
"""

from __future__ import annotations

import difflib
import importlib
from dataclasses import dataclass
from functools import lru_cache

import sympy

# Modules in the order they are listed; each defines ``results()``.
MODULES: tuple[str, ...] = (
    "solid_angles",
    "sh",
    "rsm",
    "corrections",
    "propagation",
    "occlusion",
    "errata",
)


@dataclass(frozen=True)
class Result:
    """One named exact result.

    ``expr`` is a sympy number, expression, ``Eq`` (a formula) or ``ImmutableMatrix``
    (a vector); ``glsl_name`` is set when the codegen emits it as a constant.
    """

    name: str
    expr: sympy.Basic
    statement: str
    module: str
    glsl_name: str | None = None

    @property
    def is_number(self) -> bool:
        """True when ``expr`` is a plain real number (it then has a decimal value)."""
        return isinstance(self.expr, sympy.Expr) and bool(self.expr.is_number)


def result(module: str, item: str, expr: sympy.Basic, statement: str,
           glsl_name: str | None = None) -> Result:
    """Build a :class:`Result` named ``"<module>.<item>"`` (used by the modules)."""
    if not isinstance(expr, sympy.Basic):
        expr = sympy.sympify(expr)
    return Result(f"{module}.{item}", expr, statement, module, glsl_name)


@lru_cache(maxsize=None)
def _index() -> dict[str, Result]:
    index: dict[str, Result] = {}
    glsl_names: dict[str, str] = {}
    for module_name in MODULES:
        module = importlib.import_module(f"derivations.{module_name}")
        for item in module.results():
            if not item.name.startswith(f"{module_name}."):
                raise ValueError(f"result {item.name!r} is not named after its module "
                                 f"{module_name!r}")
            if item.name in index:
                raise ValueError(f"two results are named {item.name!r}")
            if item.glsl_name is not None:
                if item.glsl_name in glsl_names:
                    raise ValueError(f"GLSL name {item.glsl_name} is used by both "
                                     f"{glsl_names[item.glsl_name]} and {item.name}")
                if item.is_number is False:
                    raise ValueError(f"{item.name} has a GLSL name but is not a number")
                glsl_names[item.glsl_name] = item.name
            index[item.name] = item
    return index


def all_results() -> list[Result]:
    """Every result, module by module in :data:`MODULES` order."""
    return list(_index().values())


def names() -> list[str]:
    """Every result name."""
    return list(_index())


def get(name: str) -> Result:
    """The result called ``name``; ``KeyError`` names the closest matches otherwise."""
    index = _index()
    try:
        return index[name]
    except KeyError:
        close = difflib.get_close_matches(name, index, n=6, cutoff=0.5)
        if not close:
            prefix = name.split(".", 1)[0]
            close = [n for n in index if n.startswith(prefix + ".")][:12]
        hint = f"; did you mean {', '.join(close)}?" if close else ""
        raise KeyError(f"no derivation result named {name!r}{hint} "
                       f"(`lpv-explorer constants` lists all {len(index)} names)") from None


def latex(name: str) -> str:
    """LaTeX of the named result (a formula keeps its ``=``)."""
    return sympy.latex(get(name).expr)
