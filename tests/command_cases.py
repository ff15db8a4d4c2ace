"""A stand-in for ``explorer.lpv.pipeline.Pipeline`` for the commands' tests: flat grey
views, and on the second view whatever :attr:`StandInPipeline.on_second_view` does (raise
``KeyboardInterrupt``, send this process a signal), so a test can stop a command after its
first output was written."""

from __future__ import annotations

import types

import numpy as np


class StandInPipeline:
    """Stands in for Pipeline (``monkeypatch.setattr("explorer.lpv.pipeline.Pipeline",
    StandInPipeline)``)."""

    on_second_view = None
    """Called with no argument when the second view is asked for; None: nothing."""

    def __init__(self, settings, ctx=None):
        self.views = 0

    def __enter__(self):
        return self

    def __exit__(self, *exc):
        return False

    def run(self, settings=None, **options):
        return types.SimpleNamespace(settings=settings, warnings=[])

    def view(self, name, **options):
        self.views += 1
        if self.views == 2 and self.on_second_view is not None:
            type(self).on_second_view()
        return np.full((8, 8, 3), 0.5)
