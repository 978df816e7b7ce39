"""Building level of detail: where facades switch to cheaper levels, and the cheapest level's
colours (shaders/city/lod.glsl).

A level is dropped where its detail shrinks below a few pixels: the distance at which a room (one
window bay, ROOM_METRES wide) spans `pixels` rows depends only on the viewport's height and the
vertical field of view, so the switches move out on a bigger image or a narrower lens.
"""

from __future__ import annotations

from dataclasses import replace
from functools import lru_cache

import numpy as np

from .. import assets
from ..assets import TileArray
from ..grammar import BUILDING_STYLES, FACADE_GRAMMAR, evaluate, facade_seed_vector, library_texture, seed_vector
from ..relief import GLASS, MATERIALS, generate_bay
from ..scene import SURFACE_WALL, vertex_face_levels

ROOM_METRES = 4.5  # a room's width on the facade: one window bay
SAMPLE_POINTS = 512  # grammar points per building for its cheap colour (a jittered grid: its mean within ~1%)
SAMPLE_GRID = (32, 16)  # the grid's columns and rows (SAMPLE_POINTS cells, twice as wide as tall)
CHUNK_POINTS = 1 << 15  # points per numpy evaluation


def room_distance(pixels: float, rows: int, fov_y_degrees: float) -> float:
    """The distance at which a room spans `pixels` of a viewport `rows` high."""
    return ROOM_METRES * rows / (2.0 * np.tan(np.radians(fov_y_degrees) / 2.0) * pixels)


def lod_distances(pixels, rows: int, fov_y_degrees: float) -> np.ndarray:
    """(relief start, relief end, cheap start, cheap end) in metres for the ShadingBlock, from the
    pixels a room spans at each (RenderSettings.building_lod_pixels)."""
    return np.array([room_distance(p, rows, fov_y_degrees) for p in pixels])


def _linear(srgb: np.ndarray) -> np.ndarray:
    return np.where(srgb <= 0.04045, srgb / 12.92, ((srgb + 0.055) / 1.055) ** 2.4)


def _wall_mean(albedo: np.ndarray, glass: np.ndarray) -> np.ndarray:
    """(mean linear albedo of the wall around the glass, glass fraction)."""
    wall = ~glass if glass.dtype == bool else 1.0 - glass
    weight = wall.astype(np.float64)
    mean = (albedo * weight[:, None]).sum(0) / max(weight.sum(), 1e-6)
    return np.array([*mean, 1.0 - weight.mean()])


@lru_cache(maxsize=1)
def bay_mean() -> np.ndarray:
    """The window bay texture's wall colour (linear, before the building's tint) and glass share."""
    image, _ = assets.facade_texture()
    pixels = image.reshape(-1, 4).astype(np.float64) / 255.0
    return _wall_mean(_linear(pixels[:, :3]), 1.0 - pixels[:, 3])


# shaders/relief/materials.glsl's palette (sRGB) by MATERIALS index, with the pattern it varies by
# over a facade: (colour, factors) a uniform spread of factors, or brick's (brick, mortar, share)
_RELIEF_FACTORS = np.linspace(0.0, 1.0, 256, endpoint=False) + 0.5 / 256  # the pattern's phase, evenly
_RELIEF_PALETTE = {
    "wall": ((0.78, 0.72, 0.60), np.ones(1)),
    "glass": ((0.10, 0.14, 0.18), np.ones(1)),
    "frame": ((0.85, 0.85, 0.80), np.ones(1)),
    "stone": ((0.62, 0.58, 0.50), 0.92 + 0.08 * _RELIEF_FACTORS),  # a hashed factor per half-metre cell
    "wood": ((0.35, 0.20, 0.10), 0.85 + 0.15 * np.sin(2.0 * np.pi * _RELIEF_FACTORS)),  # grain stripes
}
_BRICK = ((0.55, 0.24, 0.16), (0.70, 0.68, 0.62), 1.0 - (1.0 - 0.06) * (1.0 - 0.12))  # mortar: 6 % across, 12 % up


def _relief_material_means() -> np.ndarray:
    """(len(MATERIALS), 3): each relief material's mean linear albedo over its pattern."""
    means = []
    for name in MATERIALS:
        if name == "brick":
            brick, mortar, share = _BRICK
            means.append((1.0 - share) * _linear(np.array(brick)) + share * _linear(np.array(mortar)))
        else:
            colour, factors = _RELIEF_PALETTE[name]
            means.append(_linear(np.outer(factors, colour)).mean(axis=0))
    return np.array(means)


@lru_cache(maxsize=1)
def relief_mean() -> np.ndarray:
    """The city's relief bay (relief.generate_bay) seen straight on, as the relief level traced
    straight into the wall draws it: the mean linear albedo of its outermost materials around the
    glass (before the building's tint) and the glass share."""
    material = generate_bay().material.ravel()
    albedo = _relief_material_means()[np.where(material < len(MATERIALS), material, 0)]  # others: plaster
    return _wall_mean(albedo, material == GLASS)


def unit_samples() -> np.ndarray:
    """SAMPLE_POINTS points spread over the unit square, row by row of SAMPLE_GRID: one jittered
    point per cell of the grid (a fixed seed), so that no repeat of a facade's pattern aliases
    with the sampling."""
    cols, rows = SAMPLE_GRID
    cell = np.stack(np.meshgrid(np.arange(cols), np.arange(rows)), axis=-1).reshape(-1, 2)
    jitter = np.random.default_rng(11).random(cell.shape)
    return (cell + jitter) / np.array([cols, rows])


@lru_cache(maxsize=1)
def _far_tiles() -> TileArray:
    """The grammar's tiles as the full level samples them where the cheap level takes over: at its
    coarsest mipmap, each colour tile one sRGB mean (the tiles are filtered in sRGB and decoded
    after, shaders/grammar/building.glsl), the alpha that decides glass kept exact."""
    tiles = assets.tile_array()
    layers = tiles.layers.copy()
    colour = layers[0::3]  # usage 1 of each tile (TileArray.plane)
    colour[..., :3] = np.round(colour[..., :3].mean(axis=(1, 2), keepdims=True))
    layers[0::3] = colour
    return replace(tiles, layers=layers)


# grammar_sample_faces's rows: one per grammar building (a Python tuple per building would cost ten times the bytes)
SAMPLE_FACE_DTYPE = np.dtype(
    [
        ("building", "<i4"),
        ("start", "<i4"),
        ("width", "<f8"),
        ("height", "<f8"),
        ("storeys", "<i4"),
        ("style", "<i4"),
        ("seed", "<i8"),
        ("face", "<i4"),
        ("use", "<i4"),
        ("mass_height", "<f8"),
        ("level", "<i4"),
    ]
)


def grammar_sample_faces(masses, records: np.ndarray, vertices: np.ndarray) -> np.ndarray:
    """Per grammar building, the face its cheap colour is taken over: its widest grammar wall face
    (SAMPLE_FACE_DTYPE: building index, start rule, width, height, storeys, style, seed, face index,
    use, height of the mass, facade.level), the storeys and level counted as shaders/grammar/building.glsl does."""
    grammar = np.flatnonzero(records["facade"][:, 0] == FACADE_GRAMMAR)
    walls = vertices[(vertices["ids"][:, 1] == SURFACE_WALL) & np.isin(vertices["ids"][:, 0], grammar)]
    # per building its first vertex on its widest face: a stable sort by building, widest first
    walls = walls[np.lexsort((-walls["face"][:, 0], walls["ids"][:, 0]))]
    buildings, first = np.unique(walls["ids"][:, 0], return_index=True)  # no wall: every face too narrow
    widest = walls[first]
    width, base, top = (widest["face"][:, k].astype(np.float64) for k in range(3))
    faces = np.zeros(len(buildings), SAMPLE_FACE_DTYPE)
    faces["building"] = buildings
    faces["start"] = records["facade"][buildings, 1]
    faces["width"], faces["height"] = width, top - base
    faces["storeys"] = np.floor((top - base) / widest["facade"][:, 3] + 0.5)
    faces["face"] = widest["ids"][:, 2]
    faces["level"] = vertex_face_levels(widest, records)
    chosen = [masses[i] for i in buildings.tolist()]
    faces["style"] = [m.style for m in chosen]
    faces["seed"] = [m.seed for m in chosen]
    faces["use"] = [m.use for m in chosen]
    faces["mass_height"] = [m.extent[1] for m in chosen]
    return faces


def grammar_colours(faces: np.ndarray, count: int) -> np.ndarray:
    """(count, 4) float32: per building, its own grammar's mean wall colour (linear) and glass share
    over its sample face (grammar_sample_faces), evaluated with the numpy reference with the
    building's seed, since a grammar's choices made once per building (an office tower's spandrel
    finish) change its colour more than anything; zero for the buildings without a grammar."""
    colours = np.zeros((count, 4), np.float32)
    if not len(faces):
        return colours
    compiled, tiles, unit = library_texture(), _far_tiles(), unit_samples()
    index = faces["building"]
    start, width, height, storeys, style, seed, face, use, mass_height, level = (
        faces[name] for name in SAMPLE_FACE_DTYPE.names[1:]
    )
    size = np.stack([width, height], axis=1)
    seeds = np.array([facade_seed_vector(int(s), int(k)) for s, k in zip(seed, face)])  # the face's own stream
    building_seeds = np.array([seed_vector(int(s)) for s in seed])  # choices made once per building
    per = len(unit)
    buildings_per_chunk = max(1, CHUNK_POINTS // per)
    for first in range(0, len(index), buildings_per_chunk):  # the evaluation's work arrays grow with its points
        part = slice(first, first + buildings_per_chunk)

        def each(a, part=part):  # per point of the chunk's buildings
            return np.repeat(a[part], per, axis=0)

        uv = (np.tile(unit, (len(index[part]), 1)) * each(size)).astype(np.float32)
        result = evaluate(
            compiled,
            each(start),
            uv,
            each(size),
            each(seeds),
            tiles,
            building=np.stack([each(storeys), each(style), each(use), each(mass_height)], axis=1),
            building_seed=each(building_seeds),
            level=each(level),
        )
        colour = _linear(np.asarray(result.color, np.float64)).reshape(-1, per, 3)
        glass = (np.asarray(result.glass) | (np.asarray(result.hole) >= 0)).reshape(-1, per)  # a hole: a window
        colours[index[part]] = [_wall_mean(c, g) for c, g in zip(colour, glass)]
    return colours


STYLE_FACE = (20.0, 12.0, 4)  # the face a library style's wall colour is taken over: metres wide, high, storeys


@lru_cache(maxsize=1)
def style_wall_colours() -> dict[int, np.ndarray]:
    """Per building style number with a grammar, the mean linear colour of its wall around the glass
    on a STYLE_FACE (seed 0, grammar_colours): what a plain wall or a dormer's front of such a
    building is tinted to (render/_facades.py)."""
    compiled = library_texture()
    faces = np.zeros(len(BUILDING_STYLES), SAMPLE_FACE_DTYPE)
    faces["building"] = np.arange(len(faces))
    faces["start"] = [compiled.address(name) for name in BUILDING_STYLES.values()]
    faces["width"], faces["height"], faces["storeys"] = STYLE_FACE
    faces["style"] = list(BUILDING_STYLES)
    faces["mass_height"] = STYLE_FACE[1]
    colours = grammar_colours(faces, len(faces))
    return {number: colours[k, :3].astype(np.float64) for k, number in enumerate(BUILDING_STYLES)}
