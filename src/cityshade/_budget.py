"""Up-front memory estimates for images: a size that would not fit is refused with one line that
names the largest size (same aspect ratio) that does, instead of exhausting memory half-way."""

from __future__ import annotations

import ctypes
import math
import os

from .errors import UsageError

# Never plan to use more than this share of the memory available when the command starts.
MEMORY_SHARE = 0.5


def available_memory() -> int:
    """Bytes of memory available now (physical memory if the system does not say)."""
    try:
        return os.sysconf("SC_AVPHYS_PAGES") * os.sysconf("SC_PAGE_SIZE")
    except (ValueError, OSError):
        return os.sysconf("SC_PHYS_PAGES") * os.sysconf("SC_PAGE_SIZE")


def largest_fitting(size: tuple[int, int], pixels: float) -> tuple[int, int]:
    """The largest size with `size`'s aspect ratio of at most `pixels` pixels."""
    width, height = size
    scale = math.sqrt(pixels / (width * height))
    return max(1, math.floor(width * scale)), max(1, math.floor(height * scale))


def check_image_memory(size: tuple[int, int], bytes_per_pixel: float, what: str, option: str = "--size"):
    """Raises UsageError if `what` at `size` needs more than MEMORY_SHARE of the available memory."""
    budget = available_memory() * MEMORY_SHARE
    need = size[0] * size[1] * bytes_per_pixel
    if need <= budget:
        return
    fits = largest_fitting(size, budget / bytes_per_pixel)
    raise UsageError(
        f"{what} at {size[0]}x{size[1]} needs about {need / 2**30:.1f} GiB ({bytes_per_pixel:g} bytes a "
        f"pixel) but {budget / 2**30:.1f} GiB may be used here; the largest {option} that fits is "
        f"{fits[0]}x{fits[1]}"
    )


def check_gl_size(ctx, size: tuple[int, int], what: str = "the image", option: str = "--size"):
    """Raises UsageError if the OpenGL implementation cannot hold a render target of `size`."""
    limit = min(
        ctx.info["GL_MAX_TEXTURE_SIZE"], ctx.info["GL_MAX_RENDERBUFFER_SIZE"], *ctx.info["GL_MAX_VIEWPORT_DIMS"]
    )
    if max(size) > limit:
        fits = [max(1, math.floor(side * limit / max(size))) for side in size]
        raise UsageError(
            f"{what} at {size[0]}x{size[1]} is larger than this OpenGL allows ({limit} pixels a side); "
            f"the largest {option} that fits is {fits[0]}x{fits[1]}"
        )


def release_freed_memory():
    """Hands the heap pages freed since (a city's meshing temporaries, hundreds of MB for a big city)
    back to the system: glibc's malloc keeps them otherwise, and the process stays that big. A no-op
    where the C library has no malloc_trim."""
    trim = getattr(ctypes.CDLL(None), "malloc_trim", None)
    if trim is not None:
        trim(0)
