"""cityshade dataset through a local Ray runtime (one for the whole module: Ray starts slowly):
byte-identical samples whatever the number of workers, exactly once when an actor is killed,
--resume, Helsinki read back through the manifest, the command's one-line errors, and a signal
during a run (in a subprocess with its own runtime)."""

from __future__ import annotations

import json
import os
import signal
import subprocess
import sys
import threading
import time
from pathlib import Path

import numpy as np
import pytest
from PIL import Image

from cityshade.commands import main
from cityshade.dataset import CLASSES, generate, parse_config, read_manifest
from cityshade.errors import UsageError

pytestmark = pytest.mark.gl  # renders or opens a context of its own, not only through gl_context

TINY = {"image": {"width": 48, "height": 32}, "run": {"batch": 1}}
OUTPUTS = ("rgb", "depth", "distance", "normal", "class", "instance", "meta")


@pytest.fixture(scope="module")
def ray_runtime():
    ray = pytest.importorskip("ray")
    ray.init(
        num_cpus=2, include_dashboard=False, _node_ip_address="127.0.0.1", logging_level="ERROR", log_to_driver=False
    )
    yield ray
    ray.shutdown()


def _files(folder: Path) -> dict[str, bytes]:
    return {p.name: p.read_bytes() for p in sorted((folder / "samples").iterdir())}


def _check_complete(folder: Path, samples: int) -> list[dict]:
    rows = read_manifest(folder)
    assert [row["index"] for row in rows] == list(range(samples))  # every sample exactly once
    for row in rows:
        for name in OUTPUTS:
            assert (folder / row[name]).is_file(), row[name]
        Image.open(folder / row["rgb"]).verify()
        assert np.load(folder / row["depth"])["array"].dtype == np.float32
        assert json.loads((folder / row["meta"]).read_text())["index"] == row["index"]
    assert not [p for p in (folder / "samples").iterdir() if p.name.startswith(".")], "a temporary file is left"
    assert len(list((folder / "samples").iterdir())) == samples * len(OUTPUTS)
    return rows


@pytest.mark.slow  # starts Ray (make test-slow)
def test_same_seed_same_bytes_whatever_the_workers(ray_runtime, tmp_path):
    config = parse_config(TINY)
    generate(tmp_path / "one", 4, config, city="default", workers=1, seed=9, progress=False)
    generate(tmp_path / "two", 4, config, city="default", workers=2, seed=9, progress=False)
    one, two = _files(tmp_path / "one"), _files(tmp_path / "two")
    assert one.keys() == two.keys() and len(one) == 4 * len(OUTPUTS)
    differing = [name for name in one if one[name] != two[name]]
    assert not differing, f"differ between 1 and 2 workers: {differing}"
    _check_complete(tmp_path / "two", 4)


@pytest.mark.slow  # starts Ray (make test-slow)
def test_killed_actor_leaves_every_sample_exactly_once(ray_runtime, tmp_path):
    out, samples = tmp_path / "killed", 8
    killed = []

    def kill_one_when_work_starts(pids):
        def watch():
            deadline = time.monotonic() + 120
            while time.monotonic() < deadline and not list((out / "samples").glob("*.json")):
                time.sleep(0.05)
            finished = len(list((out / "samples").glob("*.json")))
            os.kill(pids[-1], signal.SIGKILL)  # the actor's own process, started by this run
            killed.append(finished)

        threading.Thread(target=watch, daemon=True).start()

    rows = generate(
        out,
        samples,
        parse_config(TINY),
        city="default",
        workers=2,
        seed=9,
        progress=False,
        on_workers=kill_one_when_work_starts,
    )
    assert killed and killed[0] < samples, f"no actor was killed mid-run: {killed}"
    assert len(read_manifest(out)) == samples and len(rows) == samples
    _check_complete(out, samples)
    clean = tmp_path / "clean"
    generate(clean, samples, parse_config(TINY), city="default", workers=1, seed=9, progress=False)
    assert _files(out) == _files(clean), "a sample written around the kill differs from an undisturbed run"


@pytest.mark.slow  # starts Ray (make test-slow)
def test_resume_completes_and_refuses_other_settings(ray_runtime, tmp_path):
    out = tmp_path / "resumed"
    generate(out, 2, parse_config(TINY), city="default", seed=4, progress=False)
    before = {p.name: p.stat().st_mtime_ns for p in (out / "samples").iterdir()}
    generate(out, 3, parse_config(TINY), city="default", seed=4, resume=True, progress=False)
    _check_complete(out, 3)
    assert all((out / "samples" / name).stat().st_mtime_ns == t for name, t in before.items()), "a sample was redone"
    with pytest.raises(UsageError, match=r"made with seed = 4, this run has 5"):
        generate(out, 3, parse_config(TINY), city="default", seed=5, resume=True, progress=False)
    with pytest.raises(UsageError, match=r"image.width = 48, this run has 64"):
        generate(
            out,
            3,
            parse_config({"image": {"width": 64, "height": 32}}),
            city="default",
            seed=4,
            resume=True,
            progress=False,
        )
    with pytest.raises(UsageError, match="add --resume"):
        generate(out, 3, parse_config(TINY), city="default", seed=4, progress=False)


@pytest.mark.slow  # starts Ray (make test-slow)
def test_helsinki_twenty_samples_read_back(ray_runtime, helsinki_pbf, tmp_path):
    """Central Helsinki (© OpenStreetMap contributors, ODbL 1.0): 20 tiny samples on 2 actors."""
    out = tmp_path / "helsinki"
    config = parse_config({"image": {"width": 40, "height": 30}, "run": {"batch": 2}})
    generate(out, 20, config, map_path=helsinki_pbf, workers=2, seed=1, progress=False)
    rows = _check_complete(out, 20)
    assert {row["kind"] for row in rows} == {"pedestrian", "vehicle", "aerial"}
    for row in rows:
        assert 24.9 < row["lon"] < 25.0 and 60.15 < row["lat"] < 60.18, (row["lon"], row["lat"])
        meta = json.loads((out / row["meta"]).read_text())
        assert np.asarray(meta["K"]).shape == (3, 3) and np.asarray(meta["world_to_camera"]).shape == (4, 4)
        assert all(v is None or v.startswith(("way/", "relation/")) for v in meta["instances"].values())
    seen = np.zeros(len(CLASSES), int)
    for row in rows:
        seen += np.bincount(np.asarray(Image.open(out / row["class"])).ravel(), minlength=256)[: len(CLASSES)]
    for name in ("sky", "road", "wall", "window", "roof"):
        assert seen[CLASSES.index(name)] > 0, f"no {name} pixel in 20 Helsinki samples"


@pytest.mark.parametrize(
    "extra, words",
    [
        (["--config", "{bad}"], "classes.ignore = 'cloud': unknown class"),
        (["--address", "127.0.0.1:9"], "no Ray cluster answers there"),
    ],
)
def test_bad_input_is_one_line_and_writes_nothing(tmp_path, capsys, extra, words):
    bad = tmp_path / "bad.toml"
    bad.write_text('[classes]\nignore = ["cloud"]\n')
    extra = [str(bad) if e == "{bad}" else e for e in extra]
    out = tmp_path / "ds"
    code = main(["dataset", "--city", "default", "--samples", "2", "--out", str(out), *extra])
    err = capsys.readouterr().err.strip()
    assert code == 2 and words in err and "\n" not in err
    assert not out.exists()


@pytest.mark.slow  # starts Ray (make test-slow)
def test_more_workers_than_the_runtime_has_cpus_is_one_line_and_writes_nothing(ray_runtime, tmp_path):
    """The module's runtime has 2 CPUs: a third actor would never start, and its batches never end."""
    out = tmp_path / "ds"
    with pytest.raises(UsageError, match=r"^--workers 3: .*give at most 2"):
        generate(out, 2, parse_config(TINY), city="default", workers=3, progress=False)
    assert not out.exists()


@pytest.mark.slow  # starts Ray (make test-slow)
@pytest.mark.parametrize("signum", [signal.SIGTERM, signal.SIGINT])
def test_a_signal_during_dataset_lists_every_finished_sample(tmp_path, signum):
    """SIGTERM ends a run as Ctrl-C does, not with Ray's crash report: exit 143 (130 for SIGINT),
    the manifest lists every sample whose files are complete, no temporary file is left."""
    config = tmp_path / "tiny.toml"
    config.write_text("[image]\nwidth = 48\nheight = 32\n[run]\nbatch = 1\n")
    out = tmp_path / "ds"
    env = {k: v for k, v in os.environ.items() if k != "RAY_LOGGER_LEVEL"}
    env["PYTHONPATH"] = os.pathsep.join(sys.path)
    argv = ["dataset", "--city", "default", "--samples", "200", "--out", str(out), "--config", str(config)]
    log = tmp_path / "stderr"  # a file, not a pipe: Ray's processes may keep a pipe open after the kill
    with open(log, "wb") as stderr:
        process = subprocess.Popen(
            [sys.executable, "-m", "cityshade", *argv], stdout=subprocess.DEVNULL, stderr=stderr, env=env
        )
    try:
        deadline = time.monotonic() + 240
        while len(list(out.glob("samples/*.json"))) < 2 and process.poll() is None and time.monotonic() < deadline:
            time.sleep(0.05)
        assert len(list(out.glob("samples/*.json"))) >= 2, "the run never finished two samples"
        process.send_signal(signum)
        process.wait(timeout=120)
    finally:
        if process.poll() is None:
            process.kill()
            process.wait()
    err = log.read_bytes()
    assert process.returncode == (130 if signum == signal.SIGINT else 128 + signum), err.decode(errors="replace")
    for words in (b"Traceback", b"SIGTERM received", b"logging.cc", b"Error"):
        assert words not in err, err.decode(errors="replace")
    finished = sorted(int(p.name.split(".")[0]) for p in out.glob("samples/*.json"))
    rows = read_manifest(out)
    assert [row["index"] for row in rows] == finished, "a finished sample is missing from the manifest"
    assert len(finished) < 200, "the run finished before the signal"
    for row in rows:
        meta = json.loads((out / row["meta"]).read_text())
        assert all((out / row[name]).is_file() for name in OUTPUTS)
        assert (row["local_time"], row["sun_elevation"]) == (meta["local_time"], meta["sun"]["elevation"])
    assert not list(out.glob("samples/.*")), "a temporary file is left"


def test_unwritable_output_is_refused(tmp_path, capsys):
    blocker = tmp_path / "file"
    blocker.write_text("x")
    code = main(["dataset", "--city", "default", "--samples", "1", "--out", str(blocker / "ds")])
    assert code == 2 and "is not a directory" in capsys.readouterr().err


@pytest.mark.slow  # starts Ray (make test-slow)
def test_command_writes_shards_and_preview(ray_runtime, tmp_path, capsys, output_dir):
    import tarfile

    from cityshade.dataset import write_shards

    config = tmp_path / "tiny.toml"
    config.write_text("[image]\nwidth = 48\nheight = 32\n")
    out = tmp_path / "ds"
    code = main(
        [
            "dataset",
            "--city",
            "default",
            "--samples",
            "3",
            "--out",
            str(out),
            "--config",
            str(config),
            "--seed",
            "2",
            "--shards",
            "2",
            "--preview",
            str(out),
        ]
    )
    assert code == 0, capsys.readouterr().err
    shards = sorted((out / "shards").iterdir())
    assert [p.name for p in shards] == ["000000.tar", "000001.tar"]
    names = []
    for shard in shards:
        with tarfile.open(shard) as tar:
            for member in tar.getmembers():
                names.append(member.name)
                assert tar.extractfile(member).read() == (out / "samples" / member.name).read_bytes()
    assert sorted(names) == sorted(p.name for p in (out / "samples").iterdir()) and len(names) == 3 * len(OUTPUTS)
    first = shards[0].read_bytes()
    write_shards(out, 2)
    assert shards[0].read_bytes() == first, "shards are not reproducible"
    preview = Image.open(out / "preview.png")
    assert preview.width == 4 * 48 and preview.height > 3 * 32
    preview.save(output_dir / "dataset_preview_tiny.png")


@pytest.mark.slow  # starts Ray (make test-slow)
def test_command_writes_a_walk_sequence_with_panoptic_and_cityscapes(ray_runtime, tmp_path, capsys):
    """--path walk --frames 5 --panoptic --classes cityscapes: every frame's files, the
    reconstruction tools' files over the five frames, and Samples reading them back."""
    from cityshade.dataset import Samples

    config = tmp_path / "tiny.toml"
    config.write_text("[image]\nwidth = 48\nheight = 32\n[output]\nkitti_depth = true\n")
    out = tmp_path / "walk"
    argv = ["dataset", "--city", "default", "--path", "walk", "--frames", "5", "--out", str(out)]
    code = main([*argv, "--config", str(config), "--panoptic", "--classes", "cityscapes"])
    assert code == 0, capsys.readouterr().err
    rows = read_manifest(out)
    assert [row["kind"] for row in rows] == ["walk"] * 5
    items = Samples(out)
    eyes = np.array([items.meta(i)["eye"] for i in range(5)])
    assert (np.linalg.norm(np.diff(eyes, axis=0), axis=1) <= 2.0 + 1e-9).all()
    assert set(items[0]) >= {"label_ids", "train_ids", "kitti_depth", "distance"}
    transforms = json.loads((out / "transforms.json").read_text())
    assert [f["file_path"] for f in transforms["frames"]] == [row["rgb"] for row in rows]
    assert (out / "colmap" / "images.txt").read_text().count(".rgb.png") == 5
    panoptic = json.loads((out / "panoptic.json").read_text())
    assert len(panoptic["annotations"]) == 5
    assert all((out / "panoptic" / a["file_name"]).is_file() for a in panoptic["annotations"])
    assert any(s["category_id"] == 100 for a in panoptic["annotations"] for s in a["segments_info"])


@pytest.mark.slow  # starts Ray (make test-slow)
def test_video_frames_on_actors_are_the_same_whatever_the_workers(ray_runtime, tmp_path):
    import imageio.v2 as imageio

    from cityshade.dataset import render_frames
    from cityshade.render import RenderSettings
    from cityshade.scene import make_city

    city = make_city("default")
    jobs = [
        (city.camera(name), RenderSettings(time_of_day=hours, samples=0))
        for name, hours in (("street", 12.0), ("aerial", 18.5), ("corner", 20.0))
    ]
    one = list(render_frames(jobs, (48, 32), city="default", workers=1))
    two = list(render_frames(jobs, (48, 32), city="default", workers=2, batch=1))
    assert len(one) == 3 and all(np.array_equal(a, b) for a, b in zip(one, two))
    assert len({a.tobytes() for a in one}) == 3, "the frames should differ from one another"
    out = tmp_path / "city.mp4"
    assert main(["video", "--frames", "4", "--size", "48x32", "--workers", "2", "--out", str(out)]) == 0
    assert imageio.get_reader(out).count_frames() == 4
