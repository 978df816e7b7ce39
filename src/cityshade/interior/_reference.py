"""numpy twin of interior mapping (shaders/interior/interior.glsl): the same rooms, faces, room
ids, lights and texture variants per pixel, vectorised over pixels, in float64, from the building
masses themselves (their own solids, _solids.py). Used by tests to check the GPU pixel by pixel."""

from __future__ import annotations

from collections.abc import Callable
from dataclasses import dataclass

import numpy as np

from ..assets import LABELS, TileArray
from ..grammar import CompiledGrammars, facade_seed_vector, seed_vector
from ..grammar import evaluate as evaluate_grammar
from ..relief import GLASS, PROFILE, RELIEF_SHAPES, DetailMaps, switch_distance, trace_reference
from ..scene import SHAPES, USE_COUNT, USES, BuildingMass, door_hit, face_levels
from ._faces import (
    FACE_CEILING,
    FACE_CURTAIN,
    FACE_EXTERIOR,
    FACE_FLOOR,
    FACE_FURNITURE,
    FACE_GROUND,
    FACE_ROOF,
    FACE_WALL_X,
    FACE_WALL_Z,
    room_state,
)
from ._hash import hash3, unit_float
from ._solids import cast_masses

SALT_LIGHT, SALT_VARIANT, SALT_FURNITURE, SALT_PHASE, SALT_CURTAIN, SALT_ROOM_DEPTH = (
    0x1000,
    0x2000,
    0x3000,
    0x4000,
    0x5000,
    0x7000,
)
FURNITURE_DEPTH = 0.45
CURTAIN_DEPTH = 0.08
SPRITE_WIDTH = 0.55
SPRITE_HEIGHT = 0.8
EMPTY_ROOM_SHARE = 0.3
CURTAIN_SHARE = 0.55
ROOM_LABEL = LABELS.index("room")  # the id pass's label of grammar glass (GRAMMAR_ROOM_LABEL)
WINDOW_LABEL = LABELS.index("window")  # a recessed window's frame and reveal (GRAMMAR_WINDOW_LABEL)


@dataclass(frozen=True)
class InteriorParams:
    """The frame-wide inputs of the interior shader (its uniforms)."""

    lights: float | tuple[float, ...]  # share of lit rooms: one for every use, or one per use code (scene.lit_shares)
    time: float
    variants: int
    glass_rect: tuple[float, float, float, float]
    sprite_alpha: np.ndarray  # (kinds, frames, H, W) alpha, row 0 at the bottom
    furniture: bool = True
    curtains: bool = True
    room_variation: bool = True


def room_id(cx, cy, cz) -> np.ndarray:
    cx, cy, cz = (np.asarray(v).astype(np.int64) & 0xFFFFFFFF for v in (cx, cy, cz))
    return (cx & 0x7FF) | ((cz & 0x7FF) << 11) | ((cy & 0x3FF) << 22)


def face_frame(n: np.ndarray) -> np.ndarray:
    """Per normal (N, 3): the rotation (N, 3, 3) from object space into its face's frame (metres along
    the face as facade u grows, up, into the building); as face_frame() in the shader."""
    out_dir = n * np.array([1.0, 0.0, 1.0])
    level = np.sum(out_dir * out_dir, axis=1) <= 1e-8  # a dome's top
    out_dir[level] = (0.0, 0.0, -1.0)
    out_dir /= np.linalg.norm(out_dir, axis=1, keepdims=True)
    zero = np.zeros(len(n))
    along = np.stack([-out_dir[:, 2], zero, out_dir[:, 0]], axis=1)
    up = np.broadcast_to([0.0, 1.0, 0.0], n.shape)
    return np.stack([along, up, -out_dir], axis=1)


def lit_threshold(mass: BuildingMass, floor: np.ndarray, params: InteriorParams) -> np.ndarray:
    """Per room (its floor index): the share of such rooms that are lit, the share of its use (a shop
    on a shop-front ground floor, else the mass's use) times the mass's own multiplier, rounded as
    the shader's float32 product is (a room is lit when its hash is below it)."""
    shares = np.broadcast_to(np.asarray(params.lights, dtype=np.float32), (USE_COUNT,))
    use = np.where((np.asarray(floor) == 0) & mass.shop_front, USES["shop"], mass.use)
    return (shares[use] * np.float32(mass.lights)).astype(np.float64)


def find_room(
    window: np.ndarray,
    facade: np.ndarray,
    face: np.ndarray,
    columns: np.ndarray,
    mass: BuildingMass,
    params: InteriorParams,
) -> dict:
    """The room behind windows (N, 4: u0, v0, u1, v1 of the glass's rectangle in facade coordinates,
    or a point) on faces with facade rows (u, v, bay, storey), face rows (width, base, top, depth)
    and room columns (first bay, last bay): cell, box (face frame), id, lit, variant."""
    seed = mass.seed
    jitter = mass.wall_jitter if params.room_variation else 0.0
    bay, storey, width, base, depth = facade[:, 2], facade[:, 3], face[:, 0], face[:, 1], face[:, 3]
    anchor = np.round(32.0 * (window[:, :2] + window[:, 2:])) / 64.0  # to 1/64 m, as the shader
    bays = np.maximum(1, np.round(width / bay)).astype(np.int64)
    j = np.clip(np.floor(anchor[:, 0] / bay).astype(np.int64), 0, bays - 1)
    cy = np.floor((anchor[:, 1] - base) / storey).astype(np.int64)
    cx = np.where(j == bays - 1, columns[:, 1], columns[:, 0] + j)
    cz = np.zeros_like(cx)
    middle = (j > 0) & (j < bays - 1)
    depth = depth * np.where(
        middle, 1.0 + (unit_float(hash3(cx, cy, cz, seed ^ SALT_ROOM_DEPTH)) - 0.5) * 2.0 * jitter, 1.0
    )
    lo = np.stack(
        [np.minimum(j * bay, window[:, 0]), np.minimum(base + cy * storey, window[:, 1]), np.zeros(len(j))], axis=1
    )
    hi = np.stack(
        [np.maximum((j + 1) * bay, window[:, 2]), np.maximum(base + (cy + 1) * storey, window[:, 3]), depth], axis=1
    )
    lit = unit_float(hash3(cx, cy, cz, seed ^ SALT_LIGHT)) < lit_threshold(mass, cy, params)
    variant = (hash3(cx, cy, cz, seed ^ SALT_VARIANT) % np.uint64(params.variants)).astype(np.int64)
    return {"cell": (cx, cy, cz), "lo": lo, "hi": hi, "id": room_id(cx, cy, cz), "lit": lit, "variant": variant}


def trace(
    p: np.ndarray, d: np.ndarray, room: dict, mass: BuildingMass, params: InteriorParams
) -> tuple[np.ndarray, ...]:
    """Per ray (facade point p and unit direction d in the face's frame, face_frame; the room it
    enters, find_room): face code, room id, distance t from the facade, whether the room is lit and
    its texture variant, as the interior shader decides them."""
    n = np.broadcast_to([0.0, 0.0, -1.0], p.shape)  # the face, seen from inside
    lo, hi = room["lo"], room["hi"]
    size = hi - lo
    with np.errstate(divide="ignore", invalid="ignore"):
        far = np.where(d >= 0, hi, lo)
        tt = (far - p) / d
    ty_wins = (tt[:, 1] <= tt[:, 0]) & (tt[:, 1] <= tt[:, 2])
    tx_wins = ~ty_wins & (tt[:, 0] <= tt[:, 2])
    face = np.where(
        ty_wins, np.where(d[:, 1] > 0, FACE_CEILING, FACE_FLOOR), np.where(tx_wins, FACE_WALL_X, FACE_WALL_Z)
    )
    t = np.where(ty_wins, tt[:, 1], np.where(tx_wins, tt[:, 0], tt[:, 2]))

    seed = mass.seed
    cx, cy, cz = room["cell"]
    facing = np.maximum(-np.sum(n * d, axis=1), 1e-4)
    if params.furniture and mass.furniture and mass.shape != "dome":  # domes have no furniture
        kind_pick = unit_float(hash3(cx, cy, cz, seed ^ SALT_FURNITURE))
        depth = FURNITURE_DEPTH * np.sum(np.abs(n) * size, axis=1)
        tf = depth / facing
        hf = p + d * tf[:, None]
        rf = (hf - lo) / size
        tangent = np.cross(np.array([0.0, 1.0, 0.0]), n)
        tangent /= np.linalg.norm(tangent, axis=1, keepdims=True)
        u = 0.5 + np.sum((rf - 0.5) * tangent, axis=1)
        centre = 0.3 + 0.4 * unit_float(hash3(cx, cy, cz, seed ^ SALT_PHASE))
        su = np.stack([(u - centre) / SPRITE_WIDTH + 0.5, rf[:, 1] / SPRITE_HEIGHT], axis=1)
        inside = np.all((su >= 0) & (su < 1), axis=1) & (kind_pick >= EMPTY_ROOM_SHARE) & (tf < t)
        kinds, frames, sh, sw = params.sprite_alpha.shape
        kind = np.minimum(((kind_pick - EMPTY_ROOM_SHARE) / (1 - EMPTY_ROOM_SHARE) * kinds).astype(np.int64), kinds - 1)
        phase = unit_float(hash3(cx, cy, cz, (seed ^ SALT_PHASE) ^ 1))
        frame = np.floor(params.time * 2.0 + 7.0 * phase).astype(np.int64) % frames
        col = np.clip((su[:, 0] * sw).astype(np.int64), 0, sw - 1)
        row = np.clip((su[:, 1] * sh).astype(np.int64), 0, sh - 1)
        opaque = params.sprite_alpha[kind, frame, row, col] >= 0.5
        hit = inside & opaque
        face = np.where(hit, FACE_FURNITURE, face)
        t = np.where(hit, tf, t)
    if params.curtains and mass.curtains:
        pick = unit_float(hash3(cx, cy, cz, seed ^ SALT_CURTAIN))
        closed = 0.15 + 0.8 * pick / CURTAIN_SHARE
        tc = CURTAIN_DEPTH / facing
        v = (p[:, 1] + d[:, 1] * tc - lo[:, 1]) / size[:, 1]
        g = params.glass_rect
        hit = (pick < CURTAIN_SHARE) & (v >= g[3] - closed * (g[3] - g[1]))
        face = np.where(hit, FACE_CURTAIN, face)
        t = np.where(hit, tc, t)
    return face, room["id"], t, room["lit"], room["variant"]


def relief_entry(maps, local: np.ndarray, d: np.ndarray, n: np.ndarray, facade: np.ndarray, base: np.ndarray):
    """Relief facades (docs/relief.md, the city): the window bay `maps` repeats across the wall, one
    bay (facade[:, 2] metres) wide and one storey (facade[:, 3]) high from the face's `base`; each
    ray is traced through it by the reference tracer. Returns, per ray, whether it meets glass and
    where (object space): the point from which it continues into the room."""
    rows, cols = maps.shape
    up = np.array([0.0, 1.0, 0.0])
    along = np.stack([-n[:, 2], np.zeros(len(n)), n[:, 0]], axis=1)  # the way facade u grows: n x up
    scale = np.stack([cols / facade[:, 2], rows / facade[:, 3], np.full(len(n), 1 / maps.depth_unit)], axis=1)
    start = np.stack([facade[:, 0], facade[:, 1] - base, np.zeros(len(n))], axis=1) * scale
    direction = np.stack([np.sum(d * along, axis=1), d[:, 1], -np.sum(d * n, axis=1)], axis=1) * scale
    # The bay tiled over the wall, with a bay and a floor to spare on every side: a ray entering
    # near a corner or the roof line meets the repeat the GPU samples there.
    bays = int(np.ceil(np.max(start[:, 0]) / cols)) + 3
    floors = int(np.ceil(np.max(start[:, 1]) / rows)) + 3
    wall = DetailMaps(
        np.tile(maps.depth, (floors, bays)), np.tile(maps.material, (floors, bays)), maps.texel, maps.depth_unit
    )
    margin = np.array([cols, rows, 0.0])
    hits = trace_reference(wall, start + margin, direction)
    offset = np.nan_to_num(hits.point - margin - start) / scale
    point = local + along * offset[:, :1] + up * offset[:, 1:2] - n * offset[:, 2:]
    return hits.material == GLASS, point


@dataclass(frozen=True)
class GrammarFacades:
    """The grammar facades of a city for the twin: the compiled grammars and their tiles (as the
    renderer's), and per building index the address of its start rule and the narrowest face its
    grammar fits, a function of the face's facade.level (narrower faces are plain walls: no glass,
    no label). With `relief` (the city's cityshade.relief.relief_atlas()) the windows nearer than
    relief_range metres are recessed, as the renderer draws them with RenderSettings.relief on
    (None: as the renderer's default, cityshade.relief.switch_distance of the view)."""

    compiled: CompiledGrammars
    tiles: TileArray
    starts: dict[int, int]
    min_widths: dict[int, Callable[[int], float]]
    relief: object | None = None
    relief_range: float | None = None


def _opening_entry(atlas, region: tuple, window, local, d, n, facade):
    """Windows recessed (shaders/relief/building.glsl opening_traced): the opening at atlas `region`
    (first row, columns, rows: its ring included) stretched over each window rectangle (facade
    coordinates) and traced from the wall point by the reference tracer. Per ray: whether it meets
    glass (or a hole's bottom), where (object space), and that point's facade coordinates."""
    row, cols, rows = region[:3]
    maps = atlas.maps
    region = DetailMaps(
        maps.depth[row : row + rows, :cols], maps.material[row : row + rows, :cols], 1.0, maps.depth_unit
    )
    up = np.array([0.0, 1.0, 0.0])
    along = np.stack([-n[:, 2], np.zeros(len(n)), n[:, 0]], axis=1)  # the way facade u grows: n x up
    scale = np.column_stack([(cols - 2) / (window[:, 2] - window[:, 0]), (rows - 2) / (window[:, 3] - window[:, 1])])
    scale = np.column_stack([scale, np.full(len(n), 1 / maps.depth_unit)])
    start = np.column_stack([1.0 + (facade[:, :2] - window[:, :2]) * scale[:, :2], np.zeros(len(n))])
    direction = np.stack([np.sum(d * along, axis=1), d[:, 1], -np.sum(d * n, axis=1)], axis=1) * scale
    hits = trace_reference(region, start, direction)
    offset = np.nan_to_num(hits.point - start) / scale
    point = local + along * offset[:, :1] + up * offset[:, 1:2] - n * offset[:, 2:]
    return hits.material == GLASS, point, facade[:, :2] + offset[:, :2]  # a miss is MISS, never glass


def _window_bay_entry(atlas, glass_rect, hits, rays: np.ndarray, local: np.ndarray):
    """The window bay's window recessed (shaders/city/building.glsl window_bay_relief): the atlas's
    window-bay opening stretched over the glass rectangle of each ray's bay (rays: indices into
    `hits`, all on the flat bay's glass). Per ray: whether it meets glass, and where."""
    facade, base = hits.facade[rays], hits.face[rays, 1]
    spacing = facade[:, 2:4]
    cell = np.floor(np.column_stack([facade[:, 0], facade[:, 1] - base]) / spacing)
    lower = (cell + glass_rect[:2]) * spacing + np.column_stack([np.zeros(len(rays)), base])
    upper = (cell + glass_rect[2:]) * spacing + np.column_stack([np.zeros(len(rays)), base])
    window = np.column_stack([lower, upper])
    return _opening_entry(atlas, atlas.window_bay, window, local, hits.direction[rays], hits.normal[rays], facade)[:2]


def grammar_entry(
    grammar: GrammarFacades,
    building: int,
    mass: BuildingMass,
    d: np.ndarray,
    n: np.ndarray,
    facade: np.ndarray,
    face: np.ndarray,
    columns: np.ndarray,
    local: np.ndarray,
    distance: np.ndarray,
    switch_m: float = 0.0,
):
    """A grammar facade (shaders/grammar/building.glsl) evaluated by the grammar's numpy twin in the
    true size of each face: per ray, whether it meets glass, its label as the id pass writes it, the
    rectangle of the window it belongs to (facade coordinates, find_room) and where the ray enters
    the room (object space: the wall point `local`, or the recessed pane, _opening_entry). A hole's
    recess (shaders/relief/building.glsl grammar_relief) shows through its bottom the grammar seen
    through that hole from there."""
    glass, label = np.zeros(len(d), dtype=bool), np.zeros(len(d), dtype=np.uint32)
    window = np.zeros((len(d), 4))
    entry = local.copy()
    right = np.stack([n[:, 2], np.zeros(len(n)), -n[:, 0]], axis=1)
    right /= np.linalg.norm(right, axis=1, keepdims=True)
    rays = np.stack([np.sum(d * right, axis=1), d[:, 1], -np.sum(d * n, axis=1)], axis=1)
    # each face's size and index, its first room column (its own random stream, as the shader)
    sizes, which = np.unique(np.column_stack([face[:, :3], columns[:, 0]]), axis=0, return_inverse=True)
    start = grammar.starts[building]
    for k, (width, base, top, side) in enumerate(sizes):
        rows = np.nonzero(which.ravel() == k)[0]
        storey = facade[rows[0], 3]
        level = int(face_levels(mass.first_level, SHAPES[mass.shape], base, storey))
        if width < grammar.min_widths[building](level) - 1e-6:
            continue  # too narrow for the grammar: a plain wall
        levels = np.floor((top - base) / storey + 0.5)

        def evaluate(rays_at, at, through=-1, width=width, base=base, top=top, side=side, levels=levels, level=level):
            """The grammar along rays `rays_at` (indices) at facade points `at` (u, v); `through`: seen
            through that SkipMask's hole (this face's sizes bound as defaults)."""
            uv = np.stack([width - at[:, 0], at[:, 1] - base], axis=1)
            seed = facade_seed_vector(mass.seed, int(side))
            building_attributes = (levels, mass.style, mass.use, mass.extent[1])
            return evaluate_grammar(
                grammar.compiled, start, uv, (width, top - base), seed, grammar.tiles, rays[rays_at],
                building_attributes, building_seed=seed_vector(mass.seed), level=level, through=through,
            )  # fmt: skip

        def rectangle(scope, width=width, base=base):
            """A scope in grammar uv as facade coordinates (u0, v0, u1, v1), as grammar_window gives them."""
            lower, extent = scope[:, :2].astype(np.float64), scope[:, 2:].astype(np.float64)
            u0, v0 = width - lower[:, 0] - extent[:, 0], base + lower[:, 1]
            return np.stack([u0, v0, u0 + extent[:, 0], v0 + extent[:, 1]], axis=1)

        g = evaluate(rows, facade[rows, :2])
        glass[rows] = g.glass
        label[rows] = np.where(g.glass, ROOM_LABEL, g.label)
        window[rows] = rectangle(g.scope)
        if grammar.relief is None:
            continue
        openings = grammar.relief.terminals
        near = distance[rows] <= switch_m
        glazed = np.isin(g.terminal, list(openings)) & (g.glass | (g.label == WINDOW_LABEL))
        hole = np.isin(g.hole, list(openings)) & ~glazed  # a hole's recess, if no glazed terminal's
        opening = np.where(glazed, g.terminal, np.where(hole, g.hole, -1))
        for terminal in np.unique(opening[near & (opening >= 0)]):
            mine = near & (opening == terminal)
            traced, is_hole = rows[mine], hole[mine][0]
            if is_hole:
                window[traced] = rectangle(g.hole_scope[mine])
            region = (openings[int(terminal)], PROFILE[0] + 2, PROFILE[1] + 2)
            through, entry[traced], bottom = _opening_entry(
                grammar.relief, region, window[traced], local[traced], d[traced], n[traced], facade[traced]
            )
            glass[traced] = through & ~is_hole
            label[traced] = np.where(glass[traced], ROOM_LABEL, WINDOW_LABEL)  # glass, or the frame and reveal
            seen = traced[through & is_hole]
            if len(seen):  # through the hole's bottom: the grammar seen through it from there
                behind = evaluate(seen, bottom[through], int(terminal))
                glass[seen] = behind.glass
                label[seen] = np.where(behind.glass, ROOM_LABEL, behind.label)
                window[seen] = np.where(behind.glass[:, None], rectangle(behind.scope), window[seen])
    return glass, label, window, entry


def reference_ids(*args, **kwargs) -> np.ndarray:
    """The id AOV with room state (face, room, building + 1, room_state(lit, variant)) of the
    building and ground passes, per pixel centre (the arguments: reference_surfaces)."""
    return reference_surfaces(*args, **kwargs)[0]


def reference_surfaces(
    masses: list[BuildingMass],
    camera,
    size: tuple[int, int],
    params: InteriorParams,
    facade_alpha: np.ndarray,
    ground_bounds: tuple[float, float, float, float],
    relief: dict | None = None,
    grammar: GrammarFacades | None = None,
    labels: bool = False,
    window_bay_relief: object | None = None,
) -> tuple[np.ndarray, np.ndarray]:
    """The id AOV with room state (face, room, building + 1, room_state(lit, variant)) of the
    building and ground passes, and each pixel's distance from the eye to the surface it shows
    (metres along the ray; inf: nothing), per pixel centre: the masses' own solids ray-cast (_solids.py),
    glass decided by the facade texel (or, for the buildings whose index maps to a window bay in
    `relief`, by the relief met along the ray, `relief_entry`; for those with a start rule in
    `grammar`, by the grammar, `grammar_entry`) unless a door stands there
    (`cityshade.scene.door_hit`), rooms by `trace` (none behind the glass of a mass without an
    interior). With `labels` the fourth channel is the grammar label instead (the id pass without
    room state). With `window_bay_relief` (cityshade.relief.relief_atlas(), as the renderer's
    default RenderSettings.relief on) the window bay's glass on flat walls nearer than the switch (the grammar's
    relief_range, else switch_distance of the view) is recessed, `_window_bay_entry`. The ground is the plane y = 0 inside `ground_bounds` (x0, z0, x1, z1), cut by the
    camera's far plane. The distance is the wall's, or where a relief is traced the relief's
    surface met along the ray behind it, as the GPU writes the depth (shaders/relief/depth.glsl)."""
    relief = relief or {}
    starts = grammar.starts if grammar is not None else {}
    switch_m = grammar.relief_range if grammar is not None else None
    if switch_m is None:
        switch_m = switch_distance(size[1], camera.fov_y)
    width, height = size
    dirs = camera.pixel_rays(size).reshape(-1, 3)
    eye = camera.eye
    hits = cast_masses(masses, eye, dirs)
    out = np.zeros((len(dirs), 4), dtype=np.uint32)
    with np.errstate(divide="ignore", invalid="ignore"):
        tg = -eye[1] / dirs[:, 1]
    gp = eye + dirs * tg[:, None]
    x0, z0, x1, z1 = ground_bounds
    on_ground = (tg > 0) & (gp[:, 0] > x0) & (gp[:, 0] < x1) & (gp[:, 2] > z0) & (gp[:, 2] < z1)
    on_ground &= tg * np.abs(dirs @ camera.forward) < camera.far
    ground = on_ground & (tg < hits.t)
    distance = np.full(len(dirs), np.inf)
    th, tw = facade_alpha.shape
    for b, mass in enumerate(masses):
        sel = np.nonzero((hits.building == b) & ~ground)[0]
        if not len(sel):
            continue
        facade, roof = hits.facade[sel], hits.roof[sel]
        entry = hits.local.copy()
        window = np.column_stack([facade[:, :2], facade[:, :2]])  # the window-bay facade: the pixel's own bay
        if b in starts:
            glass = np.zeros(len(sel), dtype=bool)
            walls = sel[~roof]
            if len(walls):
                glass[~roof], label, window[~roof], entry[walls] = grammar_entry(
                    grammar,
                    b,
                    mass,
                    hits.direction[walls],
                    hits.normal[walls],
                    hits.facade[walls],
                    hits.face[walls],
                    hits.columns[walls],
                    hits.local[walls],
                    hits.t[walls] * np.linalg.norm(dirs[walls], axis=1),
                    switch_m,
                )
                if labels:
                    out[walls, 3] = label
        elif b in relief:
            glass = np.zeros(len(sel), dtype=bool)
            walls = sel[~roof]
            if len(walls):
                glass[~roof], entry[walls] = relief_entry(
                    relief[b],
                    hits.local[walls],
                    hits.direction[walls],
                    hits.normal[walls],
                    hits.facade[walls],
                    hits.face[walls, 1],
                )
                # the bay repeats past the wall's top: a ray rising through a recess there meets
                # the roof's plane first (the GPU draws the roof's underside, nearer than the hit)
                rise = entry[walls, 1] - hits.local[walls, 1]
                above = hits.facade[walls, 1] + rise > hits.face[walls, 2]
                if above.any():
                    over = np.nonzero(~roof)[0][above]
                    roof = roof.copy()
                    roof[over], glass[over] = True, False
                    rays = walls[above]
                    climb = (hits.face[rays, 2] - hits.facade[rays, 1]) / hits.direction[rays, 1]
                    entry[rays] = hits.local[rays] + hits.direction[rays] * climb[:, None]
        else:
            col = (np.mod(facade[:, 0] / facade[:, 2], 1.0) * tw).astype(np.int64).clip(0, tw - 1)
            row = (np.mod((facade[:, 1] - hits.face[sel, 1]) / facade[:, 3], 1.0) * th).astype(np.int64).clip(0, th - 1)
            glass = ~roof & (facade_alpha[row, col] < 0.5)
            if window_bay_relief is not None and mass.shape in RELIEF_SHAPES:
                near = glass & (hits.t[sel] * np.linalg.norm(dirs[sel], axis=1) <= switch_m)
                if near.any():
                    glass[near], entry[sel[near]] = _window_bay_entry(
                        window_bay_relief, params.glass_rect, hits, sel[near], hits.local[sel[near]]
                    )
        if mass.doors:  # a door stands in front of whatever the facade has there
            glass &= roof | ~door_hit(hits.local[sel], hits.normal[sel], mass.doors)[0]
        out[sel, 0] = np.where(roof, FACE_ROOF, FACE_EXTERIOR)
        out[sel, 2] = b + 1
        # the relief's hit lies on the ray behind the wall point (the wall point where not traced)
        distance[sel] = hits.t[sel] + np.linalg.norm(entry[sel] - hits.local[sel], axis=1)
        if glass.any() and mass.interior:  # without an interior the glass stays an exterior face
            rays = sel[glass]
            to_face = face_frame(hits.normal[rays])
            offset = np.einsum("nij,nj->ni", to_face, entry[rays] - hits.local[rays])
            p = np.column_stack([hits.facade[rays, :2], np.zeros(len(rays))]) + offset
            room = find_room(window[glass], hits.facade[rays], hits.face[rays], hits.columns[rays], mass, params)
            d = np.einsum("nij,nj->ni", to_face, hits.direction[rays])
            face, room, _, lit, variant = trace(p, d, room, mass, params)
            out[rays, 0], out[rays, 1] = face, room
            if not labels:
                out[rays, 3] = room_state(lit, variant)
    # the ground plane runs on under the buildings: it hides a relief hit below it (a ray into a
    # recess at the foot of a wall), as the GPU's ground pass does against the traced depth
    ground = on_ground & (tg < distance)
    out[ground] = (FACE_GROUND, 0, 0, 0)
    distance[ground] = tg[ground]
    return out.reshape(height, width, 4), distance.reshape(height, width)
