"""`cityshade video`: a camera path (and optionally the evening) rendered to MP4."""

from __future__ import annotations

from dataclasses import replace
from pathlib import Path

import imageio.v2 as imageio
from rich.progress import Progress

from .._files import atomic_output, signals_deferred
from ..errors import UsageError
from ..scene import make_city
from ..scene import PATHS, camera_path
from ..arguments import check_writable, parse_size
from ._daylight import parse_time
from ._renderer import Renderer
from ._settings import RenderSettings


def render_video(out: Path, city: str = "default", path: str = "orbit", frames: int = 48, fps: int = 24,
                 size: tuple[int, int] = (640, 360), start_time: str = "19:10", end_time: str | None = None,
                 progress: bool = True) -> Path:
    """Renders `frames` frames along a camera path into an H.264 MP4 (written whole or not at all).
    With `end_time`, the time of day runs from start to end: the sky darkens and rooms light up."""
    if frames < 1 or fps < 1:
        raise UsageError(f"frames and fps must be at least 1 (got {frames} frames at {fps} fps)")
    _check_mp4(Path(out))
    layout = make_city(city)
    move = camera_path(path)
    begin = parse_time(start_time)
    finish = parse_time(end_time) if end_time else begin
    renderer = Renderer(size, RenderSettings(time_of_day=begin))
    renderer.set_city(layout)
    try:
        with atomic_output(out) as tmp, imageio.get_writer(tmp, fps=fps, codec="libx264", quality=8,
                                                          macro_block_size=1, ffmpeg_log_level="error") as writer, \
                Progress(disable=not progress) as bar:
            task = bar.add_task(f"rendering {out.name}", total=frames)
            for i in range(frames):
                t = i / max(frames - 1, 1)
                renderer.set_settings(replace(renderer.settings, time_of_day=begin + (finish - begin) * t,
                                              animation_time=i / fps))
                frame = renderer.render(move(layout, t))
                with signals_deferred():
                    writer.append_data(frame)
                bar.advance(task)
    finally:
        renderer.release()
    return out


def register(subparsers):
    parser = subparsers.add_parser("video", help="render a camera path to MP4")
    parser.add_argument("--city", default="default")
    parser.add_argument("--path", default="orbit", help=f"camera path: {', '.join(PATHS)}")
    parser.add_argument("--frames", type=int, default=48)
    parser.add_argument("--fps", type=int, default=24)
    parser.add_argument("--size", default="640x360", help="WIDTHxHEIGHT")
    parser.add_argument("--time", default="19:10", help="time of day at the start, HH:MM")
    parser.add_argument("--until", default=None, help="time of day at the end, HH:MM (animates dusk)")
    parser.add_argument("--out", type=Path, default=Path("out/city.mp4"))
    parser.set_defaults(run=_run)


def _check_mp4(path: Path):
    if path.suffix.lower() != ".mp4":
        raise UsageError(f"cannot write {str(path)!r}: videos are H.264 MP4 files; give a name ending in .mp4")


def _run(args) -> int:
    _check_mp4(args.out)
    size = parse_size(args.size)
    camera_path(args.path)
    parse_time(args.time)
    if args.until:
        parse_time(args.until)
    check_writable(args.out)
    render_video(args.out, args.city, args.path, args.frames, args.fps, size, args.time, args.until)
    print(f"wrote {args.out} ({args.frames} frames, {size[0]}x{size[1]}, {args.fps} fps)")
    return 0
