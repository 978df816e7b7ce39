"""Pictures of a relief facade for docs/relief.md: close up, at a grazing angle, relief mapping
against facade displacement mapping at the same view (the paper's fig. 3), a relief building
of the default city at street level, a street in Helsinki with the grammar facades' windows
recessed and flat, and a plain window-bay building (style 0) recessed and flat.

    .venv/bin/python examples/relief_facade.py [--out docs/images]
"""

from __future__ import annotations

import argparse
from pathlib import Path

import numpy as np
from PIL import Image

from cityshade.api import render_city
from cityshade.gl import ProgramCache, create_context
from cityshade.maps import city_from_map
from cityshade.relief import FacadeView, GpuFacade, facade_camera, paper_facade
from cityshade.render import RenderSettings
from cityshade.render._renderer import Renderer
from cityshade.scene import Camera, City, box, default_city

VIEWS = {  # name: renderer, azimuth, elevation, distance (m), target (fractions of the facade)
    "relief_closeup": ("bcfdm", 28, 12, 6.0, (0.30, 0.30)),
    "relief_grazing": ("bcfdm", 84, 4, 8.0, (0.35, 0.40)),
    "relief_grazing_rm": ("bcrm", 84, 4, 8.0, (0.35, 0.40)),
    "relief_facade": ("bcfdm", 20, 8, 26.0, (0.5, 0.5)),
}


def main():
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--out", type=Path, default=Path("docs/images"))
    parser.add_argument("--size", type=int, nargs=2, default=(640, 480))
    args = parser.parse_args()
    args.out.mkdir(parents=True, exist_ok=True)
    ctx = create_context()
    maps = paper_facade("F1")
    facade = GpuFacade(ctx, maps)
    view = FacadeView(ctx, tuple(args.size), ProgramCache(ctx))
    for name, (renderer, azimuth, elevation, distance, target) in VIEWS.items():
        view.draw(facade, facade_camera(maps, azimuth, elevation, distance, target, fov_y=50.0), renderer)
        image = view.read()
        rgb = np.where(np.isnan(image.point[..., :1]), np.array([0.55, 0.65, 0.78]), image.color)  # sky behind
        Image.fromarray((np.clip(rgb, 0, 1) ** (1 / 2.2) * 255).astype(np.uint8)).save(args.out / f"{name}.png")
        print(args.out / f"{name}.png")
    city_street(args.out / "relief_city_street.png", tuple(args.size))
    helsinki_windows(args.out / "relief_helsinki_windows.png")
    window_bay(args.out / "relief_window_bay.png")


def city_street(path: Path, size: tuple[int, int]):
    """The default city's street viewpoint turned towards the relief building on its left."""
    city = default_city()
    street = city.camera("street")
    eye, target = np.array(street.position), np.array(street.target)
    ahead = target - eye
    c, s = np.cos(np.radians(100)), np.sin(np.radians(100))
    look = np.array([c * ahead[0] + s * ahead[2], 0.2 * np.linalg.norm(ahead), -s * ahead[0] + c * ahead[2]])
    eye = eye - 3.0 * look / np.linalg.norm(look)
    renderer = Renderer(size)
    renderer.set_city(city)
    Image.fromarray(renderer.render(street.moved(position=tuple(eye), target=tuple(eye + look)))).save(path)
    print(path)


def helsinki_windows(path: Path, size: tuple[int, int] = (960, 640)):
    """The left side of Helsinki's street viewpoint by day: recessed windows (left), flat (right)."""
    city, camera, sky = city_from_map(Path("data/Helsinki.osm.pbf"), "street", None, "14:00")
    halves = []
    for relief in (True, False):
        image, _ = render_city(city=city, camera=camera, size=size, time="14:00", samples=0, relief=relief, **sky)
        halves.append(image[: size[1] // 2, : size[0] // 3])
    Image.fromarray(np.concatenate(halves, axis=1)).save(path)
    print(path)


def window_bay(path: Path, size: tuple[int, int] = (480, 270)):
    """A style-0 building (the plain window bay) from 5 m: recessed windows (left), flat (right)."""
    camera = Camera((-2.0, 4.0, -5.0), (6.0, 5.0, 0.5), fov_y=55.0)
    city = City("window bay", 0, [box((0.0, 0.0), 14.0, 12.0, 16.0, style=0, seed=41)], [], (-30, -30, 30, 30), {})
    halves = []
    for relief in (True, False):
        renderer = Renderer(size, RenderSettings(samples=0, relief=relief))
        renderer.set_city(city)
        halves.append(renderer.render(camera)[:, size[0] // 3 :])
        renderer.release()
    Image.fromarray(np.concatenate(halves, axis=1)).save(path)
    print(path)


if __name__ == "__main__":
    main()
