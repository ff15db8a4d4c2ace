"""What a window frame costs that draws nothing but a clear, with and without a depth and
stencil buffer in the window: wall and CPU milliseconds (all threads: llvmpipe's
rasterisers too) a frame, over 300 frames at 1600×960.

    xvfb-run -a -s "-screen 0 1700x1100x24" python scripts/window_clear_swap.py
"""

from __future__ import annotations

import resource
import subprocess
import sys
import time

FRAMES = 300


def cpu_s() -> float:
    usage = resource.getrusage(resource.RUSAGE_SELF)
    return usage.ru_utime + usage.ru_stime


def measure(depth: bool) -> str:
    import glfw
    import moderngl

    if not glfw.init():
        raise SystemExit("glfw could not start: run under xvfb-run")
    glfw.window_hint(glfw.CONTEXT_VERSION_MAJOR, 4)
    glfw.window_hint(glfw.CONTEXT_VERSION_MINOR, 3)
    glfw.window_hint(glfw.OPENGL_PROFILE, glfw.OPENGL_CORE_PROFILE)
    if not depth:
        glfw.window_hint(glfw.DEPTH_BITS, 0)
        glfw.window_hint(glfw.STENCIL_BITS, 0)
    window = glfw.create_window(1600, 960, "clear and swap", None, None)
    glfw.make_context_current(window)
    glfw.swap_interval(0)
    ctx = moderngl.create_context()

    def frame() -> None:
        ctx.screen.use()
        ctx.clear(0.1, 0.1, 0.1)
        glfw.swap_buffers(window)

    for _ in range(20):
        frame()
    ctx.finish()
    wall, cpu = time.perf_counter(), cpu_s()
    for _ in range(FRAMES):
        frame()
    ctx.finish()
    wall, cpu = (time.perf_counter() - wall) / FRAMES, (cpu_s() - cpu) / FRAMES
    glfw.terminate()
    return (f"{'with' if depth else 'without'} depth and stencil: wall {wall * 1e3:.2f} ms, "
            f"CPU {cpu * 1e3:.2f} ms a frame")


def main() -> int:
    if len(sys.argv) == 2:
        print(measure(sys.argv[1] == "depth"))
        return 0
    for kind in ("depth", "none", "depth", "none"):     # each in a process of its own
        subprocess.run([sys.executable, __file__, kind], check=True)
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
