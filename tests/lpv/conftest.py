"""The gather tests' scene as a module fixture (tests/gather_cases.py builds it)."""

import pytest
from gather_cases import gather_scene


@pytest.fixture(scope="module")
def setup(gl_context):
    yield from gather_scene(gl_context)
