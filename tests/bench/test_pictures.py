"""The picture set's figures on the real maps (bench.pictures; data/*.osm.pbf © OpenStreetMap
contributors, ODbL 1.0), each on a small frame: the faults the set was made to show stay gone.
Before (main's code, 320x180, docs/pictures/figures-before.json): Helsinki's roofs from the air at
noon had mean luminance 0.049, spread 0.10, its water 0.009; the silent town's streets at night had
no lit pixel (lit share 0.0)."""

from __future__ import annotations

import numpy as np
import pytest

from cityshade.bench.pictures import NIGHT_DATE, TIMES, Shot, measure, render_shot, shots
from cityshade.maps import load_map, map_city

pytestmark = pytest.mark.gl
SIZE = (128, 72)


def _figures(city, name: str, camera: str, when: str) -> dict:
    shot = Shot(name, camera, TIMES[when], NIGHT_DATE if when == "night" else None)
    arrays = render_shot(city, shot, SIZE)
    return measure(arrays["rgb"], arrays["class"], arrays["instance"])


def test_the_set_is_every_map_from_street_and_air_by_day_dusk_and_night():
    names = [shot.name for shot in shots()]
    assert len(names) == len(set(names)) == 3 * 2 * 3
    assert "silent-town-street-night" in names and "helsinki-aerial-day" in names


def test_helsinki_roofs_and_water_from_the_air_at_noon(helsinki_pbf):
    figures = _figures(map_city(load_map(helsinki_pbf)), "helsinki", "aerial", "day")
    assert figures["roof_luminance"] > 0.12, figures  # before: 0.049, a dark slab
    assert figures["roof_spread"] > 0.12, figures  # before: 0.10
    assert figures["water_luminance"] > 0.02, figures  # before: 0.009, a black hole


def test_the_silent_towns_streets_are_lit_at_night(silent_pbf):
    figures = _figures(map_city(load_map(silent_pbf)), "silent-town", "street", "night")
    assert figures["lit_street_share"] > 0.02, figures  # before: 0.0, pitch dark (no mapped lamps)
    assert 200.0 < figures["sky_hue"] < 260.0, figures
    assert not np.isnan(figures["sky_luminance"])
