"""`cityshade bench export`: how long exporting takes and how large the files are.

Helsinki (data/Helsinki.osm.pbf, © OpenStreetMap contributors, ODbL 1.0) to a GLB and to a 3D Tiles
tileset: seconds to read and assemble the city, seconds to export, bytes, bytes per building and the
facade atlas' texels per square metre of wall, draw calls (primitives; for a tileset, the most in
one building tile). --quick exports Helsinki at a coarse texel (0.25 m); the full run uses the
default (the finest texel that fits the atlas) and adds the Helsinki buildings tiled to 100,000
(texel 1 m). Textures and geometry are stored as the command's defaults (WebP, quantized).
"""

from __future__ import annotations

import tempfile
import time
from pathlib import Path

from ..export import export_city, map_export_city
from ._harness import BenchResult

HELSINKI = Path(__file__).resolve().parents[3] / "data" / "Helsinki.osm.pbf"
COLUMNS = [
    "extract",
    "format",
    "texel m",
    "buildings",
    "read s",
    "export s",
    "MB",
    "bytes/building",
    "atlas pages",
    "atlas Mtexels",
    "facade m²",
    "texels/m² facade",
    "triangles",
    "draw calls",
]


def _row(name: str, path: Path, fmt: str, texel: float | None, tmp: Path) -> list:
    began = time.perf_counter()
    export = map_export_city(path)
    read = time.perf_counter() - began
    out = tmp / f"{name}.{fmt if fmt != '3dtiles' else 'tiles'}"
    s = export_city(export, out, fmt, texel)
    return [
        name,
        fmt,
        s["texel"],
        s["buildings"],
        round(read, 1),
        s["seconds"],
        round(s["bytes"] / 1e6, 2),
        round(s["bytes"] / max(s["buildings"], 1)),
        len(s["atlas_pages"]),
        round(s["atlas_texels"] / 1e6, 2),
        round(s["facade_m2"]),
        round(s["atlas_texels"] / max(s["facade_m2"], 1e-9), 2),
        s["triangles"],
        s["draw_calls_per_tile"]["buildings_max"] if fmt == "3dtiles" else s["draw_calls"],
    ]


def run(quick: bool = False, out_dir: Path | None = None) -> BenchResult:
    from ..gl import create_context, describe_context

    ctx = create_context()
    device = describe_context(ctx)
    ctx.release()
    result = BenchResult("export", device)
    rows = []
    with tempfile.TemporaryDirectory() as tmp:
        tmp = Path(tmp)
        texel = 0.25 if quick else None
        rows.append(_row("Helsinki", HELSINKI, "glb", texel, tmp))
        rows.append(_row("Helsinki", HELSINKI, "3dtiles", texel, tmp))
        if not quick:
            from ..maps import tiled_extract

            extract = tmp / "tiled-100k.osm.pbf"
            tiled_extract(HELSINKI, extract, 100_000)
            rows.append(_row("Helsinki tiled to 100,000", extract, "glb", 1.0, tmp))
    result.add_table("export: time and size", COLUMNS, rows)
    result.notes.append(
        "Facades are baked on the GPU (llvmpipe on a machine without one); 'read s' is load_map + "
        "map_city (guessing, roofs, ground), 'export s' the bake, meshes, image encoding and writing. Facade "
        "m² counts every wall, window-bay walls (one repeated bay texture, no atlas) included; "
        "atlas texels per m² stay below 1/texel² also because all walls of one side of a "
        "building share one canvas (the grammar's scope is the building's width). 3D Tiles "
        "atlases include the coarser levels' smaller ones."
    )
    result.notes.append("Map data © OpenStreetMap contributors, ODbL 1.0.")
    return result
