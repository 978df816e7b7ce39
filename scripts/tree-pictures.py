"""The pictures of docs/trees.md: the park toward the low sun, silhouette fins on and off, alpha
test and alpha to coverage, and the four species.

    python scripts/tree-pictures.py --out docs/images

Each is a whole frame of the renderer (ground, sky, shadows, tone map); the tree techniques are
switched through the renderer's TreeSettings. The single trees stand on a lawn of their own,
one tree per city, at 16:00 (the sun behind the camera's left shoulder)."""

from __future__ import annotations

import argparse
from pathlib import Path

import numpy as np
from PIL import Image

from cityshade.frame import parse_time
from cityshade.gl import create_context
from cityshade.render import Renderer, RenderSettings
from cityshade.scene import GROUND_GRASS, Camera, City, Layer
from cityshade.trees import SCENE_TIME, SPECIES_ORDER, city_trees, park_scene, tree_instances

LAWN = (-300.0, -300.0, 300.0, 300.0)
PANEL = 128  # pixels per side of a single tree's picture


def one_tree(species: str) -> City:
    """A lawn with one tree of `species` at the origin, unturned and at its model's size."""
    trees = tree_instances([(0.0, 0.0, 0.0)], species, np.random.default_rng(0))
    trees["yaw"], trees["scale"] = 0.0, 1.0
    return City(species, 0, [], [(*LAWN, GROUND_GRASS)], LAWN, layers=(Layer("trees", trees=trees),))


def side_by_side(*images: np.ndarray, scale: int = 1) -> Image.Image:
    """Images in a row, enlarged `scale` times by repeating pixels (so single pixels can be seen)."""
    row = np.hstack(images)
    return Image.fromarray(row.repeat(scale, 0).repeat(scale, 1))


def park(ctx, out: Path):
    """The scene of `cityshade render --scene trees`, a little smaller (its grass keeps a PNG large)."""
    renderer = Renderer((896, 504), RenderSettings(time_of_day=parse_time(SCENE_TIME)), ctx=ctx)
    try:
        city = park_scene()
        renderer.set_city(city)
        Image.fromarray(renderer.render(city.camera("park"))).save(out, optimize=True)
    finally:
        renderer.release()


def fins(ctx, out: Path):
    """The trunk of the park's oak nearest its close-up viewpoint, seen from 2.5 m south of it,
    looking up into the crown with the sun to the left, fins on (left) and off (right)."""
    renderer = Renderer((320, 320), RenderSettings(time_of_day=parse_time(SCENE_TIME)), ctx=ctx)
    try:
        city = park_scene()
        renderer.set_city(city)
        trees = city_trees(city)
        oaks = trees[trees["species"] == SPECIES_ORDER.index("oak")]
        eye = np.array(city.camera("closeup").eye)
        x, _, z = oaks["position"][np.argmin(np.linalg.norm(oaks["position"] - eye * [1, 0, 1], axis=1))]
        camera = Camera((x + 0.5, 1.0, z + 2.4), (x, 2.0, z), fov_y=55.0, near=0.05, far=1500.0)
        settings = renderer.trees.settings
        images = []
        for on in (True, False):
            renderer.trees.settings = settings.with_(fins=on)
            images.append(renderer.render(camera))
        side_by_side(*images).save(out, optimize=True)
    finally:
        renderer.release()


def single_trees(ctx, a2c_out: Path, species_out: Path):
    """An oak's crown with alpha test (left) and alpha to coverage (right), 4x MSAA, enlarged 2x;
    then the four species, each framed by its height."""
    renderer = Renderer((PANEL, PANEL), RenderSettings(time_of_day=16.0, samples=4, god_rays=False), ctx=ctx)
    try:
        renderer.set_city(one_tree("oak"))
        crown = Camera((0.0, 5.0, 9.0), (0.0, 5.0, 0.0), fov_y=50, near=0.1, far=200)
        settings = renderer.trees.settings
        images = []
        for on in (False, True):
            renderer.trees.settings = settings.with_(alpha_to_coverage=on)
            images.append(renderer.render(crown))
        side_by_side(*images, scale=2).save(a2c_out, optimize=True)
        images = []
        for species in SPECIES_ORDER:
            renderer.set_city(one_tree(species))
            height = renderer.trees.models[next(iter(renderer.trees.models))].height
            eye = (0.0, height * 0.45, height * 1.3)
            images.append(renderer.render(Camera(eye, (0.0, height * 0.45, 0.0), fov_y=55, near=0.1, far=400)))
        side_by_side(*images).save(species_out, optimize=True)
    finally:
        renderer.release()


def main():
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--out", type=Path, default=Path("docs/images"), help="folder of the four pictures")
    args = parser.parse_args()
    args.out.mkdir(parents=True, exist_ok=True)
    ctx = create_context(headless=True)
    names = {name: args.out / f"trees_{name}.png" for name in ("park", "fins_closeup", "a2c", "species")}
    park(ctx, names["park"])
    fins(ctx, names["fins_closeup"])
    single_trees(ctx, names["a2c"], names["species"])
    for path in names.values():
        print(f"wrote {path}")


if __name__ == "__main__":
    main()
