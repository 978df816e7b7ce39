"""`cityshade view`: the viewer (cityshade.viewer) on a city, a map or a tile cache."""

from __future__ import annotations

from dataclasses import replace
from pathlib import Path

import moderngl_window as mglw

from ..errors import UsageError
from ..render import RenderSettings
from ..scene import make_city
from ..viewer import DEFAULT_TARGET_FPS, HELP, open_viewer
from .arguments import add_map_option, add_terrain_option, check_writable, parse_size, save_png
from .settings_flags import add_settings_flags, settings_from_flags
from .tile import add_streaming_arguments, streamed_tiles

SCREENSHOT_FRAMES = 30


def register(subparsers):
    parser = subparsers.add_parser("view", help="interactive viewer: " + HELP)
    parser.add_argument("--city", default="default")
    add_map_option(parser)
    add_terrain_option(parser)
    parser.add_argument(
        "--camera",
        default="street",
        help="viewpoint name, or lon,lat,height,heading with --map (HEIGHT metres above the ground there)",
    )
    parser.add_argument("--date", default=None, help="date YYYY-MM-DD: with --map, the sun and moon over the map")
    add_settings_flags(
        parser,
        RenderSettings,
        ("time_of_day", "samples", "building_lod", "grammar_cache"),
        samples={
            "default": 0,
            "help": "MSAA samples to start with (M toggles; off by default: llvmpipe shades every sample)",
        },
    )
    parser.add_argument(
        "--window",
        default=None,
        help="moderngl-window backend: pyglet, glfw, headless... (default pyglet; with --screenshot, headless)",
    )
    parser.add_argument("--size", default="1280x720", help="the window's WIDTHxHEIGHT in pixels (default 1280x720)")
    parser.add_argument(
        "--screenshot",
        type=Path,
        default=None,
        metavar="FILE",
        help="draw --frames frames, write the last one to FILE (PNG), report the frame rate and quit",
    )
    parser.add_argument(
        "--frames",
        type=_frames,
        default=None,
        metavar="N",
        help=f"frames to draw for --screenshot (default {SCREENSHOT_FRAMES})",
    )
    parser.add_argument(
        "--target-fps",
        type=float,
        default=DEFAULT_TARGET_FPS,
        metavar="N",
        help="keep N frames per second by drawing at a lower resolution and stretching it to "
        "the window, and below the smallest one by quality steps shown in the title (shadows redrawn "
        "less often, far trees fading sooner, flat facades, no shadows) "
        f"(default {DEFAULT_TARGET_FPS:g}; 0: always full resolution and quality)",
    )
    add_streaming_arguments(parser)
    parser.set_defaults(run=_run)


def _frames(text: str) -> int:
    try:
        frames = int(text)
    except ValueError:
        frames = 0
    if not 1 <= frames <= 100_000:
        raise UsageError(f"invalid --frames {text!r}; give a whole number from 1 to 100000")
    return frames


def _run(args) -> int:
    if args.screenshot is not None:
        check_writable(args.screenshot)
    elif args.frames is not None:
        raise UsageError("--frames N counts the frames of a --screenshot FILE; give both, or neither")
    window = args.window or ("headless" if args.screenshot is not None else "pyglet")
    size = parse_size(args.size)
    settings = RenderSettings(**settings_from_flags(args, RenderSettings))
    from ..maps import require_map_for_date

    require_map_for_date(args.date, args.map or args.tiles)
    city, camera, sky = args.city, args.camera, None
    builtin = make_city(args.city) if args.memory_budget is not None and not (args.map or args.tiles) else None
    with streamed_tiles(args, builtin) as (tiles, budget):
        if args.map is not None or (tiles is not None and tiles.city.origin is not None):  # a map's city
            from ..maps import city_from_map, sky_clock

            made = tiles.city if tiles is not None else None
            city, camera, placed = city_from_map(
                args.map, camera, args.date, args.time_of_day, city=made, terrain=args.terrain
            )
            settings = replace(settings, **placed)
            sky = sky_clock(city.origin, args.date)
        frames = (args.frames or SCREENSHOT_FRAMES) if args.screenshot is not None else None
        viewer = open_viewer(
            city,
            camera,
            settings,
            window,
            size,
            sky=sky,
            target_fps=args.target_fps,
            tiles=tiles,
            memory_budget=budget,
            stop_after=frames,
        )
        if frames is None:
            print(HELP)
        mglw.run_window_config_instance(viewer)
    if frames is not None:
        _report(args.screenshot, viewer)
    return 0


def _report(path: Path, viewer):
    if viewer.last_image is None:  # closed (Esc, the window's close button) before the last frame
        raise UsageError(
            f"the window was closed after {viewer.frames_drawn} of {viewer.stop_after} frames; {path} was not written"
        )
    save_png(viewer.last_image, path)
    height, width = viewer.last_image.shape[:2]
    after_first = viewer.frames_drawn - 1
    rate = f", {after_first / viewer.seconds_after_first:.1f} fps after the first" if after_first else ""
    print(f"wrote {path} ({width}x{height}): frame {viewer.frames_drawn} of a {viewer.wnd.name} window{rate}")
    print(f"its title: {viewer.status()}")
