"""``lpv-explorer render``: one frame headlessly, written as PNG (one file per view); with
``--lesson ID --step K`` the frame a lesson step shows, every option given overriding it.
``--time T`` puts the scene's animation paths (its primary light, its animated objects) at
``T`` seconds, ``--fly-through T`` the camera on the scene's camera path (the atrium's) at
parameter ``T`` (one loop per unit).

Numbers out: ``--out x.exr`` or ``x.npy`` writes the view's float data instead of a
picture (explorer/exchange/views.py); ``--dump out.npz`` every stage of the frame as float
arrays with a JSON sidecar ``out.json`` (explorer/exchange/stages.py, sidecar.py).
Numbers in: ``--vpls FILE.npz`` injects an engine's own VPLs, ``--grid0 FILE.npz``
propagates its own injected grid (explorer/exchange/inputs.py has the layout). The
grid-slice PNG carries a scale bar: the flux (or coefficient) at white and the slice's
range."""

from __future__ import annotations

import argparse
from pathlib import Path

from explorer.commands import options
from explorer.commands.lesson_folder import add_folder_option
from explorer.lpv.settings import VIEWS
from explorer.schema import Spec

MIN_PNG_SIZE = 256
"""Views not sized by --size (RSM and grid views) are enlarged by whole pixels to at least
this size."""
CAMERA_VIEWS = ("final", "direct", "indirect", "albedo", "cascade-weights")
TIME = Spec(kind="float", low=0.0, high=1e6,
            doc="Put the scene's animation paths (explorer/scene/animation.py) at this time "
                "in seconds: its primary light and its animated objects move there "
                "(an explicit --object or the light's settings win).")
FLY_THROUGH = Spec(kind="float", low=-1e6, high=1e6,
                   doc="Put the camera on the scene's camera path at this parameter (one "
                       "loop per unit; the atrium's fly-through).")
SLICED_VIEWS = ("grid-slice", "geometry-volume")


def add_arguments(parser: argparse.ArgumentParser) -> None:
    parser.add_argument("--out", default="frame.png", type=Path, metavar="FILE",
                        help="image to write: .png (the picture), .exr or .npy (the view's "
                             "float data: radiance without tone curve, raw grid values; .exr "
                             "needs the OpenEXR package); with several --view, one file per "
                             "view named <stem>-<view><suffix>")
    parser.add_argument("--view", action="append", choices=VIEWS, metavar="VIEW",
                        help=f"what to write (repeatable): {', '.join(VIEWS)}; default: final "
                             f"(with --lesson: the step's view)")
    parser.add_argument("--slice", type=int, dest="z", metavar="Z",
                        help="z slice of the grid views (default: the middle)")
    parser.add_argument("--coefficient", type=int, choices=range(9), metavar="K",
                        help="grid-slice: show SH coefficient K (0..3, or 0..8 with "
                             "--sh-order 2) instead of the flux")
    parser.add_argument("--cascade", type=int, default=None, metavar="K",
                        help="grid views (grid-slice, geometry-volume): show this cascade "
                             "(0 = finest, the default)")
    parser.add_argument("--audit", action="store_true", help="print the energy audit")
    parser.add_argument("--time", type=options.value_type("time", TIME), default=None,
                        metavar="SECONDS", help=options.spec_help(TIME))
    parser.add_argument("--animate", type=_names, default=None, metavar="PATH[,PATH...]",
                        help="with --time: the paths that play (light and/or object "
                             "names; default: every path of the scene)")
    parser.add_argument("--fly-through", type=options.value_type("fly_through", FLY_THROUGH),
                        default=None, metavar="T", help=options.spec_help(FLY_THROUGH))
    numbers = parser.add_argument_group(
        "numbers in and out", "float arrays of every stage, an engine's own VPLs or grid "
        "(the layout: `render --dump`'s arrays and its JSON sidecar)")
    numbers.add_argument("--dump", type=Path, default=None, metavar="FILE.npz",
                         help="also write every stage as float arrays (every light view's "
                              "RSM, view<k>_rsm_* past the first, a point light's six faces "
                              "included; the VPLs with vpl_view, each one's view; grid_0 … "
                              "grid_N, accumulated, geometry volume, irradiance, direct, "
                              "indirect, final) and FILE.json: grid, camera, lights, each RSM "
                              "view's light, face and matrices, settings and what each array "
                              "holds in which units")
    add_input_arguments(numbers)
    group = parser.add_argument_group(
        "lesson steps", "render what a lesson step shows: its scene, settings, corrections "
        "and view; every settings option given (and --preset) overrides the step")
    group.add_argument("--lesson", metavar="ID", help="lesson id, number or file stem")
    group.add_argument("--step", type=int, default=None, metavar="K",
                       help="step number within the lesson (default: 1)")
    add_folder_option(group)
    options.add_setting_options(parser)


def add_input_arguments(group) -> None:
    """``--vpls`` and ``--grid0`` (render and diff)."""
    group.add_argument("--vpls", type=Path, default=None, metavar="FILE.npz",
                       help="inject these VPLs instead of the RSM's: vpl_position, vpl_normal, "
                            "vpl_flux (M, 3) floats; vpl_depth (M,) and vpl_texel_area () "
                            "for the geometry volume; vpl_albedo (M, 3) optional (a dump's "
                            "own arrays); a bad file's problems are listed together, each "
                            "bad row by number")
    group.add_argument("--grid0", type=Path, default=None, metavar="FILE.npz",
                       help="propagate this injected grid instead of the frame's: grid_0 "
                            "(3, N, N, N, 4|9) float, W/sr SH, index [colour, x, y, z, k] on "
                            "the frame's grid (see a dump's sidecar); one cascade, rgba32f")


def frame_inputs(args: argparse.Namespace, settings):
    """``(vpls, grid0)`` from ``--vpls`` and ``--grid0`` (None when not given), checked
    against ``settings`` before anything renders."""
    from explorer.exchange.files import FileFormatError
    from explorer.exchange.inputs import load_grid0, load_vpls

    vpls = grid0 = None
    try:
        if args.vpls is not None:
            vpls = load_vpls(args.vpls, settings.geometry_volume != "off")
        if args.grid0 is not None:
            if settings.cascades != 1:
                raise options.CommandError("--grid0 feeds one grid: use --cascades 1")
            if settings.grid_format != "rgba32f":
                raise options.CommandError("--grid0 needs --grid-format rgba32f (a 16-bit "
                                           "grid would round it)")
            grid0 = load_grid0(args.grid0, settings)
    except FileFormatError as exc:
        raise options.CommandError(exc) from None
    return vpls, grid0


def run_frame(pipeline, settings, progress, args: argparse.Namespace, vpls, grid0,
              keep_steps: bool):
    """The frame, with ``--vpls`` and ``--grid0`` applied (explorer/exchange/inputs.py)."""
    from explorer.exchange.files import FileFormatError
    from explorer.exchange.inputs import check_grid_placement, run_with_grid0

    if grid0 is None:
        return options.run_pipeline(pipeline, settings, progress, keep_steps=keep_steps,
                                    vpls=vpls)
    try:
        result = run_with_grid0(pipeline, settings, grid0, progress, vpls=vpls,
                                check=lambda spec: check_grid_placement(args.grid0, spec))
    except FileFormatError as exc:
        raise options.CommandError(exc) from None
    warn = getattr(progress, "warn", None)       # as options.run_pipeline does
    if warn is not None:
        warn(result.warnings)
    return result


def main(args: argparse.Namespace) -> int:
    from explorer.exchange.files import EXR_MISSING, FLOAT_IMAGE_SUFFIXES, has_openexr
    from explorer.lpv.pipeline import Pipeline
    from explorer.scene import SceneError

    step = _lesson_step(args)
    if step is not None and (args.vpls is not None or args.grid0 is not None):
        raise options.CommandError("--vpls and --grid0 render the frame of the given "
                                   "settings, not a lesson step")
    settings = options.settings_from_args(args, base=step.settings() if step else None)
    views = args.view or [step.view if step else "final"]
    options.check_scene(settings.scene)
    settings = animated(args, settings)
    wanted = _view_options(args, settings, views)
    vpls, grid0 = frame_inputs(args, settings)
    with options.Outputs() as outputs:
        paths = {view: outputs.file(path, options.IMAGE_SUFFIXES + FLOAT_IMAGE_SUFFIXES)
                 for view, path in output_paths(args.out, views).items()}
        if any(path.suffix.lower() == ".exr" for path in paths.values()) and not has_openexr():
            raise options.CommandError(EXR_MISSING)
        dump = None
        if args.dump is not None:
            dump = outputs.file(args.dump, (".npz",), option="--dump")
            outputs.file(dump.with_suffix(".json"), (".json",), option="--dump")
        try:
            with Pipeline(settings) as pipeline, options.Progress("render") as progress:
                result = run_frame(pipeline, settings, progress, args, vpls, grid0,
                                   keep_steps=dump is not None)
                progress.close()
                for view, path in paths.items():
                    _write_view(outputs, path, pipeline, result, step, settings, view, wanted)
                if dump is not None:
                    write_dump(outputs, dump, result)
                if args.audit:
                    print_audit(result)
        except SceneError as exc:
            raise options.CommandError(exc, 2) from None
        except options.render_failures() as exc:
            raise options.CommandError(exc, 1) from None
    return 0


def _write_view(outputs, path: Path, pipeline, result, step, settings, view: str,
                wanted: dict[str, int]) -> None:
    """One view's file: float data (.exr, .npy), or the picture (a grid slice with its
    scale bar)."""
    from explorer.exchange.files import FLOAT_IMAGE_SUFFIXES, write_float_image
    from explorer.exchange.views import FLOAT_VIEWS, float_view

    if path.suffix.lower() in FLOAT_IMAGE_SUFFIXES:
        data = float_view(result, view, positions=result.gbuffer_position,
                          **_sliced(view, wanted))
        outputs.write(path, lambda p: write_float_image(
            p, data, f"lpv-explorer render, view {view}: {FLOAT_VIEWS[view]}"))
        print(f"wrote {path} ({view}: {FLOAT_VIEWS[view]}, {data.shape[1]}×{data.shape[0]})")
        return
    image = _view_image(pipeline, step, settings, view, wanted)
    if view == "grid-slice":
        outputs.write(path, lambda p: write_grid_slice_png(image, result, wanted, p))
    else:
        outputs.write(path, lambda p: write_png(image, p, enlarge=view in _ENLARGED))
    shown = f"{view} against {step.compare_preset}" if step and \
        step.compare_preset and view == step.view else view
    print(f"wrote {path} ({shown})")


def write_dump(outputs, path: Path, result, reference=None, extra: dict | None = None,
               stream=None) -> None:
    """Every stage of ``result`` (its steps kept) into ``path`` and the sidecar beside it
    (explorer/exchange/); ``reference``: compare's reference image."""
    from explorer.exchange.files import write_npz
    from explorer.exchange.sidecar import sidecar, sidecar_path, write_sidecar
    from explorer.exchange.stages import frame_arrays
    from explorer.truth.gbuffer import scene_for

    arrays = frame_arrays(result, reference)
    data = sidecar(result, arrays, scene_for(result.settings), extra,
                   folder=sidecar_path(path).parent)
    outputs.write(path, lambda p: write_npz(p, arrays))
    outputs.write(sidecar_path(path), lambda p: write_sidecar(p, data))
    steps = len(result.steps or ())
    print(f"wrote {path} ({len(arrays)} arrays, grid_0 … grid_{steps - 1}) and "
          f"{sidecar_path(path)}", file=stream)


def _sliced(view: str, chosen: dict[str, int]) -> dict[str, int]:
    """The --slice/--coefficient/--cascade options ``view`` takes."""
    return {k: v for k, v in chosen.items() if view in SLICED_VIEWS
            and (k != "coefficient" or view == "grid-slice")}


def _names(text: str) -> tuple[str, ...]:
    names = tuple(part.strip() for part in text.split(","))
    if not all(names):
        raise argparse.ArgumentTypeError(f"expected path names separated by commas, got "
                                         f"{text!r}")
    return names


def animated(args: argparse.Namespace, settings):
    """``settings`` with ``--time`` (the scene's paths at that time) and ``--fly-through``
    (the camera on its path) applied; an option given explicitly (``--object``) wins
    over a path."""
    if args.time is None and args.fly_through is None:
        if args.animate is not None:
            raise options.CommandError("--animate needs --time (when to put the paths)")
        return settings
    from explorer.scene import SceneError, load_scene
    from explorer.scene.animation import camera_at, pose_changes

    try:
        scene = load_scene(settings.scene)
        changes = {}
        if args.time is not None:
            changes = pose_changes(scene, args.time, args.animate, settings.object_transforms)
            if getattr(args, "light", None) is not None or settings.light is not None:
                changes.pop("light", None)
            explicit = dict(settings.object_transforms)
            if "object_transforms" in changes:
                changes["object_transforms"] = tuple(sorted(
                    {**dict(changes["object_transforms"]), **explicit}.items()))
        elif args.animate is not None:
            raise options.CommandError("--animate needs --time (when to put the paths)")
        if args.fly_through is not None:
            changes["camera"] = camera_at(scene, args.fly_through)
    except SceneError as exc:
        raise options.CommandError(exc) from None
    return settings.with_changes(**changes)


def _lesson_step(args: argparse.Namespace):
    """The lesson step ``--lesson``/``--step`` name (printing which), or None."""
    if args.lesson is None:
        if args.step is not None:
            raise options.CommandError("--step needs --lesson (the lesson whose step to render)")
        if args.lessons_dir is not None:
            raise options.CommandError(f"{args.lessons_flag} needs --lesson (the lesson of "
                                       "that folder to render)")
        return None
    from explorer.commands.lesson_folder import load_folder

    course = load_folder(args, check_formula=None)
    try:
        lesson = course.find(args.lesson)
        step = lesson.step(1 if args.step is None else args.step)
    except (KeyError, IndexError) as exc:
        raise options.CommandError(exc.args[0]) from None
    print(f"lesson {lesson.id}, step {step.number}/{len(lesson.steps)}: {step.title}")
    return step


def _view_options(args: argparse.Namespace, settings, views: list[str]) -> dict[str, int]:
    """--slice, --coefficient and --cascade, checked against the grid they index (and
    refused when no view asked shows a grid: they would be silently unused)."""
    options.only_with(args, any(view in SLICED_VIEWS for view in views),
                      "a grid view (--view grid-slice or geometry-volume)",
                      {"z": "--slice", "cascade": "--cascade"})
    options.only_with(args, "grid-slice" in views, "--view grid-slice",
                      {"coefficient": "--coefficient"})
    chosen = {}
    if args.z is not None:
        slices = settings.grid_size + (1 if "geometry-volume" in views else 0)
        if not 0 <= args.z < slices:
            raise options.CommandError(f"--slice must be a z index in [0, {slices - 1}] of the "
                               f"{settings.grid_size}³ grid, got {args.z}")
        chosen["z"] = args.z
    if args.coefficient is not None:
        count = 4 if settings.sh_order == 1 else 9
        if args.coefficient >= count:
            raise options.CommandError(f"--coefficient must be in [0, {count - 1}] with --sh-order "
                               f"{settings.sh_order}, got {args.coefficient}")
        chosen["coefficient"] = args.coefficient
    if args.cascade is not None:
        if not 0 <= args.cascade < settings.cascades:
            raise options.CommandError(f"--cascade must be in [0, {settings.cascades - 1}] with "
                               f"--cascades {settings.cascades}, got {args.cascade}")
        chosen["cascade"] = args.cascade
    return chosen


def _view_image(pipeline, step, settings, view: str, chosen: dict[str, int]):
    """The display image of ``view``: the step's own view as the lesson shows it (split
    and difference included), any other view from the pipeline."""
    if step is not None and view == step.view:
        from explorer.lessons import render_step

        return render_step(pipeline, step, settings)[0]
    if step is not None:    # the lesson's comparison may have run other settings since
        options.run_pipeline(pipeline, settings)
    return pipeline.view(view, **_sliced(view, chosen))


_ENLARGED = tuple(view for view in VIEWS if view not in CAMERA_VIEWS)
"""Views whose size is not the image size (RSM, grid): enlarged to MIN_PNG_SIZE."""


def write_png(image, path: Path, enlarge: bool = False) -> None:
    """A [0, 1] float image as 8-bit RGB PNG; with ``enlarge``, a small image is repeated
    by whole pixels up to :data:`MIN_PNG_SIZE`."""
    import numpy as np
    from PIL import Image

    pixels = np.clip(np.nan_to_num(image), 0.0, 1.0)
    repeat = max(1, -(-MIN_PNG_SIZE // max(pixels.shape[:2])))
    if enlarge and repeat > 1:
        pixels = pixels.repeat(repeat, axis=0).repeat(repeat, axis=1)
    Image.fromarray((pixels * 255.0 + 0.5).astype(np.uint8), "RGB").save(path)


def write_grid_slice_png(image, result, chosen: dict[str, int], path: Path) -> None:
    """The grid-slice picture enlarged, with its scale bar: the ramp from 0 (or −peak for a
    coefficient) to the value shown as white, the slice's range and what it shows."""
    import numpy as np

    from explorer.commands.scale_bar import save_with_scale_bar
    from explorer.lpv.twin.tonemap import linear_to_srgb
    from explorer.lpv.views import cascade_item, grid_slice_scale, grid_slice_values

    coefficient, cascade = chosen.get("coefficient"), chosen.get("cascade")
    grid = cascade_item(result, "accumulated", cascade)
    values = grid_slice_values(grid, chosen.get("z"), coefficient)
    white = grid_slice_scale(values, coefficient)
    pixels = np.clip(np.nan_to_num(image), 0.0, 1.0)
    repeat = max(1, -(-MIN_PNG_SIZE // max(pixels.shape[:2])))
    pixels = pixels.repeat(repeat, axis=0).repeat(repeat, axis=1)
    width = pixels.shape[1]
    n = grid.shape[1]
    z = n // 2 if chosen.get("z") is None else chosen["z"]
    if coefficient is None:
        ramp = np.repeat(linear_to_srgb(np.linspace(0.0, 1.0, width))[:, None], 3, axis=1)
        low, high = "0", f"{white:.3g} W"
        what = f"flux per cell [W], slice z = {z} (0..{n - 1})"
    else:
        ramp = np.repeat(np.linspace(0.0, 1.0, width)[:, None], 3, axis=1)
        low, high = f"{-white:.3g}", f"+{white:.3g}"
        what = f"SH coefficient {coefficient} [W/sr], slice z = {z} (0..{n - 1})"
    finite = values[np.isfinite(values)]
    span = (f"range {float(finite.min()):.3g} .. {float(finite.max()):.3g}" if finite.size
            else "no finite value")
    save_with_scale_bar(path, pixels, ramp, low, high,
                        [what + (f", cascade {cascade}" if cascade else ""), span])


def output_paths(out: Path, views: list[str]) -> dict[str, Path]:
    if len(views) == 1:
        return {views[0]: out}
    suffix = out.suffix or ".png"   # several views: one file each, the same suffix
    return {view: out.with_name(f"{out.stem}-{view}{suffix}") for view in views}


def _all_steps(term):
    """A per-step audit term summed over the steps; NaN where its audit mode did not
    measure it (None)."""
    import numpy as np

    return np.full(3, np.nan) if term is None else np.asarray(term).sum(axis=0)


def format_audit(audit) -> str:
    rows = [("rsm", audit.rsm), ("injected", audit.injected),
            ("accumulated", audit.accumulated), ("gathered", audit.gathered),
            ("border loss (all steps)", _all_steps(audit.border_loss)),
            ("clamp gain (all steps)", _all_steps(audit.clamp_gain)),
            ("occluded (all steps)", _all_steps(audit.occluded)),
            ("withheld by the budget", _all_steps(audit.budget_withheld)),
            ("blocked, bounces 2", _all_steps(audit.blocked)),
            ("reflected, bounces 2", _all_steps(audit.reflected))]
    lines = ["energy audit [W]            red        green       blue"]
    lines += [f"  {name:<24}" + "".join(f"{float(v):11.4g}" for v in values)
              for name, values in rows]
    return "\n".join(lines)


def print_audit(result) -> None:
    """The energy audit of a frame, and one line per cascade when there are several."""
    print(format_audit(result.audit))
    if len(result.cascade_audits) > 1:
        print(format_cascade_audits(result))


def format_cascade_audits(result) -> str:
    """One line per cascade: cell size and the flux injected / accumulated / lost at the
    border in that cascade (the cascades overlap: their fluxes do not add up)."""
    lines = ["cascades [W, summed over r, g, b]  cell size   injected  accumulated  border"]
    for k, (spec, audit) in enumerate(zip(result.cascade_specs, result.cascade_audits)):
        lines.append(f"  cascade {k:<26}{spec.cell_size:10.4g}{audit.injected.sum():11.4g}"
                     f"{audit.accumulated.sum():13.4g}{_all_steps(audit.border_loss).sum():8.4g}")
    return "\n".join(lines)

