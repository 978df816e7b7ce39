"""Grammar facades baked into texture atlases (glTF PBR maps), on the GPU with a numpy twin.

The renderer evaluates a building's grammar per pixel in the true size of the wall face it is on
(shaders/grammar/building.glsl: the face's width, base and top; a curved run of walls and each ring
of a dome is one face), so each face gets a canvas of its own, evaluated with the same scope, seed
and building values. A canvas covers the face's facade coordinates plus one texel of border (so
filtering never reads a neighbour), at `texel` metres per texel. Canvases are packed into atlas
pages; each page gives a base colour, a metallic-roughness, a normal and an emissive image: the
windows lit at NIGHT_HOUR, by each building's use as the renderer's clock lights them
(scene.lit_share); by day none glows.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from ..errors import UsageError
from ..grammar import (
    BUILDING_STYLES,
    FACADE_INDICES,
    GRAMMAR_SHAPES,
    evaluate,
    facade_seed_vector,
    library_texture,
    seed_cells,
    seed_vector,
)
from ..scene import SHAPES, face_levels, lit_share

PAGE = 2048  # texels: the side of an ordinary atlas page
ATLAS_LIMIT = 8192  # texels: the largest texture side every desktop and web GPU of the last decade loads
MAX_TEXELS = 1 << 28  # all pages together (about 1 GiB of RGBA): more would not fit in memory
STRIP = 512  # rows baked per GPU pass (bounds the render target's memory)
NIGHT_HOUR = 21.0  # the night variant's clock: homes and mixed blocks mostly lit, offices nearly dark
LIT_COLOUR = np.array([255, 196, 120], np.uint8)


@dataclass
class Canvas:
    """One wall face of one building's facade in an atlas page (positions in texels, GL rows: 0 at the bottom)."""

    building: int
    side: int  # the facade index of its walls: their face's first room column (0 for a round wall)
    u0: float  # facade coordinates (metres) at the canvas' lower-left corner
    v0: float
    cols: int
    rows: int
    width: float  # the grammar's scope: the face's width, and its height from its base to its top
    height: float
    start: int  # the grammar's start rule
    seed: tuple[float, float]  # this facade's seed vector
    building_seed: tuple[float, float]  # the building's (choices made once per building)
    room: tuple[float, float]  # room width, storey height (which windows are lit)
    lights: float
    level: int = 0  # facade.level: the storey the face starts at (the mass's first level; a dome's ring's)
    page: int = -1
    x: int = 0
    y: int = 0
    base: float = 0.0  # the face's base: facade v where the grammar's scope starts
    values: tuple[float, float, float, float] = (0.0, 0.0, 0.0, 0.0)  # building.levels, .style, .use, .height


@dataclass
class Atlas:
    """Baked pages: (rows, cols, 3 or 4) uint8 images, row 0 at the top as glTF reads them."""

    canvases: list[Canvas]
    sizes: list[tuple[int, int]]  # (cols, rows) per page
    base_colour: list[np.ndarray]
    metallic_roughness: list[np.ndarray]
    normal: list[np.ndarray]
    emissive: list[np.ndarray]


def has_grammar(mass) -> bool:
    return mass.style in BUILDING_STYLES and mass.shape in GRAMMAR_SHAPES


def wall_sides(walls: np.ndarray) -> np.ndarray:
    """The canvas of each wall vertex (scene.VERTEX_DTYPE records): its face, as the renderer scopes
    the grammar (face width, base, top) and picks the facade's random stream (the face's first room
    column); an index into canvases_of's list."""
    keys = np.column_stack([walls["face"][:, :3].astype(np.float64), walls["ids"][:, 2]])
    return np.unique(keys, axis=0, return_inverse=True)[1].ravel()


def canvases_of(index: int, mass, walls: np.ndarray, texel: float) -> list[Canvas]:
    """The canvases of one grammar building, one per wall face, from its grammar walls
    (scene.VERTEX_DTYPE records; plain walls and dormer fronts left out), in wall_sides' order."""
    compiled = library_texture()
    start = compiled.address(BUILDING_STYLES[mass.style])
    sides = wall_sides(walls)
    room = mass.room_size
    out = []
    for side in range(int(sides.max()) + 1 if len(sides) else 0):
        on_face = walls[sides == side]
        facade = on_face["facade"].astype(np.float64)
        width, base, top = (float(x) for x in on_face["face"][0, :3])
        lo, hi = facade[:, :2].min(axis=0) - texel, facade[:, :2].max(axis=0) + texel
        cols, rows = (int(np.ceil(v)) for v in (hi - lo) / texel)
        levels = np.floor((top - base) / float(facade[0, 3]) + 0.5)  # as grammar_levels
        column = int(on_face["ids"][0, 2])
        out.append(
            Canvas(
                index,
                column,
                float(lo[0]),
                float(lo[1]),
                max(cols, 1),
                max(rows, 1),
                width,
                top - base,
                start,
                facade_seed_vector(mass.seed, column),
                seed_vector(mass.seed),
                (float(room[0]), float(room[1])),
                float(mass.lights),
                int(face_levels(mass.first_level, SHAPES[mass.shape], base, facade[0, 3])),
                base=base,
                values=(float(levels), float(mass.style), float(mass.use), float(mass.extent[1])),
            )
        )
    return out


def face_extents(walls: np.ndarray) -> np.ndarray:
    """(faces, 2) metres each wall face spans in facade u and v, in wall_sides' order (the canvas
    of a face at texel t is ceil(extent / t) + 2 texels a side: canvases_of's one-texel border)."""
    sides = wall_sides(walls)
    facade = walls["facade"][:, :2].astype(np.float64)
    count = int(sides.max()) + 1 if len(sides) else 0
    lo = np.full((count, 2), np.inf)
    hi = np.full((count, 2), -np.inf)
    np.minimum.at(lo, sides, facade)
    np.maximum.at(hi, sides, facade)
    return hi - lo


def _fits(extents: np.ndarray, texel: float) -> bool:
    sides = np.maximum(np.ceil((extents + 2 * texel) / texel), 1.0)  # as canvases_of
    return bool(sides.max() <= ATLAS_LIMIT and np.prod(sides, axis=1).sum() <= MAX_TEXELS)


def finest_texel(extents: np.ndarray, finest: float) -> float:
    """The smallest texel size, no smaller than `finest` and rounded up to 3 significant digits,
    at which faces of these extents fit the atlas limits (the side and the total of check_size)."""
    if not len(extents) or _fits(extents, finest):
        return finest
    lo, hi = finest, finest * 2
    while not _fits(extents, hi):
        lo, hi = hi, hi * 2
    for _ in range(40):  # fitting only gets easier as texels grow: bisect in log space
        mid = float(np.sqrt(lo * hi))
        lo, hi = (lo, mid) if _fits(extents, mid) else (mid, hi)
    texel = largest_fitting_texel(hi, 1.0)
    while not _fits(extents, texel):  # rounding up keeps it fitting; this guards the arithmetic
        texel = largest_fitting_texel(texel, 1.001)
    return texel


def largest_fitting_texel(texel: float, ratio: float) -> float:
    """The smallest texel size (3 significant digits, rounded up) at least texel * ratio."""
    value = texel * ratio
    scale = 10 ** (np.floor(np.log10(value)) - 2)
    return float(np.ceil(value / scale) * scale)


def check_size(canvases: list[Canvas], texel: float):
    """One line naming the texel size that fits when a canvas or the whole atlas is too large."""
    if not canvases:
        return
    widest = max(max(c.cols, c.rows) for c in canvases)
    if widest > ATLAS_LIMIT:  # a canvas is ceil(extent / texel) + 2 margin texels a side
        raise UsageError(
            f"--texel {texel:g}: a facade needs a {widest}-texel atlas side, over the "
            f"{ATLAS_LIMIT}-texel GPU limit; use --texel {largest_fitting_texel(texel, (widest - 2) / (ATLAS_LIMIT - 2)):g} or more"
        )
    total = sum(c.cols * c.rows for c in canvases)
    if total > MAX_TEXELS:
        raise UsageError(
            f"--texel {texel:g}: the facades need {total:,} atlas texels, over the limit of "
            f"{MAX_TEXELS:,}; use --texel {largest_fitting_texel(texel, np.sqrt(total / MAX_TEXELS) * 1.05):g} or more"
        )


def pack(canvases: list[Canvas]) -> list[tuple[int, int]]:
    """Shelf packing, tallest first, into PAGE-wide pages (a canvas larger than PAGE gets a page of
    its own); sets each canvas' page and position; returns each page's (cols, rows)."""
    sizes: list[list[int]] = []
    shelf = None  # (page, y, height, x)
    for canvas in sorted(canvases, key=lambda c: (-c.rows, -c.cols)):
        if canvas.cols > PAGE or canvas.rows > PAGE:
            canvas.page, canvas.x, canvas.y = len(sizes), 0, 0
            sizes.append([canvas.cols, canvas.rows])
            continue
        if shelf is not None and shelf[3] + canvas.cols > PAGE:
            page, y, height, _ = shelf
            shelf = (page, y + height, canvas.rows, 0) if y + height + canvas.rows <= PAGE else None
        if shelf is None:
            sizes.append([0, 0])
            shelf = (len(sizes) - 1, 0, canvas.rows, 0)
        page, y, height, x = shelf
        canvas.page, canvas.x, canvas.y = page, x, y
        shelf = (page, y, height, x + canvas.cols)
        sizes[page][0] = max(sizes[page][0], x + canvas.cols)
        sizes[page][1] = max(sizes[page][1], y + canvas.rows)
    # sides a multiple of 4: RGB rows stay 4-byte aligned for loaders that upload them as they are
    return [(-(-w // 4) * 4, -(-h // 4) * 4) for w, h in sizes]


def texel_grid(canvas: Canvas, texel: float) -> np.ndarray:
    """(rows, cols, 2) facade coordinates of the canvas' texel centres, GL row order (bottom first)."""
    u = canvas.u0 + (np.arange(canvas.cols) + 0.5) * texel
    v = canvas.v0 + (np.arange(canvas.rows) + 0.5) * texel
    return np.stack(np.meshgrid(u, v), axis=-1)


def lit_rooms(canvas: Canvas, texel: float, hours: float = NIGHT_HOUR) -> np.ndarray:
    """(rows, cols) bool: texels in rooms whose light is on at `hours`: a hash of building, side, bay
    and storey below the share of its use lit then times the building's own `lights`."""
    grid = texel_grid(canvas, texel)
    room = np.floor(grid / np.asarray(canvas.room)).astype(np.int64)
    key = (canvas.building * FACADE_INDICES + canvas.side) * 1_000_003 + room[..., 0] * 7919 + room[..., 1] * 104_729
    h = seed_cells(key.ravel() & 0x7FFFFFFF)
    value = (h[:, 0] * 2048 + h[:, 1]) / float(1 << 22)
    share = lit_share(int(canvas.values[2]), hours) * canvas.lights
    return (value < share).reshape(room.shape[:2])


def bake_reference(canvas: Canvas, texel: float, tiles) -> dict[str, np.ndarray]:
    """The numpy twin of shaders/export/bake.glsl with GRAMMAR_NEAREST: (rows, cols, ...) arrays, bottom row first."""
    grid = texel_grid(canvas, texel).reshape(-1, 2)
    uv = np.stack([canvas.width - grid[:, 0], grid[:, 1] - canvas.base], axis=1)
    result = evaluate(
        library_texture(),
        canvas.start,
        uv,
        (canvas.width, canvas.height),
        canvas.seed,
        tiles,
        building=canvas.values,
        building_seed=canvas.building_seed,
        level=canvas.level,
    )
    shape = (canvas.rows, canvas.cols)
    return {
        "colour": np.concatenate([result.color, result.specular[:, :1]], axis=1).reshape(*shape, 4),
        "normal": np.concatenate([result.normal, result.specular[:, 1:]], axis=1).reshape(*shape, 4),
        "ids": np.stack(
            [result.terminal + 1, result.label, result.glass.astype(np.int32), np.zeros_like(result.label)], axis=1
        )
        .reshape(*shape, 4)
        .astype(np.uint32),
    }


class GpuBaker:
    """Renders canvases with shaders/export/bake.glsl into float targets, STRIP rows at a time."""

    def __init__(self, ctx, tiles, nearest: bool = False):
        from ..gl import programs
        from ..grammar import GrammarTextures, shader_defines

        self.ctx = ctx
        self.textures = GrammarTextures(ctx, library_texture(), tiles)
        self.program = programs(ctx).get("export/bake.glsl", shader_defines(nearest))

    def bake_page(self, canvases: list[Canvas], size: tuple[int, int], texel: float) -> dict[str, np.ndarray]:
        """(rows, cols, 4) colour, normal (float32) and ids (uint32) of one page, bottom row first."""
        import moderngl

        from ..gl import RenderTarget, draw_fullscreen

        cols, rows = size
        out = {
            "colour": np.zeros((rows, cols, 4), np.float32),
            "normal": np.zeros((rows, cols, 4), np.float32),
            "ids": np.zeros((rows, cols, 4), np.uint32),
        }
        target = RenderTarget(self.ctx, (cols, min(rows, STRIP)), colors=(("f4", 4), ("f4", 4), ("u4", 4)))
        try:
            self.ctx.disable(moderngl.DEPTH_TEST)
            self.textures.bind(self.program)
            self.program["texel"] = float(texel)
            for y0 in range(0, rows, STRIP):
                target.use()
                target.fbo.clear()
                height = min(STRIP, rows - y0)
                for c in canvases:
                    if c.y >= y0 + height or c.y + c.rows <= y0:
                        continue
                    self.ctx.viewport = (c.x, c.y - y0, c.cols, c.rows)
                    self.program["canvas_origin"] = (float(c.x), float(c.y - y0))
                    self.program["facade_origin"] = (c.u0, c.v0 - c.base)
                    self.program["facade_size"] = (c.width, c.height)
                    self.program["building_values"] = c.values
                    self.program["facade_seed"] = c.seed
                    self.program["building_seed"] = c.building_seed
                    self.program["start_rule"] = int(c.start)
                    self.program["facade_level"] = float(c.level)
                    draw_fullscreen(self.program)
                for name, texture in zip(("colour", "normal", "ids"), target.colors):
                    dtype = np.uint32 if name == "ids" else np.float32
                    data = np.frombuffer(texture.read(), dtype).reshape(-1, cols, 4)
                    out[name][y0 : y0 + height] = data[:height]
        finally:
            target.release()
        return out

    def release(self):
        self.textures.release()  # the program stays in the context's cache


def _encode(page: dict[str, np.ndarray], canvases: list[Canvas], texel: float):
    """Float results of one page -> glTF images (row 0 at the top)."""
    colour, normal, ids = page["colour"], page["normal"], page["ids"]
    base = (np.clip(colour[..., :3], 0, 1) * 255 + 0.5).astype(np.uint8)
    # Phong shininess -> GGX roughness (alpha = sqrt(2 / (n + 2)), roughness = sqrt(alpha)); dielectric
    shininess = 1.0 + 128.0 * normal[..., 3]
    roughness = np.sqrt(np.sqrt(2.0 / (shininess + 2.0)))
    mr = np.zeros(base.shape, np.uint8)
    mr[..., 1] = (np.clip(roughness, 0, 1) * 255 + 0.5).astype(np.uint8)
    # the tangent frame's x runs along mesh u, opposite to the grammar's right (mesh u is mirrored)
    n = normal[..., :3] * np.array([-1.0, 1.0, 1.0], np.float32)
    n /= np.maximum(np.linalg.norm(n, axis=-1, keepdims=True), 1e-6)
    n[np.all(normal[..., :3] == 0, axis=-1)] = (0.0, 0.0, 1.0)
    normal_image = ((n * 0.5 + 0.5) * 255 + 0.5).astype(np.uint8)
    emissive = np.zeros(base.shape, np.uint8)
    glass = ids[..., 2] == 1
    for c in canvases:
        rows, cols = slice(c.y, c.y + c.rows), slice(c.x, c.x + c.cols)
        lit = lit_rooms(c, texel) & glass[rows, cols]
        emissive[rows, cols][lit] = LIT_COLOUR
    return base[::-1], mr[::-1], normal_image[::-1], emissive[::-1]


def bake_atlas(canvases: list[Canvas], texel: float) -> Atlas:
    """Packs and bakes every canvas (one GL context, created here)."""
    sizes = pack(canvases)
    atlas = Atlas(canvases, sizes, [], [], [], [])
    if not canvases:
        return atlas
    from ..assets import tile_array
    from ..gl import create_context

    ctx = create_context()
    baker = GpuBaker(ctx, tile_array(128))
    try:
        for page, size in enumerate(sizes):
            on_page = [c for c in canvases if c.page == page]
            images = _encode(baker.bake_page(on_page, size, texel), on_page, texel)
            for store, image in zip(
                (atlas.base_colour, atlas.metallic_roughness, atlas.normal, atlas.emissive), images
            ):
                store.append(image)
    finally:
        baker.release()
        ctx.release()
    return atlas


def atlas_uv(canvas: Canvas, facade: np.ndarray, size: tuple[int, int], texel: float) -> np.ndarray:
    """glTF texture coordinates (0..1, v down) of facade points (u, v metres) on a baked canvas."""
    cols, rows = size
    x = canvas.x + (facade[:, 0] - canvas.u0) / texel
    y = canvas.y + (facade[:, 1] - canvas.v0) / texel
    return np.stack([x / cols, 1.0 - y / rows], axis=1).astype(np.float32)
