"""SIGTERM and SIGHUP during a long command leave no temporary or partial file, like Ctrl-C."""

from __future__ import annotations

import os
import signal
import subprocess
import sys
import time

import pytest

pytestmark = pytest.mark.gl  # renders or opens a context of its own, not only through gl_context


@pytest.mark.parametrize("signum", [signal.SIGTERM, signal.SIGHUP, signal.SIGINT])
def test_a_signal_during_video_leaves_nothing(tmp_path, signum):
    out = tmp_path / "city.mp4"
    env = dict(os.environ, PYTHONPATH=os.pathsep.join(sys.path))
    process = subprocess.Popen(
        [sys.executable, "-m", "cityshade", "video", "--size", "64x36", "--frames", "2000", "--out", str(out)],
        stdout=subprocess.DEVNULL,
        stderr=subprocess.PIPE,
        env=env,
    )
    deadline = time.monotonic() + 120
    while not list(tmp_path.glob(".city.mp4.*")) and time.monotonic() < deadline and process.poll() is None:
        time.sleep(0.2)
    (partial,) = tmp_path.glob(".city.mp4.*")
    while partial.stat().st_size == 0 and process.poll() is None:  # until frames are encoded into it
        time.sleep(0.05)
    process.send_signal(signum)
    _, err = process.communicate(timeout=60)
    assert process.returncode == (130 if signum == signal.SIGINT else 128 + signum), err
    assert b"Traceback" not in err
    assert list(tmp_path.iterdir()) == []


@pytest.mark.parametrize("signum", [signal.SIGTERM, signal.SIGHUP])
def test_a_signal_during_compress_exits_cleanly(tmp_path, signum):
    from cityshade.grammar import library_path

    env = dict(os.environ, PYTHONPATH=os.pathsep.join(sys.path))
    process = subprocess.Popen(
        [
            sys.executable,
            "-m",
            "cityshade",
            "compress",
            str(library_path("dusk.grammar")),
            "--facade",
            "60x60",
            "--texel",
            "0.05",  # 1200 x 1200 texels: factorising takes seconds, reaching it no more
            "--out",
            str(tmp_path / "f.cfdm"),
        ],
        stdout=subprocess.DEVNULL,
        stderr=subprocess.PIPE,
        env={**env, "FORCE_COLOR": "1"},  # rich draws its progress line on the pipe too
    )
    shown = b""
    while b"BMF" not in shown and process.poll() is None:  # the progress line: factorising
        shown += process.stderr.read1(4096)
    assert process.poll() is None, "compress finished before the signal; give it more work"
    process.send_signal(signum)
    _, err = process.communicate(timeout=60)
    assert process.returncode == 128 + signum and b"Traceback" not in err
    assert list(tmp_path.iterdir()) == []


def test_a_video_needs_an_mp4_name(tmp_path, capsys):
    from cityshade.commands import main

    assert main(["video", "--size", "8x8", "--frames", "1", "--out", str(tmp_path / "city")]) == 2
    assert "give a name ending in .mp4" in capsys.readouterr().err
    assert not list(tmp_path.iterdir())
