"""The trees in the city frame: cascaded shadows on the ground, the tree scene from the CLI."""

import numpy as np
import pytest
from PIL import Image

from cityshade.commands import main
from cityshade.frame import parse_time
from cityshade.render import Daylight, Renderer, RenderSettings
from cityshade.render.testing import god_ray_uniforms
from cityshade.scene import GROUND_PAVEMENT, Camera, City, box
from cityshade.trees import SCENE_TIME, city_trees, park_scene
from render_checks import render_finite

pytestmark = pytest.mark.gl  # renders or opens a context of its own, not only through gl_context

SIZE = (160, 120)


def test_a_tower_shades_the_ground_and_a_roof_on_its_far_side_from_the_sun(output_dir):
    sun = Daylight.at(15.0).sun_direction
    flat = np.array([sun[0], 0.0, sun[2]]) / np.hypot(sun[0], sun[2])
    centre = np.array([5.0, 0.0, 5.0])
    shed = centre - flat * 16  # a low building in the tower's shadow: buildings receive too
    masses = [box((0.0, 0.0), 10.0, 10.0, 30.0), box((shed[0] - 3, shed[2] - 3), 6.0, 6.0, 3.0)]
    city = City(
        "tower",
        1,
        masses,
        [(-80.0, -80.0, 80.0, 80.0, GROUND_PAVEMENT)],
        (-80.0, -80.0, 80.0, 80.0),
        {"top": Camera((5.0, 160.0, 5.1), (5.0, 0.0, 5.0), fov_y=50.0, near=1.0, far=400.0)},
    )
    camera = city.camera("top")
    shots = {}
    for shadows in (True, False):
        renderer = Renderer(SIZE, RenderSettings(time_of_day=15.0, shadows=shadows, samples=0, god_rays=False))
        renderer.set_city(city)
        shots[shadows] = render_finite(renderer, camera).astype(float).sum(axis=2)
        renderer.release()
    Image.fromarray(np.clip(shots[True] / 3, 0, 255).astype(np.uint8)).save(output_dir / "trees_tower_shadow.png")
    view_projection = camera.view_projection(SIZE[0] / SIZE[1])

    def pixel(point):
        p = view_projection @ np.append(point, 1.0)
        x, y = (p[:2] / p[3] * 0.5 + 0.5) * SIZE
        return int(SIZE[1] - 1 - y), int(x)

    ground, roof, ahead = pixel(centre - flat * 9), pixel(shed + [0.0, 3.0, 0.0]), pixel(centre + flat * 14)
    assert shots[True][ground] < 0.6 * shots[False][ground]  # ground in the tower's shadow
    assert shots[True][roof] < 0.6 * shots[False][roof]  # the low building's roof too
    assert shots[True][ahead] > 0.9 * shots[False][ahead]  # in the sun


def test_the_park_has_groves_and_the_city_has_street_rows():
    park = park_scene()
    assert len(city_trees(park)) > 40
    from cityshade.scene import default_city

    trees = city_trees(default_city())
    assert len(np.unique(trees["species"])) == 3 and len(trees) > 300


def test_render_scene_trees_from_the_cli(tmp_path, output_dir):
    out = tmp_path / "trees.png"
    assert main(["render", "--scene", "trees", "--size", "160x90", "--samples", "0", "--out", str(out)]) == 0
    image = np.asarray(Image.open(out))
    assert image.shape == (90, 160, 3) and image.std() > 10
    Image.fromarray(image).save(output_dir / "trees_scene_cli.png")


def test_god_rays_brighten_toward_the_sun_only():
    """SpeedTree §4.5: a radial blur of bright pixels around the sun adds light; nothing else changes
    colour much. Rendered with and without, looking toward the low sun of the tree scene."""
    city = park_scene()
    camera = city.camera("park")
    images = {}
    for rays in (True, False):
        renderer = Renderer(SIZE, RenderSettings(time_of_day=parse_time(SCENE_TIME), samples=0, god_rays=rays))
        renderer.set_city(city)
        images[rays] = render_finite(renderer, camera).astype(float).mean(axis=2)
        renderer.release()
    daylight, aspect = Daylight.at(parse_time(SCENE_TIME)), SIZE[0] / SIZE[1]
    sun = god_ray_uniforms(camera.view_projection(aspect), camera.eye, daylight.sun_direction, daylight.sun_color)[
        "u_sun_screen"
    ]
    added = images[True] - images[False]
    y, x = np.mgrid[0 : SIZE[1], 0 : SIZE[0]]
    near = np.hypot(x / SIZE[0] - sun[0], (1 - y / SIZE[1]) - sun[1]) < 0.25
    print(f"god rays add {added[near].mean():.1f}/255 near the sun, {added[~near].mean():.1f}/255 elsewhere")
    assert near.any() and added[near].mean() > 3 and added[near].mean() > 2 * added[~near].mean()
    assert (added > -2).mean() > 0.99, "god rays only add light"
