"""The exported GLB drawn by another renderer (pyrender, headless EGL) beside cityshade's own
render of the same view: docs/images/export-*.png.

    PYOPENGL_PLATFORM=egl python scripts/export-picture.py --city default --camera aerial --out docs/images/export-default.png
    PYOPENGL_PLATFORM=egl python scripts/export-picture.py --map data/Helsinki.osm.pbf --camera aerial --out ...

Needs pyrender (`pip install -e .[docs]`). trimesh reads the GLB (it ignores EXT_mesh_gpu_instancing,
so the trees' instances are read here and each tree mesh is added at every pose)."""

from __future__ import annotations

import argparse
import os
import subprocess
import sys
import tempfile
from pathlib import Path

import numpy as np

os.environ.setdefault("PYOPENGL_PLATFORM", "egl")
SRC = Path(__file__).resolve().parents[1] / "src"


def cityshade(*args: str):
    env = dict(os.environ, PYTHONPATH=str(SRC))
    subprocess.run([sys.executable, "-m", "cityshade", *args], check=True, env=env, stdout=subprocess.DEVNULL)


def instance_poses(gltf, node) -> np.ndarray:
    """4x4 poses of an EXT_mesh_gpu_instancing node."""
    import trimesh.transformations as tf

    attributes = node.extensions["EXT_mesh_gpu_instancing"]["attributes"]
    blob = gltf.binary_blob()

    def read(index, width):
        accessor = gltf.accessors[index]
        view = gltf.bufferViews[accessor.bufferView]
        return np.frombuffer(blob, np.float32, accessor.count * width, view.byteOffset).reshape(-1, width)

    t, r, s = read(attributes["TRANSLATION"], 3), read(attributes["ROTATION"], 4), read(attributes["SCALE"], 3)
    poses = []
    for translation, (x, y, z, w), scale in zip(t, r, s):
        pose = tf.quaternion_matrix([w, x, y, z])
        pose[:3, :3] *= scale
        pose[:3, 3] = translation
        poses.append(pose)
    return np.asarray(poses)


def _material(material, cache: dict):
    """One pyrender material per glTF material (trimesh shares it between primitives), so each
    atlas is uploaded once."""
    import pyrender

    key = (
        id(material.baseColorTexture),
        tuple(np.ravel(material.baseColorFactor)) if material.baseColorFactor is not None else None,
    )
    if key not in cache:
        cache.setdefault("alive", []).append(material)  # ids stay unique while the cache lives

        def texture(image):
            return (
                None
                if image is None
                else pyrender.Texture(source=np.asarray(image.convert("RGBA")), source_channels="RGBA")
            )

        cache[key] = pyrender.MetallicRoughnessMaterial(
            baseColorFactor=np.asarray(material.baseColorFactor if material.baseColorFactor is not None else [255] * 4)
            / 255.0,
            baseColorTexture=texture(material.baseColorTexture),
            metallicFactor=0.0,
            roughnessFactor=0.9,
            emissiveTexture=None,
            doubleSided=bool(material.doubleSided),
        )
    return cache[key]


def _unit_colours(colours) -> np.ndarray:
    colours = np.asarray(colours, np.float64)
    return colours / 255.0 if colours.max() > 1.0 else colours


def _primitive(mesh, cache: dict):
    import pyrender

    visual = mesh.visual
    uv = getattr(visual, "uv", None)
    colours = getattr(visual, "vertex_attributes", {}).get("color")
    return pyrender.Primitive(
        positions=mesh.vertices,
        normals=mesh.vertex_normals,
        indices=mesh.faces,
        texcoord_0=uv,
        color_0=None if colours is None else _unit_colours(colours),
        material=_material(visual.material, cache),
    )


def pyrender_image(glb: Path, camera, size) -> np.ndarray:
    import pygltflib
    import pyrender
    import trimesh

    gltf = pygltflib.GLTF2.load(str(glb))
    instanced = {n.name: n for n in gltf.nodes if n.extensions and "EXT_mesh_gpu_instancing" in n.extensions}
    loaded = trimesh.load(glb, force="scene", process=False)  # keep the file's vertices and normals
    scene = pyrender.Scene(bg_color=[0.55, 0.68, 0.85, 1.0], ambient_light=[0.35, 0.35, 0.38])
    cache: dict = {}
    for name in loaded.graph.nodes_geometry:
        transform, geometry = loaded.graph[name]
        mesh = pyrender.Mesh([_primitive(loaded.geometry[geometry], cache)])
        base = next((n for n in instanced if name == n or name.startswith(n + "_")), None)
        if base is not None:
            for pose in instance_poses(gltf, instanced[base]):
                scene.add(mesh, pose=pose @ transform)
        else:
            scene.add(mesh, pose=transform)
    width, height = size
    view = camera.view()
    cam = pyrender.PerspectiveCamera(
        yfov=np.radians(camera.fov_y), aspectRatio=width / height, znear=camera.near, zfar=camera.far
    )
    scene.add(cam, pose=np.linalg.inv(view))
    sun = np.eye(4)
    sun[:3, :3] = np.linalg.inv(view)[:3, :3] @ np.array([[1, 0, 0], [0, 0.6, -0.8], [0, 0.8, 0.6]])
    scene.add(pyrender.DirectionalLight(intensity=3.5), pose=sun)
    renderer = pyrender.OffscreenRenderer(width, height)
    try:
        colour, _ = renderer.render(scene)
    finally:
        renderer.delete()
    return colour[..., :3]


def main():
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    source = parser.add_mutually_exclusive_group(required=True)
    source.add_argument("--city")
    source.add_argument("--map", type=Path)
    parser.add_argument("--camera", default="aerial")
    parser.add_argument("--texel", default="0.1")
    parser.add_argument("--time", default="12:00")
    parser.add_argument("--size", default="640x400")
    parser.add_argument("--out", type=Path, required=True)
    args = parser.parse_args()
    sys.path.insert(0, str(SRC))
    from PIL import Image, ImageDraw

    from cityshade.scene import make_city

    size = tuple(int(v) for v in args.size.split("x"))
    source = ["--city", args.city] if args.city else ["--map", str(args.map)]
    with tempfile.TemporaryDirectory() as tmp:
        glb, own = Path(tmp) / "city.glb", Path(tmp) / "own.png"
        cityshade("export", *source, "--out", str(glb), "--texel", args.texel)
        cityshade(
            "render",
            *source,
            "--camera",
            args.camera,
            "--size",
            args.size,
            "--time",
            args.time,
            "--samples",
            "0",
            "--out",
            str(own),
        )
        if args.city:
            camera = make_city(args.city).camera(args.camera)
        else:
            from cityshade.maps import load_map, map_city

            camera = map_city(load_map(args.map)).camera(args.camera)
        other = pyrender_image(glb, camera, size)
        mine = np.asarray(Image.open(own).convert("RGB"))
    picture = Image.new("RGB", (size[0] * 2 + 8, size[1]), "white")
    picture.paste(Image.fromarray(mine), (0, 0))
    picture.paste(Image.fromarray(other), (size[0] + 8, 0))
    draw = ImageDraw.Draw(picture)
    draw.text((8, 8), "cityshade render", fill="white")
    draw.text((size[0] + 16, 8), "exported GLB in pyrender", fill="white")
    args.out.parent.mkdir(parents=True, exist_ok=True)
    picture.save(args.out)
    print(f"wrote {args.out}")


if __name__ == "__main__":
    main()
