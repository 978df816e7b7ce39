"""A glTF 2.0 document assembled with pygltflib: one binary buffer, accessors per array, PNG images
inside the buffer, and nodes carrying their metadata in `extras`."""

from __future__ import annotations

import io

import numpy as np
import pygltflib as gl

INSTANCING = "EXT_mesh_gpu_instancing"
_COMPONENTS = {np.dtype(np.float32): gl.FLOAT, np.dtype(np.uint32): gl.UNSIGNED_INT,
               np.dtype(np.uint16): gl.UNSIGNED_SHORT}
_TYPES = {1: gl.SCALAR, 2: gl.VEC2, 3: gl.VEC3, 4: gl.VEC4}


def png_bytes(image: np.ndarray) -> bytes:
    from PIL import Image

    out = io.BytesIO()
    Image.fromarray(image).save(out, format="PNG", compress_level=1)
    return out.getvalue()


class Document:
    """Grows a GLTF2 and its binary blob; `finish()` returns the GLTF2 ready to save."""

    def __init__(self, extras: dict):
        self.gltf = gl.GLTF2(asset=gl.Asset(version="2.0", generator="cityshade export", extras=extras))
        self.gltf.scenes.append(gl.Scene(nodes=[], extras=extras))
        self.gltf.scene = 0
        self.blob = bytearray()
        self.samplers: dict[tuple, int] = {}

    def _view(self, data: bytes, target: int | None = None) -> int:
        self.blob.extend(b"\0" * (-len(self.blob) % 4))
        self.gltf.bufferViews.append(gl.BufferView(buffer=0, byteOffset=len(self.blob), byteLength=len(data),
                                                   target=target))
        self.blob.extend(data)
        return len(self.gltf.bufferViews) - 1

    def accessor(self, array: np.ndarray, bounds: bool = False, target: int | None = gl.ARRAY_BUFFER) -> int:
        """An accessor over a (n,) or (n, k) array of float32/uint32; bounds for POSITION."""
        array = np.ascontiguousarray(array)
        width = 1 if array.ndim == 1 else array.shape[1]
        view = self._view(array.tobytes(), target)
        accessor = gl.Accessor(bufferView=view, componentType=_COMPONENTS[array.dtype], count=len(array),
                               type=_TYPES[width])
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
            self.gltf.samplers.append(gl.Sampler(magFilter=gl.LINEAR, minFilter=gl.LINEAR_MIPMAP_LINEAR,
                                                 wrapS=wrap, wrapT=wrap))
            self.samplers[key] = len(self.gltf.samplers) - 1
        view = self._view(png_bytes(image))
        self.gltf.images.append(gl.Image(bufferView=view, mimeType="image/png", name=name))
        self.gltf.textures.append(gl.Texture(source=len(self.gltf.images) - 1, sampler=self.samplers[key]))
        return len(self.gltf.textures) - 1

    def material(self, name: str, colour=(1.0, 1.0, 1.0, 1.0), roughness: float = 0.9, metallic: float = 0.0,
                 base_texture: int | None = None, mr_texture: int | None = None, normal_texture: int | None = None,
                 emissive_texture: int | None = None, double_sided: bool = False) -> int:
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

    def primitive(self, material: int, positions, normals, uv=None, tangents=None, colours=None) -> gl.Primitive:
        """A triangle list (three vertices per triangle, no indices)."""
        attributes = gl.Attributes(POSITION=self.accessor(positions.astype(np.float32), bounds=True),
                                   NORMAL=self.accessor(unit(normals)))
        if uv is not None:
            attributes.TEXCOORD_0 = self.accessor(uv.astype(np.float32))
        if tangents is not None:
            attributes.TANGENT = self.accessor(tangents.astype(np.float32))
        if colours is not None:
            attributes.COLOR_0 = self.accessor(colours.astype(np.float32))
        return gl.Primitive(attributes=attributes, material=material, mode=gl.TRIANGLES)

    def indexed_primitive(self, material: int, positions, normals, indices) -> gl.Primitive:
        attributes = gl.Attributes(POSITION=self.accessor(positions.astype(np.float32), bounds=True),
                                   NORMAL=self.accessor(unit(normals)))
        return gl.Primitive(attributes=attributes, material=material, mode=gl.TRIANGLES,
                            indices=self.accessor(indices.astype(np.uint32), target=gl.ELEMENT_ARRAY_BUFFER))

    def node(self, name: str, primitives: list[gl.Primitive], extras: dict | None = None,
             extensions: dict | None = None) -> int:
        """A mesh of the primitives and a root node showing it."""
        self.gltf.meshes.append(gl.Mesh(name=name, primitives=primitives))
        node = gl.Node(name=name, mesh=len(self.gltf.meshes) - 1, extras=extras or {})
        if extensions:
            node.extensions = extensions
        self.gltf.nodes.append(node)
        self.gltf.scenes[0].nodes.append(len(self.gltf.nodes) - 1)
        return len(self.gltf.nodes) - 1

    def instanced(self, name: str, primitives, translations, rotations, scales, extras=None) -> int:
        """A mesh drawn at many places through EXT_mesh_gpu_instancing."""
        extension = {"attributes": {
            "TRANSLATION": self.accessor(translations.astype(np.float32), target=None),
            "ROTATION": self.accessor(rotations.astype(np.float32), target=None),
            "SCALE": self.accessor(scales.astype(np.float32), target=None),
        }}
        if INSTANCING not in self.gltf.extensionsUsed:
            self.gltf.extensionsUsed.append(INSTANCING)
        return self.node(name, primitives, extras, {INSTANCING: extension})

    def finish(self) -> gl.GLTF2:
        self.blob.extend(b"\0" * (-len(self.blob) % 4))
        self.gltf.buffers = [gl.Buffer(byteLength=len(self.blob))]
        self.gltf.set_binary_blob(bytes(self.blob))
        return self.gltf


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
