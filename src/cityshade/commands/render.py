"""`cityshade render`: the default city (or another) to a PNG."""

from __future__ import annotations

import time
from pathlib import Path

from ..api import AOVS
from ..errors import UsageError
from ..render import RenderSettings, format_bytes
from ..scene import CITIES
from .arguments import (
    add_cityjson_lod_option,
    add_map_option,
    add_terrain_option,
    check_seed,
    check_writable,
    parse_size,
    save_png,
)
from .settings_flags import add_settings_flags, settings_from_flags
from .tile import add_streaming_arguments, streamed_tiles

SETTINGS_FLAGS = ("lights", "time_of_day", "interior_mapping", "relief", "samples", "building_lod", "grammar_cache")


def _trees_scene(args) -> int:
    """A park at low sun seen toward the sun: back-lit leaves, god rays, cascaded shadows."""
    from ..api import render_city
    from ..trees import SCENE_TIME, park_scene

    camera = args.camera if args.camera != "street" else "park"
    image, info = render_city(
        city=park_scene(), camera=camera, size=parse_size(args.size), time=SCENE_TIME, samples=args.samples
    )
    save_png(image, args.out)
    print(f"wrote {args.out}: {info['trees']} trees, frame {info['frame_ms']:.1f} ms on {info['device']}")
    return 0


SCENES = {"trees": _trees_scene}  # a technique's own scene: name -> callable(args) -> exit code


def print_profile(pass_ms: dict[str, float]):
    """Each pass's median wall time and their sum, in the order the passes run (docs/frame.md)."""
    width = max(len(name) for name in (*pass_ms, "frame total"))
    for name, ms in pass_ms.items():
        print(f"  {name:<{width}}  {ms:8.2f} ms")
    print(f"  {'frame total':<{width}}  {sum(pass_ms.values()):8.2f} ms")


def check_aov_suffix(aov: str | None, out: Path):
    """The AOV's file kind follows --out's suffix: fail before rendering when it cannot."""
    allowed = {"depth": (".npz", ".exr")}.get(aov, (".png",))
    if aov is not None and out.suffix.lower() not in allowed:
        raise UsageError(f"--aov {aov} writes {' or '.join(allowed)}; --out {out} has another suffix")


def write_aov(aov: str, image, out: Path, info: dict, source=None):
    """The AOV array to `out`, and for class and instance the JSON naming its values beside it
    (OUT with the suffix .json). An instance image of a map's `source` (dataset.Source) numbers its
    buildings, not their masses: the parts of one building share its number and map id."""
    import io
    import json

    import numpy as np

    from .._files import write_bytes, write_png, write_text

    if aov == "depth":
        if out.suffix.lower() == ".exr":
            write_exr_depth(image, out)
        else:
            buffer = io.BytesIO()
            np.savez_compressed(buffer, depth=image)
            write_bytes(out, buffer.getvalue())
        return
    if aov == "instance" and source is not None:
        from ..dataset import building_instances

        image = building_instances(image, source.mass_building, source.mass_part)[..., 0].astype(np.uint16)
    write_png(image, out)
    if aov == "class":
        table = {"classes": info["classes"]}
    else:
        seen = (int(i) for i in np.unique(image) if i > 0)
        table = {"instances": {str(i): source.instances[i - 1] if source else None for i in seen}}
    write_text(out.with_suffix(".json"), json.dumps(table, indent=1) + "\n")


def write_exr_depth(depth, out: Path):
    """A 32-bit float single-channel EXR, channel Z (OpenEXR's name for depth)."""
    import OpenEXR

    from .._files import atomic_output

    header = {"compression": OpenEXR.ZIP_COMPRESSION, "type": OpenEXR.scanlineimage}
    with atomic_output(out) as tmp, OpenEXR.File(header, {"Z": depth}) as exr:
        exr.write(str(tmp))


def register(subparsers):
    parser = subparsers.add_parser("render", help="render a city to a PNG")
    parser.add_argument("--city", default="default", help=f"city layout: {', '.join(CITIES)}")
    add_map_option(parser, "--footprints")
    add_terrain_option(parser)
    add_cityjson_lod_option(parser)
    parser.add_argument("--scene", default=None, help="a technique's own scene instead of a city")
    parser.add_argument("--seed", type=check_seed, default=None, help="layout seed, 0 to 2^31-1")
    parser.add_argument(
        "--camera",
        default="street",
        help="named viewpoint of the city, or lon,lat,height,heading for a city from --map "
        "(HEIGHT in metres above the ground there: the terrain's with --terrain)",
    )
    parser.add_argument("--date", default=None, help="date YYYY-MM-DD: with --map, the sun and moon over the map")
    parser.add_argument("--size", default="1280x720", help="WIDTHxHEIGHT in pixels")
    add_settings_flags(parser, RenderSettings, SETTINGS_FLAGS)
    parser.add_argument(
        "--aov",
        choices=AOVS,
        default=None,
        help="write this AOV to --out instead of the picture (same camera and size): class (8-bit PNG of "
        "the dataset's class ids, OUT.json names them), instance (16-bit PNG of building index + 1, "
        "OUT.json gives each one's map id), depth (camera z in metres: .npz array 'depth' or 32-bit "
        ".exr channel Z, +inf on the sky), guessed (with --map: walls and roofs the map did not give "
        "tinted orange, what it gave blue)",
    )
    add_streaming_arguments(parser)
    parser.add_argument("--out", type=Path, default=Path("out/city.png"), help="PNG to write")
    parser.add_argument(
        "--profile",
        action="store_true",
        help="print each pass's wall time (ctx.finish() around it) and the frame total",
    )
    parser.set_defaults(run=run)


def run(args) -> int:
    from ..api import render_city
    from ..dataset import load_source

    start = time.perf_counter()

    size = parse_size(args.size)
    settings = settings_from_flags(args, RenderSettings)
    del settings["time_of_day"]  # render_city takes the clock time as typed, as the map's sun does
    check_writable(args.out)
    if args.scene is not None:
        if args.scene not in SCENES:
            raise UsageError(f"unknown scene {args.scene!r}; allowed: {', '.join(SCENES) or 'none'}")
        return SCENES[args.scene](args)
    if args.aov == "guessed" and args.map is None and args.tiles is None:
        raise UsageError(f"--aov {args.aov} shows what a map gave and what was guessed; it needs --map FILE")
    check_aov_suffix(args.aov, args.out)
    from ..maps import require_map_for_date

    require_map_for_date(args.date, args.map or args.tiles)
    city, sky = args.city, {}
    builtin, source = None, None
    if args.memory_budget is not None and args.map is None and args.tiles is None:
        from ..scene import make_city

        builtin = make_city(args.city, args.seed)
    with streamed_tiles(args, builtin) as (tiles, budget):
        if args.map is not None or (tiles is not None and tiles.city.origin is not None):  # a map's city
            from ..maps import city_from_map

            made = tiles.city if tiles is not None else None
            if args.aov == "instance" and made is None:
                source = load_source(args.map, terrain=args.terrain)  # the map id of every building mass
                made = source.city
            city, args.camera, sky = city_from_map(
                args.map, args.camera, args.date, args.time_of_day, city=made, lod=args.lod, terrain=args.terrain
            )
        before_render = time.perf_counter() - start
        image, info = render_city(
            city=city,
            seed=args.seed,
            camera=args.camera,
            size=size,
            time=args.time_of_day,
            profile=args.profile,
            aov=args.aov,
            tiles=tiles,
            memory_budget=budget,
            **settings,
            **sky,
        )
    if args.aov in (None, "guessed"):
        save_png(image, args.out)
    else:
        write_aov(args.aov, image, args.out, info, source)
    if args.profile:
        print_profile(info["pass_ms"])
    msaa = f"{info['samples']}x MSAA" if info["samples"] else "no MSAA"
    print(
        f"wrote {args.out} ({size[0]}x{size[1]}, {msaa}): {info['buildings']} buildings, "
        f"frame {info['frame_ms']:.1f} ms (median of {info['frames']}) on {info['device']}"
    )
    if "tiles" in info:
        t = info["tiles"]
        print(
            f"streamed: {t['resident']} of {t['total']} tiles resident, {format_bytes(t['resident_bytes'])}; "
            f"the city was ready to draw {before_render + info['city_s']:.1f} s after the command started"
        )
    return 0
