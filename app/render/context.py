"""Creating an OpenGL context: headless through EGL on Linux, default backend elsewhere.

The window context is created by :mod:`app.ui.window` (glfw) and wrapped with
``moderngl.create_context()``; everything after that is shared.
"""

from __future__ import annotations

import sys

import moderngl

from ..errors import GLContextError

REQUIRED_GL = 330

_EGL_HINT = ("install Mesa's EGL and OpenGL drivers, e.g. on Debian/Ubuntu: "
             "apt-get install libegl1 libgl1-mesa-dri")


_SHARED: list[moderngl.Context] = []


def shared_headless_context() -> moderngl.Context:
    """The process's one headless context, made on first use and kept until exit.

    Every headless renderer in a process draws in it (``gaitlab render``, the tests, a
    script recording several clips): making and releasing a second standalone EGL
    context while another is alive corrupts the survivor's rendering on Mesa (seen as
    noise in every later frame), and one context saves its start-up cost per clip."""
    if not _SHARED:
        _SHARED.append(create_headless_context())
    return _SHARED[0]


def create_headless_context() -> moderngl.Context:
    """A standalone OpenGL >= 3.3 context with no window (EGL on Linux).

    Raises :class:`GLContextError` with the package to install when it cannot be made.
    """
    try:
        if sys.platform.startswith("linux"):
            ctx = moderngl.create_standalone_context(require=REQUIRED_GL, backend="egl")  # type: ignore[arg-type]
        else:
            ctx = moderngl.create_standalone_context(require=REQUIRED_GL)
    except Exception as exc:  # moderngl/glcontext raise bare Exceptions with library messages
        detail = str(exc).strip().splitlines()[0] if str(exc).strip() else type(exc).__name__
        raise GLContextError(f"cannot create a headless OpenGL context through EGL ({detail}); "
                             f"{_EGL_HINT}") from None
    if ctx.version_code < REQUIRED_GL:
        raise GLContextError(f"OpenGL {ctx.version_code / 100:.1f} found, Gaitlab needs 3.3; {_EGL_HINT}")
    return ctx
