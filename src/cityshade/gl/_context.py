"""The one place an OpenGL context is made: headless through EGL, or adopted from a window."""

from __future__ import annotations

import moderngl

from ..errors import GLUnavailableError

REQUIRED_GL = 430
EGL_PACKAGES = "libegl1 libegl-mesa0 libgl1-mesa-dri"


def create_context(headless: bool = True) -> moderngl.Context:
    """An OpenGL 4.3+ core context. Headless uses EGL (Mesa llvmpipe when there is no GPU);
    otherwise the context current in this thread (made by a window) is adopted."""
    try:
        if headless:
            ctx = moderngl.create_standalone_context(backend="egl", require=REQUIRED_GL)
        else:
            ctx = moderngl.create_context(require=REQUIRED_GL)
    except Exception as exc:  # moderngl/glcontext raise plain Exceptions for every failure
        raise GLUnavailableError(
            f"could not create an OpenGL {REQUIRED_GL // 100}.{REQUIRED_GL // 10 % 10} context ({exc}); "
            f"on Debian/Ubuntu install the packages: apt-get install {EGL_PACKAGES}"
        ) from None
    return ctx


def describe_context(ctx: moderngl.Context) -> str:
    info = ctx.info
    return f"{info['GL_RENDERER']} (OpenGL {info['GL_VERSION']})"
