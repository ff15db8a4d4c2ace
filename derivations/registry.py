"""The named exact results of every derivation module.

Each module in :data:`MODULES` exposes ``results() -> list[Result]``; the registry
collects them once (cached) under dotted names ``"<module>.<item>"``, ``<module>`` being
the module's ``MODULE`` (``implementation_switches`` names its results ``corrections.…``,
beside the published formulas it builds on). The codegen, the
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

import importlib
from dataclasses import dataclass
from functools import cache

import sympy
from sympy.printing.latex import LatexPrinter

from derivations.names import unknown_name

# Modules in the order they are listed; each defines ``results()``.
MODULES: tuple[str, ...] = (
    "solid_angles",
    "sh",
    "rsm",
    "corrections",
    "implementation_switches",
    "propagation",
    "neighbours26",
    "occlusion",
    "media",
    "errata",
)


@dataclass(frozen=True)
class Result:
    """One named exact result.

    ``expr`` is a sympy number, expression, ``Eq`` (a formula) or ``ImmutableMatrix``
    (a vector); ``glsl_name`` is set when the codegen emits it as a constant;
    ``printed_decimals``: its rationals with a finite decimal expansion are decimals printed
    in a source (e.g. 0.4006696846), so :func:`latex` typesets them as those decimals.
    """

    name: str
    expr: sympy.Basic
    statement: str
    module: str
    glsl_name: str | None = None
    printed_decimals: bool = False

    @property
    def is_number(self) -> bool:
        """True when ``expr`` is a plain real number (it then has a decimal value)."""
        return isinstance(self.expr, sympy.Expr) and bool(self.expr.is_number)


def result(module: str, item: str, expr: sympy.Basic, statement: str,
           glsl_name: str | None = None, printed_decimals: bool = False) -> Result:
    """Build a :class:`Result` named ``"<module>.<item>"`` (used by the modules)."""
    if not isinstance(expr, sympy.Basic):
        expr = sympy.sympify(expr)
    return Result(f"{module}.{item}", expr, statement, module, glsl_name, printed_decimals)


@cache
def _index() -> dict[str, Result]:
    index: dict[str, Result] = {}
    glsl_names: dict[str, str] = {}
    for module_name in MODULES:
        module = importlib.import_module(f"derivations.{module_name}")
        prefix = getattr(module, "MODULE", module_name)
        for item in module.results():
            if not item.name.startswith(f"{prefix}."):
                raise ValueError(f"result {item.name!r} is not named after its module "
                                 f"{prefix!r}")
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
        raise unknown_name(name, list(index)) from None


def get_one(name: str) -> Result:
    """The result called ``name``, deriving only the modules its prefix names (what
    ``lpv-explorer constants --name`` needs: the whole registry takes seconds of sympy);
    an unknown name falls back to :func:`get`, which names the closest matches."""
    if _index.cache_info().currsize:
        return get(name)
    for module_name in MODULES:
        module = importlib.import_module(f"derivations.{module_name}")
        if name.startswith(f"{getattr(module, 'MODULE', module_name)}."):
            for item in module.results():
                if item.name == name:
                    return item
    return get(name)


class _DecimalLatexPrinter(LatexPrinter):
    """Typesets a rational with a finite decimal expansion (denominator 2^a·5^b) as that
    decimal, exactly: for results that hold numbers printed in a source as decimals."""

    def _print_Rational(self, expr: sympy.Rational) -> str:
        q = int(expr.q)
        for prime in (2, 5):
            while q % prime == 0:
                q //= prime
        if q != 1:
            return super()._print_Rational(expr)
        places = 0
        while (expr * 10 ** places).q != 1:
            places += 1
        digits = str(abs(int(expr * 10 ** places))).rjust(places + 1, "0")
        sign = "-" if expr < 0 else ""
        return f"{sign}{digits[:-places]}.{digits[-places:]}" if places else sign + digits


def latex(name: str) -> str:
    """LaTeX of the named result, always with a left-hand side: a formula keeps its
    ``=``; any other result is written ``symbol = value`` with its symbol from
    :data:`derivations.symbols.SYMBOLS`."""
    from derivations.symbols import SYMBOL_LATEX, SYMBOLS

    item = get(name)
    names = {symbol: SYMBOL_LATEX[symbol.name] for symbol in item.expr.free_symbols
             if isinstance(symbol, sympy.Symbol) and symbol.name in SYMBOL_LATEX}
    if item.printed_decimals:
        body = _DecimalLatexPrinter({"symbol_names": names}).doprint(item.expr)
    else:
        body = sympy.latex(item.expr, symbol_names=names)
    if isinstance(item.expr, sympy.Equality):
        return body
    if name not in SYMBOLS:
        raise KeyError(f"{name} is not a formula and has no symbol in derivations/symbols.py")
    return f"{SYMBOLS[name]} = {body}"
