"""`cityshade export`: a city to glTF or 3D Tiles."""

from __future__ import annotations

import json
import sys
from pathlib import Path

from ..scene import CITIES
from .arguments import add_map_option, add_terrain_option


def register(subparsers):
    parser = subparsers.add_parser("export", help="export a city as glTF (GLB) or a 3D Tiles tileset")
    source = parser.add_mutually_exclusive_group(required=True)
    add_map_option(source)
    add_terrain_option(parser)
    source.add_argument("--city", choices=tuple(CITIES), help="a built-in city layout")
    parser.add_argument("--out", type=Path, required=True, help="the .glb/.gltf file, or the tileset's directory")
    parser.add_argument("--format", default=None, help="glb, gltf or 3dtiles (default: from --out's suffix, else glb)")
    parser.add_argument(
        "--texel",
        type=float,
        default=None,
        help="metres per facade atlas texel (default: the finest, no finer than 0.05, that fits the atlas limit)",
    )
    parser.add_argument(
        "--lod",
        type=int,
        default=0,
        help="level of detail: 0 full; from 1 flat-topped prisms; each level doubles the texel",
    )
    parser.add_argument(
        "--textures",
        default="webp",
        help="webp (EXT_texture_webp: lossy colour, lossless data maps; default) or png",
    )
    parser.add_argument(
        "--geometry",
        default="quantized",
        help="quantized (KHR_mesh_quantization; default), draco (KHR_draco_mesh_compression: smallest) "
        "or plain (32-bit floats)",
    )
    parser.add_argument(
        "--trees",
        default="instanced",
        help="instanced (EXT_mesh_gpu_instancing: CesiumJS, three.js, Blender; default) or nodes "
        "(a node per tree sharing its species' mesh: every reader, trimesh included)",
    )
    parser.add_argument(
        "--region",
        default=None,
        metavar="MINLON,MINLAT,MAXLON,MAXLAT",
        help="export only the buildings, ground and trees inside this box (maps only)",
    )
    parser.add_argument(
        "--viewer",
        action="store_true",
        help="with --format 3dtiles: write a CesiumJS page (index.html) beside the tileset; see `cityshade serve`",
    )
    parser.set_defaults(run=run)


def output_format(args) -> str:
    if args.format is not None:
        return args.format
    suffix = args.out.suffix.lower().lstrip(".")
    return suffix if suffix in ("glb", "gltf") else "glb"


def run(args) -> int:
    from ..export import (
        Encoding,
        check_output,
        crop,
        default_texel,
        default_texel_note,
        export_city,
        layout_export_city,
        map_export_city,
        parse_region,
    )

    fmt = output_format(args)
    encoding = Encoding(args.textures, args.geometry, args.trees)
    check_output(args.out, fmt, args.texel, args.lod, encoding, args.viewer)  # before the map is read
    region = parse_region(args.region) if args.region is not None else None
    export = map_export_city(args.map, args.terrain) if args.map is not None else layout_export_city(args.city)
    if region is not None:
        export = crop(export, region, args.region)
    texel = args.texel
    if texel is None:
        texel = default_texel(export, args.lod)
        print(default_texel_note(texel), file=sys.stderr, flush=True)
    summary = export_city(export, args.out, fmt, texel, args.lod, encoding, args.viewer)
    print(json.dumps(summary))
    return 0
