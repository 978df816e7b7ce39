"""`cityshade render --aov class|instance|depth`: the AOV written to --out instead of the picture, with
the same camera and size, and the JSON that names its values beside it."""

from __future__ import annotations

import json
from pathlib import Path

import numpy as np
import OpenEXR
import pytest
from PIL import Image

from cityshade.api import render_city
from cityshade.commands import main
from cityshade.dataset import CLASSES
from cityshade.maps import city_from_map, load_map, map_city

PARTS = Path(__file__).parents[1] / "data" / "maps" / "parts.osm"  # Simple 3D Buildings parts, hand-made
SIZE = (96, 64)
pytestmark = pytest.mark.gl


def _render(tmp_path: Path, aov: str, name: str) -> Path:
    out = tmp_path / name
    args = ["render", "--map", str(PARTS), "--camera", "aerial", "--time", "12:00", "--samples", "0"]
    assert main([*args, "--size", "x".join(map(str, SIZE)), "--aov", aov, "--out", str(out)]) == 0
    return out


def test_class_png_holds_the_dataset_class_ids_and_names_them(tmp_path):
    out = _render(tmp_path, "class", "frame.png")
    image = Image.open(out)
    assert image.mode == "L" and image.size == SIZE
    names = json.loads(out.with_suffix(".json").read_text())["classes"]
    assert names == {str(i): name for i, name in enumerate(CLASSES)}
    ids = np.asarray(image)
    city = map_city(load_map(PARTS))
    expected, _ = render_city(city, camera="aerial", size=SIZE, frames=0, time="12:00", samples=0, aov="class")
    assert np.array_equal(ids, expected), f"{int((ids != expected).sum())} pixels differ from the API's class AOV"
    seen = {names[str(v)] for v in np.unique(ids)}
    assert {"roof", "wall"} <= seen, seen


def test_instance_png_gives_each_building_its_map_id(tmp_path):
    out = _render(tmp_path, "instance", "frame.png")
    image = Image.open(out)
    assert image.mode == "I;16" and image.size == SIZE
    values = np.asarray(image)
    table = json.loads(out.with_suffix(".json").read_text())["instances"]
    assert set(table) == {str(v) for v in np.unique(values) if v > 0}
    assert {"way/400", "way/201", "way/301"} <= set(table.values()), table  # a plain way and two parts
    assert (values == 0).mean() > 0.3, "the ground between the buildings is no building"


def _ground_depth(camera, size) -> np.ndarray:
    """Camera-space z of the plane y = 0 through each pixel's centre (numpy), +inf above the horizon."""
    w, h = size
    aspect = w / h
    f = 1.0 / np.tan(np.radians(camera.fov_y) / 2.0)
    u, v = np.meshgrid((np.arange(w) + 0.5) / w * 2 - 1, 1 - (np.arange(h) + 0.5) / h * 2)
    rays = np.stack([u * aspect / f, v / f, -np.ones_like(u)], axis=-1)  # camera space, z = -1
    to_world = np.linalg.inv(camera.view())
    directions = rays @ to_world[:3, :3].T
    eye = to_world[:3, 3]
    t = -eye[1] / directions[..., 1]
    return np.where(t > 0, t, np.inf)  # z = 1 along the ray per unit t


@pytest.mark.parametrize("suffix", [".npz", ".exr"])
def test_depth_is_camera_z_in_metres(tmp_path, suffix):
    out = _render(tmp_path, "depth", "depth" + suffix)
    if suffix == ".npz":
        depth = np.load(out)["depth"]
    else:
        depth = OpenEXR.File(str(out)).channels()["Z"].pixels
    assert depth.dtype == np.float32 and depth.shape == SIZE[::-1]
    city, camera, _ = city_from_map(PARTS, "aerial", time="12:00")
    classes, _ = render_city(city, camera="aerial", size=SIZE, frames=0, time="12:00", samples=0, aov="class")
    ground = np.isin(classes, [CLASSES.index(n) for n in ("grass", "bare_ground", "road", "pavement")])
    assert ground.mean() > 0.3
    expected = _ground_depth(city.camera(camera), SIZE)
    error = np.abs(depth[ground] - expected[ground]) / expected[ground]
    assert np.median(error) < 0.01 and (error > 0.05).mean() < 0.02, f"median relative error {np.median(error):.4f}"
    buildings = classes == CLASSES.index("roof")
    assert (depth[buildings] < expected[buildings]).mean() > 0.95, "roofs stand in front of the ground"


def test_depth_refuses_a_png(tmp_path, capsys):
    code = main(["render", "--map", str(PARTS), "--aov", "depth", "--out", str(tmp_path / "depth.png")])
    assert code != 0 and "writes .npz or .exr" in capsys.readouterr().err
    assert not (tmp_path / "depth.png").exists()
