"""`cityshade info FILE [--json]`: what a map holds, what the guessing model filled in, what was repaired.

What each map feature says of itself (maps/features/, in their order; `guess_missing` runs first, as
it does before rendering): buildings and parts, roof shapes, per attribute how many buildings had it
tagged and how many got it guessed, road and railway lengths by class, green and water areas (each
kind's union, so overlapping polygons count once), trees, street lamps, doors (at mapped entrances
or guessed) and shop fronts; and every repaired, skipped or fallen-back feature with its reason and
one example.
"""

from __future__ import annotations

import argparse
import json
import os
import sys
from collections import Counter
from pathlib import Path

from ..maps import FEATURES, MapData, guess_missing, load_map
from .arguments import add_cityjson_lod_option, add_terrain_option


def _report(counter: Counter, examples: dict) -> list[dict]:
    return [
        {"what": what, "why": why, "count": count, "example": examples.get((what, why))}
        for (what, why), count in counter.most_common()
    ]


def summary(data: MapData) -> dict:
    """The numbers `info` prints, as a JSON-ready dict (guessing must already have run)."""
    info = {"file": str(data.source), "crs": data.crs, "origin_lon_lat": list(data.origin)}
    for feature in FEATURES:
        info.update(feature.summary(data))
    return {
        **info,
        "repaired": _report(data.report.repaired, data.report.examples),
        "skipped": _report(data.report.skipped, data.report.examples),
        "fallbacks": _report(data.report.fallbacks, data.report.examples),
    }


def _text(info: dict) -> str:
    lon, lat = info["origin_lon_lat"]
    lines = [
        f"{info['file']}  ({info['crs']}, origin {lon:.6f}, {lat:.6f})",
        f"buildings: {info['buildings']}  parts: {info['parts']}  outlines replaced by parts: "
        f"{info['outlines_replaced_by_parts']}  cut by parts: {info['outlines_cut_by_parts']}  "
        f"roofs without walls: {info['roofs_without_walls']}",
        "roof shapes: " + ", ".join(f"{k} {v}" for k, v in info["roof_shapes"].items()),
        "roof shapes tagged: " + (", ".join(f"{k} {v}" for k, v in info["roof_shapes_tagged"].items()) or "none"),
        "building attributes (tagged / guessed):",
    ]
    lines += [f"  {name:18s} {c['tagged']:7d} / {c['guessed']:d}" for name, c in info["building_attributes"].items()]
    confidence = info["guess_confidence"]
    lines.append(
        "guess confidence (mean, guessed): "
        + ", ".join(f"{k} {v['mean']:.2f} ({v['guessed']})" for k, v in confidence.items() if v["guessed"])
    )
    if info["guess_forms"]:
        lines.append("forms recognised: " + ", ".join(f"{k} {v}" for k, v in info["guess_forms"].items()))
    road_total = sum(info["roads_km"].values())
    lines.append(f"roads: {road_total:.2f} km  " + ", ".join(f"{k} {v:.2f}" for k, v in info["roads_km"].items()))
    if info["railways_km"]:
        lines.append("railways km: " + ", ".join(f"{k} {v:.2f}" for k, v in info["railways_km"].items()))
    areas = info["area_m2"]
    green = ", ".join(f"{k} {areas[k]:.0f}" for k in info["green_kinds"])
    other = ", ".join(f"{k} {v:.0f}" for k, v in areas.items() if k not in info["green_kinds"] and k != "water")
    lines.append(
        f"water: {info['water_m2']:.0f} m²  green: {info['green_m2']:.0f} m²"
        + (f" ({green})" if green else "")
        + (f"  other areas: {other}" if other else "")
    )
    lines.append(
        f"trees: {info['trees']}  street lamps: {info['street_lamps']}, {info['street_lamps_guessed']} guessed"
    )
    doors = info["doors"]
    lines.append(
        f"doors: {doors['from_entrances']} at mapped entrances ({doors['entrances']} entrances mapped), "
        f"{doors['guessed']} guessed on the street side; shop fronts: {doors['buildings_with_shop_fronts']}"
    )
    if "city_objects" in info:
        lines.append(
            "city objects drawn: " + (", ".join(f"{k} {v}" for k, v in info["city_objects"].items()) or "none")
        )
        lines.append("buildings by LoD: " + (", ".join(f"LoD {k} {v}" for k, v in info["lod"].items()) or "none"))
    for section in ("repaired", "skipped", "fallbacks"):
        for entry in info[section]:
            example = f" (e.g. {entry['example']})" if entry["example"] else ""
            lines.append(f"{section}: {entry['count']} {entry['what']}: {entry['why']}{example}")
    return "\n".join(lines)


def run(args: argparse.Namespace) -> int:
    data = guess_missing(load_map(args.file, args.lod, args.terrain))
    info = summary(data)
    try:
        print(json.dumps(info, indent=2, ensure_ascii=False) if args.json else _text(info), file=sys.stdout)
        sys.stdout.flush()
    except BrokenPipeError:  # `cityshade info FILE | head`: the reader has all it wanted
        os.dup2(os.open(os.devnull, os.O_WRONLY), sys.stdout.fileno())
    return 0


def register(subparsers) -> None:
    parser = subparsers.add_parser(
        "info", help="what a map file holds (OpenStreetMap, GeoJSON, CityJSON)", description=__doc__.split("\n\n")[0]
    )
    parser.add_argument("file", type=Path, metavar="FILE", help=".osm.pbf, .osm, .geojson, .json or .city.json")
    parser.add_argument("--json", action="store_true", help="print the same as JSON")
    add_terrain_option(parser)
    add_cityjson_lod_option(parser)
    parser.set_defaults(run=run)
