"""A close look from above at the Helsinki building with the most dormers and the roofs around it
(rooftop units, parapets, roof materials): docs/images/roofscape_helsinki_dormers.png.

    python scripts/roofscape-picture.py --map data/Helsinki.osm.pbf --out docs/images/roofscape_helsinki_dormers.png

The `render` command's spot cameras tilt at most 45 degrees and only from far up; this one looks
down on one building from 0.6 of its size above its roof."""

from __future__ import annotations

import argparse
from pathlib import Path

import numpy as np
from PIL import Image

from cityshade.gl import create_context
from cityshade.maps import load_map, map_city
from cityshade.render import Renderer, RenderSettings
from cityshade.scene import ROOF_PARTS, SURFACE_ROOF, Camera, batch


def main():
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--map", required=True, type=Path)
    parser.add_argument("--out", required=True, type=Path)
    parser.add_argument("--size", default="960x540")
    args = parser.parse_args()
    width, height = (int(v) for v in args.size.split("x"))
    city = map_city(load_map(args.map))
    vertices, _ = batch(city.masses)
    sheet = (vertices["ids"][:, 1] == SURFACE_ROOF) & (vertices["ids"][:, 2] == ROOF_PARTS["ROOF_PART_SHEET"])
    attic = np.array([m.roof.attic_storey > 0 for m in city.masses])
    counts = np.bincount(vertices["ids"][sheet, 0], minlength=len(city.masses)) * attic  # dormer cheeks
    chosen = vertices[vertices["ids"][:, 0] == np.argmax(counts)]["position"]
    low, high = chosen.min(axis=0), chosen.max(axis=0)
    centre, size = (low + high) / 2, float(max(high[0] - low[0], high[2] - low[2]))
    camera = Camera(
        (centre[0] + 0.3 * size, high[1] + 0.6 * size, centre[2] + 0.9 * size),
        (centre[0], high[1] - 3.0, centre[2]),
        fov_y=50.0,
    )
    renderer = Renderer((width, height), RenderSettings(time_of_day=11.0, god_rays=False), ctx=create_context())
    renderer.set_city(city)
    try:
        Image.fromarray(renderer.render(camera)).save(args.out)
    finally:
        renderer.release()
    print(f"wrote {args.out}")


if __name__ == "__main__":
    main()
