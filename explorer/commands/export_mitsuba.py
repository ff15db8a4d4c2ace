"""``lpv-explorer export-mitsuba SCENE OUT.xml|OUT.py``: the scene as Mitsuba 3 renders it.

Writes the scene (``.xml`` for ``mitsuba OUT.xml``, ``.py`` for ``python OUT.py``, which
loads it with ``mi.load_dict``) and beside it ``scene.ply`` (the triangles with their
linear albedo) and one falloff texture per spot light (explorer/truth/mitsuba_scene.py
says how every light, the camera and the surfaces map onto Mitsuba's plugins). Mitsuba is
not needed to export. The scene's overrides (``--lights``, ``--camera``, ``--object``,
the spot cone, ``--size``) apply as in ``render``.
"""

from __future__ import annotations

import argparse
from dataclasses import fields
from pathlib import Path

from explorer.commands import options
from explorer.lpv.settings import Settings

SCENE_FIELDS = ("lights", "light", "camera", "light_flux", "spot_cone", "spot_cone_degrees",
                "object_transforms", "width", "height")
"""The Settings fields that change what is exported (the rest are the LPV's)."""


def add_arguments(parser: argparse.ArgumentParser) -> None:
    parser.add_argument("scene", metavar="SCENE",
                        help=options.scene_help("a built-in scene name or a mesh file."))
    parser.add_argument("out", metavar="OUT", type=Path,
                        help="the Mitsuba scene to write: .xml or .py (its PLY mesh and "
                             "spot textures go beside it)")
    keep = set(SCENE_FIELDS)
    options.add_setting_options(
        parser, exclude=[f.name for f in fields(Settings) if f.name not in keep])


def main(args: argparse.Namespace) -> int:
    from explorer.commands.compare import load_scene
    from explorer.truth.mitsuba_scene import EXPORT_SUFFIXES, ExportError, export_scene

    base = options.settings_from_args(args, Settings(scene=args.scene))
    options.check_scene(base.scene)
    with options.Outputs("OUT") as outputs:
        out = outputs.file(args.out, EXPORT_SUFFIXES)
        scene = load_scene(base)
        try:
            exported = export_scene(scene, base.width, base.height)
            contents = exported.contents(out)
        except ExportError as exc:
            raise options.CommandError(exc) from None
        for path, data in contents.items():
            outputs.write(path, lambda p, data=data: p.write_bytes(data))
    names = ", ".join(path.name for path in contents)
    print(f"wrote {names} to {out.parent}/ ({base.width}×{base.height} px, "
          f"{scene.triangle_count} triangles, {len(scene.lights)} light(s))")
    return 0

