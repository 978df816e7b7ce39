"""How large a facade's detail maps may be, checked before anything is allocated.

A side of 16384 texels is the largest texture OpenGL 4.5 implementations commonly allow (llvmpipe's
GL_MAX_TEXTURE_SIZE); 2^24 texels (4096 x 4096, 82 x 82 m at the paper's 2 cm) keeps every map,
its float32 reconstruction and the factorisation's work arrays within about 2 GB. The paper's
largest facade, F2, is 1536 x 2048 texels.
"""

from __future__ import annotations

from ..errors import UsageError

MAX_SIDE = 16384
MAX_TEXELS = 1 << 24
# A .cfdm stores at most the factors of MAX_TEXELS texels; SVD factors of such a facade at a few
# hundred terms take tens of MB, so 256 MiB leaves ample room and refuses absurd files unread.
MAX_FILE_BYTES = 256 << 20


def check_facade_texels(cols: int, rows: int, what: str, texel: float | None = None):
    """Raises UsageError (exit 2) naming `what` and the largest size that fits."""
    if 1 <= cols <= MAX_SIDE and 1 <= rows <= MAX_SIDE and cols * rows <= MAX_TEXELS:
        return
    largest = f"at most {MAX_SIDE} texels a side and {MAX_TEXELS} texels in all (4096x4096)"
    if texel is not None:
        side = 4096 * texel
        largest += f"; at a texel of {texel:g} m that is {side:g}x{side:g} metres"
    raise UsageError(f"{what} is {cols}x{rows} texels; a facade may have {largest}")
