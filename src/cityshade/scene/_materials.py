"""Wall and roof materials of map buildings (OpenStreetMap `building:material`, `roof:material`):
the colour each is painted in unless a colour is tagged, and the roof's shading model in
shaders/city/roof.glsl (the ROOF_* ids there)."""

from __future__ import annotations

import numpy as np

# roof material -> (shading id in roof.glsl, sRGB colour): colours as aerial imagery shows them at
# noon, weathered (bitumen felt reads mid-grey from the air, not black)
ROOF_MATERIALS = {
    "roofing_felt": (0, (0.4, 0.4, 0.41)),
    "roof_tiles": (1, (0.62, 0.27, 0.18)),
    "metal": (2, (0.5, 0.52, 0.55)),
    "slate": (3, (0.28, 0.3, 0.33)),
    "copper": (4, (0.33, 0.6, 0.5)),  # weathered green
    "concrete": (5, (0.6, 0.6, 0.58)),
    "glass": (6, (0.45, 0.55, 0.6)),
    "grass": (7, (0.3, 0.45, 0.2)),
    "wood": (8, (0.45, 0.33, 0.22)),
    "stone": (3, (0.55, 0.53, 0.5)),
    "gravel": (9, (0.5, 0.48, 0.45)),
}
ROOF_ALIASES = {
    "asphalt": "roofing_felt",
    "tar_paper": "roofing_felt",
    "tile": "roof_tiles",
    "tiles": "roof_tiles",
    "clay": "roof_tiles",
    "eternit": "slate",
    "plants": "grass",
    "steel": "metal",
    "tin": "metal",
    "zinc": "metal",
    "aluminium": "metal",
    "thatch": "wood",
    "wood_shingles": "wood",
    "pebblestone": "gravel",
}
# The look of a flat roof whose material and colour the map does not give: chosen building by building
# (by its seed) with these weights, offices, shops and industry more often under light membranes and
# gravel ballast, homes under bitumen felt; (weight for homes and mixed use, weight for the others,
# material, sRGB colour). Every guessed roof's brightness also varies by GUESSED_ROOF_SPREAD.
GUESSED_FLAT_ROOFS = (
    (0.40, 0.20, "roofing_felt", (0.36, 0.36, 0.37)),  # bitumen felt, dark grey
    (0.25, 0.15, "roofing_felt", (0.5, 0.49, 0.47)),  # mineral-surfaced felt, lighter and warmer
    (0.20, 0.30, "gravel", (0.58, 0.56, 0.52)),  # gravel ballast
    (0.10, 0.30, "concrete", (0.74, 0.74, 0.72)),  # a light PVC or TPO membrane
    (0.05, 0.05, "grass", (0.36, 0.46, 0.24)),  # a green roof (sedum)
)
GUESSED_ROOF_SPREAD = 0.12  # +- this share of its colour's brightness, building to building
PLAIN_ROOF = (0, (0.6012, 0.5926, 0.5839))  # untagged roofs of the procedural district: a plain grey

# wall material -> sRGB colour the facade is tinted with
WALL_MATERIALS = {
    "brick": (0.62, 0.32, 0.24),
    "concrete": (0.68, 0.68, 0.66),
    "glass": (0.5, 0.62, 0.7),
    "metal": (0.6, 0.63, 0.66),
    "wood": (0.6, 0.4, 0.28),
    "plaster": (0.9, 0.85, 0.72),
    "stone": (0.74, 0.71, 0.65),
    "sandstone": (0.82, 0.72, 0.55),
    "limestone": (0.85, 0.82, 0.74),
    "timber_framing": (0.85, 0.8, 0.7),
    "steel": (0.6, 0.63, 0.66),
    "cement_block": (0.66, 0.66, 0.64),
}


def linear(colour) -> np.ndarray:
    """sRGB 0..1 -> linear light."""
    c = np.asarray(colour, dtype=np.float64)
    return np.where(c <= 0.04045, c / 12.92, ((c + 0.055) / 1.055) ** 2.4)


def roof_material(name: str | None) -> tuple[int, tuple[float, float, float]]:
    """(shading id, sRGB colour) of a roof material name; none or an unknown one is plain grey."""
    return ROOF_MATERIALS.get(ROOF_ALIASES.get(name, name), PLAIN_ROOF)


def _unit_hash(seed: int, salt: int) -> float:
    """A repeatable number in [0, 1) for a building's seed (golden-ratio mixing of 32-bit integers)."""
    h = (seed * 0x9E3779B1 + salt * 0x85EBCA77) & 0xFFFFFFFF
    h ^= h >> 15
    h = (h * 0x2C1B3C6D) & 0xFFFFFFFF
    h ^= h >> 12
    return (h & 0xFFFF) / 65536.0


def guessed_roof(seed: int, home: bool, flat: bool, material: str | None, colour) -> tuple[str | None, tuple]:
    """(material, sRGB colour) of a roof whose material and colour were guessed: a flat roof one of
    GUESSED_FLAT_ROOFS (weights by use, `home` for homes and mixed use), a pitched one its guessed
    material; the brightness varied by GUESSED_ROOF_SPREAD, both chosen by `seed`."""
    if flat:
        weights = np.array([row[0 if home else 1] for row in GUESSED_FLAT_ROOFS])
        pick = int(np.searchsorted(np.cumsum(weights) / weights.sum(), _unit_hash(seed, 1), side="right"))
        _, _, material, colour = GUESSED_FLAT_ROOFS[min(pick, len(GUESSED_FLAT_ROOFS) - 1)]
    elif colour is None:
        colour = roof_material(material)[1]
    gain = 1.0 + GUESSED_ROOF_SPREAD * (2.0 * _unit_hash(seed, 2) - 1.0)
    return material, tuple(float(min(c * gain, 1.0)) for c in colour)


# building_tint (common/facade.glsl): the window bay's grey wall times the tint times this is the colour
TINT_GAIN = 1.6


def wall_tint(colour, material: str | None):
    """The sRGB colour a facade is tinted with: the tagged colour, else the material's, else None."""
    if colour is not None:
        return tuple(colour)
    return WALL_MATERIALS.get(material)


(
    ROOF_PLAIN,
    ROOF_TILES,
    ROOF_METAL,
    ROOF_SLATE,
    ROOF_COPPER,
    ROOF_CONCRETE,
    ROOF_GLASS,
    ROOF_GRASS,
    ROOF_WOOD,
    ROOF_GRAVEL,
) = range(10)
# roof.glsl's pattern ids (cityshade.shader_constants)
ROOF_PATTERNS = {
    name: value for name, value in globals().items() if name.startswith("ROOF_") and isinstance(value, int)
}


# What part of a roof a triangle is (scene vertex ids[:, 2] of roof rows): the roof's own surface in
# its tagged material, or sheet metal (rooftop units, dormer cheeks) of one colour whatever the roof.
ROOF_PART_SURFACE, ROOF_PART_SHEET = 0, 1
SHEET_METAL = (0.62, 0.63, 0.64)  # sRGB: galvanised steel
ROOF_PARTS = {
    "ROOF_PART_SURFACE": ROOF_PART_SURFACE,
    "ROOF_PART_SHEET": ROOF_PART_SHEET,
    "ROOF_SHEET_ALBEDO": "vec3({:.6f}, {:.6f}, {:.6f})".format(*linear(SHEET_METAL)),
}


def roof_part_material(part: int, roof) -> tuple[np.ndarray, int]:
    """numpy twin of roof_part_material() in roof.glsl: (linear albedo, pattern id) of a roof part
    on a building whose record's roof is `roof` (linear rgb, pattern id)."""
    if part == ROOF_PART_SHEET:
        return np.float32(linear(SHEET_METAL)), ROOF_METAL
    return np.asarray(roof[:3], np.float32), int(roof[3])


def _smoothstep(e0: float, e1: float, x: np.ndarray) -> np.ndarray:
    t = np.clip((x - np.float32(e0)) / np.float32(e1 - e0), 0, 1).astype(np.float32)
    return t * t * (np.float32(3) - np.float32(2) * t)


def _fract(x: np.ndarray) -> np.ndarray:
    return x - np.floor(x)


def _stone(cx: np.ndarray, cy: np.ndarray) -> np.ndarray:
    """A stone's own shade, 0..1, from its integer cell (an avalanche hash in uint32, as stone() in roof.glsl)."""
    with np.errstate(over="ignore"):
        h = (cx.astype(np.int64).astype(np.uint32) * np.uint32(0x9E3779B1)) ^ (
            cy.astype(np.int64).astype(np.uint32) * np.uint32(0x85EBCA77)
        )
        h ^= h >> np.uint32(15)
        h *= np.uint32(0x2C1B3C6D)
        h ^= h >> np.uint32(12)
    return (h & np.uint32(255)).astype(np.float32) / np.float32(255)


def roof_pattern(material: int, local: np.ndarray, normal) -> np.ndarray:
    """numpy twin of roof_pattern() in shaders/city/roof.glsl, in float32: (n, 4) of the albedo
    factor (rgb) and the sky reflectance f0 (a) at object-space points `local` (n, 3) of a roof
    facing the unit `normal`."""
    f = np.float32
    local = np.asarray(local, dtype=f)
    n = np.asarray(normal, dtype=f)
    slope = np.sqrt(n[0] * n[0] + n[2] * n[2])
    down = np.array([n[0], n[2]], dtype=f) / slope if slope > 1e-3 else np.array([0, 1], dtype=f)
    s = (local[:, 0] * down[0] + local[:, 2] * down[1]) / max(n[1], f(0.2))
    t = local[:, 0] * -down[1] + local[:, 2] * down[0]
    cx, cy = np.floor(s / f(0.3)).astype(np.int64), np.floor(t / f(0.3)).astype(np.int64)
    cell = ((cx * 7 + cy * 13 + 500000) % 5).astype(f) / f(4)
    out = np.zeros((len(local), 4), dtype=f)
    if material == ROOF_TILES:
        row = _fract((s + f(0.5) * np.floor(t / f(0.25))) / f(0.33))
        out[:, :3] = (f(0.7) + f(0.3) * _smoothstep(0.0, 0.25, row) + f(0.08) * (cell - f(0.5)))[:, None]
    elif material == ROOF_SLATE:
        row = _fract(s / f(0.22))
        out[:, :3] = (f(0.8) + f(0.2) * _smoothstep(0.0, 0.15, row) + f(0.12) * (cell - f(0.5)))[:, None]
        out[:, 3] = 0.04
    elif material in (ROOF_METAL, ROOF_COPPER):
        seam = _smoothstep(0.0, 0.04, np.abs(_fract(t / f(0.55)) - f(0.5)) - f(0.44))
        out[:, :3] = (f(1) - f(0.35) * seam)[:, None]
        out[:, 3] = 0.25 if material == ROOF_METAL else 0.1
    elif material == ROOF_GLASS:
        out[:] = (0.6, 0.6, 0.6, 0.5)
    elif material == ROOF_GRAVEL:
        fine = _stone(np.floor(s / f(0.04)).astype(np.int64), np.floor(t / f(0.04)).astype(np.int64))
        coarse = _stone(np.floor(s / f(0.13)).astype(np.int64) + 7919, np.floor(t / f(0.13)).astype(np.int64))
        out[:, :3] = (f(0.8) + f(0.35) * fine + f(0.15) * coarse)[:, None] - f(0.25)
    elif material in (ROOF_GRASS, ROOF_CONCRETE, ROOF_WOOD):
        out[:, :3] = (f(0.85) + f(0.3) * (cell - f(0.5)))[:, None]
    else:
        out[:, :3] = 1.0
    return out
