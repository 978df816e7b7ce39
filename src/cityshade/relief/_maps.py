"""Detail maps of one facade: displacement D and material index M, loaded from PNG pairs.

Maps are integer matrices indexed [row, column] with row 0 at the BOTTOM of the facade, so a
facade point (u, v) in metres lies in texel (v / texel, u / texel) and the arrays upload to
OpenGL textures without a flip. D counts depth steps of `depth_unit` metres behind the
outermost surface (0 = outermost); M indexes MATERIALS.
"""

from __future__ import annotations

import warnings
from dataclasses import dataclass
from pathlib import Path

import numpy as np
from PIL import Image

from .._files import write_png
from ..errors import CityshadeError
from ._limits import check_facade_texels

# Material indices of the tile library; the shaders' palette (shaders/relief/materials.glsl)
# lists them in the same order.
MATERIALS = ("wall", "glass", "frame", "stone", "wood", "brick")
GLASS = MATERIALS.index("glass")


@dataclass(frozen=True)
class DetailMaps:
    depth: np.ndarray  # (rows, cols) uint16, depth steps behind the outermost surface
    material: np.ndarray  # (rows, cols) uint16, index into MATERIALS (or a user's tile library)
    texel: float  # metres per texel
    depth_unit: float  # metres per depth step

    def __post_init__(self):
        if self.depth.shape != self.material.shape or self.depth.ndim != 2:
            raise CityshadeError(f"depth map {self.depth.shape} and material map {self.material.shape} differ in size")

    @property
    def shape(self) -> tuple[int, int]:
        return self.depth.shape

    @property
    def size_m(self) -> tuple[float, float]:
        """Facade width and height in metres."""
        return self.depth.shape[1] * self.texel, self.depth.shape[0] * self.texel

    @property
    def max_depth(self) -> int:
        return int(self.depth.max())


def load_png_maps(height_png: Path, material_png: Path, texel: float, depth_unit: float) -> DetailMaps:
    """D from a 16-bit (or 8-bit) greyscale PNG whose values are depth steps behind the outermost
    surface, M from an 8- or 16-bit greyscale PNG of material indices. Top image row = top of facade."""
    depth = _read_integer_image(height_png, "height")
    material = _read_integer_image(material_png, "material")
    if depth.shape != material.shape:
        raise CityshadeError(
            f"{height_png} is {depth.shape[1]}x{depth.shape[0]} but {material_png} is "
            f"{material.shape[1]}x{material.shape[0]}: the height and material images must have the same size"
        )
    return DetailMaps(depth[::-1].copy(), material[::-1].copy(), texel, depth_unit)


def _read_integer_image(path: Path, role: str) -> np.ndarray:
    try:
        with warnings.catch_warnings():  # Pillow's bomb warning: the size is checked here instead
            warnings.simplefilter("ignore", Image.DecompressionBombWarning)
            image = Image.open(path)  # reads the header only: the size is checked before decoding
        with image:
            check_facade_texels(*image.size, f"{path}: the {role} image")
            mode = image.mode
            data = np.asarray(image)
    except FileNotFoundError:
        raise CityshadeError(f"{path}: no such file") from None
    except (OSError, SyntaxError, Image.DecompressionBombError) as exc:
        raise CityshadeError(f"{path}: not a readable image ({exc})") from None
    if mode not in ("L", "I;16", "I;16B", "I;16L", "I", "P") or data.ndim != 2 or data.dtype.kind not in "ui":
        raise CityshadeError(
            f"{path}: the {role} image has mode {mode}; it must be one-channel integer greyscale "
            "(8- or 16-bit PNG), not colour or floating point"
        )
    if data.min() < 0 or data.max() > 0xFFFF:
        raise CityshadeError(f"{path}: {role} values must lie in 0..65535, found {data.min()}..{data.max()}")
    return data.astype(np.uint16)


def save_png_maps(maps: DetailMaps, height_png: Path, material_png: Path):
    """Writes the pair load_png_maps reads (16-bit PNGs, top row = top of facade)."""
    write_png(maps.depth[::-1].astype(np.uint16), height_png)
    write_png(maps.material[::-1].astype(np.uint16), material_png)
