"""Checks every render test applies: colours are finite (a NaN clipped to 0 or 255 looks like a
dark or bright pixel, so the 8-bit picture cannot show it); and the edges of a twin's id picture,
the only pixels where a GPU id may differ from its twin's."""

import numpy as np


def assert_finite(colour: np.ndarray, what: str):
    bad = ~np.isfinite(colour).all(axis=-1)
    assert not bad.any(), (
        f"{what}: {int(bad.sum())} pixels are not finite (first at row, column {tuple(np.argwhere(bad)[0])})"
    )


def render_finite(renderer, camera) -> np.ndarray:
    """renderer.render(camera), after checking that the frame's HDR colour is finite."""
    image = renderer.render(camera)
    assert_finite(renderer.read_hdr(), f"HDR frame of {renderer.city.city.name if renderer.city else 'no city'}")
    return image


def key_edges(key: np.ndarray) -> np.ndarray:
    """Pixels whose 3x3 neighbourhood holds another value of `key` (H, W): where a ray grazes an
    edge and two tracers may pick either side. Built from one picture (the twin's) alone, so a
    false answer of the other is never excused elsewhere."""
    padded = np.pad(key, 1, mode="edge")
    h, w = key.shape
    return np.any(
        [padded[1 + dy : 1 + dy + h, 1 + dx : 1 + dx + w] != key for dy in (-1, 0, 1) for dx in (-1, 0, 1)], axis=0
    )


def id_edges(ids: np.ndarray) -> np.ndarray:
    """key_edges of the id AOV's (face, room, building)."""
    return key_edges(
        ids[..., 0].astype(np.int64) << 48 ^ ids[..., 1].astype(np.int64) << 8 ^ ids[..., 2].astype(np.int64)
    )


def hit_edges(hits) -> np.ndarray:
    """key_edges of relief hits' (material, face); a miss (material -1) is a surface of its own."""
    return key_edges(np.where(hits.material < 0, -1, hits.material * 8 + hits.face))


def style_face_labels(style: str, size, seed: int, face: int, level: int, building=(0, 0, 0, 0)) -> np.ndarray:
    """The twin's labels of library style `style` on a grid of points over a face of `size` metres
    at facade.level `level` (facade `face` of a building of seed `seed`)."""
    from cityshade.assets import tile_array
    from cityshade.grammar import evaluate, facade_seed_vector, library_texture, seed_vector

    compiled = library_texture()
    u, v = np.meshgrid(np.linspace(0.05, size[0] - 0.05, 400), np.linspace(0.05, size[1] - 0.05, 40))
    return evaluate(
        compiled,
        compiled.address(style),
        np.stack([u.ravel(), v.ravel()], axis=1),
        size,
        facade_seed_vector(seed, face),
        tile_array(16),
        building=building,
        building_seed=seed_vector(seed),
        level=level,
    ).label


def style_min_width(style: str):
    """The narrowest face a library style fits, as a function of the face's facade.level (GrammarFacades)."""
    from cityshade.grammar import library_min_widths

    return lambda level: library_min_widths(level)[style]


def grammar_facades(masses):
    """The twin's GrammarFacades of `masses`: the library, each grammar building's start rule and the
    narrowest face its style fits, as the renderer assigns them, and the relief atlas that recesses
    their windows (relief is on by default)."""
    from cityshade import assets
    from cityshade.grammar import FACADE_GRAMMAR, library_texture
    from cityshade.interior import GrammarFacades
    from cityshade.relief import relief_atlas
    from cityshade.render import assign_facades, choose_facade
    from cityshade.scene import batch

    _, records = batch(masses)
    assign_facades(records, masses)
    starts = {i: int(rec["facade"][1]) for i, rec in enumerate(records) if rec["facade"][0] == FACADE_GRAMMAR}
    widths = {i: style_min_width(choose_facade(masses[i]).grammar_style) for i in starts}
    return GrammarFacades(library_texture(), assets.tile_array(), starts, widths, relief_atlas())


def interior_params(renderer, lights=None):
    """The twin's InteriorParams for what `renderer` draws: its settings' share of lit rooms (or
    `lights`) and animation time, and its textures' room variants and glass rectangle."""
    from cityshade import assets
    from cityshade.interior import InteriorParams

    s = renderer.settings
    return InteriorParams(
        lights=s.lights if lights is None else lights,
        time=s.animation_time,
        variants=renderer.textures.room_variants,
        glass_rect=renderer.textures.glass_rect,
        sprite_alpha=assets.furniture_sprites()[..., 3] / 255.0,
    )


def grammar_test_settings(grammar_file, start: str, path: str, **extra):
    """Settings that draw every grammar facade with the grammar `start` of `grammar_file` (compiled
    after the library), lit at midday with no trees, shadows or rooms, by `path` (forward or deferred)."""
    from cityshade.render import RenderSettings

    return RenderSettings(
        trees=False,
        shadows=False,
        god_rays=False,
        interior_mapping=False,
        time_of_day=13.0,
        grammar_deferred=path == "deferred",
        grammar_files=(str(grammar_file),),
        grammar_start=start,
        **extra,
    )


def interior_twin(renderer, masses, camera, size, bounds, lights=None, grammar=None, labels=False) -> np.ndarray:
    """The numpy twin's id AOV with room state (cityshade.interior.reference_ids) of `masses` standing
    on a city of `bounds`, with the renderer's frame settings and textures; `lights` (one share, or
    one per use) replaces the settings' share of lit rooms; `grammar` (grammar_facades) evaluates
    the grammar facades, and with `labels` the fourth channel is the grammar label. The window bay's
    windows are recessed near the eye when the settings have relief on (their default)."""
    from cityshade import assets
    from cityshade.interior import reference_ids
    from cityshade.relief import relief_atlas
    from cityshade.render.testing import GROUND_MARGIN

    s = renderer.settings
    params = interior_params(renderer, lights)
    x0, z0, x1, z1 = bounds
    ground = (x0 - GROUND_MARGIN, z0 - GROUND_MARGIN, x1 + GROUND_MARGIN, z1 + GROUND_MARGIN)
    alpha = assets.facade_texture()[0][..., 3] / 255.0
    bay_relief = relief_atlas() if s.relief else None  # the window bay's windows recessed, as the renderer's
    return reference_ids(
        masses, camera, size, params, alpha, ground, grammar=grammar, labels=labels, window_bay_relief=bay_relief
    )
