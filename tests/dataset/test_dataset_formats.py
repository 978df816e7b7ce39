"""A dataset folder in other tools' formats, written without Ray or a renderer from hand-made
arrays (write_sample, write_gathered): nerfstudio's transforms.json, COLMAP's text model read by
pycolmap, COCO panoptic checked by its format rules and pycocotools' masks, Cityscapes ids, the
compressed and KITTI depth, and the Samples reader over the folder and its WebDataset shards."""

from __future__ import annotations

import io
import json
from dataclasses import replace

import numpy as np
import pytest
from PIL import Image

from cityshade.dataset import (
    BUILDING_CATEGORY,
    CITYSCAPES_LABEL_IDS,
    CITYSCAPES_TRAIN_IDS,
    CLASSES,
    IGNORE,
    Samples,
    Streets,
    View,
    building_instances,
    extrinsics,
    intrinsics,
    parse_config,
    ray_distance,
    read_manifest,
    sequence_view,
    walk_camera,
    walk_route,
    write_gathered,
    write_sample,
    write_shards,
)
from cityshade.dataset.testing import (
    CV_TO_GL,
    KITTI_MAX,
    ProgressLines,
    building_tables,
    decode,
    encode,
    write_manifest,
)
from cityshade.errors import UsageError
from cityshade.scene import PATHS, make_city

W, H = 24, 16
CONFIG = parse_config(
    {
        "image": {"width": W, "height": H},
        "output": {"panoptic": True, "classes": "cityscapes", "kitti_depth": True},
    }
)
SOURCE_IDS = ["way/1", "relation/2", "way/3"]
WHEN = {"date": "2025-06-01", "local_time": "12:00", "sun": {"elevation": 50.0, "azimuth": 180.0}}


def _view(index: int) -> View:
    eye = (3.0 * index, 1.7 + index, -2.0 * index)
    return View(index, "pedestrian", eye, 30.0 * index, 5.0 - 4 * index, 66.0, 0.3, "2025-06-01", 12.0)


def _arrays(index: int) -> dict:
    """A sample's arrays: a sky band, a ground plane, two buildings (one of two parts), a tree."""
    rng = np.random.default_rng(index)
    z = np.full((H, W), np.inf, np.float32)
    z[4:] = np.linspace(5.0, 300.0 + 10 * index, (H - 4) * W, dtype=np.float32).reshape(H - 4, W)
    classes = np.zeros((H, W), np.uint8)
    classes[4:] = CLASSES.index("road")
    classes[10:, :6] = CLASSES.index("pavement")
    masses = np.zeros((H, W), np.uint32)
    masses[4:9, 2:8], masses[4:9, 8:12], masses[5:12, 15:20] = 1, 2, 3  # masses 1 and 2: building 1
    classes[masses > 0] = rng.choice([CLASSES.index(n) for n in ("wall", "window", "roof")], int((masses > 0).sum()))
    classes[12:14, 20:22] = CLASSES.index("foliage")
    classes[15, 0] = IGNORE
    buildings, parts = building_tables([2, 1])
    k = intrinsics(66.0, W, H)
    return {
        "rgb": rng.integers(0, 255, (H, W, 3), dtype=np.uint8),
        "depth": z,
        "distance": ray_distance(z, k),
        "normal": np.broadcast_to(np.array([0.0, -1.0, 0.0], np.float32), (H, W, 3)).copy(),
        "class": classes,
        "instance": building_instances(masses, buildings, parts),
    }


@pytest.fixture(scope="module")
def folder(tmp_path_factory):
    out = tmp_path_factory.mktemp("formats")
    (out / "samples").mkdir()
    rows = [write_sample(out, _view(i), _arrays(i), CONFIG, SOURCE_IDS, WHEN, None) for i in range(3)]
    write_manifest(out, rows)
    write_gathered(out, CONFIG)
    return out


def test_transforms_json_states_k_and_poses_in_nerfstudio_axes(folder):
    document = json.loads((folder / "transforms.json").read_text())
    k = intrinsics(66.0, W, H)
    assert (document["w"], document["h"], document["camera_model"]) == (W, H, "OPENCV")
    assert document["fl_x"] == document["fl_y"] == pytest.approx(k[0, 0])
    assert (document["cx"], document["cy"]) == (W / 2, H / 2)  # pixel centres at half-integers
    assert document["depth_unit_scale_factor"] == 1 / 256
    assert len(document["frames"]) == 3
    for i, frame in enumerate(document["frames"]):
        assert frame["file_path"] == f"samples/{i:07d}.rgb.png" and (folder / frame["file_path"]).is_file()
        assert (folder / frame["depth_file_path"]).is_file()
        c2w = np.asarray(frame["transform_matrix"])
        np.testing.assert_allclose(c2w[:3, 3], _view(i).eye, atol=1e-9)  # the camera's centre
        # OpenGL axes: the camera looks down its -z column, y up; back to OpenCV's world_to_camera
        np.testing.assert_allclose(np.linalg.inv(c2w @ CV_TO_GL), extrinsics(_view(i)), atol=1e-9)
        camera = _view(i).camera()
        forward = np.subtract(camera.target, camera.eye)
        np.testing.assert_allclose(-c2w[:3, 2], forward / np.linalg.norm(forward), atol=1e-9)
        assert c2w[1, 1] > 0  # the camera's up has a positive world y: no roll, pitch under 90 degrees


def test_colmap_text_model_reads_in_pycolmap(folder):
    pycolmap = pytest.importorskip("pycolmap")
    model = pycolmap.Reconstruction()
    model.read_text(str(folder / "colmap"))
    assert len(model.cameras) == 1 and len(model.images) == 3 and len(model.points3D) == 0
    camera = model.cameras[1]
    k = intrinsics(66.0, W, H)
    assert camera.model.name == "PINHOLE" and (camera.width, camera.height) == (W, H)
    np.testing.assert_allclose(camera.params, [k[0, 0], k[1, 1], k[0, 2] + 0.5, k[1, 2] + 0.5])
    for image_id, image in model.images.items():
        index = image_id - 1
        assert image.name == f"samples/{index:07d}.rgb.png"
        pose = image.cam_from_world()
        np.testing.assert_allclose(pose.matrix(), extrinsics(_view(index))[:3], atol=1e-9)
        np.testing.assert_allclose(image.projection_center(), _view(index).eye, atol=1e-9)


def test_panoptic_follows_the_coco_format(folder):
    mask_api = pytest.importorskip("pycocotools.mask")
    document = json.loads((folder / "panoptic.json").read_text())
    assert set(document) >= {"images", "annotations", "categories"}
    categories = {c["id"]: c for c in document["categories"]}
    assert categories[BUILDING_CATEGORY]["isthing"] == 1 and categories[BUILDING_CATEGORY]["name"] == "building"
    assert all(c["isthing"] == 0 for i, c in categories.items() if i != BUILDING_CATEGORY)
    assert [image["id"] for image in document["images"]] == [a["image_id"] for a in document["annotations"]]
    for image, annotation in zip(document["images"], document["annotations"]):
        assert (folder / "samples" / image["file_name"]).is_file() and (image["width"], image["height"]) == (W, H)
        rgb = np.asarray(Image.open(folder / "panoptic" / annotation["file_name"]), np.uint32)
        ids = rgb[..., 0] + 256 * rgb[..., 1] + 256 * 256 * rgb[..., 2]  # panopticapi.utils.rgb2id
        segments = {s["id"]: s for s in annotation["segments_info"]}
        assert set(np.unique(ids)) - {0} == set(segments)  # panopticapi: every id in the PNG and the JSON
        arrays = _arrays(image["id"])
        assert (ids == 0).sum() == 1  # the one ignored pixel is void
        for segment_id, segment in segments.items():
            mask = ids == segment_id
            assert segment["category_id"] in categories and segment["iscrowd"] == 0
            rle = mask_api.encode(np.asfortranarray(mask.astype(np.uint8)))
            assert segment["area"] == mask.sum() == mask_api.area(rle)
            assert segment["bbox"] == mask_api.toBbox(rle).tolist()
            if segment["category_id"] == BUILDING_CATEGORY:  # one segment per building, all its parts
                assert np.array_equal(mask, arrays["instance"][..., 0] == segment_id)
            else:
                assert (arrays["class"][mask] == segment["category_id"] - 1).all()
        assert sorted(s for s in segments if s < 1 << 23) == [1, 2]


def test_instances_number_buildings_with_the_part_in_a_second_channel(folder):
    buildings, parts = building_tables([2, 0, 3])
    assert buildings.tolist() == [1, 1, 3, 3, 3] and parts.tolist() == [1, 2, 1, 2, 3]
    instance = Samples(folder)[0]["instance"]
    assert instance.shape == (H, W, 2) and instance.dtype == np.uint32
    assert set(map(tuple, instance[4:9, 2:8].reshape(-1, 2).tolist())) == {(1, 1)}
    assert set(map(tuple, instance[4:9, 8:12].reshape(-1, 2).tolist())) == {(1, 2)}  # the second part of building 1
    assert set(map(tuple, instance[5:12, 15:20].reshape(-1, 2).tolist())) == {(2, 1)}
    meta = Samples(folder).meta(0)
    assert meta["instances"] == {"1": "way/1", "2": "relation/2"}


def test_cityscapes_ids_follow_the_documented_mapping(folder):
    expected = {"sky": (23, 10), "road": (7, 0), "pavement": (8, 1), "lane_marking": (7, 0), "wall": (11, 2)}
    expected |= {"roof": (11, 2), "window": (11, 2), "foliage": (21, 8), "tree_trunk": (21, 8), "lamp": (17, 5)}
    expected |= {"water": (0, 255), "rail": (10, 255), "grass": (22, 9), "bare_ground": (22, 9)}
    for name, (label, train) in expected.items():
        assert (CITYSCAPES_LABEL_IDS[CLASSES.index(name)], CITYSCAPES_TRAIN_IDS[CLASSES.index(name)]) == (label, train)
    assert (CITYSCAPES_LABEL_IDS[IGNORE], CITYSCAPES_TRAIN_IDS[IGNORE]) == (0, 255)
    item = Samples(folder)[1]
    assert np.array_equal(item["label_ids"], CITYSCAPES_LABEL_IDS[item["class"]])
    assert np.array_equal(item["train_ids"], CITYSCAPES_TRAIN_IDS[item["class"]])


def test_depth_distance_and_kitti_depth(folder):
    item, arrays = Samples(folder)[2], _arrays(2)
    assert item["depth"].dtype == item["distance"].dtype == np.float32
    assert np.array_equal(item["depth"], arrays["depth"])  # compressed without loss
    k = intrinsics(66.0, W, H)
    v, u = 9, 0  # a pixel's ray: z along the axis, distance along the ray
    ray = np.array([(u - k[0, 2]) / k[0, 0], (v - k[1, 2]) / k[1, 1], 1.0])
    assert item["distance"][v, u] == pytest.approx(item["depth"][v, u] * np.linalg.norm(ray), rel=1e-6)
    assert (item["distance"][4:] > item["depth"][4:]).all() and np.isinf(item["distance"][:4]).all()
    kitti = item["kitti_depth"]
    assert kitti.dtype == np.uint16
    near = np.isfinite(arrays["depth"]) & (arrays["depth"] <= KITTI_MAX)
    np.testing.assert_allclose(kitti[near] / 256.0, arrays["depth"][near], atol=0.5 / 256)
    assert not kitti[~near].any()  # no value on the sky and beyond 256 m
    assert np.abs(item["normal"] - arrays["normal"]).max() == 0  # float16 holds these exactly


@pytest.mark.parametrize("fmt", ["npz", "exr"])
def test_array_formats_round_trip(fmt):
    pytest.importorskip("OpenEXR") if fmt == "exr" else None
    z = np.random.default_rng(0).uniform(0.3, 900.0, (5, 7)).astype(np.float32)
    z[0, 0] = np.inf
    normals = np.random.default_rng(1).uniform(-1, 1, (5, 7, 3)).astype(np.float16)
    for array in (z, normals):
        back = decode(encode(array, fmt), f"x.depth.{fmt}")
        assert back.dtype == array.dtype and np.array_equal(back, array)


def test_exr_config_writes_exr_files(tmp_path):
    pytest.importorskip("OpenEXR")
    config = replace(CONFIG, arrays="exr", panoptic=False, classes="native", kitti_depth=False)
    (tmp_path / "samples").mkdir()
    row = write_sample(tmp_path, _view(0), _arrays(0), config, SOURCE_IDS, WHEN, None)
    assert row["depth"].endswith(".depth.exr") and row["normal"].endswith(".normal.exr")
    write_manifest(tmp_path, [row])
    item = Samples(tmp_path)[0]
    assert np.array_equal(item["depth"], _arrays(0)["depth"]) and item["normal"].dtype == np.float32
    assert not (tmp_path / "panoptic.json").exists()


def test_samples_read_the_folder_and_its_shards_alike(folder):
    shards = write_shards(folder, 2)
    from_folder, from_shards = Samples(folder), Samples(shards)
    assert len(from_folder) == len(from_shards) == 3
    for a, b in zip(from_folder, from_shards):
        assert set(a) == set(b) >= {"rgb", "depth", "distance", "normal", "class", "instance", "K"}
        for key in a:
            assert np.array_equal(a[key], b[key]), key
    assert from_folder[-1]["index"] == 2
    with pytest.raises(IndexError):
        from_folder[3]
    assert read_manifest(folder)[0]["distance"] == "samples/0000000.distance.npz"


def test_a_bad_output_setting_is_one_line():
    with pytest.raises(UsageError, match=r"^my.toml: output.arrays = 'tiff': expected one of npz, exr$"):
        parse_config({"output": {"arrays": "tiff"}}, "my.toml")
    with pytest.raises(UsageError, match=r"output.panoptic = 1: expected true or false$"):
        parse_config({"output": {"panoptic": 1}}, "my.toml")


def test_progress_lines_each_tenth():
    stream = io.StringIO()
    lines = ProgressLines("dataset ds", 50, done=5, stream=stream)
    for _ in range(45):
        lines.advance(1)
    text = stream.getvalue().splitlines()
    assert len(text) == 9 and text[-1].startswith("dataset ds: 50/50 samples (100%), ")
    assert text[0].startswith("dataset ds: 10/50 samples (20%)")


# --- sequences ------------------------------------------------------------------------------------

# an L of two streets and a spur: the walk goes on along the straighter way at the junction
STREETS = Streets(
    np.array([[[0.0, 0.0], [100.0, 0.0]], [[100.0, 0.0], [100.0, 60.0]], [[100.0, 0.0], [160.0, 5.0]]]),
    np.array([10.0, 10.0, 10.0]),
)


def test_walk_views_follow_a_street_close_together():
    route = walk_route(STREETS)
    assert route.tolist() == [[0.0, 0.0], [100.0, 0.0], [160.0, 5.0]]
    config = parse_config({})
    views = [sequence_view(i, 40, "walk", 3, config, STREETS, True) for i in range(40)]
    eyes = np.array([v.eye for v in views])
    steps = np.linalg.norm(np.diff(eyes, axis=0), axis=1)
    assert (steps > 0).all() and steps.max() <= 2.0 + 1e-9
    assert np.allclose(eyes[:, 1], config.pedestrian_height)
    assert np.allclose(eyes[:, 2], 6.0)  # beside the carriageway: half its width and a metre off
    assert {v.heading for v in views} == {90.0} and {(v.date, v.hours) for v in views} == {
        (views[0].date, views[0].hours)
    }


def test_orbit_views_are_the_video_orbit_from_the_seed_time():
    city = make_city("default")
    config = parse_config({})
    views = [sequence_view(i, 8, "orbit", 0, config, STREETS, False, city) for i in range(8)]
    for k, view in enumerate(views):
        expected = PATHS["orbit"](city, k / 8)
        camera = view.camera()
        np.testing.assert_allclose(camera.eye, expected.eye, atol=1e-9)
        forward = np.subtract(camera.target, camera.eye)
        towards = np.subtract(expected.target, expected.eye)
        np.testing.assert_allclose(forward / np.linalg.norm(forward), towards / np.linalg.norm(towards), atol=1e-9)
        assert view.kind == "orbit" and view.date is None and view.hours == views[0].hours


def test_a_video_walk_goes_the_whole_route():
    start, end = walk_camera(STREETS, 0.0), walk_camera(STREETS, 1.0)
    np.testing.assert_allclose(start.eye, (0.0, 1.7, 6.0))
    direction = np.array([60.0, 5.0]) / np.hypot(60.0, 5.0)
    np.testing.assert_allclose(
        np.take(end.eye, [0, 2]), np.array([160.0, 5.0]) + 6.0 * np.array([-direction[1], direction[0]])
    )
    middle = walk_camera(STREETS, 0.25)  # 40 m of 160 m: on the first street, looking east along it
    assert middle.eye[0] == pytest.approx(0.25 * (100.0 + np.hypot(60.0, 5.0)))
    assert middle.target[0] > middle.eye[0] and middle.target[2] == pytest.approx(middle.eye[2])


def test_samples_name_a_damaged_file_in_one_line(tmp_path):
    import tarfile

    (tmp_path / "samples").mkdir()
    row = write_sample(tmp_path, _view(0), _arrays(0), CONFIG, SOURCE_IDS, WHEN, None)
    write_manifest(tmp_path, [row])
    (tmp_path / row["distance"]).write_bytes(b"PK\x03\x04 not a zip")
    with pytest.raises(UsageError, match=r"row of sample 0, column distance: not a readable .npz archive; remove"):
        Samples(tmp_path)[0]
    shard = tmp_path / "bad.tar"
    with tarfile.open(shard, "w") as tar:
        for name in ("rgb", "meta"):
            tar.add(tmp_path / row[name], arcname=row[name].rpartition("/")[2])
        tar.add(tmp_path / row["distance"], arcname="0000000.class.png")  # not a PNG
    with pytest.raises(UsageError, match=r"bad.tar: 0000000.class.png: not a readable PNG image$"):
        Samples(shard)[0]


@pytest.mark.parametrize(
    "extra, words",
    [
        (["--path", "walk"], "give --path walk|orbit with --frames N"),
        (["--frames", "4"], "give --path walk|orbit with --frames N"),
        (["--path", "walk", "--frames", "4", "--samples", "4"], "give --frames N with --path, not --samples"),
    ],
)
def test_sequence_arguments_are_one_line(tmp_path, capsys, extra, words):
    from cityshade.commands import main

    out = tmp_path / "ds"
    argv = ["dataset", "--city", "default", "--out", str(out), *extra]
    assert main(argv) == 2
    err = capsys.readouterr().err.strip()
    assert words in err and len(err.splitlines()) == 1 and not out.exists()
