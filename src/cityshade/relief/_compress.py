"""A facade's detail maps D, M, A factorised for random access on the GPU."""

from __future__ import annotations

import hashlib
from dataclasses import dataclass
from typing import Callable

import numpy as np

from ._boxes import free_boxes
from ._factor import Factors, factorize
from ._maps import DetailMaps

MAP_NAMES = ("depth", "material", "boxes")  # D, M, A in the paper's order


def digest(matrix: np.ndarray) -> str:
    """A fingerprint of a map's values (shape and uint32 values), independent of its dtype."""
    data = np.ascontiguousarray(matrix, dtype="<u4")
    return hashlib.sha256(str(matrix.shape).encode() + data.tobytes()).hexdigest()


@dataclass(frozen=True)
class CompressedFacade:
    method: str
    texel: float
    depth_unit: float
    factors: dict[str, Factors]  # MAP_NAMES -> factors
    boxes: np.ndarray  # (n, 4) uint16 free boxes x0, y0, x1, y1 that A indexes
    digests: dict[str, str]  # MAP_NAMES -> digest of the map the factors were made from

    @property
    def shape(self) -> tuple[int, int]:
        return self.factors["depth"].shape

    def decompress(self) -> dict[str, np.ndarray]:
        return {name: f.reconstruct() for name, f in self.factors.items()}

    def maps(self) -> DetailMaps:
        out = self.decompress()
        return DetailMaps(
            out["depth"].astype(np.uint16), out["material"].astype(np.uint16), self.texel, self.depth_unit
        )

    def raw_nbytes(self) -> dict[str, int]:
        """GPU bytes of the uncompressed maps: R16UI D and M, R32UI A plus the box list."""
        rows, cols = self.shape
        return {"depth": 2 * rows * cols, "material": 2 * rows * cols, "boxes": 4 * rows * cols + self.boxes.nbytes}

    def nbytes(self) -> dict[str, int]:
        """GPU bytes per map; the box list is counted with A."""
        sizes = {name: f.nbytes() for name, f in self.factors.items()}
        sizes["boxes"] += self.boxes.nbytes
        return sizes


def detail_matrices(maps: DetailMaps) -> tuple[dict[str, np.ndarray], np.ndarray]:
    """D, M and the free-box index map A of a facade, plus the box list A indexes."""
    index, boxes = free_boxes(maps.depth)
    return {"depth": maps.depth, "material": maps.material, "boxes": index}, boxes


def compress(
    maps: DetailMaps,
    method: str,
    max_terms: int | None = None,
    on_map: Callable[[str], None] | None = None,
    source: str = "facade",
) -> CompressedFacade:
    """Builds A and factorises D, M and A; on_map(name) is called after each map (progress);
    source names the facade in errors."""
    matrices, boxes = detail_matrices(maps)
    if on_map:
        on_map("acceleration")
    factors = {}
    for name in MAP_NAMES:
        limit = {} if max_terms is None else {"max_terms": max_terms}
        factors[name] = factorize(matrices[name], method, name=f"{source}: {name} map", **limit)
        if on_map:
            on_map(name)
    digests = {name: digest(matrices[name]) for name in MAP_NAMES}
    return CompressedFacade(method, maps.texel, maps.depth_unit, factors, boxes, digests)
