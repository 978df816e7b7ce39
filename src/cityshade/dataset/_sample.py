"""One sample: the frame and the id AOV of a view, turned into the dataset's files.

Depth is the camera-space z (metres along the optical axis, OpenCV's depth) of the frame's depth
buffer, linearised exactly: z = 2 n f / (f + n - (2 d - 1)(f - n)) for the perspective projection
of scene.perspective; +inf where nothing was drawn (the sky). The ray distance (metres from the
camera's centre to the surface) is z times the length of the pixel's ray at z = 1. Normals are
estimated from that depth (back-projected points, cross product of the smaller-step neighbours),
unit vectors in the OpenCV camera frame (x right, y down, z forward), zero on the sky, stored as
float16 (steps of 0.0005 at most: under 0.06 degrees). Arrays are compressed (.npz or EXR, the
config's output.arrays; instances always .npz).
"""

from __future__ import annotations

import io
import json
import os
from pathlib import Path

import numpy as np
from PIL import Image

from .._files import atomic_output, inside_folder
from ..render import Daylight, Renderer, RenderSettings
from ._arrays import encode, encode_npz, encode_png16, kitti_depth
from ._classes import building_instances, cityscapes_images, class_image, instance_image
from ._config import DatasetConfig
from ._panoptic import panoptic
from ._source import Source
from ._views import View

GL_TO_CV = np.diag([1.0, -1.0, -1.0])  # OpenGL camera (y up, looks down -z) -> OpenCV (y down, looks down +z)
# every sample's files (the manifest's columns), {arrays} the config's output.arrays; the meta JSON
# is written last: it marks a complete sample
SUFFIXES = {
    "rgb": "rgb.png",
    "depth": "depth.{arrays}",
    "distance": "distance.{arrays}",
    "normal": "normal.{arrays}",
    "class": "class.png",
    "instance": "instance.npz",
    "meta": "json",
}
# the files the config's output section adds
EXTRA_SUFFIXES = {"kitti_depth": "depth.png", "label_ids": "labelIds.png", "train_ids": "trainIds.png"}


def sample_files(index: int, arrays: str = "npz") -> dict[str, str]:
    """Output name -> file name (relative to the dataset folder) of sample `index`."""
    return {name: f"samples/{index:07d}.{suffix.format(arrays=arrays)}" for name, suffix in SUFFIXES.items()}


def extra_files(index: int, config: DatasetConfig) -> dict[str, str]:
    """The optional files of sample `index` that `config` asks for (relative to the dataset folder)."""
    wanted = {"kitti_depth": config.kitti_depth, "label_ids": config.classes == "cityscapes"}
    wanted["train_ids"] = wanted["label_ids"]
    files = {name: f"samples/{index:07d}.{suffix}" for name, suffix in EXTRA_SUFFIXES.items() if wanted[name]}
    if config.panoptic:
        files["panoptic"] = f"panoptic/{index:07d}.png"
    return files


def linear_depth(buffer: np.ndarray, near: float, far: float) -> np.ndarray:
    """Depth buffer values (0..1) -> camera-space z in metres; +inf at the far plane (nothing drawn)."""
    ndc = 2.0 * buffer.astype(np.float64) - 1.0
    with np.errstate(divide="ignore"):
        z = 2.0 * far * near / (far + near - ndc * (far - near))
    return np.where(buffer >= 1.0, np.inf, z).astype(np.float32)


def intrinsics(fov: float, width: int, height: int) -> np.ndarray:
    """OpenCV K: square pixels, pixel (u, v)'s centre at integer coordinates, principal point in the middle."""
    f = (height / 2.0) / np.tan(np.radians(fov) / 2.0)
    return np.array([[f, 0.0, width / 2.0 - 0.5], [0.0, f, height / 2.0 - 0.5], [0.0, 0.0, 1.0]])


def extrinsics(view: View) -> np.ndarray:
    """World -> camera 4x4 in OpenCV's convention (world: scene metres, x east, y up, z south)."""
    m = view.camera().view()
    out = np.identity(4)
    out[:3, :3] = GL_TO_CV @ m[:3, :3]
    out[:3, 3] = GL_TO_CV @ m[:3, 3]
    return out


def ray_distance(z: np.ndarray, k: np.ndarray) -> np.ndarray:
    """HxW float32 distance from the camera centre along each pixel's ray, from z-depth and K."""
    h, w = z.shape
    u, v = np.meshgrid(np.arange(w, dtype=np.float64), np.arange(h, dtype=np.float64))
    stretch = np.sqrt(((u - k[0, 2]) / k[0, 0]) ** 2 + ((v - k[1, 2]) / k[1, 1]) ** 2 + 1.0)
    return (z.astype(np.float64) * stretch).astype(np.float32)


def normals_from_depth(z: np.ndarray, k: np.ndarray) -> np.ndarray:
    """HxWx3 float32 unit normals (OpenCV camera frame) facing the camera; zero where z is not finite."""
    h, w = z.shape
    u, v = np.meshgrid(np.arange(w, dtype=np.float64), np.arange(h, dtype=np.float64))
    zz = np.where(np.isfinite(z), z, np.nan).astype(np.float64)
    points = np.stack([(u - k[0, 2]) / k[0, 0] * zz, (v - k[1, 2]) / k[1, 1] * zz, zz], axis=-1)
    padded = np.pad(points, ((1, 1), (1, 1), (0, 0)), constant_values=np.nan)

    def step(forward, backward):  # the neighbour difference across the smaller depth jump
        f, b = forward - points, points - backward
        use_b = np.nan_to_num(np.abs(b[..., 2]), nan=np.inf) < np.nan_to_num(np.abs(f[..., 2]), nan=np.inf)
        return np.where(use_b[..., None], b, f)

    du = step(padded[1:-1, 2:], padded[1:-1, :-2])
    dv = step(padded[2:, 1:-1], padded[:-2, 1:-1])
    n = np.cross(dv, du)
    length = np.linalg.norm(n, axis=-1, keepdims=True)
    with np.errstate(invalid="ignore", divide="ignore"):
        n = n / length
    facing = np.sum(n * points, axis=-1, keepdims=True) > 0
    n = np.where(facing, -n, n)
    return np.nan_to_num(n, nan=0.0).astype(np.float32)


def _png(image: np.ndarray) -> bytes:
    buffer = io.BytesIO()
    Image.fromarray(image).save(buffer, format="PNG")
    return buffer.getvalue()


def manifest_row(view: View, meta: dict, arrays: str = "npz") -> dict:
    """A sample's manifest row, from its view and its camera JSON (as written, or as read back)."""
    geo = meta["geographic"] or {}
    return {
        "index": view.index,
        "kind": view.kind,
        **sample_files(view.index, arrays),
        "lon": geo.get("lon"),
        "lat": geo.get("lat"),
        "height_m": view.eye[1],
        "heading_deg": view.heading,
        "pitch_deg": view.pitch,
        "date": view.date,
        "local_time": meta["local_time"],
        "sun_elevation": meta["sun"]["elevation"],
        "sun_azimuth": meta["sun"]["azimuth"],
    }


def write_atomic(path: Path, data: bytes):
    with atomic_output(path) as tmp:
        tmp.write_bytes(data)


class SampleRenderer:
    """One headless Renderer and one loaded Source: renders views and writes their files."""

    def __init__(self, source: Source, config: DatasetConfig):
        self.source, self.config = source, config
        self.renderer = Renderer((config.width, config.height), RenderSettings(samples=0))
        self.renderer.set_city(source.city)
        self._to_lonlat = None
        if source.city.crs is not None:
            from pyproj import Transformer

            self._to_lonlat = Transformer.from_crs(source.city.crs, "EPSG:4326", always_xy=True)
            self._origin = Transformer.from_crs("EPSG:4326", source.city.crs, always_xy=True).transform(
                *source.city.origin
            )

    def sky(self, view: View) -> tuple[dict, dict]:
        """(render settings for the sun and moon, the record of the sun and the time)."""
        clock = f"{int(view.hours):02d}:{int(round((view.hours % 1) * 60)) % 60:02d}"
        if view.date is None:
            daylight = Daylight.at(view.hours)
            toward = daylight.sky_sun
            azimuth = float(np.degrees(np.arctan2(toward[0], -toward[2])) % 360.0)
            return {}, {
                "date": None,
                "local_time": clock,
                "sun": {"elevation": daylight.sun_elevation, "azimuth": azimuth},
            }
        from ..maps import sky_clock

        bodies = sky_clock(self.source.city.origin, view.date)(view.hours)
        return bodies, {
            "date": view.date,
            "local_time": clock,
            "sun": {"elevation": bodies["sun"][0], "azimuth": bodies["sun"][1]},
        }

    def geographic(self, view: View) -> dict | None:
        if self._to_lonlat is None:
            return None
        x, y, z = view.eye
        lon, lat = self._to_lonlat.transform(self._origin[0] + x, self._origin[1] - z)
        return {
            "lon": lon,
            "lat": lat,
            "height_m": y,
            "heading_deg": view.heading,
            "pitch_deg": view.pitch,
            "crs": self.source.city.crs,
        }

    def frame(self, camera, settings: RenderSettings) -> np.ndarray:
        """One RGB frame with these settings, every shadow cascade drawn afresh."""
        self.renderer.set_settings(settings)
        self.renderer.frame_index = 0
        return self.renderer.render(camera)

    def render(self, view: View, outputs: bool = True) -> dict:
        """The view's arrays: rgb, and with `outputs` depth, normal, class, instance."""
        bodies, _ = self.sky(view)
        r = self.renderer
        r.set_settings(r.settings.with_(time_of_day=view.hours, sun=bodies.get("sun"), moon=bodies.get("moon")))
        r.frame_index = 0  # every shadow cascade drawn afresh: a frame does not depend on the ones before
        camera = view.camera()
        arrays = {"rgb": r.render(camera)}
        if not outputs:
            return arrays
        frame_z = linear_depth(r.depth(), camera.near, camera.far)
        ids = r.render_ids(camera)
        k = intrinsics(view.fov, self.config.width, self.config.height)
        masses = instance_image(ids)
        arrays.update(
            depth=frame_z,
            distance=ray_distance(frame_z, k),
            normal=normals_from_depth(frame_z, k),
            **{"class": class_image(ids, self.config.ignore)},
            instance=building_instances(masses, self.source.mass_building, self.source.mass_part),
        )
        return arrays

    def write(self, view: View, out: Path) -> dict:
        """Renders `view` and writes its files (each atomically, the JSON last); returns its manifest row."""
        arrays, when = self.render(view), self.sky(view)[1]
        return write_sample(out, view, arrays, self.config, self.source.instances, when, self.geographic(view))

    def release(self):
        self.renderer.release()


def encoded_files(arrays: dict, config: DatasetConfig) -> dict[str, bytes]:
    """A sample's arrays (SampleRenderer.render) as the bytes of its files, by output name."""
    data = {
        "rgb": _png(arrays["rgb"]),
        "depth": encode(arrays["depth"], config.arrays),
        "distance": encode(arrays["distance"], config.arrays),
        "normal": encode(arrays["normal"].astype(np.float16), config.arrays),  # unit vectors: 0.001 is enough
        "class": _png(arrays["class"]),
        "instance": encode_npz(arrays["instance"]),
    }
    if config.kitti_depth:
        data["kitti_depth"] = encode_png16(kitti_depth(arrays["depth"]))
    if config.classes == "cityscapes":
        data["label_ids"], data["train_ids"] = (_png(image) for image in cityscapes_images(arrays["class"]))
    return data


def write_sample(
    out: Path, view: View, arrays: dict, config: DatasetConfig, instances: list, when: dict, geographic: dict | None
) -> dict:
    """Writes a rendered view's files (each atomically, the camera JSON last) into the dataset
    folder `out`; `instances` are the source ids by building number - 1. Returns the manifest row."""
    files = {**sample_files(view.index, config.arrays), **extra_files(view.index, config)}
    data = encoded_files(arrays, config)
    panoptic_info = None
    if config.panoptic:
        picture, panoptic_info = panoptic(arrays["class"], arrays["instance"][..., 0])
        data["panoptic"] = _png(picture)
    for name, content in data.items():
        write_atomic(inside_folder(out, files[name], str(out / files[name])), content)
    visible = np.unique(arrays["instance"][..., 0])
    meta = {
        "index": view.index,
        "kind": view.kind,
        "width": config.width,
        "height": config.height,
        "K": intrinsics(view.fov, config.width, config.height).tolist(),
        "world_to_camera": extrinsics(view).tolist(),
        "convention": "OpenCV (x right, y down, z forward); world: scene metres, x east, y up, z south",
        "eye": list(view.eye),
        "fov_y_deg": view.fov,
        "near": view.near,
        "geographic": geographic,
        **when,
        "instances": {str(int(i)): instances[int(i) - 1] for i in visible if i > 0},
        "files": {k: os.path.basename(v) if v.startswith("samples/") else v for k, v in files.items()},
    }
    if panoptic_info is not None:
        meta["panoptic_segments"] = panoptic_info
    write_atomic(inside_folder(out, files["meta"], str(out / files["meta"])), json.dumps(meta, indent=1).encode())
    return manifest_row(view, meta, config.arrays)
