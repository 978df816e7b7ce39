"""What the tests use of cityshade.export's internals: its numpy twins and the parts they check one
by one, and a reader of a written tileset's vertices on Earth that shares no code with the writer."""

from __future__ import annotations

import json
from pathlib import Path

import numpy as np

from ._bake import check_size, finest_texel, lit_rooms
from ._content import BuildingWriter, Stats
from ._gltf import Document

__all__ = ["BuildingWriter", "Document", "Stats", "check_size", "finest_texel", "lit_rooms", "tileset_points"]

_DTYPES = {5120: np.int8, 5121: np.uint8, 5122: np.int16, 5123: np.uint16, 5126: np.float32}
Y_UP_TO_Z_UP = np.array([[1.0, 0, 0, 0], [0, 0, -1, 0], [0, 1, 0, 0], [0, 0, 0, 1]])  # 3D Tiles' glTF rule


def _node_matrix(node) -> np.ndarray:
    if node.matrix:
        return np.asarray(node.matrix, np.float64).reshape(4, 4).T
    m = np.eye(4)
    if node.translation:
        m[:3, 3] = node.translation
    if node.scale:
        m[:3, :3] = np.diag(node.scale)
    if node.rotation and node.rotation != [0, 0, 0, 1]:
        raise ValueError("a rotated node: not read here")
    return m


def _positions(gltf, blob: bytes, primitive) -> np.ndarray:
    """A primitive's POSITION, from its accessor or its Draco buffer (decoded by DracoPy)."""
    draco = (primitive.extensions or {}).get("KHR_draco_mesh_compression")
    if draco is not None:
        import DracoPy

        view = gltf.bufferViews[draco["bufferView"]]
        mesh = DracoPy.decode(blob[view.byteOffset : view.byteOffset + view.byteLength])
        wanted = draco["attributes"]["POSITION"]
        return next(np.asarray(a["data"]) for a in mesh.attributes if a["unique_id"] == wanted)
    accessor = gltf.accessors[primitive.attributes.POSITION]
    view = gltf.bufferViews[accessor.bufferView]
    dtype = np.dtype(_DTYPES[accessor.componentType])
    stride = view.byteStride or 3 * dtype.itemsize
    start = view.byteOffset + (accessor.byteOffset or 0)
    rows = np.frombuffer(blob, np.uint8, stride * accessor.count, start).reshape(accessor.count, stride)
    xyz = rows[:, : 3 * dtype.itemsize].copy().view(dtype).reshape(-1, 3).astype(np.float64)
    if accessor.normalized:  # KHR_mesh_quantization's normalized integers
        xyz = np.maximum(xyz / np.iinfo(dtype).max, -1.0)
    return xyz


def _glb_points(path: Path, matrix: np.ndarray) -> np.ndarray:
    import pygltflib

    gltf = pygltflib.GLTF2.load(str(path))
    blob = gltf.binary_blob()
    out = []

    def visit(index, parent):
        node = gltf.nodes[index]
        m = parent @ _node_matrix(node)
        if node.mesh is not None and not (node.extensions or {}).get("EXT_mesh_gpu_instancing"):
            for primitive in gltf.meshes[node.mesh].primitives:
                xyz = _positions(gltf, blob, primitive).astype(np.float64)
                out.append(xyz @ m[:3, :3].T + m[:3, 3])
        for child in node.children or []:
            visit(child, m)

    for index in gltf.scenes[gltf.scene or 0].nodes:
        visit(index, matrix @ Y_UP_TO_Z_UP)
    return np.concatenate(out) if out else np.zeros((0, 3))


def tileset_points(folder: Path, leaves_only: bool = True) -> np.ndarray:
    """(n, 3) EPSG:4978 metres of every mesh vertex of a tileset's tiles (instanced meshes left out),
    through each tile's transform chain, glTF's y-up turned z-up and the glTF node transforms."""
    folder = Path(folder)
    tileset = json.loads((folder / "tileset.json").read_text(encoding="utf-8"))
    points = []

    def walk(tile, parent):
        m = parent
        if "transform" in tile:
            m = parent @ np.asarray(tile["transform"], np.float64).reshape(4, 4).T
        children = tile.get("children", [])
        if "content" in tile and (children == [] or not leaves_only):
            points.append(_glb_points(folder / tile["content"]["uri"], m))
        for child in children:
            walk(child, m)

    walk(tileset["root"], np.eye(4))
    return np.concatenate(points)
