"""The picture set (`make pictures`): real maps from the street and the air, by day, at dusk and at
night, into docs/pictures/ with a contact sheet and the figures that measure each known fault.

Each frame is measured through the dataset's class and instance AOVs (dataset.class_image,
dataset.instance_image), so a figure names what it counts:

- building_share: the share of the frame that buildings cover (instance > 0);
- roof_luminance, roof_spread: mean and standard deviation of the roofs' relative luminance (0..1,
  Rec. 709 weights on linearised sRGB) over roof pixels;
- water_luminance: the mean luminance of water pixels;
- sky_hue, sky_luminance: the hue (degrees, 0 red, 30 orange-brown, 220 blue) and mean luminance of
  the mean sky colour;
- lit_street_share: the share of road and pavement pixels brighter than LIT_STREET luminance
  (a street under a lamp at night; unlit asphalt under the night sky stays far below it).

Maps: data/Helsinki.osm.pbf and data/test.osm.pbf (© OpenStreetMap contributors, ODbL 1.0) and the
Simple 3D Buildings test file tests/data/maps/parts.osm.
"""

from __future__ import annotations

import colorsys
import json
from dataclasses import dataclass
from pathlib import Path

import numpy as np

from ..dataset import CLASSES, class_image, instance_image

LIT_STREET = 0.05  # relative luminance of a street pixel counted as lit at night
MAPS = {
    "helsinki": "data/Helsinki.osm.pbf",
    "silent-town": "data/test.osm.pbf",
    "s3db": "tests/data/maps/parts.osm",
}
TIMES = {"day": "12:00", "dusk": "22:30", "night": "01:00"}  # on DEFAULT_DATE, midsummer: dusk is a white night
NIGHT_DATE = "2025-12-21"  # a real night at 60 degrees north: midsummer has none
CAMERAS = ("street", "aerial")


def luminance(rgb: np.ndarray) -> np.ndarray:
    """Relative luminance (0..1) of sRGB uint8 pixels."""
    c = rgb.astype(np.float64) / 255.0
    linear = np.where(c <= 0.04045, c / 12.92, ((c + 0.055) / 1.055) ** 2.4)
    return linear @ np.array([0.2126, 0.7152, 0.0722])


def _mean_or_nan(values: np.ndarray) -> float:
    return float(values.mean()) if values.size else float("nan")


def measure(rgb: np.ndarray, classes: np.ndarray, instances: np.ndarray) -> dict:
    """The figures of one frame (see the module's docstring); NaN where the frame shows no such pixel."""
    lum = luminance(rgb)
    roof = classes == CLASSES.index("roof")
    water = classes == CLASSES.index("water")
    sky = classes == CLASSES.index("sky")
    street = np.isin(classes, [CLASSES.index("road"), CLASSES.index("pavement"), CLASSES.index("lane_marking")])
    hue = float("nan")
    if sky.any():
        r, g, b = rgb[sky].astype(np.float64).mean(axis=0) / 255.0
        hue = colorsys.rgb_to_hsv(r, g, b)[0] * 360.0
    return {
        "building_share": float((instances > 0).mean()),
        "roof_luminance": _mean_or_nan(lum[roof]),
        "roof_spread": float(lum[roof].std()) if roof.any() else float("nan"),
        "water_luminance": _mean_or_nan(lum[water]),
        "sky_hue": hue,
        "sky_luminance": _mean_or_nan(lum[sky]),
        "lit_street_share": _mean_or_nan(lum[street] > LIT_STREET),
    }


@dataclass
class Shot:
    map: str
    camera: str
    time: str
    date: str | None = None

    @property
    def name(self) -> str:
        when = next(k for k, v in TIMES.items() if v == self.time)
        return f"{self.map}-{self.camera}-{when}"


def shots() -> list[Shot]:
    """The fixed set: every map from every camera at every time (the night on NIGHT_DATE)."""
    out = []
    for name in MAPS:
        for camera in CAMERAS:
            for when, clock in TIMES.items():
                out.append(Shot(name, camera, clock, NIGHT_DATE if when == "night" else None))
    return out


def _street_stand(city) -> str:
    """A map without a walked street (the S3DB file) is seen from eye height 25 m south of its
    buildings, looking north at them: the viewpoint 'street' added to the city."""
    from ..scene import Camera

    x0, z0, x1, z1 = city.bounds
    eye = ((x0 + x1) / 2, 1.7, z1 + 25.0)
    city.viewpoints["street"] = Camera(eye, ((x0 + x1) / 2, 6.0, (z0 + z1) / 2), fov_y=66.0, near=0.3, far=1e6)
    return "street"


def render_shot(city, shot: Shot, size: tuple[int, int]) -> dict:
    """rgb, class and instance arrays of one shot of a map's city (the frame and its id AOV)."""
    from .._values import parse_time
    from ..maps import city_from_map
    from ..render import Renderer, RenderSettings

    if shot.camera == "street" and "street" not in city.viewpoints:
        _street_stand(city)
    city, camera, sky = city_from_map(None, shot.camera, shot.date, shot.time, city=city)
    renderer = Renderer(size, RenderSettings(samples=0, time_of_day=parse_time(shot.time), **sky))
    try:
        renderer.set_city(city)
        view = city.camera(camera)
        rgb = renderer.render(view)
        ids = renderer.render_ids(view)
    finally:
        renderer.release()
    return {"rgb": rgb, "class": class_image(ids), "instance": instance_image(ids), "camera": camera}


def contact_sheet(images: dict[str, np.ndarray], columns: int) -> np.ndarray:
    """The images in rows of `columns`, in order, each labelled with its name."""
    from PIL import Image, ImageDraw

    tiles = list(images.items())
    h, w = tiles[0][1].shape[:2]
    rows = (len(tiles) + columns - 1) // columns
    sheet = Image.new("RGB", (columns * w, rows * (h + 14)), (24, 24, 24))
    draw = ImageDraw.Draw(sheet)
    for i, (name, image) in enumerate(tiles):
        x, y = (i % columns) * w, (i // columns) * (h + 14)
        sheet.paste(Image.fromarray(image), (x, y + 14))
        draw.text((x + 3, y + 1), name, fill=(230, 230, 230))
    return np.asarray(sheet)


def make_pictures(out: Path, size: tuple[int, int] = (320, 180), root: Path = Path(".")) -> dict:
    """Renders every shot into `out` (NAME.png), the contact sheet (contact-sheet.png) and the
    figures (figures.json); returns the figures by shot name."""
    from .._files import write_png, write_text
    from ..maps import load_map, map_city

    figures, images = {}, {}
    for name, path in MAPS.items():
        city = map_city(load_map(root / path))
        for shot in (s for s in shots() if s.map == name):
            arrays = render_shot(city, shot, size)
            write_png(arrays["rgb"], out / f"{shot.name}.png")
            figures[shot.name] = measure(arrays["rgb"], arrays["class"], arrays["instance"])
            figures[shot.name]["camera"] = arrays["camera"]
            images[shot.name] = arrays["rgb"]
            print(
                shot.name,
                json.dumps({k: round(v, 4) if isinstance(v, float) else v for k, v in figures[shot.name].items()}),
            )
    write_png(contact_sheet(images, columns=len(TIMES) * len(CAMERAS)), out / "contact-sheet.png")
    write_text(out / "figures.json", json.dumps(figures, indent=1) + "\n")
    return figures


def main(argv: list[str] | None = None) -> int:
    """`python -m cityshade.bench.pictures [--out docs/pictures] [--size 320x180]` (`make pictures`)."""
    import argparse

    parser = argparse.ArgumentParser(description="the picture set: real maps from the street and the air")
    parser.add_argument("--out", type=Path, default=Path("docs/pictures"))
    parser.add_argument("--size", default="320x180", help="WIDTHxHEIGHT of each picture")
    args = parser.parse_args(argv)
    width, height = (int(v) for v in args.size.lower().split("x"))
    make_pictures(args.out, (width, height))
    print(f"wrote {args.out}/contact-sheet.png and {args.out}/figures.json")
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
