"""``lpv-explorer export-mitsuba SCENE OUT.xml|OUT.py``: the scene as Mitsuba 3 renders it.

Writes the scene (``.xml`` for ``mitsuba OUT.xml``, ``.py`` for ``python OUT.py``, which
loads it with ``mi.load_dict``) and, in the folder ``OUT-files/`` beside it (its name
derived from OUT's, so nothing else beside OUT is touched), ``scene.ply`` (the triangles
with their linear albedo), the textures and one falloff texture per spot light
(explorer/truth/mitsuba_scene.py says how every light, the camera and the surfaces map
onto Mitsuba's plugins). A folder of that name that an export did not make is never
written into; files an earlier export put there and this one does not are removed. Mitsuba is
not needed to export. The scene's overrides (``--lights``, ``--camera``, ``--object``,
the spot cone, ``--size``) apply as in ``render``.
"""

from __future__ import annotations

import argparse
import sys
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
                        help="the Mitsuba scene to write: .xml or .py (its PLY meshes and "
                             "textures go into the folder OUT-files/ beside it)")
    keep = set(SCENE_FIELDS)
    options.add_setting_options(
        parser, exclude=[f.name for f in fields(Settings) if f.name not in keep])


def main(args: argparse.Namespace) -> int:
    from explorer.commands.compare import load_scene
    from explorer.truth.mitsuba_scene import (
        EXPORT_SUFFIXES,
        ExportError,
        companion_folder,
        export_scene,
    )

    base = options.settings_from_args(args, Settings(scene=args.scene))
    options.check_scene(base.scene)
    with options.Outputs("OUT") as outputs:
        out = outputs.file(args.out, EXPORT_SUFFIXES)
        earlier, sharers = earlier_export(companion_folder(out), out)
        folder = outputs.folder(companion_folder(out), option="OUT")
        scene = load_scene(base)
        try:
            exported = export_scene(scene, base.width, base.height)
            contents = exported.contents(out, sharers)
        except ExportError as exc:
            raise options.CommandError(exc) from None
        if sharers:
            check_shared(folder, sharers, earlier, contents)
        for path, data in contents.items():
            outputs.write(path, lambda p, data=data: p.write_bytes(data))
        for name in earlier - set(exported.files):
            outputs.remove(folder / name)
    for warning in exported.warnings:
        print(f"warning: {warning}", file=sys.stderr)
    print(f"wrote {out} and {len(exported.files)} file(s) in {folder}/ "
          f"({base.width}×{base.height} px, {scene.triangle_count} triangles, "
          f"{len(scene.lights)} light(s))")
    if exported.integrator != "path":
        print(f"one-sided surfaces: render with python {folder}/lpv_one_sided.py {out} "
              f"(it registers their plugin; stock mitsuba does not know it)"
              if out.suffix == ".xml" else "one-sided surfaces: the script registers "
              "their plugin from its folder")
    return 0


def earlier_export(folder: Path, out: Path) -> tuple[set[str], tuple[str, ...]]:
    """The files an earlier export put in ``folder`` (its listing) and the other scene
    files beside ``out`` that still use them; refuses a folder of that name the export
    did not make (a :class:`options.CommandError` naming it)."""
    from explorer.safe_files import UserFileError, read_text
    from explorer.truth.mitsuba_scene import LISTING_SCENE, OWNER_FILE

    if not folder.is_dir() or not any(folder.iterdir()):
        return set(), ()
    try:
        listing = read_text(folder / OWNER_FILE, "export listing", 64 * 1024)
    except UserFileError:
        raise options.CommandError(
            f"OUT: {folder}/ exists and was not made by export-mitsuba (no {OWNER_FILE} "
            f"in it), so its files are not replaced; move it or give another OUT") from None
    lines = listing.splitlines()
    owners = [line[len(LISTING_SCENE):] for line in lines if line.startswith(LISTING_SCENE)]
    sharers = tuple(name for name in owners if name != out.name and Path(name).name == name
                    and (out.parent / name).exists())
    # only plain names: a listing never reaches outside its folder
    return {name for name in lines if name and Path(name).name == name
            and not name.startswith((".", "#"))}, sharers


def check_shared(folder: Path, sharers: tuple[str, ...], earlier: set[str],
                 contents: dict[Path, bytes]) -> None:
    """Refuse (one line) an export that would change or remove a file of ``folder`` that
    the scene files ``sharers`` (``NAME.py`` beside ``NAME.xml``) still use."""
    from explorer.truth.mitsuba_scene import OWNER_FILE

    ours = {path.name: data for path, data in contents.items()
            if path.parent == folder and path.name != OWNER_FILE}
    changed = sorted(name for name in earlier | set(ours) if name not in ours
                     or not (folder / name).is_file()
                     or (folder / name).read_bytes() != ours[name])
    if changed:
        raise options.CommandError(
            f"OUT: {folder}/ holds the files of {folder.parent / sharers[0]} (exported "
            f"before) and this export would change {changed[0]}; give OUT another name or "
            f"remove {sharers[0]} first")
