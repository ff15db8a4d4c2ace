"""The LPV passes. ``inject`` and ``propagate`` run one GPU pass on numpy input (a headless
context is created on first use when ``ctx`` is None); ``explorer.lpv.reference`` holds the
same functions in pure numpy."""

from explorer.lpv.inject import inject
from explorer.lpv.propagate import propagate

__all__ = ["inject", "propagate"]
