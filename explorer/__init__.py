"""lpv-explorer: an interactive explorer of Light Propagation Volumes.

The scripting API is :mod:`explorer.lpv` (``render``, ``Pipeline``, ``Settings``,
``Corrections``, ``FrameResult``, ``inject``, ``propagate``); its names are also reachable
from here (``explorer.render(...)``), imported on first use so that ``import explorer``
stays light for the command line and the code generator.
"""

__version__ = "0.1.0"

_API = ("Corrections", "FrameResult", "Pipeline", "Settings", "inject", "propagate",
        "render")


def __getattr__(name: str):
    if name in _API:
        import explorer.lpv

        return getattr(explorer.lpv, name)
    raise AttributeError(f"module 'explorer' has no attribute {name!r}")


def __dir__() -> list[str]:
    return sorted([*globals(), *_API])
