"""The files of the scene on screen, watched like the shaders: a scene file (or a mesh)
edited while the window shows it is read again and shown; an edit that does not load
keeps the scene as it was, with the one-line error in Messages.

The controller polls :meth:`SceneWatch.changed` every ``scene_reload.SHADER_POLL_S``; a stamp is a
file's modification time and size, so an editor's save (in place or by rename) counts and
reading the file is left to the one load that follows."""

from __future__ import annotations

import os
from dataclasses import dataclass, field

Stamp = tuple[int, int] | None
"""(st_mtime_ns, st_size) of a file, None while it is missing (an editor's rename)."""


def stamps(files: tuple[str, ...]) -> dict[str, Stamp]:
    found: dict[str, Stamp] = {}
    for path in files:
        try:
            status = os.stat(path)
        except OSError:
            found[path] = None
        else:
            found[path] = (status.st_mtime_ns, status.st_size)
    return found


@dataclass
class SceneWatch:
    """The scene shown (its name as ``Settings.scene`` holds it) and its files' stamps."""

    name: str | None = None
    files: tuple[str, ...] = ()
    seen: dict[str, Stamp] = field(default_factory=dict)

    def watch(self, name: str, files: tuple[str, ...]) -> None:
        """Watch the files of the scene ``name`` from their present state."""
        self.name, self.files, self.seen = name, tuple(files), stamps(tuple(files))

    def changed(self) -> bool:
        """True once per change of any watched file since :meth:`watch` or the last call
        that said so; a file that is missing now waits (an editor may be replacing it)."""
        now = stamps(self.files)
        if now == self.seen or any(stamp is None for stamp in now.values()):
            return False
        self.seen = now
        return True
