"""`cityshade view`: the viewer (cityshade.viewer) on a city, a map or a tile cache."""

from __future__ import annotations

from dataclasses import replace

import moderngl_window as mglw

from ..render import RenderSettings
from ..scene import make_city
from ..viewer import DEFAULT_TARGET_FPS, HELP, open_viewer
from .arguments import add_map_option
from .settings_flags import add_settings_flags, settings_from_flags
from .tile import add_streaming_arguments, streamed_tiles


def register(subparsers):
    parser = subparsers.add_parser("view", help="interactive viewer: " + HELP)
    parser.add_argument("--city", default="default")
    add_map_option(parser)
    parser.add_argument("--camera", default="street", help="viewpoint name, or lon,lat,height,heading with --map")
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
    parser.add_argument("--window", default="pyglet", help="moderngl-window backend: pyglet, glfw, headless...")
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


def _run(args) -> int:
    settings = RenderSettings(**settings_from_flags(args, RenderSettings))
    from ..maps import require_map_for_date

    require_map_for_date(args.date, args.map or args.tiles)
    city, camera, sky = args.city, args.camera, None
    builtin = make_city(args.city) if args.memory_budget is not None and not (args.map or args.tiles) else None
    with streamed_tiles(args, builtin) as (tiles, budget):
        if args.map is not None or (tiles is not None and tiles.city.origin is not None):  # a map's city
            from ..maps import city_from_map, sky_clock

            made = tiles.city if tiles is not None else None
            city, camera, placed = city_from_map(args.map, camera, args.date, args.time_of_day, city=made)
            settings = replace(settings, **placed)
            sky = sky_clock(city.origin, args.date)
        viewer = open_viewer(
            city, camera, settings, args.window, sky=sky, target_fps=args.target_fps, tiles=tiles, memory_budget=budget
        )
        print(HELP)
        mglw.run_window_config_instance(viewer)
    return 0
