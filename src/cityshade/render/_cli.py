"""`cityshade render`: the default city (or another) to a PNG."""

from __future__ import annotations

import os
import re
from pathlib import Path

from .._files import atomic_output
from ..errors import UsageError
from ..scene import CITIES

def _trees_scene(args) -> int:
    """A park at low sun seen toward the sun: back-lit leaves, god rays, cascaded shadows."""
    from ..api import render_city
    from ..trees import SCENE_TIME, park_scene

    camera = args.camera if args.camera != "street" else "park"
    image, info = render_city(city=park_scene(), camera=camera, size=parse_size(args.size), time=SCENE_TIME,
                              samples=args.samples)
    save_png(image, args.out)
    print(f"wrote {args.out}: {info['trees']} trees, frame {info['frame_ms']:.1f} ms on {info['device']}")
    return 0


SCENES = {"trees": _trees_scene}  # a technique's own scene: name -> callable(args) -> exit code


def parse_size(text: str) -> tuple[int, int]:
    match = re.fullmatch(r"(\d+)x(\d+)", text.strip())
    if not match or not (1 <= int(match.group(1)) <= 16384 and 1 <= int(match.group(2)) <= 16384):
        raise UsageError(f"invalid size {text!r}; use WIDTHxHEIGHT with each from 1 to 16384, e.g. 1280x720")
    return int(match.group(1)), int(match.group(2))


def parse_metres(text: str, option: str = "--facade", limit: float = 4096.0) -> tuple[float, float]:
    """'20x16' -> (20.0, 16.0) metres, each side in (0, limit]."""
    try:
        width, height = (float(v) for v in text.lower().split("x"))
    except ValueError:
        raise UsageError(f"invalid {option} {text!r}; use WIDTHxHEIGHT in metres, e.g. 20x16") from None
    if not (0 < width <= limit and 0 < height <= limit):
        raise UsageError(f"invalid {option} {text!r}; each side must be in (0, {limit:g}] metres")
    return width, height


def parse_lights(text: str) -> float:
    try:
        value = float(text)
    except ValueError:
        value = float("nan")
    if not 0.0 <= value <= 1.0:
        raise UsageError(f"invalid --lights {text!r}; the share of lit rooms is a number from 0 to 1")
    return value


def check_writable(path: Path) -> Path:
    """Fails early, with one line, if the output cannot be written (nothing is created)."""
    folder = path.parent if str(path.parent) else Path(".")
    if path.is_dir():
        raise UsageError(f"output path {str(path)!r} is a directory; give a file name such as out/city.png")
    probe = folder
    while not probe.exists():
        probe = probe.parent
    if not os.access(probe, os.W_OK) or (path.exists() and not os.access(path, os.W_OK)):
        raise UsageError(f"cannot write {str(path)!r}: permission denied; choose another --out")
    if not probe.is_dir():
        raise UsageError(f"cannot write {str(path)!r}: {str(probe)!r} is not a directory")
    return path


def save_png(image, path: Path):
    """Writes atomically: a finished PNG or nothing."""
    from PIL import Image

    with atomic_output(path) as tmp:
        Image.fromarray(image).save(tmp, format="PNG")


def register(subparsers):
    parser = subparsers.add_parser("render", help="render a city to a PNG")
    parser.add_argument("--city", default="default", help=f"city layout: {', '.join(CITIES)}")
    parser.add_argument("--map", "--footprints", dest="map", type=Path, default=None, metavar="FILE",
                        help="a real city from a map: OpenStreetMap (.osm.pbf, .osm), GeoJSON or CityJSON")
    parser.add_argument("--scene", default=None, help="a technique's own scene instead of a city")
    parser.add_argument("--seed", type=int, default=None, help="layout seed")
    parser.add_argument("--camera", default="street",
                        help="named viewpoint of the city, or lon,lat,height,heading for a city from --map")
    parser.add_argument("--date", default=None, help="date YYYY-MM-DD: with --map, the sun and moon over the map")
    parser.add_argument("--size", default="1280x720", help="WIDTHxHEIGHT in pixels")
    parser.add_argument("--lights", default=None, help="share of lit rooms, 0..1 (default: from --time)")
    parser.add_argument("--time", default="19:10", help="time of day HH:MM (sun, sky, lit rooms)")
    parser.add_argument("--no-interiors", action="store_true", help="reflective windows only")
    parser.add_argument("--samples", type=int, default=4, choices=(0, 2, 4, 8),
                        help="MSAA samples (0: off; llvmpipe shades every sample, so 0 is about 4x faster there)")
    parser.add_argument("--aov", choices=("guessed",), default=None,
                        help="with --map: tint walls whose height and roofs whose shape the map did not give "
                             "(orange) apart from what it gave (blue)")
    parser.add_argument("--out", type=Path, default=Path("out/city.png"), help="PNG to write")
    parser.set_defaults(run=run)


def run(args) -> int:
    from ..api import render_city

    size = parse_size(args.size)
    lights = None if args.lights is None else parse_lights(args.lights)
    check_writable(args.out)
    if args.scene is not None:
        if args.scene not in SCENES:
            raise UsageError(f"unknown scene {args.scene!r}; allowed: {', '.join(SCENES) or 'none'}")
        return SCENES[args.scene](args)
    if args.aov is not None and args.map is None:
        raise UsageError(f"--aov {args.aov} shows what a map gave and what was guessed; it needs --map FILE")
    from ..maps import require_map_for_date

    require_map_for_date(args.date, args.map)
    city, sky = args.city, {}
    if args.map is not None:
        from ..maps import city_from_map

        city, args.camera, sky = city_from_map(args.map, args.camera, args.date, args.time)
    image, info = render_city(city=city, seed=args.seed, camera=args.camera, size=size, lights=lights,
                              time=args.time, interior_mapping=not args.no_interiors, samples=args.samples,
                              aov=args.aov, **sky)
    save_png(image, args.out)
    msaa = f"{info['samples']}x MSAA" if info["samples"] else "no MSAA"
    print(f"wrote {args.out} ({size[0]}x{size[1]}, {msaa}): {info['buildings']} buildings, "
          f"frame {info['frame_ms']:.1f} ms (median of {info['frames']}) on {info['device']}")
    return 0
