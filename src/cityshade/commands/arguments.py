"""Command-line arguments shared by every command: sizes, metres, shares and seeds, and checking and
writing output files. Command modules import these from here, not from each other. The checks
themselves live in `_values` (shared with the Python API) and `_files` (the one atomic writer)."""

from __future__ import annotations

import argparse
import re
from pathlib import Path

from .._files import output_target, write_png
from .._values import check_count, check_lights, check_seed, parse_size
from ..errors import UsageError

__all__ = [
    "add_terrain_option",
    "check_count",
    "check_lights",
    "check_seed",
    "check_writable",
    "parse_memory_size",
    "parse_metres",
    "parse_size",
    "save_png",
]

save_png = write_png  # a finished PNG or nothing


def parse_metres(text: str, option: str = "--facade", limit: float = 4096.0) -> tuple[float, float]:
    """'20x16' -> (20.0, 16.0) metres, each side in (0, limit]."""
    try:
        width, height = (float(v) for v in text.lower().split("x"))
    except ValueError:
        raise UsageError(f"invalid {option} {text!r}; use WIDTHxHEIGHT in metres, e.g. 20x16") from None
    if not (0 < width <= limit and 0 < height <= limit):
        raise UsageError(f"invalid {option} {text!r}; each side must be in (0, {limit:g}] metres")
    return width, height


MEMORY_UNITS = {
    "": 1,
    "b": 1,
    "kb": 10**3,
    "mb": 10**6,
    "gb": 10**9,
    "tb": 10**12,
    "kib": 2**10,
    "mib": 2**20,
    "gib": 2**30,
    "tib": 2**40,
}


def parse_memory_size(text: str, option: str = "--memory-budget") -> int:
    """'1GB' -> 10**9 bytes ('512MB', '1.5GiB', '300000'); KB, MB, GB are powers of 1000, KiB,
    MiB, GiB of 1024."""
    match = re.fullmatch(r"\s*([0-9]*\.?[0-9]+)\s*([a-zA-Z]*)\s*", text)
    unit = match.group(2).lower() if match else None
    if unit not in MEMORY_UNITS:
        raise UsageError(f"invalid {option} {text!r}; use a size such as 512MB or 1GB (KB, MB, GB, KiB, MiB, GiB)")
    size = int(float(match.group(1)) * MEMORY_UNITS[unit])
    if size <= 0:
        raise UsageError(f"invalid {option} {text!r}; the size must be more than 0 bytes")
    return size


def check_writable(path: Path) -> Path:
    """Fails early, with one line, if the output cannot be written (nothing is created)."""
    output_target(path)
    return path


MAP_HELP = "a real city from a map: OpenStreetMap (.osm.pbf, .osm), GeoJSON or CityJSON"


def add_map_option(parser, *aliases: str):
    """--map FILE (and `aliases`): the map a command draws its city from."""
    parser.add_argument("--map", *aliases, dest="map", type=Path, default=None, metavar="FILE", help=MAP_HELP)


TERRAIN_HELP = (
    "the ground's relief under --map: a DEM (GeoTIFF or any raster GDAL reads) in any CRS, read only over "
    "the map and reprojected to it; buildings stand on it, streets and land lie on it"
)


def add_terrain_option(parser):
    """--terrain FILE: the DEM a map's city stands on (terrain.read_terrain)."""
    parser.add_argument("--terrain", type=Path, default=None, metavar="FILE", help=TERRAIN_HELP)


def cityjson_lod(text: str) -> str:
    """A CityJSON level of detail as `--lod` takes it: '2' (the highest of 2.x) or '2.2'."""
    if not re.fullmatch(r"[0-4](\.[0-3])?", text.strip()):
        raise argparse.ArgumentTypeError(f"{text!r}: give a CityJSON LoD such as 1, 2 or 2.2 (0 to 4)")
    return text.strip()


def add_cityjson_lod_option(parser):
    """--lod N: which CityJSON level of detail a map's objects are drawn at (default: each one's highest)."""
    parser.add_argument(
        "--lod",
        type=cityjson_lod,
        default=None,
        metavar="N",
        help="CityJSON maps: draw each object's geometry of this LoD (2 picks the highest 2.x); "
        "default: each object's highest",
    )
