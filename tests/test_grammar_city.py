"""Grammar facades in the city: buildings pick a library style by their style number, the label
AOV shows the grammar's labels, and glass opens onto interior-mapped rooms."""

from __future__ import annotations

import numpy as np
import pytest
from PIL import Image

from cityshade.assets import LABELS
from cityshade.grammar import BUILDING_STYLES, library_texture
from cityshade.interior._faces import FACE_EXTERIOR
from cityshade.render import Renderer, RenderSettings, assign_facades
from cityshade.scene import Camera, City, batch, box, make_city
from render_checks import render_finite

SIZE = (128, 96)
STYLE = {name: number for number, name in BUILDING_STYLES.items()}


@pytest.fixture(scope="module")
def renderer(gl_context):
    masses = [box((0.0, 0.0), 20.0, 14.0, 19.0, seed=5, style=STYLE["brick"]),
              box((26.0, 0.0), 14.0, 14.0, 19.0, seed=6, style=0)]
    r = Renderer(SIZE, RenderSettings(lights=0.7), ctx=gl_context)
    r.set_city(City("grammar", 0, masses, [], (-40.0, -40.0, 60.0, 60.0)))
    yield r
    r.release()


def test_records_carry_start_rule_and_seed():
    masses = [box((0.0, 0.0), 10.0, 10.0, 9.0, seed=3, style=STYLE["dusk"]), box((20.0, 0.0), 10.0, 10.0, 9.0)]
    _, records = batch(masses)
    assert assign_facades(records, masses)["grammar dusk"] == 1
    assert records["facade"][0, 0] == 1 and records["facade"][0, 1] == library_texture().address("dusk")
    assert not records["facade"][1].any()  # the default style keeps the window bays


def test_label_aov_shows_grammar_labels_and_rooms(renderer, output_dir):
    camera = Camera((10.0, 6.0, -18.0), (16.0, 8.0, 7.0), fov_y=60.0)
    ids = renderer.render_ids(camera)
    colour = render_finite(renderer, camera)
    Image.fromarray(colour).save(output_dir / "grammar_city.png")
    grammar_pixels = ids[..., 2] == 1
    labels = {LABELS[v] for v in np.unique(ids[..., 3][grammar_pixels])}
    assert {"wall", "window", "room", "door"} <= labels
    assert not ids[..., 3][ids[..., 2] == 2].any()  # the window-bay building has no grammar labels
    room = grammar_pixels & (ids[..., 3] == LABELS.index("room"))
    assert room.any() and (ids[..., 0][room] != FACE_EXTERIOR).all()  # behind the glass: interior-mapped faces


def test_default_city_uses_grammar_facades():
    city = make_city("default")
    styles = {m.style for m in city.masses}
    assert len(styles & set(BUILDING_STYLES)) >= 5
