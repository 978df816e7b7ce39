"""`cityshade render`: the default city (or another) to a PNG."""

from __future__ import annotations

from pathlib import Path

from .._files import output_target, write_png
from .._values import check_lights as parse_lights
from .._values import check_seed, parse_size
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


def parse_metres(text: str, option: str = "--facade", limit: float = 4096.0) -> tuple[float, float]:
    """'20x16' -> (20.0, 16.0) metres, each side in (0, limit]."""
    try:
        width, height = (float(v) for v in text.lower().split("x"))
    except ValueError:
        raise UsageError(f"invalid {option} {text!r}; use WIDTHxHEIGHT in metres, e.g. 20x16") from None
    if not (0 < width <= limit and 0 < height <= limit):
        raise UsageError(f"invalid {option} {text!r}; each side must be in (0, {limit:g}] metres")
    return width, height


def check_writable(path: Path) -> Path:
    """Fails early, with one line, if the output cannot be written (nothing is created)."""
    output_target(path)
    return path


save_png = write_png  # a finished PNG or nothing


def register(subparsers):
    parser = subparsers.add_parser("render", help="render a city to a PNG")
    parser.add_argument("--city", default="default", help=f"city layout: {', '.join(CITIES)}")
    parser.add_argument("--footprints", type=Path, default=None, metavar="FILE",
                        help="build the city from footprints: GeoJSON or OpenStreetMap XML (.osm), "
                             "extruded by height / building:levels tags")
    parser.add_argument("--scene", default=None, help="a technique's own scene instead of a city")
    parser.add_argument("--seed", type=check_seed, default=None, help="layout seed, 0 to 2^31-1")
    parser.add_argument("--camera", default="street", help="named viewpoint of the city")
    parser.add_argument("--size", default="1280x720", help="WIDTHxHEIGHT in pixels")
    parser.add_argument("--lights", default=None, help="share of lit rooms, 0..1 (default: from --time)")
    parser.add_argument("--time", default="19:10", help="time of day HH:MM (sun, sky, lit rooms)")
    parser.add_argument("--no-interiors", action="store_true", help="reflective windows only")
    parser.add_argument("--samples", type=int, default=4, choices=(0, 2, 4, 8),
                        help="MSAA samples (0: off; llvmpipe shades every sample, so 0 is about 4x faster there)")
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
    city = args.city
    if args.footprints is not None:
        from ..scene import load_footprints

        city = load_footprints(args.footprints)
        if args.camera == "street" and "street" not in city.viewpoints:
            args.camera = "aerial"
    image, info = render_city(city=city, seed=args.seed, camera=args.camera, size=size, lights=lights,
                              time=args.time, interior_mapping=not args.no_interiors, samples=args.samples)
    save_png(image, args.out)
    msaa = f"{info['samples']}x MSAA" if info["samples"] else "no MSAA"
    print(f"wrote {args.out} ({size[0]}x{size[1]}, {msaa}): {info['buildings']} buildings, "
          f"frame {info['frame_ms']:.1f} ms (median of {info['frames']}) on {info['device']}")
    return 0
