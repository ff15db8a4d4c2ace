"""Command-line plumbing every subcommand shares.

* options derived from the settings schema (:func:`add_setting_options`): each
  :class:`~explorer.lpv.settings.Settings` field that declares a ``flag`` becomes an option
  whose type, choices, help and allowed range come from its :class:`~explorer.schema.Spec`
  (``--size WxH`` sets width and height, ``--preset`` the corrections);
* :func:`settings_from_args`: the parsed options as Settings, through the schema;
* :class:`CommandError`: what a command raises for bad input or a request it cannot do;
  ``explorer.cli.main`` prints it as one line, ``lpv-explorer <cmd>: error: ...``;
* :class:`Outputs`: output paths checked before any work starts (folder exists or can be
  made, writable, a known image suffix), files written whole or not at all, and removed
  again when the command fails or is interrupted;
* :class:`Progress`: a bar on a terminal, nothing when piped;
* :func:`run_pipeline`: the one place a command runs the pipeline.
"""

from __future__ import annotations

import argparse
import os
import re
import sys
import tempfile
import time
from collections.abc import Callable, Iterable, Mapping
from pathlib import Path
from typing import Any, TextIO

from explorer.lpv.settings import PRESETS, Settings
from explorer.schema import SettingError, Spec, specs

IMAGE_SUFFIXES = (".png", ".jpg", ".jpeg", ".bmp", ".tif", ".tiff")
"""File types the image writers (Pillow) produce from an RGB image."""
REPEATABLE_ACTIONS = ("append", "append_const", "extend", "count", "help", "version", "parsers")
"""argparse's names of the actions given more than once by design: not refused as repeats."""


class CommandError(Exception):
    """A command could not do what was asked; ``explorer.cli.main`` prints the message as
    one line on stderr and exits with ``code`` (2: bad input, 1: it failed)."""

    def __init__(self, message: object, code: int = 2) -> None:
        super().__init__(str(message))
        self.code = code


class ArgumentParser(argparse.ArgumentParser):
    """argparse with a one-line error (``prog: error: message``) instead of the usage
    text followed by the error; ``--help`` still shows the usage. ``command_parsers``:
    the subcommands' parsers by name (``explorer.cli.build_parser`` fills it)."""

    def __init__(self, *args: Any, **kwargs: Any) -> None:
        super().__init__(*args, **kwargs)
        self.command_parsers: dict[str, argparse.ArgumentParser] = {}
        # a value that starts with a minus and a digit is a value, not an option:
        # ``--camera -1.5,1.7,1.8:0,0,0`` (argparse alone takes only a plain negative
        # number for a value and would say "expected one argument")
        self._negative_number_matcher = re.compile(r"^-\.?\d")

    def error(self, message: str):  # type: ignore[override]
        self.exit(2, f"{self.prog}: error: {message}\n")

    def parse_known_args(self, args=None, namespace=None):  # type: ignore[override]
        """argparse's, after refusing an option given twice with different values (argparse
        would silently keep the last): ``--grid 8 --grid 16``, ``--fog --no-fog``, two
        ``--preset``, ``--check A --check B`` (an optional value). Repeatable options
        (``--view``, ``--object``) are not checked."""
        given = list(sys.argv[1:] if args is None else args)
        self._refuse_repeated(given)
        return super().parse_known_args(given, namespace)

    def _refuse_repeated(self, given: list[str]) -> None:
        seen: dict[str, tuple[str, str]] = {}     # dest -> (option, value) as first given
        # argparse's own classes for the actions that repeat by design, by their public
        # names (the classes themselves are private to argparse)
        repeatable = tuple(self._registry_get("action", name) for name in REPEATABLE_ACTIONS)
        index = 0
        while index < len(given):
            token = given[index]
            index += 1
            if token == "--":
                return
            if token in self._subparser_names():
                return                  # the rest is the subcommand's, checked by its parser
            found = self._parse_optional(token) if token.startswith("-") else None
            if isinstance(found, list):          # Python 3.12+: the candidates
                found = found[0] if len(found) == 1 else None
            if not found or found[0] is None:
                continue
            action, option, explicit = found[0], found[1], found[-1]
            if isinstance(action, repeatable):
                continue
            takes_next = index < len(given) and (
                action.nargs is None or action.nargs == "?" and not
                given[index].startswith("-") and given[index] not in self._subparser_names())
            if explicit is None and takes_next:
                value = given[index]
                index += 1
            else:
                value = "" if explicit is None else explicit
            if action.nargs not in (None, 0, "?"):
                continue                # a variable number of values: not compared
            said = f"{option} {value}".strip()
            first = seen.setdefault(action.dest, (option, said))
            if first[1] != said:
                self.error(f"{first[1]} and {said} both given; give {_flag_of(action)} once")

    def _subparser_names(self) -> set[str]:
        names: set[str] = set()
        subparsers = self._registry_get("action", "parsers")
        for action in self._actions:
            if isinstance(action, subparsers):
                names.update(action.choices)
        return names


def _flag_of(action: argparse.Action) -> str:
    """The option's name as its help shows it (``--fog/--no-fog``, ``--grid``)."""
    longs = [option for option in action.option_strings if option.startswith("--")]
    return "/".join(longs or action.option_strings)


# --- options from the schema -----------------------------------------------------------

def setting_type(name: str, cls: type = Settings) -> Callable[[str], Any]:
    """argparse ``type=`` for field ``name`` of ``cls``: the text converted to the field's
    kind and checked by its spec; a bad value gives the schema's message."""
    return value_type(name, specs(cls)[name])


def value_type(name: str, spec: Spec) -> Callable[[str], Any]:
    """argparse ``type=`` for a value ``spec`` describes (a command's own option)."""

    def parse(text: str) -> Any:
        try:
            value = _from_text(spec, text)
        except ValueError:
            raise argparse.ArgumentTypeError(
                f"{name} must be {spec.allowed()}, got {text!r}") from None
        try:
            return spec.check(name, value)
        except SettingError as exc:
            raise argparse.ArgumentTypeError(str(exc)) from None

    parse.__name__ = name
    return parse


def _from_text(spec: Spec, text: str) -> Any:
    """Command-line text as the field's Python type (the spec then checks the value);
    ValueError when it is not even that type."""
    kind = spec.kind
    if kind == "choice" and spec.choices and not isinstance(spec.choices[0], str):
        kind = type(spec.choices[0]).__name__      # a numeric choice, e.g. sh_order
    if kind == "int":
        return int(text)
    if kind == "float":
        return float(text)
    if kind == "range2":                          # "30,60"
        first, second = text.split(",")
        return float(first), float(second)
    if kind == "int3":                            # "7,12,5"
        return [int(part) for part in text.split(",")]
    if kind == "point":                           # "-1.6,0,-2.6"
        return [float(part) for part in text.split(",")]
    if kind in ("names", "name_set"):              # "spot,bulb"
        return [part.strip() for part in text.split(",")]
    if kind == "transforms":                      # "short block=0.1,0,0,0,30,0"
        name, equals, numbers = text.partition("=")
        if not equals:
            raise ValueError("expected NAME=numbers")
        return {name.strip(): [float(part) for part in numbers.split(",")]}
    return text


def list_type(name: str, cls: type = Settings) -> Callable[[str], tuple]:
    """argparse ``type=`` for a comma list of values of field ``name`` (a sweep), each
    checked as :func:`setting_type` checks one."""
    one = setting_type(name, cls)

    def parse(text: str) -> tuple:
        parts = [part.strip() for part in text.split(",")]
        if not all(parts):
            raise argparse.ArgumentTypeError(
                f"expected {name} values separated by commas, got {text!r}")
        return tuple(one(part) for part in parts)

    parse.__name__ = f"{name} list"
    return parse


def size_type(check: Callable[[int, int], tuple[int, int]]) -> Callable[[str], tuple]:
    """argparse ``type=`` for ``WxH``; ``check(width, height)`` raises SettingError."""

    def parse(text: str) -> tuple[int, int]:
        try:
            width, height = (int(part) for part in text.lower().split("x"))
        except ValueError:
            raise argparse.ArgumentTypeError(
                f"size must look like 512x512 (width x height), got {text!r}") from None
        try:
            return check(width, height)
        except SettingError as exc:
            raise argparse.ArgumentTypeError(str(exc)) from None

    parse.__name__ = "size"
    return parse


def image_size(width: int, height: int) -> tuple[int, int]:
    """(width, height) checked by the Settings specs of ``width`` and ``height``."""
    fields = specs(Settings)
    return fields["width"].check("width", width), fields["height"].check("height", height)


def spec_help(spec: Spec, default: object = None) -> str:
    """Help text of an option: the field's doc, what it allows and its default. An
    optional field's None is the option left out (nobody types None on a command line)."""
    doc, allowed = spec.doc, spec.allowed()
    if spec.optional:
        doc = doc.replace(". None = ", ". Left out: ").replace("None = ", "left out: ")
        allowed = allowed.removesuffix(" or None")
        if default == "automatic" and "left out" in doc:
            default = None                  # the doc says what leaving it out does
    text = f"{doc} Allowed: {allowed}"
    if default is not None:
        text += f"; default {default}"
    return (text + ".").replace("%", "%%")     # argparse %-formats help texts


def add_setting_options(parser: argparse.ArgumentParser, *, exclude: Iterable[str] = (),
                        sweep: Iterable[str] = (), defaults: Mapping[str, object] = (),
                        aliases: Mapping[str, tuple[str, ...]] = ()) -> None:
    """Add an option for every Settings field that declares a ``flag`` (``dest`` is the
    field name; left out it is None and the field keeps its value), plus ``--size WxH``
    and ``--preset``. ``sweep``: fields taking a comma list (one run per value);
    ``defaults``: what this command uses when an option is left out (shown in the help,
    applied by :func:`settings_from_args`); ``aliases``: extra flags per field."""
    exclude, sweep = set(exclude), set(sweep)
    defaults, aliases = dict(defaults), dict(aliases)
    base = Settings()
    group = parser.add_argument_group(
        "settings", "each option sets one Settings field (explorer/lpv/settings.py); left "
        "out, the field keeps its default")
    for name, spec in specs(Settings).items():
        if spec.flag is None or name in exclude:
            continue
        flags = (spec.flag, *aliases.get(name, ()))
        shown = defaults.get(name, getattr(base, name))
        help_text = spec_help(spec, _shown(shown))
        if name == "scene":
            help_text = scene_help(help_text)
        if spec.kind == "bool":
            group.add_argument(*flags, dest=name, action=argparse.BooleanOptionalAction,
                               default=None, help=help_text)
        elif spec.kind == "transforms":       # one object per option, repeatable
            group.add_argument(*flags, dest=name, type=setting_type(name), default=None,
                               action="append", metavar="NAME=TX,TY,TZ[,RX,RY,RZ[,SX,SY,SZ]]",
                               help=help_text[:-1] + "; repeat for several objects.")
        elif name in sweep:
            group.add_argument(*flags, dest=name, type=list_type(name), default=None,
                               metavar=f"{_metavar(spec)}[,...]",
                               help=help_text[:-1] + "; a comma list runs each value.")
        else:
            group.add_argument(*flags, dest=name, type=setting_type(name), default=None,
                               metavar="NAME|PATH" if name == "scene" else _metavar(spec),
                               help=help_text)
    add_placement_options(group)
    if "width" not in exclude:
        size = defaults.get("size", (base.width, base.height))
        group.add_argument("--size", type=size_type(image_size), default=None, metavar="WxH",
                           help=f"image size in pixels: width and height, whole numbers in "
                                f"[1, {specs(Settings)['width'].high:g}]; default "
                                f"{size[0]}x{size[1]}")
    if "corrections" not in exclude:
        group.add_argument("--preset", choices=list(PRESETS), default=None,
                           help=f"the formulas: {', '.join(PRESETS)} (default "
                                f"{defaults.get('preset', 'corrected')})")
    parser.set_defaults(_setting_defaults=defaults, _sweep=tuple(sorted(sweep)),
                        _setting_options=tuple(sorted({"size", "preset"} - (
                            {"preset"} if "corrections" in exclude else set()) - (
                            {"size"} if "width" in exclude else set()))))


def add_placement_options(group) -> None:
    """``--light KIND:x,y,z[:tx,ty,tz]`` and ``--camera ex,ey,ez:tx,ty,tz[:fov]``: a quick
    look at one's own mesh without a scene file (they set ``Settings.light`` /
    ``light_kind`` and ``camera`` / ``camera_fov``, :func:`placement_changes`)."""
    from explorer.scene.lights import LIGHT_KINDS

    group.add_argument("--light", dest="_light_option", type=light_option, default=None,
                       metavar="KIND:X,Y,Z[:TX,TY,TZ]",
                       help=f"the primary light: its kind ({', '.join(LIGHT_KINDS)}), "
                            f"position and target (a spot and a directional light need "
                            f"one; a point light ignores it); a new kind gets the flux "
                            f"that gives 2 W/m² at the target unless --light-flux says")
    group.add_argument("--camera", dest="_camera_option", type=camera_option, default=None,
                       metavar="EX,EY,EZ:TX,TY,TZ[:FOV]",
                       help="the camera: eye, target and optionally the vertical field of "
                            "view in degrees, in [1, 170]")


def _point(text: str, what: str) -> tuple[float, float, float]:
    import math

    try:
        point = tuple(float(part) for part in text.split(","))
    except ValueError:
        point = ()
    if len(point) != 3 or not all(math.isfinite(v) for v in point):
        raise argparse.ArgumentTypeError(f"{what} must be three numbers x,y,z, got {text!r}")
    return point


def light_option(text: str) -> tuple[str, tuple, tuple]:
    """``KIND:x,y,z[:tx,ty,tz]`` as ``(kind, position, target)`` (a point light without a
    target: the point below it, as ``PointLight.target``)."""
    from explorer.scene.lights import LIGHT_KINDS

    kind, *points = text.split(":")
    if kind not in LIGHT_KINDS or len(points) not in (1, 2):
        raise argparse.ArgumentTypeError(
            f"--light must look like KIND:x,y,z[:tx,ty,tz] with KIND one of "
            f"{', '.join(LIGHT_KINDS)}, got {text!r}")
    position = _point(points[0], "the light's position")
    if len(points) == 1 and kind != "point":
        raise argparse.ArgumentTypeError(
            f"a {kind} light needs a target: --light {kind}:x,y,z:tx,ty,tz")
    target = _point(points[1], "the light's target") if len(points) == 2 else \
        (position[0], position[1] - 1.0, position[2])
    if target == position:
        raise argparse.ArgumentTypeError("the light's position and target must differ")
    return kind, position, target


def camera_option(text: str) -> tuple[tuple, tuple, float | None]:
    """``ex,ey,ez:tx,ty,tz[:fov]`` as ``(eye, target, fov or None)``."""
    parts = text.split(":")
    if len(parts) not in (2, 3):
        raise argparse.ArgumentTypeError(
            f"--camera must look like ex,ey,ez:tx,ty,tz[:fov], got {text!r}")
    eye, target = _point(parts[0], "the camera's eye"), _point(parts[1], "its target")
    if eye == target:
        raise argparse.ArgumentTypeError("the camera's eye and target must differ")
    fov = None
    if len(parts) == 3:
        fov = setting_type("camera_fov")(parts[2])
    return eye, target, fov


def placement_changes(args: argparse.Namespace) -> dict[str, object]:
    """The Settings changes ``--light`` and ``--camera`` ask for."""
    changes: dict[str, object] = {}
    light = getattr(args, "_light_option", None)
    if light is not None:
        kind, position, target = light
        changes.update(light=(position, target), light_kind=kind)
    camera = getattr(args, "_camera_option", None)
    if camera is not None:
        eye, target, fov = camera
        changes["camera"] = (eye, target)
        if fov is not None:
            changes["camera_fov"] = fov
    return changes


def scene_help(help_text: str) -> str:
    """The scene option's help text (ending in a full stop) with the built-in scenes
    (explorer/scene/builtin.py, their one list) named."""
    from explorer.scene.builtin import BUILTIN_SCENES

    return help_text[:-1] + f"; built-in scenes: {', '.join(BUILTIN_SCENES)}."


def _metavar(spec: Spec) -> str:
    if spec.kind == "choice":
        return "{" + ",".join(str(choice) for choice in spec.choices) + "}"
    return {"int": "N", "float": "X", "str": "TEXT", "range2": "LOW,HIGH",
            "int3": "NX,NY,NZ", "point": "X,Y,Z",
            "names": "NAME[,NAME...]", "name_set": "NAME[,NAME...]"}.get(spec.kind,
                                                                         "VALUE")


def _shown(value: object) -> object:
    return "automatic" if value is None else value


def settings_from_args(args: argparse.Namespace, base: Settings | None = None) -> Settings:
    """``base`` (default: ``Settings()`` with the command's defaults) with every option
    given on the command line applied; sweep options are left to the command. A value
    or combination the schema refuses raises :class:`CommandError`."""
    defaults = dict(getattr(args, "_setting_defaults", {}))
    sweep = set(getattr(args, "_sweep", ()))
    changes: dict[str, object] = {}
    if base is None:
        changes.update({k: v for k, v in defaults.items() if k not in ("size", "preset")})
        if "size" in defaults:
            changes["width"], changes["height"] = defaults["size"]
        if "preset" in defaults:
            changes["corrections"] = defaults["preset"]
    for name, spec in specs(Settings).items():
        value = getattr(args, name, None)
        if spec.kind == "transforms" and value is not None:    # repeated --object options
            value = _merged_transforms(name, value)
        if value is not None and name not in sweep:
            changes[name] = value
    changes.update(placement_changes(args))
    own = getattr(args, "_setting_options", ())   # --size and --preset, when they are ours
    sizes = given_options(args, {"width": "--width", "height": "--height"})
    if "size" in own and args.size is not None and sizes:
        raise CommandError(f"--size and {'/'.join(sizes)} both set the image size; give one")
    if "size" in own and args.size is not None:
        changes["width"], changes["height"] = args.size
    if "preset" in own and args.preset is not None:
        changes["corrections"] = args.preset
    try:
        settings = (base or Settings()).with_changes(**changes)
    except SettingError as exc:
        raise CommandError(exc) from None
    check_dependent_options(args, settings)
    return settings


DEPENDENT_OPTIONS: dict[str, tuple[object, tuple[str, ...]]] = {
    "spot_cone": (False, ("spot_cone_degrees",)),
    "fog": (False, ("fog_density", "fog_albedo", "fog_phase", "fog_g", "fog_steps")),
    "fog_phase": ("isotropic", ("fog_g",)),
    "glossy": (False, ("glossy_roughness", "glossy_strength", "glossy_samples")),
    "downsample": ("none", ("downsample_factor",)),
    "cascades": (1, ("cascade_extent", "cascade_focus", "cascade_snap",
                     "cascade_iterations")),
}
"""Settings that only matter while another is not at a value that switches them off: the
switch field, that value, the fields it makes unused (the spot cone's angles without the
cone, fog's parameters without fog, Henyey-Greenstein's g for isotropic fog, the glossy
lobe's without it, the downsample factor without downsampling, the cascades' parameters
with one grid)."""


def _off_text(name: str, value: object) -> str:
    spec = specs(Settings)[name]
    if spec.kind == "bool":
        return f"--no-{spec.flag[2:]}" if value is False else spec.flag
    return f"{spec.flag} {value}"


def check_dependent_options(args: argparse.Namespace, settings: Settings,
                            stream: TextIO | None = None) -> None:
    """Options that contradict each other: a setting given on the command line together
    with the option that switches it off (``--no-spot-cone --cone-angles 20,30``) is a
    :class:`CommandError` naming both; given while its switch is off only by default (or
    by the lesson step), a warning on ``stream`` (stderr) says it has no effect and what
    would give it one."""
    fields = specs(Settings)
    out = sys.stderr if stream is None else stream
    for switch, (off, dependents) in DEPENDENT_OPTIONS.items():
        given = [name for name in dependents if getattr(args, name, None) is not None]
        if not given or getattr(settings, switch) != off:
            continue
        flags = ", ".join(fields[name].flag for name in given)
        if getattr(args, switch, None) is not None:
            raise CommandError(f"{_off_text(switch, off)} and {flags} contradict each other: "
                               f"{flags} would have no effect; give one of them")
        out.write(f"lpv-explorer: warning: {flags} has no effect: the settings have "
                  f"{_off_text(switch, off)}; {_on_hint(switch, off)}\n")


def _on_hint(name: str, off: object) -> str:
    spec = specs(Settings)[name]
    if spec.kind == "bool":
        return f"add {spec.flag} to use it"
    if spec.kind == "choice":
        others = [str(c) for c in spec.choices if c != off]
        return f"add {spec.flag} {'|'.join(others)} to use it"
    return f"add {spec.flag} N with N other than {off} to use it"


def given_options(args: argparse.Namespace, flags: Mapping[str, str]) -> list[str]:
    """The flags of ``flags`` (dest -> flag) the command line gave: a value other than
    None or False (the defaults every such option here has)."""
    def given(value: object) -> bool:       # 0 is a value given (0 == False in Python)
        return not (value is None or value is False or (isinstance(value, (list, tuple))
                                                        and not value))

    return [flag for dest, flag in flags.items() if given(getattr(args, dest, None))]


def one_of(args: argparse.Namespace, flags: Mapping[str, str]) -> None:
    """Refuse two of ``flags`` (dest -> flag: options that each choose what the command
    does) given together, naming both."""
    given = given_options(args, flags)
    if len(given) > 1:
        raise CommandError(f"{' and '.join(given)} each choose a different run; give one")


def only_with(args: argparse.Namespace, present: bool, needs: str,
              flags: Mapping[str, str]) -> None:
    """Refuse options (dest -> flag) that only act with ``needs`` when it is not
    ``present``: silently unused, they would look as if they had been applied."""
    given = given_options(args, flags)
    if given and not present:
        named = ", ".join(given)
        raise CommandError(f"{named} only {'acts' if len(given) == 1 else 'act'} with "
                           f"{needs}; add that or leave {named} out")


def setting_flags(args: argparse.Namespace) -> dict[str, str]:
    """dest -> flag of every Settings option this command has, with ``--size``,
    ``--preset``, ``--light`` and ``--camera``."""
    flags = {name: spec.flag for name, spec in specs(Settings).items()
             if spec.flag is not None and hasattr(args, name)}
    for dest, flag in (("size", "--size"), ("preset", "--preset"),
                       ("_light_option", "--light"), ("_camera_option", "--camera")):
        if hasattr(args, dest):
            flags[dest] = flag
    return flags


def _merged_transforms(name: str, given: list) -> tuple:
    """The transforms of repeated ``--object`` options as one value; an object named twice
    is a :class:`CommandError`."""
    merged: dict[str, tuple] = {}
    for item in given:
        for key, values in item:
            if key in merged:
                raise CommandError(f"{specs(Settings)[name].flag} names object {key!r} twice")
            merged[key] = values
    return tuple(sorted(merged.items()))


def sweep_values(args: argparse.Namespace, name: str, base: Settings) -> tuple:
    """The values of sweep option ``name``: those given, else the base's one value."""
    given = getattr(args, name, None)
    return tuple(given) if given else (getattr(base, name),)


def check_settings(settings: Iterable[Callable[[], Settings]]) -> list[Settings]:
    """Build every Settings a command will run before it runs any, so a combination the
    schema refuses stops the command at once (one line) instead of half-way."""
    try:
        return [make() for make in settings]
    except SettingError as exc:
        raise CommandError(exc) from None


def render_failures() -> tuple[type[BaseException], ...]:
    """What rendering raises for a request this machine cannot do (exit 1, one line): a
    driver or texture-budget limit (ValueError), a NaN found by --debug-nan, no usable
    GL, a shader that does not compile, GL refusing an object (an incomplete framebuffer:
    ``moderngl.Error``), a file that cannot be written."""
    import moderngl

    from explorer.gl.context import GLUnavailableError
    from explorer.gl.program import ShaderError

    return (ValueError, FloatingPointError, OSError, GLUnavailableError, ShaderError,
            moderngl.Error)


def check_scene(name: str, stream: TextIO | None = None) -> None:
    """A built-in scene name or an existing file; :class:`CommandError` otherwise (the
    loader's message: the built-in names and the mesh types). A file (a scene file or a
    mesh) is read and checked whole now, so a mistake is refused before any work rather
    than later, and what the loader chose for the user (``Scene.notice``: where it put a
    light) is printed on ``stream`` (stderr)."""
    from explorer.scene import SceneError, load_scene
    from explorer.scene.loader import check_scene_name

    try:
        path = check_scene_name(name)
        if path is not None:
            scene = load_scene(name)
            out = sys.stderr if stream is None else stream
            for line in filter(None, (scene.notice, *(f"warning: {w}" for w in scene.warnings))):
                out.write(f"lpv-explorer: {line}\n")
            out.flush()
    except SceneError as exc:
        raise CommandError(exc) from None


# --- output paths ------------------------------------------------------------------------

def _existing_ancestor(folder: Path) -> tuple[Path, list[Path]]:
    """The nearest of ``folder`` and its parents that exists, and the missing ones below
    it (nearest to ``folder`` first)."""
    missing = []
    while not folder.exists() and folder != folder.parent:
        missing.append(folder)
        folder = folder.parent
    return folder, missing


class Outputs:
    """The files and folders one command writes, all or none: paths are checked before any
    work (:meth:`file`, :meth:`folder`), each file is written to a unique temporary beside
    it (:meth:`write`), and all are renamed into place, with the stop signals held, only
    when the command succeeds (a failed rename puts back what it replaced). A failed or
    stopped command removes its temporaries and the folders made for them, so the old set
    of outputs stays whole or the new one is, never a mix."""

    def __init__(self, option: str = "--out") -> None:
        self.option = option
        self.written: list[Path] = []
        self.made: list[Path] = []
        self._staged: dict[Path, Path] = {}             # output path -> its temporary
        self._removed: list[Path] = []

    def __enter__(self) -> Outputs:
        return self

    def __exit__(self, exc_type, exc, traceback) -> None:
        if exc_type is None:
            self._commit()
            return
        for partial in self._staged.values():
            partial.unlink(missing_ok=True)
        self._staged.clear()
        self._remove_made_folders()

    def _remove_made_folders(self) -> None:
        for folder in reversed(self.made):
            try:
                folder.rmdir()
            except OSError:
                pass                    # not empty: something else is in it now

    def _commit(self) -> None:
        """Rename every staged file into place (old contents kept as hard links until all
        are in), remove the files :meth:`remove` named; on a failure undo it all."""
        from explorer.safe_files import os_error_text
        from explorer.stop_signals import held

        done: list[tuple[Path, Path | None]] = []        # path -> its old content
        with held():
            try:
                for path, partial in self._staged.items():
                    backup = self._keep_old(path)
                    done.append((path, backup))
                    os.replace(partial, path)
                    self.written.append(path)
                for path in self._removed:
                    if path.exists():
                        backup = self._keep_old(path)
                        done.append((path, backup))
                        path.unlink()
            except OSError as exc:
                for path, backup in reversed(done):
                    try:
                        if backup is not None:
                            os.replace(backup, path)
                        elif path in self._staged:
                            path.unlink(missing_ok=True)
                    except OSError:
                        pass            # the folder went away: nothing left to restore
                for partial in self._staged.values():
                    partial.unlink(missing_ok=True)
                self.written.clear()
                self._remove_made_folders()
                raise CommandError(f"cannot write {path}: {os_error_text(exc)}", 1) from None
            finally:
                self._staged.clear()
            for _, backup in done:
                if backup is not None:
                    backup.unlink(missing_ok=True)

    def file(self, path: Path | str, suffixes: tuple[str, ...] = IMAGE_SUFFIXES,
             option: str | None = None) -> Path:
        """``path`` checked as a file to write: not a folder, a suffix in ``suffixes``
        (any when empty), a name the file system allows, its folder made if missing and
        writable."""
        option = option or self.option
        folder_like = str(path).endswith(("/", os.sep))
        path = Path(path).expanduser()
        self._name_fits(path, option)
        if path.is_dir() or folder_like:
            raise CommandError(f"{option} {path} is a folder; give a file name"
                               + (f" ending in {suffixes[0]}" if suffixes else ""))
        if suffixes and not path.suffix:
            raise CommandError(f"{option} {path} has no suffix; end the name in "
                               f"{', '.join(suffixes)}")
        if suffixes and path.suffix.lower() not in suffixes:
            raise CommandError(f"{option} {path}: this command writes "
                               f"{', '.join(suffixes)}, not {path.suffix!r}")
        self._writable_folder(path.parent, option)
        return path

    @staticmethod
    def _name_fits(path: Path, option: str) -> None:
        existing, _ = _existing_ancestor(path.parent)   # the folder may not be made yet
        try:
            longest = os.pathconf(existing, "PC_NAME_MAX")
        except (OSError, ValueError):
            longest = 255
        length = len(os.fsencode(path.name))
        if length > longest:
            raise CommandError(f"{option}: the file name is {length} bytes long, over the "
                               f"{longest} the file system allows: {path.name[:40]}...")

    def folder(self, path: Path | str, option: str | None = None) -> Path:
        """``path`` checked as a folder to write into (made now if missing)."""
        option = option or self.option
        path = Path(path).expanduser()
        if path.exists() and not path.is_dir():
            raise CommandError(f"{option} {path} is a file, not a folder")
        self._writable_folder(path, option)
        return path

    def _writable_folder(self, folder: Path, option: str) -> None:
        probe, missing = _existing_ancestor(folder)
        if probe.exists() and not probe.is_dir():
            raise CommandError(f"{option}: cannot make the folder {folder}: {probe} is a file")
        try:
            folder.mkdir(parents=True, exist_ok=True)
        except OSError as exc:
            raise CommandError(f"{option}: cannot make the folder {folder}: "
                               f"{exc.strerror or exc}") from None
        self.made += reversed(missing)
        try:
            with tempfile.TemporaryFile(dir=folder):
                pass
        except OSError as exc:
            raise CommandError(f"{option}: cannot write in {folder}: {exc.strerror or exc}"
                               ) from None

    def write(self, path: Path, save: Callable[[Path], None]) -> Path:
        """Stage ``path``: ``save(temporary path)`` (same suffix) now, the rename when the
        command succeeds (class docstring). A write that fails (a full disk, a folder
        that went away) is a :class:`CommandError` naming the file, with nothing left
        behind."""
        from explorer.safe_files import os_error_text, output_mode, temporary_beside

        try:
            partial = temporary_beside(path)
        except OSError as exc:
            raise CommandError(f"cannot write {path}: {os_error_text(exc)}", 1) from None
        try:
            save(partial)
            os.chmod(partial, output_mode(path))
        except BaseException as exc:
            partial.unlink(missing_ok=True)
            if isinstance(exc, OSError):
                raise CommandError(f"cannot write {path}: {os_error_text(exc)}", 1) from None
            raise
        earlier = self._staged.pop(path, None)
        if earlier is not None:
            earlier.unlink(missing_ok=True)
        self._staged[path] = partial
        return path

    def remove(self, path: Path) -> None:
        """Remove ``path`` when the command succeeds (a file an earlier run of the same
        command wrote and this one no longer does), with the renames."""
        self._removed.append(path)

    @staticmethod
    def _keep_old(path: Path) -> Path | None:
        """A hard link to ``path``'s current content (None when there is no file yet), so
        that a failed commit can put it back."""
        from explorer.safe_files import temporary_beside

        if not path.is_file():
            return None
        backup = temporary_beside(path)
        backup.unlink()
        try:
            os.link(path, backup)
        except OSError:                 # a file system without hard links: copy it
            import shutil
            shutil.copy2(path, backup)
        return backup


# --- progress ----------------------------------------------------------------------------

class Progress:
    """Progress of a long command: ``progress(stage, done, total)`` redraws one line on a
    terminal (a bar, the stage and the counts), at most every ``interval`` seconds; when
    the stream is not a terminal (piped, a CI log) it stays silent.

    The call matches the pipeline's progress callback; :meth:`fraction` adapts it to the
    reference renderer's ``progress(fraction) -> bool``. :attr:`prefix` is shown before
    the stage (a command running many frames names the frame there). :meth:`warn` prints
    the pipeline's warnings (always, piped or not), each text once per command."""

    def __init__(self, label: str, stream: TextIO | None = None, enabled: bool | None = None,
                 width: int = 24, interval: float = 0.1,
                 clock: Callable[[], float] = time.monotonic) -> None:
        self.label = label
        self.stream = sys.stderr if stream is None else stream
        isatty = getattr(self.stream, "isatty", None)
        self.enabled = bool(isatty and isatty()) if enabled is None else enabled
        self.width = width
        self.interval = interval
        self.clock = clock
        self._last_draw = -float("inf")
        self._stage: str | None = None
        self._shown = 0               # characters on the line now
        self.prefix = ""
        self._warned: set[str] = set()

    def __call__(self, stage: str, done: int, total: int) -> None:
        if not self.enabled:
            return
        now = self.clock()
        stage = self.prefix + stage
        if done < total and stage == self._stage and now - self._last_draw < self.interval:
            return                      # a new stage and a finished one are always drawn
        self._last_draw, self._stage = now, stage
        fraction = min(max(done / total, 0.0), 1.0) if total > 0 else 1.0
        filled = int(fraction * self.width)
        line = (f"{self.label}: {stage} [{'#' * filled}{'.' * (self.width - filled)}] "
                f"{int(100 * fraction):3d}% ({done}/{total})")
        self.stream.write("\r" + line + " " * max(self._shown - len(line), 0))
        self.stream.flush()
        self._shown = len(line)

    def fraction(self, stage: str, steps: int = 1000) -> Callable[[float], bool]:
        """A ``progress(fraction) -> True`` callback drawing this bar for ``stage``."""
        def report(done: float) -> bool:
            self(stage, int(round(done * steps)), steps)
            return True

        return report

    def warn(self, messages: Iterable[str]) -> None:
        """Print each message not printed before as ``lpv-explorer <label>: warning: ...``
        on the stream (the bar's line cleared first)."""
        new = [text for text in dict.fromkeys(messages) if text not in self._warned]
        if not new:
            return
        self.close()
        for text in new:
            self.stream.write(f"lpv-explorer {self.label}: warning: {text}\n")
            self._warned.add(text)
        self.stream.flush()

    def close(self) -> None:
        """Clear the bar's line, so what is printed next starts on a clean line."""
        if self._shown:
            self.stream.write("\r" + " " * self._shown + "\r")
            self.stream.flush()
            self._shown = 0

    def __enter__(self) -> Progress:
        return self

    def __exit__(self, *exc_info) -> None:
        self.close()


def run_pipeline(pipeline: Any, settings: Settings | None = None,
                 progress: Callable[[str, int, int], None] | None = None, **options: Any):
    """Run ``pipeline`` for ``settings``: the one call site every command shares.
    ``progress(stage, done, total)`` is called as the stages run (a :class:`Progress`
    bar), and a :class:`Progress` prints the frame's warnings (``FrameResult.warnings``:
    the numeric guards, explorer/lpv/guards.py) once each; ``options`` go to
    ``Pipeline.run`` (``keep_steps``, ``vpls``, ``need_audit``)."""
    result = pipeline.run(settings, progress=progress, **options)
    warn = getattr(progress, "warn", None)
    if warn is not None:
        warn(result.warnings)
    return result
