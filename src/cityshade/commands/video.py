"""`cityshade video`: a camera path (and optionally the evening) rendered to MP4."""

from __future__ import annotations

from dataclasses import replace
from pathlib import Path

import imageio.v2 as imageio
from rich.progress import Progress

from .._files import atomic_output, signals_deferred
from .._values import parse_time
from ..errors import UsageError
from ..render import Renderer, RenderSettings
from ..scene import LOOPS, PATHS, City, camera_path, make_city
from .arguments import add_map_option, add_terrain_option, check_writable, parse_size
from .settings_flags import add_settings_flags, settings_from_flags

# H.264 quality (x264's constant rate factor): 0 lossless, 51 worst; 23 is x264's own default,
# transparent for rendered cities, and the bitrate follows the size and the motion (docs/video.md)
DEFAULT_CRF = 23


def check_crf(crf) -> int:
    if isinstance(crf, bool) or not isinstance(crf, int) or not 0 <= crf <= 51:
        raise UsageError(f"invalid --crf {crf!r}; give x264's quality from 0 (lossless) to 51, e.g. {DEFAULT_CRF}")
    return crf


def video_writer(path: Path, fps: int, crf: int = DEFAULT_CRF):
    """imageio's writer of an H.264 MP4 at quality `crf` (yuv420p, the index at the front for the web)."""
    return imageio.get_writer(
        path,
        fps=fps,
        codec="libx264",
        quality=None,  # the quality is the CRF, not imageio's bitrate scale
        pixelformat="yuv420p",
        output_params=["-crf", str(check_crf(crf)), "-preset", "medium", "-movflags", "+faststart"],
        macro_block_size=1,
        ffmpeg_log_level="error",
    )


def render_video(
    out: Path,
    city: str | City = "default",
    path: str = "orbit",
    frames: int = 48,
    fps: int = 24,
    size: tuple[int, int] = (640, 360),
    start_time: str | float = "19:10",
    end_time: str | float | None = None,
    progress: bool = True,
    sky=None,
    workers: int | None = None,
    map_path: Path | None = None,
    crf: int = DEFAULT_CRF,
    streets=None,
    terrain: Path | None = None,
) -> Path:
    """Renders `frames` frames along a camera path into an H.264 MP4 (written whole or not at all).
    With `end_time`, the time of day runs from start to end: the sky darkens and rooms light up.
    `sky` (hours -> settings, e.g. `maps.sky_clock`) places the sun and moon for each frame's time.
    With `workers`, Ray actors render the frames (cityshade.dataset.render_frames); they load the
    city themselves: from `map_path` (on `terrain`) when `city` came from that map, else by the name `city`.
    `crf` is x264's quality (lower is better and larger). The walk follows the route over `streets`
    (cityshade.dataset.Streets: the map's roads or the city's streets) from one end to the other."""
    if frames < 1 or fps < 1:
        raise UsageError(f"frames and fps must be at least 1 (got {frames} frames at {fps} fps)")
    _check_mp4(Path(out))
    crf = check_crf(crf)
    layout = city if isinstance(city, City) else make_city(city)
    move = camera_path(path)
    if path == "walk":
        from ..dataset import Streets, walk_camera

        route = streets if streets is not None else Streets.from_city(layout)
        if len(route.segments):
            move = lambda _, t: walk_camera(route, t)  # noqa: E731
    begin = parse_time(start_time)
    finish = parse_time(end_time) if end_time is not None else begin
    base = RenderSettings(time_of_day=begin)

    def job(i: int):
        t = i / max(frames - 1, 1)
        hours = begin + (finish - begin) * t
        along = i / frames if path in LOOPS else t  # a loop's last frame is one step before its first
        return move(layout, along), replace(
            base, time_of_day=hours, animation_time=i / fps, **(sky(hours) if sky else {})
        )

    renderer = None
    if workers:
        from ..dataset import render_frames

        pictures = render_frames(
            (job(i) for i in range(frames)),
            size,
            map_path,
            None if map_path else layout.name,
            workers,
            terrain=terrain,
        )
    else:
        renderer = Renderer(size, base)
        renderer.set_city(layout)

        def serial():
            for i in range(frames):
                camera, settings = job(i)
                renderer.set_settings(settings)
                yield renderer.render(camera)

        pictures = serial()
    try:
        with (
            atomic_output(out) as tmp,
            video_writer(tmp, fps, crf) as writer,
            Progress(disable=not progress) as bar,
        ):
            task = bar.add_task(f"rendering {out.name}", total=frames)
            for picture in pictures:
                with signals_deferred():
                    writer.append_data(picture)
                bar.advance(task)
    finally:
        if renderer is not None:
            renderer.release()
    return out


def register(subparsers):
    parser = subparsers.add_parser("video", help="render a camera path to MP4")
    parser.add_argument("--city", default="default")
    add_map_option(parser)
    add_terrain_option(parser)
    parser.add_argument("--date", default=None, help="date YYYY-MM-DD: with --map, the sun and moon over the map")
    parser.add_argument("--path", default="orbit", help=f"camera path: {', '.join(PATHS)}")
    parser.add_argument("--frames", type=int, default=48)
    parser.add_argument("--fps", type=int, default=24)
    parser.add_argument("--size", default="640x360", help="WIDTHxHEIGHT")
    add_settings_flags(
        parser, RenderSettings, ("time_of_day",), time_of_day={"help": "time of day at the start, HH:MM"}
    )
    parser.add_argument("--until", default=None, help="time of day at the end, HH:MM (animates dusk)")
    parser.add_argument("--out", type=Path, default=Path("out/city.mp4"))
    parser.add_argument(
        "--crf",
        type=int,
        default=DEFAULT_CRF,
        help=f"H.264 quality, 0 (lossless) to 51; lower is better and larger (default {DEFAULT_CRF})",
    )
    parser.add_argument(
        "--workers",
        type=int,
        default=None,
        metavar="K",
        help="render the frames on K Ray actors (as cityshade dataset does)",
    )
    parser.set_defaults(run=_run)


def _check_mp4(path: Path):
    if path.suffix.lower() != ".mp4":
        raise UsageError(f"cannot write {str(path)!r}: videos are H.264 MP4 files; give a name ending in .mp4")


def _run(args) -> int:
    _check_mp4(args.out)
    check_crf(args.crf)
    size = parse_size(args.size)
    camera_path(args.path)
    settings_from_flags(args, RenderSettings)  # a bad --time fails before the map is read
    if args.until:
        parse_time(args.until)
    check_writable(args.out)
    from ..maps import require_map_for_date

    require_map_for_date(args.date, args.map)
    city, sky, streets = args.city, None, None
    if args.map is not None:
        from ..maps import city_from_map, sky_clock

        if args.path == "walk":  # the map's roads too, for the route
            from ..dataset import load_source

            source = load_source(args.map, terrain=args.terrain)
            city, streets = source.city, source.streets
        else:
            city = city_from_map(args.map, "aerial", args.date, args.time_of_day, terrain=args.terrain)[0]
        sky = sky_clock(city.origin, args.date)
    if args.workers is not None and args.workers < 1:
        raise UsageError(f"--workers {args.workers}: give at least 1")
    render_video(
        args.out,
        city,
        args.path,
        args.frames,
        args.fps,
        size,
        args.time_of_day,
        args.until,
        sky=sky,
        workers=args.workers,
        map_path=args.map,
        terrain=args.terrain,
        crf=args.crf,
        streets=streets,
    )
    print(f"wrote {args.out} ({args.frames} frames, {size[0]}x{size[1]}, {args.fps} fps)")
    return 0
