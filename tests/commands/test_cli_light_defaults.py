"""A point or spot light gets the same defaults from a scene file's ``[[lights]]`` table
as from ``--light`` (both go through ``explorer.scene.lights.default_flux`` and
``new_light``): the same light, flux to the last bit."""

from __future__ import annotations

import numpy as np
import pytest

from explorer.cli import build_parser
from explorer.commands.options import settings_from_args
from explorer.scene import load_scene

OTHER_KIND = {"spot": "point", "point": "spot", "directional": "spot"}


def _scene_file(tmp_path, kind: str, position, target, stem: str):
    lines = ["builtin = 'cornell'", "[[lights]]", f"kind = '{kind}'", "name = 'key'",
             f"position = {list(position)}"]
    if target is not None:
        lines.append(f"target = {list(target)}")
    path = tmp_path / f"{stem}.toml"
    path.write_text("\n".join(lines) + "\n")
    return str(path)


def _from_option(tmp_path, kind: str, position, target):
    """The light ``--light`` makes on a scene whose light 'key' is of another kind."""
    base = _scene_file(tmp_path, OTHER_KIND[kind], (0.1, 0.4, 0.2), (0.0, 0.0, 0.0), "other")
    text = f"{kind}:{','.join(map(str, position))}"
    if target is not None:
        text += f":{','.join(map(str, target))}"
    args = build_parser().parse_args(["render", "--scene", base, "--light", text])
    settings = settings_from_args(args)
    return load_scene(base).for_settings(settings).light


CASES = [("spot", (0.3, 0.9, -0.2), (0.0, 0.0, 0.1)),
         ("point", (0.3, 0.9, -0.2), None),
         ("point", (0.01, 0.2, 0.0), None),       # near the box's centre: the nearest floor
         ("directional", (0.3, 0.9, -0.2), (0.0, 0.0, 0.1))]


@pytest.mark.parametrize("kind, position, target", CASES,
                         ids=[f"{k}-{i}" for i, (k, _, _) in enumerate(CASES)])
def test_scene_file_and_light_option_give_equal_lights(tmp_path, kind, position, target):
    from_file = load_scene(_scene_file(tmp_path, kind, position, target, "file")).light
    from_option = _from_option(tmp_path, kind, position, target)
    assert from_file.kind == from_option.kind == kind
    assert from_file == from_option                   # every field, the flux exactly
    assert from_file.flux > 0


def test_a_point_light_near_the_centre_is_lit_for_a_quarter_radius():
    """The one rule both paths share: 2 W/m² at the box's centre, at least a quarter of its
    half-diagonal away (a light at the centre would otherwise get almost no flux)."""
    from explorer.scene.lights import DEFAULT_IRRADIANCE, POINT_LIGHT_NEAREST, default_flux

    scene = load_scene("cornell")
    lo, hi = np.asarray(scene.bounds_min), np.asarray(scene.bounds_max)
    centre, radius = 0.5 * (lo + hi), 0.5 * float(np.linalg.norm(hi - lo))
    flux = default_flux("point", centre, None, lo, hi)
    nearest = POINT_LIGHT_NEAREST * radius
    assert flux == pytest.approx(4 * np.pi * nearest ** 2 * DEFAULT_IRRADIANCE, rel=1e-12)
    far = centre + np.array([0.0, 0.0, 2.0 * nearest])
    assert default_flux("point", far, None, lo, hi) == pytest.approx(
        4 * np.pi * (2.0 * nearest) ** 2 * DEFAULT_IRRADIANCE, rel=1e-12)
