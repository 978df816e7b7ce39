"""A glTF 2.0 document assembled with pygltflib: one binary buffer, accessors per array, PNG images
inside the buffer, and nodes carrying their metadata in `extras`."""

from __future__ import annotations

import io
import json

import numpy as np
import pygltflib as gl

INSTANCING = "EXT_mesh_gpu_instancing"
FEATURES, METADATA = "EXT_mesh_features", "EXT_structural_metadata"
# The building class of EXT_structural_metadata: property -> (type, from a metadata dict)
BUILDING_PROPERTIES = {
    "source_id": "STRING",
    "kind": "STRING",
    "part_of": "STRING",
    "height": "FLOAT32",
    "min_height": "FLOAT32",
    "levels": "FLOAT32",
    "roof_shape": "STRING",
    "facade": "STRING",
    "tags": "STRING",  # JSON object text
    "tagged": "STRING",
    "guessed": "STRING",  # comma-separated attribute names
}
NO_DATA = -1.0
_COMPONENTS = {
    np.dtype(np.float32): gl.FLOAT,
    np.dtype(np.uint32): gl.UNSIGNED_INT,
    np.dtype(np.uint16): gl.UNSIGNED_SHORT,
}
_TYPES = {1: gl.SCALAR, 2: gl.VEC2, 3: gl.VEC3, 4: gl.VEC4}


def png_bytes(image: np.ndarray) -> bytes:
    from PIL import Image

    out = io.BytesIO()
    Image.fromarray(image).save(out, format="PNG", compress_level=1)
    return out.getvalue()


class Document:
    """Grows a GLTF2 and its binary blob; `finish()` returns the GLTF2 ready to save."""

    def __init__(self, extras: dict, place=None):
        self.place = place  # export._place.Placement for 3D Tiles content, None: the scene's frame
        self.gltf = gl.GLTF2(asset=gl.Asset(version="2.0", generator="cityshade export", extras=extras))
        self.gltf.scenes.append(gl.Scene(nodes=[], extras=extras))
        self.gltf.scene = 0
        self.blob = bytearray()
        self.samplers: dict[tuple, int] = {}
        self.features: list[dict] = []  # one metadata row per building (EXT_structural_metadata)

    def _view(self, data: bytes, target: int | None = None) -> int:
        self.blob.extend(b"\0" * (-len(self.blob) % 8))  # EXT_structural_metadata wants 8-byte alignment
        self.gltf.bufferViews.append(
            gl.BufferView(buffer=0, byteOffset=len(self.blob), byteLength=len(data), target=target)
        )
        self.blob.extend(data)
        return len(self.gltf.bufferViews) - 1

    def accessor(self, array: np.ndarray, bounds: bool = False, target: int | None = gl.ARRAY_BUFFER) -> int:
        """An accessor over a (n,) or (n, k) array of float32/uint32; bounds for POSITION."""
        array = np.ascontiguousarray(array)
        width = 1 if array.ndim == 1 else array.shape[1]
        view = self._view(array.tobytes(), target)
        accessor = gl.Accessor(
            bufferView=view, componentType=_COMPONENTS[array.dtype], count=len(array), type=_TYPES[width]
        )
        if bounds:
            accessor.min = [float(v) for v in array.reshape(len(array), -1).min(axis=0)]
            accessor.max = [float(v) for v in array.reshape(len(array), -1).max(axis=0)]
        self.gltf.accessors.append(accessor)
        return len(self.gltf.accessors) - 1

    def texture(self, image: np.ndarray, repeat: bool = False, name: str | None = None) -> int:
        """A PNG image in the buffer and a texture sampling it (linear, mipmapped)."""
        wrap = gl.REPEAT if repeat else gl.CLAMP_TO_EDGE
        key = (wrap,)
        if key not in self.samplers:
            self.gltf.samplers.append(
                gl.Sampler(magFilter=gl.LINEAR, minFilter=gl.LINEAR_MIPMAP_LINEAR, wrapS=wrap, wrapT=wrap)
            )
            self.samplers[key] = len(self.gltf.samplers) - 1
        view = self._view(png_bytes(image))
        self.gltf.images.append(gl.Image(bufferView=view, mimeType="image/png", name=name))
        self.gltf.textures.append(gl.Texture(source=len(self.gltf.images) - 1, sampler=self.samplers[key]))
        return len(self.gltf.textures) - 1

    def material(
        self,
        name: str,
        colour=(1.0, 1.0, 1.0, 1.0),
        roughness: float = 0.9,
        metallic: float = 0.0,
        base_texture: int | None = None,
        mr_texture: int | None = None,
        normal_texture: int | None = None,
        emissive_texture: int | None = None,
        double_sided: bool = False,
    ) -> int:
        pbr = gl.PbrMetallicRoughness(baseColorFactor=list(colour), metallicFactor=metallic, roughnessFactor=roughness)
        if base_texture is not None:
            pbr.baseColorTexture = gl.TextureInfo(index=base_texture)
        if mr_texture is not None:
            pbr.metallicRoughnessTexture = gl.TextureInfo(index=mr_texture)
        material = gl.Material(name=name, pbrMetallicRoughness=pbr, doubleSided=double_sided)
        if normal_texture is not None:
            material.normalTexture = gl.NormalMaterialTexture(index=normal_texture)
        if emissive_texture is not None:
            material.emissiveTexture = gl.TextureInfo(index=emissive_texture)
            material.emissiveFactor = [1.0, 1.0, 1.0]
        self.gltf.materials.append(material)
        return len(self.gltf.materials) - 1

    def world(self, points) -> np.ndarray:
        """(n, 3) scene points in the document's frame: as they are, or placed on Earth (export._place)."""
        points = np.asarray(points, np.float64).reshape(-1, 3)
        return points if self.place is None else self.place.positions(points)

    def turn(self, vectors) -> np.ndarray:
        """Scene directions (normals, tangents' xyz) in the document's frame."""
        vectors = np.asarray(vectors, np.float64).reshape(-1, 3)
        return vectors if self.place is None else self.place.directions(vectors)

    def primitive(
        self, material: int, positions, normals, uv=None, tangents=None, colours=None, features=None, indices=None
    ) -> gl.Primitive:
        """Triangles: a vertex list, or vertices and indices; `features`: each vertex's row of the
        building property table (EXT_mesh_features)."""
        attributes = gl.Attributes(
            POSITION=self.accessor(positions.astype(np.float32), bounds=True), NORMAL=self.accessor(unit(normals))
        )
        if uv is not None:
            attributes.TEXCOORD_0 = self.accessor(uv.astype(np.float32))
        if tangents is not None:
            attributes.TANGENT = self.accessor(tangents.astype(np.float32))
        if colours is not None:
            attributes.COLOR_0 = self.accessor(colours.astype(np.float32))
        primitive = gl.Primitive(attributes=attributes, material=material, mode=gl.TRIANGLES)
        if indices is not None:
            small = len(positions) <= np.iinfo(np.uint16).max
            indices = indices.astype(np.uint16 if small else np.uint32)
            primitive.indices = self.accessor(indices, target=gl.ELEMENT_ARRAY_BUFFER)
        if features is not None:
            attributes._FEATURE_ID_0 = self.accessor(np.asarray(features, np.float32))
            primitive.extensions = {FEATURES: {"featureIds": [{"attribute": 0, "propertyTable": 0, "featureCount": 0}]}}
        return primitive

    def feature_row(self, metadata: dict) -> int:
        """A row of the building property table (EXT_structural_metadata): primitives select it
        through their _FEATURE_ID_0."""
        self.features.append(metadata)
        return len(self.features) - 1

    def _property_table(self):
        rows = self.features
        properties, schema = {}, {}
        for name, kind in BUILDING_PROPERTIES.items():
            values = [row.get(name) for row in rows]
            if kind == "FLOAT32":
                data = np.array([NO_DATA if v is None else float(v) for v in values], np.float32)
                properties[name] = {"values": self._view(data.tobytes())}
                schema[name] = {"type": "SCALAR", "componentType": "FLOAT32", "noData": NO_DATA}
                continue
            texts = [_text(v) for v in values]
            encoded = [t.encode("utf-8") for t in texts]
            offsets = np.concatenate([[0], np.cumsum([len(e) for e in encoded])]).astype(np.uint32)
            properties[name] = {
                "values": self._view(b"".join(encoded) or b"\0"),
                "stringOffsets": self._view(offsets.tobytes()),
                "stringOffsetType": "UINT32",
            }
            schema[name] = {"type": "STRING"}
        self.gltf.extensions[METADATA] = {
            "schema": {"id": "cityshade", "classes": {"building": {"properties": schema}}},
            "propertyTables": [{"class": "building", "count": len(rows), "properties": properties}],
        }
        for mesh in self.gltf.meshes:
            for primitive in mesh.primitives:
                if primitive.extensions and FEATURES in primitive.extensions:
                    primitive.extensions[FEATURES]["featureIds"][0]["featureCount"] = len(rows)
        self.gltf.extensionsUsed += [FEATURES, METADATA]

    def node(
        self,
        name: str,
        primitives: list[gl.Primitive],
        extras: dict | None = None,
        extensions: dict | None = None,
        translation=None,
    ) -> int:
        """A mesh of the primitives and a root node showing it (at `translation`, its origin)."""
        self.gltf.meshes.append(gl.Mesh(name=name, primitives=primitives))
        node = gl.Node(name=name, mesh=len(self.gltf.meshes) - 1, extras=extras or {})
        if translation is not None:
            node.translation = [float(v) for v in translation]
        if extensions:
            node.extensions = extensions
        self.gltf.nodes.append(node)
        self.gltf.scenes[0].nodes.append(len(self.gltf.nodes) - 1)
        return len(self.gltf.nodes) - 1

    def instanced(self, name: str, primitives, translations, rotations, scales, extras=None) -> int:
        """A mesh drawn at many places through EXT_mesh_gpu_instancing."""
        extension = {
            "attributes": {
                "TRANSLATION": self.accessor(translations.astype(np.float32), target=None),
                "ROTATION": self.accessor(rotations.astype(np.float32), target=None),
                "SCALE": self.accessor(scales.astype(np.float32), target=None),
            }
        }
        if INSTANCING not in self.gltf.extensionsUsed:
            self.gltf.extensionsUsed.append(INSTANCING)
        return self.node(name, primitives, extras, {INSTANCING: extension})

    def finish(self) -> gl.GLTF2:
        if self.features:
            self._property_table()
        self.blob.extend(b"\0" * (-len(self.blob) % 4))
        self.gltf.buffers = [gl.Buffer(byteLength=len(self.blob))]
        self.gltf.set_binary_blob(bytes(self.blob))
        return self.gltf


def _text(value) -> str:
    if value is None:
        return ""
    if isinstance(value, dict):
        return json.dumps(value, ensure_ascii=False, sort_keys=True)
    if isinstance(value, (list, tuple)):
        return ",".join(str(v) for v in value)
    return str(value)


def unit(vectors: np.ndarray) -> np.ndarray:
    """Unit float32 vectors; zero vectors become +y (the validator rejects non-unit normals)."""
    v = np.asarray(vectors, np.float64)
    length = np.linalg.norm(v, axis=1, keepdims=True)
    out = np.where(length > 1e-9, v / np.maximum(length, 1e-12), np.array([0.0, 1.0, 0.0]))
    return out.astype(np.float32)


def glb_bytes(gltf: gl.GLTF2) -> bytes:
    return b"".join(gltf.save_to_bytes())


def gltf_text(gltf: gl.GLTF2) -> str:
    """A self-contained .gltf: the buffer as a base64 data URI."""
    gltf.convert_buffers(gl.BufferFormat.DATAURI)
    return gltf.to_json()
