"""Program loading: one ``.glsl`` file per program, ``#include``, defines, hot reload.

Conventions (after moderngl-window): line 1 of every file is ``#version 430 core``;
stages live under ``#if defined VERTEX_SHADER`` / ``GEOMETRY_SHADER`` /
``FRAGMENT_SHADER`` / ``COMPUTE_SHADER``. The loader inserts ``#define <STAGE> 1`` and a
``#line`` directive so compiler line numbers match the file, resolves
``#include "file.glsl"`` relative to the shader folder (depth-guarded), and overrides only
``#define`` values already present in the source, so every file still compiles on its own.

Uniforms are set strictly (:func:`set_uniforms`): a name the program's source does not
declare raises, and a pass names the uniforms its program must actually read (e.g. the
correction switches of its stage), so a misspelt or dropped switch cannot silently stay 0.
"""

from __future__ import annotations

import difflib
import re
from collections.abc import Iterable
from dataclasses import dataclass, field
from pathlib import Path

import moderngl
import numpy as np

from explorer.resources import shader_dir
from explorer.safe_files import UserFileError, read_text

STAGES = ("VERTEX_SHADER", "GEOMETRY_SHADER", "FRAGMENT_SHADER", "COMPUTE_SHADER")
_INCLUDE = re.compile(r'^\s*#include\s+"([^"]+)"\s*$', re.MULTILINE)
_DEFINE = re.compile(r"^(\s*#define\s+)(\w+)(\s+)(.*)$", re.MULTILINE)
_MAX_INCLUDE_DEPTH = 8


class ShaderError(RuntimeError):
    """A shader failed to load or compile; ``log`` holds the compiler output."""

    def __init__(self, path: Path, log: str):
        super().__init__(f"{path.name}: {log}")
        self.path = path
        self.log = log


def _resolve_includes(source: str, base: Path, depth: int, seen: tuple[Path, ...]) -> str:
    def include(match: re.Match) -> str:
        target = (base / match.group(1)).resolve()
        if depth >= _MAX_INCLUDE_DEPTH or target in seen:
            raise ShaderError(target, f"#include nested too deep or cyclic at {target.name}")
        if not target.is_file():
            raise ShaderError(target, f"#include file not found: {match.group(1)}")
        text = read_source(target)
        text = _strip_version(text)
        body = _resolve_includes(text, base, depth + 1, seen + (target,))
        return f"{body}\n"

    return _INCLUDE.sub(include, source)


def _strip_version(text: str) -> str:
    lines = text.splitlines()
    if lines and lines[0].startswith("#version"):
        lines[0] = ""
    return "\n".join(lines)


def read_source(path: Path) -> str:
    """A shader file's text; :class:`ShaderError` (naming the file and line) when it
    cannot be read, is not a regular file, is too large or is not UTF-8 (an editor saved
    a stray byte): hot reload then keeps the last good program."""
    try:
        return read_text(path, "shader")
    except UserFileError as exc:
        raise ShaderError(path, str(exc)) from None


def preprocess(path: Path, stage: str, defines: dict[str, object] | None = None) -> str:
    """The source handed to the compiler for one stage of ``path``."""
    text = read_source(path)
    lines = text.splitlines()
    if not lines or not lines[0].startswith("#version"):
        raise ShaderError(path, "line 1 must be '#version 430 core'")
    version, body = lines[0], "\n".join(lines[1:])
    if defines:
        def override(match: re.Match) -> str:
            name = match.group(2)
            if name in defines:
                return f"{match.group(1)}{name}{match.group(3)}{defines[name]}"
            return match.group(0)

        body = _DEFINE.sub(override, body)
    body = _resolve_includes(body, shader_dir(), 0, (path.resolve(),))
    # The #line after the includes would be wrong for code below an include; includes sit
    # at the top of our files, so errors in the body still point near the right line.
    return f"{version}\n#define {stage} 1\n#line 2\n{body}\n"


_COMMENT = re.compile(r"//[^\n]*|/\*.*?\*/", re.DOTALL)
_UNIFORM = re.compile(r"\buniform\b[^;{}]*?\b(\w+)\s*(?:\[[^\]]*\])?\s*;")


def declared_uniforms(source: str) -> frozenset[str]:
    """Names of the uniforms ``source`` declares (comments ignored; declarations inside
    inactive ``#if`` branches count too: the name is known, only unused)."""
    return frozenset(_UNIFORM.findall(_COMMENT.sub(" ", source)))


class UniformError(ValueError):
    """A uniform name the program does not declare, or one it should read but does not."""


def stages_in(path: Path) -> list[str]:
    text = read_source(path)
    return [s for s in STAGES if re.search(rf"#if\s+defined\s*\(?\s*{s}\b", text)]


def load_program(ctx: moderngl.Context, name: str, defines: dict[str, object] | None = None,
                 varyings: tuple[str, ...] = ()) -> moderngl.Program | moderngl.ComputeShader:
    """Compile ``shaders/<name>`` (a render program or a compute shader)."""
    path = shader_dir() / name
    if not path.exists():
        raise ShaderError(path, f"no shader file {path}")
    stages = stages_in(path)
    if not stages:
        raise ShaderError(path, "no '#if defined <STAGE>_SHADER' section found")
    sources = {s: preprocess(path, s, defines) for s in stages}
    try:
        if stages == ["COMPUTE_SHADER"]:
            program = ctx.compute_shader(sources["COMPUTE_SHADER"])
        else:
            program = ctx.program(
                vertex_shader=sources.get("VERTEX_SHADER"),
                geometry_shader=sources.get("GEOMETRY_SHADER"),
                fragment_shader=sources.get("FRAGMENT_SHADER"),
                varyings=varyings,
            )
    except moderngl.Error as exc:
        raise ShaderError(path, str(exc)) from exc
    # What set_uniforms checks names against (moderngl keeps user data in ``extra``).
    # "set" and "read": what the code has set on it and required it to read, so that a
    # hot reload can refuse a new version that lacks them (see ProgramCache).
    program.extra = {"name": name, "declared": frozenset().union(
        *(declared_uniforms(source) for source in sources.values())),
        "set": set(), "read": set()}
    return program


def set_uniforms(program, values: dict[str, object], reads: Iterable[str] = ()) -> None:
    """Set ``values`` on a program from :func:`load_program`.

    A name the program's source does not declare raises :class:`UniformError` (a misspelt
    uniform would otherwise keep the value 0). A declared name the compiler removed
    because the program does not use it is skipped. ``reads``: uniforms the program must
    use (the passes give the correction switches of their stage,
    ``explorer.lpv.corrections.uniforms_read_by``); each must be in ``values`` and active
    in the compiled program, else :class:`UniformError`. The same ``values`` object as the
    last call's is taken as unchanged (a caller must not change a dict it passed).
    """
    # (written to make few calls: every pass sets its uniforms every frame)
    try:
        info = program.extra
        declared = info["declared"]
    except (AttributeError, TypeError, KeyError):
        raise TypeError("set_uniforms needs a program made by load_program (ProgramCache), "
                        "which records the uniforms its source declares") from None
    if reads:
        _check_reads(program, info, info.get("name", "program"), values, reads, declared)
    if values is info.get("last values"):
        # the dict of the last call again: a pass that keeps its uniforms while their
        # inputs do not change hands the same (unchanged) dict, so nothing is uploaded
        return
    uploaded = info.get("values")
    if uploaded is None:
        uploaded = info["values"] = {}
    for key, value in values.items():
        # a uniform keeps its value in the program: one the last call set is not
        # uploaded again (a frame sets most of them to what they were)
        kind = value.__class__
        stamp = (kind, value) if kind is int or kind is float else _value_key(value)
        if key in uploaded:             # active: it was uploaded before
            if uploaded[key] != stamp:
                program[key] = value
                uploaded[key] = stamp
        # program.get, not ``in``: moderngl's programs have no __contains__ (``in`` iterates)
        elif program.get(key, None) is not None:
            program[key] = value
            uploaded[key] = stamp
        elif key not in declared:
            close = difflib.get_close_matches(key, sorted(declared), n=3)
            hint = f"; did you mean {', '.join(close)}?" if close else ""
            label = info.get("name", "program")
            raise UniformError(f"{label} declares no uniform {key!r}{hint}")
    names = info.get("set")
    if names is None:
        names = info["set"] = set()
    names.update(values)
    info["last values"] = values


def set_uniform(program, name: str, value: int | float) -> None:
    """Set one uniform of a plain number, as ``set_uniforms(program, {name: value})`` does
    (uploaded only when it changed), in fewer steps for a value that changes every call
    (the audit's result slot, once a propagation step): a name not uploaded before goes
    through :func:`set_uniforms` (its checks), later ones compare the kept stamp."""
    info = program.extra
    uploaded = info.get("values")
    if uploaded is None or name not in uploaded:
        set_uniforms(program, {name: value})
        return
    stamp = (type(value), value)
    if uploaded[name] != stamp:
        # the Uniform object kept (the program's own: a reloaded program is a new one)
        uniform = info.setdefault("uniforms", {}).get(name)
        if uniform is None:
            uniform = info["uniforms"][name] = program[name]
        uniform.value = value
        uploaded[name] = stamp
        # set_uniforms skips the dict of its last call as unchanged: no longer true of one
        # that holds this name
        info["last values"] = None


def _check_reads(program, info: dict, label: str, values: dict[str, object],
                 reads: Iterable[str], declared: frozenset) -> None:
    """:func:`set_uniforms`' check of ``reads``: each in ``values`` and active in the
    program (a tuple found active once is not asked about again: a compiled program's
    active uniforms do not change)."""
    checked = info.setdefault("reads checked", set())
    known = type(reads) is tuple and reads in checked
    for name in reads:
        if name not in values:
            raise UniformError(f"{label}: no value given for {name}, which it must read")
        if not known and program.get(name, None) is None:
            raise UniformError(f"{label} must read the uniform {name} but the compiled program "
                               f"does not use it (declared: {name in declared})")
    if not known:
        info.setdefault("read", set()).update(reads)
        if type(reads) is tuple:
            checked.add(reads)


_PLAIN_NUMBERS = frozenset((int, float, bool))


def _value_key(value: object) -> object:
    """A uniform value as something ``==`` compares exactly (arrays by their bytes)."""
    kind = type(value)
    if kind is float or kind is int or kind is bool:
        return (kind, value)
    if isinstance(value, np.ndarray):
        return (value.dtype.str, value.shape, value.tobytes())
    if kind is tuple or kind is list or isinstance(value, (list, tuple)):
        types = tuple(map(type, value))
        if _PLAIN_NUMBERS.issuperset(types):
            # a vector or matrix of plain numbers: what the element-wise keys would
            # compare, in one tuple (a 4×4 matrix: 1 call, not 17)
            return (types, tuple(value))
        return tuple(map(_value_key, value))
    if isinstance(value, np.generic):
        return (value.dtype.str, value.item())
    return (type(value), value)


PROGRAM_CAPACITY = 48
"""Programs one cache keeps compiled at once; the least recently used beyond it are
released. The variants are finite (defines chosen from settings), but they multiply: the
propagation alone has over a hundred, and llvmpipe keeps megabytes of machine code per
program. One pipeline's frame uses about fifteen."""


@dataclass
class ProgramCache:
    """Programs keyed by file and defines, reloaded when a file under shaders/ changes.

    A reload that fails keeps the last good program and records the log in ``errors``
    (the app shows it in a panel) instead of raising. At most ``capacity`` programs stay
    compiled, the least recently used go first: a caller gets its program again for each
    use (a pass that runs one over several frames gets it each frame).
    """

    ctx: moderngl.Context
    capacity: int = PROGRAM_CAPACITY
    _programs: dict = field(default_factory=dict)
    _stamp: float = 0.0
    errors: dict[str, str] = field(default_factory=dict)
    releases: int = 0
    """Counts the programs that left the cache (evicted, replaced by a reload, released):
    while it is unchanged a program got before is still the cache's, so a caller that
    gets one many times in a row (a propagation's steps) may keep it and compare this."""

    @staticmethod
    def key(name: str, defines: dict[str, object] | None = None) -> tuple:
        """What the cache knows the program of ``name`` with ``defines`` by (a caller that
        gets one program many times may make it once and pass it to :meth:`get`)."""
        return (name, tuple(sorted(defines.items())) if defines else ())

    def get(self, name: str, defines: dict[str, object] | None = None,
            key: tuple | None = None):
        """The program of ``shaders/<name>`` with ``defines``, compiled on first use; valid
        until ``capacity`` other programs have been got since (then it may be released).
        ``key``: :meth:`key` of the same name and defines, made already."""
        if key is None:
            key = self.key(name, defines)
        programs = self._programs
        program = programs.pop(key, None)
        if program is None:
            program = load_program(self.ctx, name, defines)
            programs[key] = program
            self._evict()
        else:
            programs[key] = program             # most recently used last
        return program

    def __len__(self) -> int:
        return len(self._programs)

    def _evict(self) -> None:
        """Release the least recently used programs beyond ``capacity``."""
        while len(self._programs) > self.capacity:
            self._programs.pop(next(iter(self._programs))).release()
            self.releases += 1

    @staticmethod
    def newest_change() -> float:
        """The newest modification time of the shader files (see :func:`shader_files`)."""
        stamps = []
        for path in shader_files():
            try:
                stamps.append(path.stat().st_mtime)
            except OSError:             # removed between the listing and the stat
                continue
        return max(stamps, default=0.0)

    def reload_if_changed(self) -> bool:
        """Recompile every cached program if a shader file changed; True if any did."""
        stamp = self.newest_change()
        if stamp <= self._stamp:
            return False
        first = self._stamp == 0.0
        self._stamp = stamp
        if first:
            return False
        changed = False
        for key in list(self._programs):
            name, defines = key
            try:
                fresh = load_program(self.ctx, name, dict(defines))
                problem = _lacks_what_was_used(self._programs[key], fresh)
            except ShaderError as exc:
                self.errors[name] = exc.log
                continue
            except Exception as exc:  # noqa: BLE001 - any failure keeps the last good one
                self.errors[name] = f"{name}: {type(exc).__name__}: {exc}"
                continue
            if problem:
                fresh.release()
                self.errors[name] = problem
                continue
            self.errors.pop(name, None)
            old = self._programs[key]
            fresh.extra["set"].update(old.extra.get("set", ()))
            fresh.extra["read"].update(old.extra.get("read", ()))
            old.release()
            self._programs[key] = fresh
            self.releases += 1
            changed = True
        return changed

    def release(self) -> None:
        for program in self._programs.values():
            program.release()
        self.releases += len(self._programs)
        self._programs.clear()


def shader_files() -> list[Path]:
    """The ``*.glsl`` files under the shader folder that hot reload watches: regular
    files only, no hidden names and no editor lock, swap or backup files (Emacs's
    ``.#gather.glsl`` is a dangling link, vim's ``.gather.glsl.swp`` a hidden file), no
    folders."""
    found = []
    root = shader_dir()
    for path in root.rglob("*.glsl"):
        relative = path.relative_to(root).parts
        if any(part.startswith((".", "#")) or part.endswith("~") for part in relative):
            continue
        try:
            if not path.is_file():
                continue
        except OSError:
            continue
        found.append(path)
    return found


def _lacks_what_was_used(old, fresh) -> str | None:
    """Why a recompiled program cannot replace ``old``: it no longer declares a uniform
    the code sets on it, or no longer uses one the code requires it to read. None when
    it can."""
    name = old.extra.get("name", "program")
    missing = sorted(set(old.extra.get("set", ())) - fresh.extra["declared"])
    if missing:
        return (f"{name}: no longer declares the uniform(s) {', '.join(missing)} that the "
                f"code sets; keeping the last good program")
    unread = sorted(u for u in old.extra.get("read", ()) if u not in fresh)
    if unread:
        return (f"{name}: no longer uses the uniform(s) {', '.join(unread)} that its pass "
                f"must read; keeping the last good program")
    return None
