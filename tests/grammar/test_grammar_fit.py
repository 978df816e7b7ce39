"""Bad input: a grammar that cannot fit a face (the face is narrower than its fixed-size parts
need) degrades to a plain wall with a counted warning: no stretched or garbage facade, no crash."""

from __future__ import annotations

import numpy as np
import pytest

from cityshade.assets import LABELS
from cityshade.grammar import BUILDING_STYLES, library_min_widths, loads, min_width
from cityshade.interior.testing import FACE_EXTERIOR
from cityshade.render import GrammarFitWarning, Renderer, RenderSettings, assign_facades
from cityshade.render.testing import NARROW_FACES
from cityshade.scene import SURFACE_PLAIN_WALL, Camera, City, batch, box

STYLE = {name: number for number, name in BUILDING_STYLES.items()}


def test_the_narrowest_face_is_the_fixed_parts_side_by_side():
    grammar = loads("""
F->SplitY(Abs, 3, G, Rel, 1, U)
G->SplitX(Rel, 1, Bays, Abs, 2.4, Door, Rel, 1, Bays)
U->RepeatX(3, Bay)
Bays->RepeatX(3, Bay)
Bay->SplitX(Rel, 1, Wall, Abs, 1.3, Window, Rel, 1, Wall)
Door->Mat(Color, Fit>door1, 0, 0, 1, 1)
Window->Mat(Color, Fit>window1, 0, 0, 1, 1)
Wall->Mat(Color, Rep:wall1, 0, 0, 1, 1)
""")
    assert min_width(grammar) == pytest.approx(1.3 + 2.4 + 1.3)  # a window bay each side of the door
    assert library_min_widths()["brick"] == pytest.approx(5.0)  # the same layout: door 2.4 m, windows 1.3 m


def test_faces_too_narrow_for_the_grammar_are_plain_walls_with_a_counted_warning(gl_context):
    masses = [box((0.0, 0.0), 3.0, 14.0, 12.0, seed=4, style=STYLE["brick"])]  # 3 m ends, 14 m sides
    vertices, records = batch(masses)
    with pytest.warns(GrammarFitWarning, match="2 wall faces are narrower"):
        counts = assign_facades(records, masses, vertices)
    assert counts[NARROW_FACES] == 2
    plain = vertices["ids"][:, 1] == SURFACE_PLAIN_WALL
    walls = vertices["ids"][:, 1] == 0
    assert np.allclose(vertices["face"][plain, 0], 3.0) and np.allclose(vertices["face"][walls, 0], 14.0)

    r = Renderer((96, 72), RenderSettings(lights=0.7), ctx=gl_context)
    with pytest.warns(GrammarFitWarning):
        r.set_city(City("narrow", 0, masses, [], (-30.0, -30.0, 30.0, 30.0)))
    try:
        end = r.render_ids(Camera((1.5, 6.0, -12.0), (1.5, 6.0, 7.0), fov_y=50.0))  # the 3 m end, face on
        side = r.render_ids(Camera((-16.0, 6.0, 7.0), (0.0, 6.0, 7.0), fov_y=60.0))  # a 14 m side
    finally:
        r.release()
    on_end, on_side = end[..., 2] == 1, side[..., 2] == 1
    assert on_end.sum() > 200 and on_side.sum() > 200
    assert not end[..., 3][on_end].any() and (end[..., 0][on_end] == FACE_EXTERIOR).all()  # no labels, no glass
    labels = {LABELS[v] for v in np.unique(side[..., 3][on_side])}
    assert {"wall", "window", "room"} <= labels


def test_plain_walls_take_the_grammars_wall_colour_not_the_buildings_tint(gl_context):
    """Two brick-style boxes with a saturated mapped colour (which the grammar does not show), both
    facing south: the 3 m plain end of one looks like the grammar's wall on the other's 14 m side
    (chromaticity in linear light within 0.06: plain walls take the style's wall colour, and a
    building's own seed moves its grammar's tone by about 0.05), not like the mapped colour (0.3 off)."""
    from dataclasses import replace

    from cityshade.interior.testing import FACE_EXTERIOR

    red = (0.6, 0.27, 0.2)
    masses = [
        replace(box((0.0, 0.0), 3.0, 14.0, 12.0, seed=4, style=STYLE["brick"]), wall_colour=red),  # a 3 m end south
        replace(box((8.0, 11.0), 14.0, 3.0, 12.0, seed=4, style=STYLE["brick"]), wall_colour=red),  # a 14 m side south
    ]
    r = Renderer((160, 120), RenderSettings(time_of_day=11.0, trees=False, god_rays=False), ctx=gl_context)
    with pytest.warns(GrammarFitWarning):
        r.set_city(City("narrow", 0, masses, [], (-30.0, -30.0, 40.0, 40.0)))
    try:
        camera = Camera((11.0, 6.0, 40.0), (11.0, 6.0, 14.0), fov_y=50.0)
        ids = r.render_ids(camera)
        r.render(camera)
        hdr = r.read_hdr().astype(np.float64)
    finally:
        r.release()
    plain = (ids[..., 2] == 1) & (ids[..., 0] == FACE_EXTERIOR) & (ids[..., 3] == 0)
    wall = (ids[..., 2] == 2) & (ids[..., 3] == LABELS.index("wall"))
    chroma = [hdr[m].mean(axis=0) / hdr[m].mean(axis=0).sum() for m in (plain, wall)]
    print(
        f"plain pixels {plain.sum()} chromaticity {np.round(chroma[0], 3)}, grammar wall {wall.sum()} {np.round(chroma[1], 3)}"
    )
    assert plain.sum() > 200 and wall.sum() > 200
    assert np.abs(chroma[0] - chroma[1]).max() < 0.06
