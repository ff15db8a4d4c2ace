r"""Lesson LaTeX as MathML, so the page needs no script or network to typeset it.

``latex2mathml`` (pure Python) converts the subset the lessons use (fractions, roots,
sub/superscripts, ``\left( \right)``, ``\operatorname``, ``\text``, matrices); the
browser lays MathML Core out natively. The LaTeX source is kept in an ``annotation``
element so copy and screen readers still have it.

>>> "<mfrac>" in to_mathml(r"\frac{1}{2}")
True
"""

from __future__ import annotations

import html
import re

from latex2mathml.converter import convert

LONG_INLINE = 24
"""Inline formulas with this much LaTeX or more may be wider than a phone's column: they
are wrapped in ``<span class="long-math">``, which the stylesheet lets scroll sideways
instead of widening the page."""
_ANNOTATION = re.compile(r"<annotation\b.*?</annotation>", re.S)


class MathError(ValueError):
    """LaTeX the converter cannot read; names the formula."""


def to_mathml(latex: str, display: bool = False) -> str:
    """``latex`` as one ``<math>`` element (``display="block"`` for display math), with
    the source as its TeX annotation."""
    try:
        body = convert(latex, display="block" if display else "inline")
    except Exception as exc:  # noqa: BLE001 - the converter raises several kinds
        raise MathError(f"cannot typeset {latex!r}: {exc}") from None
    # latex2mathml writes <math ...><mrow>...</mrow></math>: wrap the content in a
    # <semantics> so the TeX rides along as an annotation (MathML Core ignores it).
    start = body.index(">") + 1
    end = body.rindex("</math>")
    annotation = (f'<annotation encoding="application/x-tex">{html.escape(latex)}'
                  f"</annotation>")
    markup = f"{body[:start]}<semantics>{body[start:end]}{annotation}</semantics></math>"
    if not display and len(latex) >= LONG_INLINE:
        markup = f'<span class="long-math">{markup}</span>'
    return markup


def strip_annotations(markup: str) -> str:
    """``markup`` without its TeX annotations (what the no-raw-TeX check reads)."""
    return _ANNOTATION.sub("", markup)
