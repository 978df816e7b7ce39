"""Building level of detail (shaders/city/lod.glsl): off and on agree where no building is far
enough to switch, the dithered cross-fade does not pop on a camera path moving away, and the
cheapest level's colour is near the full level's mean where they switch."""

from __future__ import annotations

import numpy as np
import pytest

from cityshade.grammar import BUILDING_STYLES
from cityshade.relief import RELIEF_STYLES
from cityshade.render import Renderer, RenderSettings
from cityshade.scene import Camera, City, box, make_city

SIZE = (160, 120)
FOV = 8.0  # a narrow lens: a far building still covers many pixels
BOUNDS = (-60.0, -60.0, 60.0, 60.0)
STYLES = {"window bay": 0, "office grammar": 1}  # facade style codes (grammar.BUILDING_STYLES)
FULL = (1e-3, 9e-4, 5e-4, 4e-4)  # switches far beyond any building: the full level everywhere
CHEAP = (1e6, 9e5, 1e6, 9e5)  # switches nearer than any building: the cheapest level everywhere


def room_pixels(distance: float) -> float:
    """Rows a 4.5 m room spans at `distance` in SIZE with FOV (render._building_lod.room_distance)."""
    return 4.5 * SIZE[1] / (2.0 * np.tan(np.radians(FOV) / 2.0) * distance)


def one_building(style: int, seed: int = 3) -> City:
    return City(
        "lod",
        0,
        [box((-12.0, -4.0), 24.0, 8.0, 30.0, seed=seed, room_width=4.5, floor_height=3.0, style=style)],
        [],
        BOUNDS,
    )


def facade_means(renderer: Renderer, cameras: list[Camera]) -> np.ndarray:
    """Per camera, the mean colour of the building's pixels (the id AOV's building channel)."""
    means = []
    for camera in cameras:
        image = renderer.render(camera).astype(float)
        mask = renderer.render_ids(camera)[..., 2] == 1
        assert mask.sum() > 200, "the building fills part of the view"
        means.append(image[mask].mean(axis=0))
    return np.array(means)


def renderer_for(gl_context, style: int, pixels, seed: int = 3, lights: float = 0.5, **settings) -> Renderer:
    renderer = Renderer(
        SIZE,
        RenderSettings(
            samples=0,
            trees=False,
            shadows=False,
            god_rays=False,
            lights=lights,
            building_lod=True,
            building_lod_pixels=pixels,
            **settings,
        ),
        ctx=gl_context,
    )
    renderer.set_city(one_building(style, seed))
    return renderer


def test_lod_on_and_off_give_the_same_pixels_before_the_first_switch(gl_context):
    city = make_city("default")
    differing = {}
    for view in ("street", "closeup", "corner"):
        camera = city.camera(view)
        # a bound on each building's farthest point: its local origin plus its footprint's reach
        farthest = max(
            np.linalg.norm(np.array([m.position[0], 0.0, m.position[1]]) - camera.eye)
            + np.hypot(np.abs(np.array(m.footprint)).sum(axis=1).max(), m.height)
            for m in city.masses
        )
        pixels = tuple(p / 100.0 for p in RenderSettings().building_lod_pixels)  # rooms 100x smaller on screen
        distance = 4.5 * SIZE[1] / (2.0 * np.tan(np.radians(camera.fov_y) / 2.0) * pixels[0])
        assert farthest < distance, f"{view}: a building at {farthest:.0f} m is beyond the first switch"
        images = [
            Renderer(SIZE, RenderSettings(samples=0, building_lod=on, building_lod_pixels=pixels), ctx=gl_context)
            for on in (True, False)
        ]
        try:
            for r in images:
                r.set_city(city)
            on, off = (r.render(camera) for r in images)
        finally:
            for r in images:
                r.release()
        differing[view] = int(np.count_nonzero(np.any(on != off, axis=-1)))
    assert differing == dict.fromkeys(differing, 0), f"pixels differing with building LOD on: {differing}"


@pytest.mark.parametrize("style", STYLES.values(), ids=STYLES.keys())
def test_moving_away_the_cross_fade_does_not_pop(gl_context, style):
    """A camera backing away from a facade through the cheap level's band in 20 steps: no step
    changes the facade's mean colour by more than half of what the same path's largest step does
    with a hard switch (a band narrower than a step), or, where the two levels agree so well that
    the switch is no larger a step than moving is, than either level's own largest step on the
    path (windows a few pixels wide shift against the pixel grid as the camera moves) or than
    3 of 255 summed over the channels, a step nobody sees."""
    start, end = (
        4.5 * SIZE[1] / (2.0 * np.tan(np.radians(FOV) / 2.0) * p) for p in RenderSettings().building_lod_pixels[2:]
    )
    distances = np.linspace(start - 20.0, end + 20.0, 21)
    cameras = [Camera((0.0, 15.0, -4.0 - d), (0.0, 15.0, 0.0), fov_y=FOV, far=2000.0) for d in distances]
    steps = {}
    for name, pixels in (
        ("cross-fade", RenderSettings().building_lod_pixels),
        ("hard switch", (*RenderSettings().building_lod_pixels[:2], 8.0, 7.995)),
        ("full", FULL),
        ("cheap", CHEAP),
    ):
        renderer = renderer_for(gl_context, style, pixels)
        try:
            means = facade_means(renderer, cameras)
        finally:
            renderer.release()
        steps[name] = np.abs(np.diff(means, axis=0)).sum(axis=1)
    print("largest step of the facade's mean colour:", {k: round(float(v.max()), 2) for k, v in steps.items()})
    assert steps["cross-fade"].max() <= max(
        0.5 * steps["hard switch"].max(), steps["full"].max(), steps["cheap"].max(), 3.0
    )


# every facade of the city: the window bay, the relief bay and each library grammar a building
# style gets (the relief bay takes the styles it shares with a grammar, render/_facades.py)
CITY_STYLES = {
    "window bay": 0,
    "relief bay": RELIEF_STYLES[0],
    **{f"{name} grammar": code for code, name in BUILDING_STYLES.items() if code not in RELIEF_STYLES},
}


@pytest.mark.parametrize("seed", [3, 8])
@pytest.mark.parametrize("style", CITY_STYLES.values(), ids=CITY_STYLES.keys())
def test_the_cheap_level_is_near_the_full_levels_mean(gl_context, style, seed):
    """At the first distance of the cheap band, the cheap level's facade colour against the full
    level's mean over the same pixels: within 12 of 255 per channel (what one step of the
    cross-fade band's 16 dither levels may carry without a visible jump). Two seeds, as a grammar
    makes some choices once per building (the office's spandrels: concrete, dark or light). The
    rooms are dark: the wall colour and the glass share are compared, not which few of the
    building's rooms happen to be lit (a room glows over its whole cell at the cheap level, and
    over the windows a grammar gives it at the full one)."""
    distance = 4.5 * SIZE[1] / (2.0 * np.tan(np.radians(FOV) / 2.0) * RenderSettings().building_lod_pixels[2])
    camera = [Camera((0.0, 15.0, -4.0 - distance), (0.0, 15.0, 0.0), fov_y=FOV, far=2000.0)]
    means = {}
    for name, pixels in (("full", FULL), ("cheap", CHEAP)):
        renderer = renderer_for(gl_context, style, pixels, seed, lights=0.0)
        try:
            means[name] = facade_means(renderer, camera)[0]
        finally:
            renderer.release()
    print("facade mean colour:", {k: v.round(1).tolist() for k, v in means.items()})
    assert np.abs(means["cheap"] - means["full"]).max() < 12.0


def test_the_grammar_reference_evaluates_several_facades_at_once():
    """The cheap colours evaluate every grammar building in one numpy evaluation (start rule,
    facade size, seed and building given per point): the same as one evaluation per facade."""
    from cityshade import assets
    from cityshade.grammar import evaluate, library_texture, seed_vector

    compiled, tiles = library_texture(), assets.tile_array()
    uv = np.random.default_rng(5).random((400, 2)).astype(np.float32) * 12.0
    facades = [
        ("office", (14.0, 30.0), 3, (8, 1, 2, 30.0)),
        ("office", (14.0, 30.0), 8, (8, 1, 2, 30.0)),
        ("classical", (12.5, 18.0), 3, (5, 3, 1, 18.0)),
    ]
    alone = [
        evaluate(compiled, compiled.address(style), uv, size, seed_vector(seed), tiles, building=building)
        for style, size, seed, building in facades
    ]
    per = lambda values: np.repeat(np.array(values), len(uv), axis=0)  # noqa: E731
    together = evaluate(
        compiled,
        per([compiled.address(f[0]) for f in facades]),
        np.tile(uv, (len(facades), 1)),
        per([f[1] for f in facades]),
        per([seed_vector(f[2]) for f in facades]),
        tiles,
        building=per([f[3] for f in facades]),
    )
    for name in ("color", "glass", "label"):
        expected = np.concatenate([np.asarray(getattr(a, name)) for a in alone])
        assert np.array_equal(np.asarray(getattr(together, name)), expected), name
    assert not np.array_equal(np.asarray(alone[0].color), np.asarray(alone[1].color)), "the seeds choose differently"


def test_the_cheap_colours_on_the_gpu_match_the_numpy_reference(gl_context):
    """grammar_colours_gpu (the frame's grammar program over each building's sample face) against
    its numpy twin grammar_colours, building by building of the built-in district's grammar
    buildings: the glass share within 0.002, the linear colour within 0.03 (the GPU blends a
    tile's layers with its coarsest mipmap's alpha, as the frame does far away, where the twin
    keeps the exact alpha; and its mipmaps are box-filtered in 8 bits level by level). Evaluated
    lazily into the city's colours buffer, those buildings hold them, the city's other grammar
    buildings the not-ready marker and the buildings without a grammar zero."""
    from cityshade.render.testing import NOT_READY, grammar_colours, grammar_colours_gpu

    renderer = Renderer((32, 24), RenderSettings(samples=0), ctx=gl_context)
    try:
        renderer.set_city(make_city("default"))
        faces = renderer.city._lod_faces[::7][:40]  # a spread of styles, sizes and seeds
        count = renderer.city.building_count
        gpu = grammar_colours_gpu(gl_context, renderer.textures.grammar, faces)
        lazy = renderer.city.lod_colours()
        lazy.evaluate(renderer.textures.grammar, np.arange(0, len(lazy.faces), 7)[:40])
        held = np.frombuffer(lazy.buffer.read(), np.float32).reshape(-1, 4)
        grammar = renderer.city._lod_faces["building"]
    finally:
        renderer.release()
    reference = grammar_colours(faces, count)
    index = faces["building"]
    difference = np.abs(gpu - reference[index])
    print(f"{len(faces)} buildings: largest difference {difference.max(axis=0).round(4).tolist()} (r, g, b, glass)")
    assert len(np.unique(faces["style"])) > 1 and reference[index, :3].std(axis=0).max() > 0.02
    assert difference[:, 3].max() < 0.002 and difference[:, :3].max() < 0.03
    assert np.array_equal(held[index], gpu)
    waiting = np.setdiff1d(grammar, index)
    assert len(waiting) and np.all(held[waiting, 3] == NOT_READY)
    assert not np.any(held[np.setdiff1d(np.arange(count), grammar)]), "buildings without a sampled face stay zero"


def eager_and_lazy(renderer: Renderer, camera: Camera) -> dict[str, np.ndarray]:
    """The still with the cheap colours evaluated lazily (only those the view needs), then with every
    grammar building's colour evaluated up front."""
    lazy = renderer.city.lod_colours()
    images = {"lazy": renderer.render(camera)}
    evaluated = int(np.count_nonzero(~lazy.pending))
    print(f"the lazy still evaluated {evaluated} of {len(lazy.faces)} grammar buildings' colours")
    assert 0 < evaluated < len(lazy.faces), "the view needs some colours, not all"
    lazy.evaluate(renderer.textures.grammar, np.arange(len(lazy.faces)))
    images["eager"] = renderer.render(camera)
    return images


def test_a_lazy_still_equals_evaluating_every_colour_up_front(gl_context, tmp_path):
    """A still (whole city and streamed) evaluates the colours its view needs before its frame: the
    same picture, pixel for pixel, as every colour evaluated first; and building LOD
    changes the picture there (some buildings are at the cheap level)."""
    from cityshade.render import open_tiles, write_tiles

    city = make_city("default")
    camera = city.camera("street")
    write_tiles(city, tmp_path / "tiles", tile_size=64.0)
    differing, images = {}, {}
    for source in ("whole", "streamed"):
        renderer = Renderer(SIZE, RenderSettings(samples=0, building_lod=True), ctx=gl_context)
        try:
            if source == "whole":
                renderer.set_city(city)
            else:
                cache = open_tiles(tmp_path / "tiles")
                renderer.set_tiles(cache, int(0.9 * cache.total_bytes))  # one tile holds three quarters
                renderer.wait_for_tiles(camera)
                assert not renderer.city.drawn_buildings().all(), "some tiles stay on disk"
            images[source] = eager_and_lazy(renderer, camera)
        finally:
            renderer.release()
        differing[source] = int(np.count_nonzero(np.any(images[source]["lazy"] != images[source]["eager"], axis=-1)))
    print("pixels differing, lazy against eager:", differing)
    assert differing == dict.fromkeys(differing, 0)
    full = Renderer(SIZE, RenderSettings(samples=0, building_lod=False), ctx=gl_context)
    try:
        full.set_city(city)
        shown = np.count_nonzero(np.any(full.render(camera) != images["whole"]["eager"], axis=-1))
    finally:
        full.release()
    assert shown > 100, "the LOD shows"


@pytest.mark.parametrize("deferred", [True, False], ids=["deferred grammar", "forward grammar"])
def test_a_colour_not_evaluated_keeps_the_finer_level(gl_context, deferred):
    """Every pixel in the cheap band (CHEAP) but no colour evaluated (a budget of none per drawn
    frame): the grammar building is drawn as with the cheap band beyond it, pixel for pixel; the
    still, which evaluates its colour, differs (it is at the cheap level)."""
    camera = Camera((0.0, 15.0, -150.0), (0.0, 15.0, 0.0), fov_y=FOV, far=2000.0)
    images = {}
    for name, pixels, budget in (
        ("not ready", CHEAP, 0),
        ("finer", (*CHEAP[:2], *FULL[2:]), 0),
        ("ready", CHEAP, 0),
    ):
        renderer = renderer_for(
            gl_context, STYLES["office grammar"], pixels, building_lod_budget=budget, grammar_deferred=deferred
        )
        try:
            images[name] = renderer.render(camera) if name == "ready" else renderer.draw(camera).read()[..., :3]
            assert renderer.last_lod_colours == (1 if name == "ready" else 0)
        finally:
            renderer.release()
    differing = {
        k: int(np.count_nonzero(np.any(images[k] != images["finer"], axis=-1))) for k in ("not ready", "ready")
    }
    print("pixels differing from the finer level:", differing)
    assert differing["not ready"] == 0 and differing["ready"] > 200


def test_a_negative_budget_is_refused():
    from cityshade.errors import UsageError

    with pytest.raises(UsageError, match="building_lod_budget must be 0 or more, not -1"):
        RenderSettings(building_lod_budget=-1)
