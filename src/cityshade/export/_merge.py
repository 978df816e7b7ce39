"""Triangles gathered per material and written as one indexed primitive each: the fewer primitives,
the fewer draw calls, and the vertices that triangles share (a wall quad's corners) stored once."""

from __future__ import annotations

from collections import defaultdict

import numpy as np

ATTRIBUTES = ("positions", "normals", "uv", "tangents", "colours", "features")
WIDTHS = {"positions": 3, "normals": 3, "uv": 2, "tangents": 4, "colours": 4, "features": 1}


class Pieces:
    """Triangle lists (three vertices a triangle) by material; the attributes a material's pieces
    carry must agree (a facade page: uv and tangents; roofs: colours)."""

    def __init__(self):
        self.by_material: dict[int, list[dict]] = defaultdict(list)

    def add(self, material: int, **arrays):
        self.by_material[material].append({k: v for k, v in arrays.items() if v is not None})

    def __bool__(self) -> bool:
        return bool(self.by_material)

    def bounds(self) -> tuple[np.ndarray, np.ndarray]:
        points = np.concatenate([p["positions"] for pieces in self.by_material.values() for p in pieces])
        return points.min(axis=0), points.max(axis=0)

    def primitives(self, doc, origin: np.ndarray) -> tuple[list, float]:
        """One indexed primitive per material, positions relative to `origin`; and the unit their
        quantized positions count in (the node's scale): the farthest vertex at 32767 units."""
        merged = {}
        for material, pieces in self.by_material.items():
            names = [n for n in ATTRIBUTES if n in pieces[0]]
            arrays = {
                n: np.concatenate([np.asarray(p[n], np.float64).reshape(-1, WIDTHS[n]) for p in pieces]) for n in names
            }
            arrays["positions"] = arrays["positions"] - origin
            merged[material] = (names, arrays)
        reach = max(float(np.abs(arrays["positions"]).max(initial=0.0)) for _, arrays in merged.values())
        scale = max(reach, 1e-3) / 32767.0
        out = []
        for material, (names, arrays) in merged.items():
            vertices, indices = weld(arrays, names)
            if "features" in vertices:
                vertices["features"] = vertices["features"][:, 0]
            out.append(doc.primitive(material, **vertices, indices=indices, scale=scale))
        return out, scale


def weld(merged: dict[str, np.ndarray], names: list[str]) -> tuple[dict[str, np.ndarray], np.ndarray]:
    """Vertices equal in every attribute (as float32, as they are written) become one; returns the
    unique vertices and each triangle corner's index."""
    table = np.concatenate([merged[n].astype(np.float32) for n in names], axis=1)
    rows = np.ascontiguousarray(table).view(np.dtype((np.void, table.dtype.itemsize * table.shape[1]))).ravel()
    _, first, inverse = np.unique(rows, return_index=True, return_inverse=True)
    return {n: merged[n][first] for n in names}, inverse.ravel().astype(np.uint32)
