"""The settings schema's kinds (explorer/schema.py): what each accepts, what it
refuses with a message naming the field, the value and the allowed range."""

from __future__ import annotations

import math

import pytest

from explorer.schema import SettingError, Spec

CONE = Spec(kind="range2", low=0.0, low_open=True, high=80.0, optional=True,
            doc="inner and outer half-angles")


@pytest.mark.parametrize("value, expected", [
    ((30, 60), (30.0, 60.0)),
    ([0, 45.5], (0.0, 45.5)),          # a TOML or JSON array
    ((20.0, 20.0), (20.0, 20.0)),      # a hard edge: both angles equal
    ((0.0, 80.0), (0.0, 80.0)),        # both ends of the range
    (None, None),                      # optional: the scene's own
])
def test_range2_accepts_an_ordered_pair_in_its_range(value, expected):
    assert CONE.check("cone", value) == expected


@pytest.mark.parametrize("value", [
    (60, 30),                          # out of order
    (-1, 30), (10, 80.5),              # out of range
    (0, 0),                            # low_open: the second must exceed low
    (10, math.nan), (10, math.inf),
    (True, 30), ("10", 30), (10,), (10, 20, 30), 45, "30,60", {"a": 1, "b": 2},
])
def test_range2_refuses_with_the_allowed_range_named(value):
    with pytest.raises(SettingError) as caught:
        CONE.check("cone", value)
    assert caught.value.field == "cone"
    assert str(caught.value).startswith(
        "cone must be two numbers [first, second] with 0 <= first <= second <= 80, "
        "second > 0 or None, got ")


def test_range2_needs_both_ends():
    with pytest.raises(ValueError, match="both low and high"):
        Spec(kind="range2", low=0.0, doc="x")
    closed = Spec(kind="range2", low=1.0, high=2.0, doc="x")
    assert closed.allowed() == "two numbers [first, second] with 1 <= first <= second <= 2"
    assert closed.check("pair", (1, 1)) == (1.0, 1.0)     # low not open: an empty pair


def test_transforms_are_checked_by_the_function_their_declaration_gives():
    """The schema imports nothing of the project (it sits below the scene and the LPV in
    tests/test_import_graph.py): a transforms field brings its own check."""
    from explorer.scene.objects import check_transforms

    with pytest.raises(ValueError, match="needs parse"):
        Spec(kind="transforms", doc="moved objects")
    moved = Spec(kind="transforms", parse=check_transforms, doc="moved objects")
    assert moved.check("objects", {"box": [1, 2, 3]}) == (
        ("box", (1.0, 2.0, 3.0, 0.0, 0.0, 0.0, 1.0, 1.0, 1.0)),)
    with pytest.raises(SettingError, match="objects must be a table of object names"):
        moved.check("objects", {"box": [1, 2]})
