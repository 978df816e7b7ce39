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
