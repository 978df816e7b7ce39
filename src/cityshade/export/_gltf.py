"""A glTF 2.0 document assembled with pygltflib: one binary buffer, accessors per array, PNG images
inside the buffer, and nodes carrying their metadata in `extras`."""

from __future__ import annotations

import io
import json
from dataclasses import dataclass

import numpy as np
import pygltflib as gl

INSTANCING = "EXT_mesh_gpu_instancing"
VARIANTS = "KHR_materials_variants"  # the facades' day (default) and night materials
VARIANT_NAMES = ("day", "night")
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
SCHEMA_ID = "cityshade"


def building_class() -> dict:
    """The `building` class of the metadata schema (the glTF property tables' and the tileset's)."""
    properties = {}
    for name, kind in BUILDING_PROPERTIES.items():
        if kind == "FLOAT32":
            properties[name] = {"type": "SCALAR", "componentType": "FLOAT32", "noData": NO_DATA}
        else:
            properties[name] = {"type": "STRING"}
    return {"properties": properties}


_COMPONENTS = {
    np.dtype(np.int8): gl.BYTE,
    np.dtype(np.uint8): gl.UNSIGNED_BYTE,
    np.dtype(np.int16): gl.SHORT,
    np.dtype(np.float32): gl.FLOAT,
    np.dtype(np.uint32): gl.UNSIGNED_INT,
    np.dtype(np.uint16): gl.UNSIGNED_SHORT,
}
_TYPES = {1: gl.SCALAR, 2: gl.VEC2, 3: gl.VEC3, 4: gl.VEC4}


TEXTURES = ("webp", "png")  # --textures: the first is the default
# --geometry, the first the default: quantized (KHR_mesh_quantization: 16-bit positions scaled by
# their node, 8-bit normals, tangents and colours), draco (smallest; the Khronos validator cannot
# check it), plain (32-bit floats)
GEOMETRY = ("quantized", "draco", "plain")
QUANTIZED = "KHR_mesh_quantization"
TREES = ("instanced", "nodes")  # --trees: EXT_mesh_gpu_instancing (default), or a node per tree
DRACO = "KHR_draco_mesh_compression"
# Draco's quantization (bits over a primitive's extent): positions to under 1 cm in a 1 km tile,
# atlas coordinates to 1/8 texel of an 8192-texel page, normals to about 0.1 degree
POSITION_BITS, UV_BITS, NORMAL_BITS = 17, 16, 12
WEBP = "EXT_texture_webp"
WEBP_QUALITY = 90  # lossy base colour; the data maps (normal, roughness, emissive) are lossless


@dataclass(frozen=True)
class Encoding:
    """How images and meshes are stored: --textures and --geometry."""

    textures: str = TEXTURES[0]
    geometry: str = GEOMETRY[0]
    trees: str = TREES[0]


DEFAULT_ENCODING = Encoding()


def image_bytes(image: np.ndarray, encoding: str, lossy: bool) -> tuple[bytes, str]:
    """(encoded bytes, MIME type) of an 8-bit image: PNG, or WebP (lossy for colour, else lossless)."""
    from PIL import Image

    out = io.BytesIO()
    if encoding == "png":
        Image.fromarray(image).save(out, format="PNG", compress_level=1)
        return out.getvalue(), "image/png"
    options = {"quality": WEBP_QUALITY, "method": 4} if lossy else {"lossless": True, "quality": 50, "method": 2}
    Image.fromarray(image).save(out, format="WEBP", **options)
    return out.getvalue(), "image/webp"


class Document:
    """Grows a GLTF2 and its binary blob; `finish()` returns the GLTF2 ready to save."""

    def __init__(self, extras: dict, place=None, encoding: Encoding = DEFAULT_ENCODING):
        self.place = place  # export._place.Placement for 3D Tiles content, None: the scene's frame
        self.textures, self.geometry, self.trees = encoding.textures, encoding.geometry, encoding.trees
        self.gltf = gl.GLTF2(asset=gl.Asset(version="2.0", generator="cityshade export", extras=extras))
        self.gltf.scenes.append(gl.Scene(nodes=[], extras=extras))
        self.gltf.scene = 0
        self.blob = bytearray()
        self.samplers: dict[tuple, int] = {}
        self.features: list[dict] = []  # one metadata row per building (EXT_structural_metadata)
        self.night: dict[int, int] = {}  # a day material -> its night variant

    def _view(self, data: bytes, target: int | None = None) -> int:
        self.blob.extend(b"\0" * (-len(self.blob) % 8))  # EXT_structural_metadata wants 8-byte alignment
        self.gltf.bufferViews.append(
            gl.BufferView(buffer=0, byteOffset=len(self.blob), byteLength=len(data), target=target)
        )
        self.blob.extend(data)
        return len(self.gltf.bufferViews) - 1

    def accessor(
        self,
        array: np.ndarray,
        bounds: bool = False,
        target: int | None = gl.ARRAY_BUFFER,
        width: int | None = None,
        normalized: bool = False,
    ) -> int:
        """An accessor over a (n,) or (n, k) array (float32, 8/16/32-bit integers); bounds for
        POSITION; `width` < k: the first `width` components of padded rows (byteStride k items)."""
        array = np.ascontiguousarray(array)
        columns = 1 if array.ndim == 1 else array.shape[1]
        width = columns if width is None else width
        view = self._view(array.tobytes(), target)
        if width != columns:
            self.gltf.bufferViews[view].byteStride = columns * array.itemsize
        accessor = gl.Accessor(
            bufferView=view, componentType=_COMPONENTS[array.dtype], count=len(array), type=_TYPES[width]
        )
        if normalized:
            accessor.normalized = True
        if bounds:
            used = array.reshape(len(array), -1)[:, :width]
            accessor.min = [v.item() for v in used.min(axis=0)]
            accessor.max = [v.item() for v in used.max(axis=0)]
        self.gltf.accessors.append(accessor)
        return len(self.gltf.accessors) - 1

    def texture(self, image: np.ndarray, repeat: bool = False, name: str | None = None, colour: bool = False) -> int:
        """An image in the buffer (self.textures: PNG, or WebP through EXT_texture_webp with no PNG
        fallback) and a texture sampling it (linear, mipmapped); `colour` images may be lossy."""
        wrap = gl.REPEAT if repeat else gl.CLAMP_TO_EDGE
        key = (wrap,)
        if key not in self.samplers:
            self.gltf.samplers.append(
                gl.Sampler(magFilter=gl.LINEAR, minFilter=gl.LINEAR_MIPMAP_LINEAR, wrapS=wrap, wrapT=wrap)
            )
            self.samplers[key] = len(self.gltf.samplers) - 1
        data, mime = image_bytes(image, self.textures, lossy=colour)
        self.gltf.images.append(gl.Image(bufferView=self._view(data), mimeType=mime, name=name))
        source = len(self.gltf.images) - 1
        if self.textures == "png":
            self.gltf.textures.append(gl.Texture(source=source, sampler=self.samplers[key]))
        else:
            self.gltf.textures.append(gl.Texture(sampler=self.samplers[key], extensions={WEBP: {"source": source}}))
            self._require(WEBP)
        return len(self.gltf.textures) - 1

    def _require(self, extension: str):
        if extension not in self.gltf.extensionsUsed:
            self.gltf.extensionsUsed.append(extension)
            self.gltf.extensionsRequired.append(extension)

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

    def night_variant(self, day: int, night: int):
        """Primitives of material `day` (their default) get `night` as the variant "night"."""
        self.night[day] = night
        if VARIANTS not in self.gltf.extensionsUsed:
            self.gltf.extensionsUsed.append(VARIANTS)
            self.gltf.extensions[VARIANTS] = {"variants": [{"name": n} for n in VARIANT_NAMES]}

    def world(self, points) -> np.ndarray:
        """(n, 3) scene points in the document's frame: as they are, or placed on Earth (export._place)."""
        points = np.asarray(points, np.float64).reshape(-1, 3)
        return points if self.place is None else self.place.positions(points)

    def turn(self, vectors) -> np.ndarray:
        """Scene directions (normals, tangents' xyz) in the document's frame."""
        vectors = np.asarray(vectors, np.float64).reshape(-1, 3)
        return vectors if self.place is None else self.place.directions(vectors)

    def primitive(
        self,
        material: int,
        positions,
        normals,
        uv=None,
        tangents=None,
        colours=None,
        features=None,
        indices=None,
        scale: float | None = None,
    ) -> gl.Primitive:
        """Triangles: a vertex list, or vertices and indices, stored as self.geometry says
        (quantized: positions in units of `scale` metres, the scale of the node that shows the
        primitive; without a scale, plain); `features`: each vertex's row of the building property
        table (EXT_mesh_features)."""
        arrays = {
            "POSITION": np.asarray(positions, np.float32),
            "NORMAL": unit(normals),
            "TEXCOORD_0": None if uv is None else np.asarray(uv, np.float32),
            "TANGENT": None if tangents is None else np.asarray(tangents, np.float32),
            "COLOR_0": None if colours is None else np.asarray(colours, np.float32),
            "_FEATURE_ID_0": None if features is None else np.asarray(features, np.float32),
        }
        arrays = {k: v for k, v in arrays.items() if v is not None}
        if self.geometry == "draco" and indices is not None:
            primitive = self._draco(material, arrays, indices)
        elif self.geometry == "quantized" and scale is not None:
            primitive = self._plain(material, quantized(arrays, scale), indices)
            self._require(QUANTIZED)
        else:
            primitive = self._plain(material, arrays, indices)
        if features is not None:
            primitive.extensions[FEATURES] = {"featureIds": [{"attribute": 0, "propertyTable": 0, "featureCount": 0}]}
        if material in self.night:
            mappings = [{"material": material, "variants": [0]}, {"material": self.night[material], "variants": [1]}]
            primitive.extensions[VARIANTS] = {"mappings": mappings}
        primitive.extensions = primitive.extensions or None
        return primitive

    def _plain(self, material: int, arrays: dict, indices) -> gl.Primitive:
        attributes = gl.Attributes()
        for name, array in arrays.items():
            if isinstance(array, tuple):  # quantized: (padded array, components used, normalized)
                setattr(
                    attributes,
                    name,
                    self.accessor(array[0], bounds=name == "POSITION", width=array[1], normalized=array[2]),
                )
            else:
                setattr(attributes, name, self.accessor(array, bounds=name == "POSITION"))
        primitive = gl.Primitive(attributes=attributes, material=material, mode=gl.TRIANGLES, extensions={})
        if indices is not None:
            positions = arrays["POSITION"]
            count = len(positions[0] if isinstance(positions, tuple) else positions)
            small = count <= np.iinfo(np.uint16).max  # the largest index 65534: 65535 restarts strips
            indices = np.asarray(indices).astype(np.uint16 if small else np.uint32)
            primitive.indices = self.accessor(indices, target=gl.ELEMENT_ARRAY_BUFFER)
        return primitive

    def _draco(self, material: int, arrays: dict, indices) -> gl.Primitive:
        """One Draco buffer for all of a primitive's attributes; its accessors hold no data
        (KHR_draco_mesh_compression), their counts and bounds from the decoded mesh."""
        import DracoPy

        generic = {n: a.reshape(len(a), -1) for n, a in arrays.items() if n in ("TANGENT", "_FEATURE_ID_0")}
        colours = arrays.get("COLOR_0")
        buffer = DracoPy.encode(
            points=arrays["POSITION"],
            faces=np.asarray(indices, np.uint32).reshape(-1, 3),
            quantization_bits=POSITION_BITS,
            compression_level=7,
            normals=arrays["NORMAL"].astype(np.float64),
            normal_quantization_bits=NORMAL_BITS,
            tex_coord=None if "TEXCOORD_0" not in arrays else arrays["TEXCOORD_0"].astype(np.float64),
            tex_coord_quantization_bits=UV_BITS,
            colors=None if colours is None else (np.clip(colours, 0, 1) * 255 + 0.5).astype(np.uint8),
            generic_attributes=generic or None,
        )
        decoded = DracoPy.decode(buffer)
        kinds = {0: "POSITION", 1: "NORMAL", 2: "COLOR_0", 3: "TEXCOORD_0"}
        ids, data = {}, {}
        for attribute in decoded.attributes:
            name = attribute["name"] if attribute["attribute_type"] == 4 else kinds[attribute["attribute_type"]]
            ids[name], data[name] = attribute["unique_id"], np.asarray(attribute["data"])
        if set(ids) != set(arrays):
            raise RuntimeError(f"Draco kept {sorted(ids)} of {sorted(arrays)}")
        attributes = gl.Attributes()
        for name, values in data.items():
            accessor = gl.Accessor(
                count=len(values), componentType=gl.FLOAT, type=_TYPES[values.reshape(len(values), -1).shape[1]]
            )
            if name == "COLOR_0":
                accessor.componentType, accessor.normalized = gl.UNSIGNED_BYTE, True
            if name == "POSITION":
                accessor.min = [float(v) for v in values.min(axis=0)]
                accessor.max = [float(v) for v in values.max(axis=0)]
            self.gltf.accessors.append(accessor)
            setattr(attributes, name, len(self.gltf.accessors) - 1)
        small = len(decoded.points) <= np.iinfo(np.uint16).max
        self.gltf.accessors.append(
            gl.Accessor(
                count=int(np.asarray(decoded.faces).size),
                componentType=gl.UNSIGNED_SHORT if small else gl.UNSIGNED_INT,
                type=gl.SCALAR,
            )
        )
        self._require(DRACO)
        extension = {"bufferView": self._view(buffer), "attributes": ids}
        return gl.Primitive(
            attributes=attributes,
            material=material,
            mode=gl.TRIANGLES,
            indices=len(self.gltf.accessors) - 1,
            extensions={DRACO: extension},
        )

    def feature_row(self, metadata: dict) -> int:
        """A row of the building property table (EXT_structural_metadata): primitives select it
        through their _FEATURE_ID_0."""
        self.features.append(metadata)
        return len(self.features) - 1

    def _property_table(self):
        rows = self.features
        properties = {}
        for name, kind in BUILDING_PROPERTIES.items():
            values = [row.get(name) for row in rows]
            if kind == "FLOAT32":
                data = np.array([NO_DATA if v is None else float(v) for v in values], np.float32)
                properties[name] = {"values": self._view(data.tobytes())}
                continue
            texts = [_text(v) for v in values]
            encoded = [t.encode("utf-8") for t in texts]
            offsets = np.concatenate([[0], np.cumsum([len(e) for e in encoded])]).astype(np.uint32)
            properties[name] = {
                "values": self._view(b"".join(encoded) or b"\0"),
                "stringOffsets": self._view(offsets.tobytes()),
                "stringOffsetType": "UINT32",
            }
        self.gltf.extensions[METADATA] = {
            "schema": {"id": SCHEMA_ID, "classes": {"building": building_class()}},
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
        scale: float | None = None,
    ) -> int:
        """A mesh of the primitives and a root node showing it (at `translation`, its origin;
        `scale`: quantized positions' unit)."""
        self.gltf.meshes.append(gl.Mesh(name=name, primitives=primitives))
        node = gl.Node(name=name, mesh=len(self.gltf.meshes) - 1, extras=extras or {})
        if translation is not None:
            node.translation = [float(v) for v in translation]
        if scale is not None and self.geometry == "quantized":
            node.scale = [float(scale)] * 3
        if extensions:
            node.extensions = extensions
        self.gltf.nodes.append(node)
        self.gltf.scenes[0].nodes.append(len(self.gltf.nodes) - 1)
        return len(self.gltf.nodes) - 1

    def instanced(self, name: str, primitives, translations, rotations, scales, extras=None) -> int:
        """A mesh drawn at many places: through EXT_mesh_gpu_instancing, or (self.trees "nodes")
        as one node per place under a group node, all showing the one mesh (core glTF, which every
        reader draws, one draw call per place)."""
        if self.trees == "nodes":
            self.gltf.meshes.append(gl.Mesh(name=name, primitives=primitives))
            mesh = len(self.gltf.meshes) - 1
            first = len(self.gltf.nodes)
            for t, r, sc in zip(translations.tolist(), rotations.tolist(), scales.tolist()):
                self.gltf.nodes.append(gl.Node(mesh=mesh, translation=t, rotation=r, scale=sc))
            group = gl.Node(name=name, children=list(range(first, len(self.gltf.nodes))), extras=extras or {})
            self.gltf.nodes.append(group)
            self.gltf.scenes[0].nodes.append(len(self.gltf.nodes) - 1)
            return len(self.gltf.nodes) - 1
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


def quantized(arrays: dict, scale: float) -> dict:
    """KHR_mesh_quantization: positions as 16-bit integers in units of `scale` (the node's scale),
    normals and tangents as normalized 8-bit, colours as normalized unsigned 8-bit; rows padded to
    4 bytes. Atlas coordinates stay float (an 8192-texel page needs more than 16 bits to a texel
    edge) and so do feature ids."""

    def padded(values, dtype, width):
        out = np.zeros((len(values), 4), dtype)
        out[:, :width] = values
        return out

    out = dict(arrays)
    out["POSITION"] = (padded(np.round(arrays["POSITION"] / scale), np.int16, 3), 3, False)
    out["NORMAL"] = (padded(np.round(arrays["NORMAL"] * 127), np.int8, 3), 3, True)
    if "TANGENT" in arrays:
        out["TANGENT"] = (np.round(arrays["TANGENT"] * 127).astype(np.int8), 4, True)
    if "COLOR_0" in arrays:
        out["COLOR_0"] = ((np.clip(arrays["COLOR_0"], 0, 1) * 255 + 0.5).astype(np.uint8), 4, True)
    return out


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
