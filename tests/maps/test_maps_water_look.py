"""Water from the air: never black by day, and no ripples finer than a pixel that crawl as stripes
and moire from frame to frame (measured on a lake among four houses, framed from the air)."""

from __future__ import annotations

from pathlib import Path

import numpy as np
import pytest
import shapely

from cityshade.bench.pictures import luminance
from cityshade.dataset import CLASSES, class_image
from cityshade.maps import Area, MapBuilding, MapData, map_city
from cityshade.render import Renderer, RenderSettings

pytestmark = pytest.mark.gl
SIZE = (96, 54)
NOON = (50.0, 180.0)


def lake() -> MapData:
    """A 500 m lake with a house at each corner (the aerial view frames the houses, so the lake)."""
    houses = [
        MapBuilding(i, f"way/{i}", shapely.box(x, y, x + 20, y + 20))
        for i, (x, y) in enumerate([(-280, -280), (260, -280), (260, 260), (-280, 260)])
    ]
    water = Area("way/9", shapely.box(-250, -250, 250, 250), "water")
    return MapData(Path("lake.osm"), (24.94, 60.17), "EPSG:32635", buildings=houses, areas=[water])


@pytest.fixture(scope="module")
def lake_view(gl_context):
    city = map_city(lake())
    renderer = Renderer(SIZE, RenderSettings(samples=0, sun=NOON, god_rays=False), ctx=gl_context)
    renderer.set_city(city)
    view = city.camera("aerial")
    water = class_image(renderer.render_ids(view)) == CLASSES.index("water")
    yield renderer, view, water
    renderer.release()


def _frame(lake_view, **settings):
    renderer, view, _ = lake_view
    renderer.set_settings(renderer.settings.with_(**settings))
    return renderer.render(view)


def test_water_from_the_air_is_not_black(lake_view):
    water = lake_view[2]
    noon = _frame(lake_view, sun=NOON, animation_time=0.0)
    assert water.mean() > 0.3
    lum = luminance(noon[water])
    assert lum.mean() > 0.02, f"water luminance {lum.mean():.4f} (before: 0.009, a black hole)"
    blue = noon[water].astype(float).mean(axis=0)
    assert blue[2] > blue[0] + 10, f"water reads blue: mean sRGB {blue.round()}"


def test_the_suns_glint_does_not_crawl_from_frame_to_frame(lake_view):
    """The sun where the view's mirror image of it lies on the lake: before, ripples finer than a
    pixel broke the glint into sparkles that changed from frame to frame (99th percentile of the
    change in luminance 0.24 between these two times); filtered, it holds still."""
    _, view, water = lake_view
    f = view.forward
    mirror = (float(np.degrees(np.arcsin(-f[1]))), float(np.degrees(np.arctan2(f[0], -f[2])) % 360.0))
    a, b = (_frame(lake_view, sun=mirror, animation_time=t) for t in (0.0, 0.37))
    assert luminance(a[water]).max() > 0.5, "the glint is in view"
    change = np.abs(luminance(a[water]) - luminance(b[water]))
    assert np.quantile(change, 0.99) < 0.02, f"1% of water pixels change by {np.quantile(change, 0.99):.3f} or more"
