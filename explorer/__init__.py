"""lpv-explorer: an interactive explorer of Light Propagation Volumes.

The scripting API is :mod:`explorer.lpv` (``render``, ``Pipeline``, ``Settings``,
``Corrections``, ``FrameResult``, ``GridSpec``, ``VplArrays``, ``inject``, ``propagate``,
…: its ``__all__``); each of its names is also reachable from here
(``explorer.render(...)``), imported on first use so that ``import explorer`` stays light
for the command line and the code generator.
"""

__version__ = "0.1.0"


def _api() -> list[str]:
    import explorer.lpv

    return list(explorer.lpv.__all__)


def __getattr__(name: str):
    if not name.startswith("_") and name in _api():
        import explorer.lpv

        return getattr(explorer.lpv, name)
    raise AttributeError(f"module 'explorer' has no attribute {name!r}")


def __dir__() -> list[str]:
    return sorted([*globals(), *_api()])
