"""`cityshade video`: frames along a camera path into an MP4 that reads back."""

from __future__ import annotations

import subprocess
import sys

import imageio.v2 as imageio
import numpy as np
import pytest

from cityshade.commands.video import render_video
from cityshade.errors import UsageError
from cityshade.scene import PATHS, make_city

pytestmark = pytest.mark.gl  # renders or opens a context of its own, not only through gl_context


def test_video_has_every_frame_and_the_evening_darkens(tmp_path):
    out = render_video(
        tmp_path / "dusk.mp4",
        city="interior",
        path="orbit",
        frames=4,
        fps=4,
        size=(64, 48),
        start_time="17:00",
        end_time="21:00",
        progress=False,
    )
    frames = [np.asarray(f, dtype=float) for f in imageio.get_reader(out)]
    assert len(frames) == 4 and frames[0].shape == (48, 64, 3)
    assert frames[-1].mean() < frames[0].mean()
    assert [p.name for p in tmp_path.iterdir()] == ["dusk.mp4"]


@pytest.mark.parametrize("name", sorted(PATHS))
def test_paths_start_where_they_say(name):
    city = make_city("default")
    cameras = [PATHS[name](city, t) for t in (0.0, 0.5, 1.0)]
    assert all(np.isfinite(c.eye).all() for c in cameras)
    if name == "still":
        assert cameras[0] == cameras[2] == city.camera("street")
    else:
        assert not np.allclose(cameras[0].eye, cameras[1].eye)


def test_bad_path_name_writes_nothing(tmp_path):
    with pytest.raises(UsageError, match="unknown camera path 'zigzag'; allowed: orbit, walk, still"):
        render_video(tmp_path / "x.mp4", path="zigzag", frames=1)
    assert not list(tmp_path.iterdir())


def test_zero_frames_is_one_line_exit_2_and_no_file(tmp_path):
    out = tmp_path / "none.mp4"
    result = subprocess.run(
        [sys.executable, "-m", "cityshade", "video", "--frames", "0", "--out", str(out)],
        capture_output=True,
        text=True,
        timeout=120,
    )
    assert result.returncode == 2 and len(result.stderr.strip().splitlines()) == 1, result.stderr
    assert "frames and fps must be at least 1" in result.stderr and not out.exists()


def test_crf_is_the_quality_of_the_stream(tmp_path):
    from cityshade.commands.video import check_crf, video_writer

    rng = np.random.default_rng(0)
    base = rng.integers(0, 255, (48, 64, 3), dtype=np.uint8)
    frames = [np.roll(base, 3 * k, axis=1) for k in range(6)]  # a pan over detail
    sizes, errors = {}, {}
    for crf in (12, 40):
        with video_writer(tmp_path / f"{crf}.mp4", 24, crf) as writer:
            for frame in frames:
                writer.append_data(frame)
        back = [np.asarray(f, float) for f in imageio.get_reader(tmp_path / f"{crf}.mp4")]
        sizes[crf] = (tmp_path / f"{crf}.mp4").stat().st_size
        errors[crf] = np.mean([np.abs(a - b).mean() for a, b in zip(back, frames)])
    assert sizes[40] < sizes[12] / 2 and errors[40] > errors[12]  # fewer bits, less faithful
    for bad in (52, -1, True, 23.5):
        with pytest.raises(UsageError, match=r"^invalid --crf .+; give x264's quality from 0 \(lossless\) to 51"):
            check_crf(bad)


def test_orbit_sees_every_building_in_eight_frames():
    """Over the default district, each building's centre (at half its height) is inside the
    view of at least one of 8 frames, and the loop's frames are 45 degrees apart."""
    city = make_city("default")
    positions = city.masses.column("position")
    centres = np.column_stack([positions[:, 0], city.masses.column("height") / 2, positions[:, 1]])
    seen = np.zeros(len(centres), bool)
    eyes = []
    for k in range(8):
        camera = PATHS["orbit"](city, k / 8)
        clip = np.column_stack([centres, np.ones(len(centres))]) @ camera.view_projection(16 / 9).T
        ndc = clip[:, :3] / clip[:, 3:]
        seen |= (clip[:, 3] > 0) & (np.abs(ndc[:, :2]) <= 1).all(axis=1)
        eyes.append(camera.eye)
        assert camera.eye[1] > city.masses.column("height").max()  # above the towers
    assert seen.all(), f"{(~seen).sum()} of {len(seen)} buildings in no frame"
    offsets = np.array(eyes)[:, [0, 2]] - np.mean(np.array(eyes)[:, [0, 2]], axis=0)
    offsets /= np.abs(offsets).max(axis=0)  # the ellipse's axes (reached at 0 and 90 degrees) to a circle
    angles = np.unwrap(np.arctan2(offsets[:, 1], offsets[:, 0]))
    np.testing.assert_allclose(np.diff(angles), np.radians(45.0), atol=1e-9)
    np.testing.assert_allclose(PATHS["orbit"](city, 1.0).eye, PATHS["orbit"](city, 0.0).eye, atol=1e-9)
