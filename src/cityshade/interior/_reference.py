"""numpy twin of interior mapping (shaders/interior/interior.glsl): the same rooms, faces, room
ids, lights and texture variants per pixel, vectorised over pixels, in float64, from the building
masses themselves (their own solids, _solids.py). Used by tests to check the GPU pixel by pixel."""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from ..relief import GLASS, DetailMaps, trace_reference
from ..scene import USE_COUNT, USES, BuildingMass, door_hit
from ._faces import (FACE_CEILING, FACE_CURTAIN, FACE_EXTERIOR, FACE_FLOOR, FACE_FURNITURE, FACE_GROUND, FACE_ROOF,
                     FACE_WALL_X, FACE_WALL_Z, room_state)
from ._hash import hash3, unit_float
from ._solids import cast_masses

SALT_LIGHT, SALT_VARIANT, SALT_FURNITURE, SALT_PHASE, SALT_CURTAIN, SALT_WALL_X, SALT_WALL_Z = (
    0x1000, 0x2000, 0x3000, 0x4000, 0x5000, 0x6000, 0x7000)
FURNITURE_DEPTH = 0.45
CURTAIN_DEPTH = 0.08
SPRITE_WIDTH = 0.55
SPRITE_HEIGHT = 0.8
EMPTY_ROOM_SHARE = 0.3
CURTAIN_SHARE = 0.55


@dataclass(frozen=True)
class InteriorParams:
    """The frame-wide inputs of the interior shader (its uniforms)."""

    lights: float | tuple[float, ...]  # share of lit rooms: one for every use, or one per use code (scene.lit_shares)
    time: float
    variants: int
    glass_rect: tuple[float, float, float, float]
    sprite_alpha: np.ndarray      # (kinds, frames, H, W) alpha, row 0 at the bottom
    furniture: bool = True
    curtains: bool = True
    room_variation: bool = True


def room_id(cx, cy, cz) -> np.ndarray:
    cx, cy, cz = (np.asarray(v).astype(np.int64) & 0xFFFFFFFF for v in (cx, cy, cz))
    return (cx & 0x7FF) | ((cz & 0x7FF) << 11) | ((cy & 0x3FF) << 22)


def _wall_offset(k, floor_index, lines, salt, jitter):
    off = (unit_float(hash3(k, floor_index, np.zeros_like(k), salt)) - 0.5) * 2.0 * jitter
    return np.where((k <= 0) | (k >= lines), 0.0, off)


def _room_interval(x, size, lines, floor_index, salt, jitter):
    k0 = np.floor(x / size).astype(np.int64)
    w0 = (k0 + _wall_offset(k0, floor_index, lines, salt, jitter)) * size
    w1 = (k0 + 1 + _wall_offset(k0 + 1, floor_index, lines, salt, jitter)) * size
    below, above = x < w0, x >= w1
    k = np.where(below, k0 - 1, np.where(above, k0 + 1, k0))
    lo = np.where(below, (k0 - 1 + _wall_offset(k0 - 1, floor_index, lines, salt, jitter)) * size,
                  np.where(above, w1, w0))
    hi = np.where(below, w0, np.where(above, (k0 + 2 + _wall_offset(k0 + 2, floor_index, lines, salt, jitter)) * size, w1))
    return k, lo, hi


def lit_threshold(mass: BuildingMass, floor: np.ndarray, params: InteriorParams) -> np.ndarray:
    """Per room (its floor index): the share of such rooms that are lit, the share of its use (a shop
    on a shop-front ground floor, else the mass's use) times the mass's own multiplier, rounded as
    the shader's float32 product is (a room is lit when its hash is below it)."""
    shares = np.broadcast_to(np.asarray(params.lights, dtype=np.float32), (USE_COUNT,))
    use = np.where((np.asarray(floor) == 0) & mass.shop_front, USES["shop"], mass.use)
    return (shares[use] * np.float32(mass.lights)).astype(np.float64)


def find_room(p: np.ndarray, n: np.ndarray, mass: BuildingMass, params: InteriorParams) -> dict:
    """The room entered at facade points p (N, 3) with normals n: cell, box, id, lit, variant."""
    size = mass.room_size
    seed = mass.seed
    jitter = mass.wall_jitter if params.room_variation else 0.0
    lines = np.round(mass.extent / size).astype(np.int64)
    q = p - n * (1e-3 * size.min())
    cy = np.floor(q[:, 1] / size[1]).astype(np.int64)
    cx, x0, x1 = _room_interval(q[:, 0], size[0], lines[0], cy, seed ^ SALT_WALL_X, jitter)
    cz, z0, z1 = _room_interval(q[:, 2], size[2], lines[2], cy, seed ^ SALT_WALL_Z, jitter)
    lo = np.stack([x0, cy * size[1], z0], axis=1)
    hi = np.stack([x1, (cy + 1) * size[1], z1], axis=1)
    lit = unit_float(hash3(cx, cy, cz, seed ^ SALT_LIGHT)) < lit_threshold(mass, cy, params)
    variant = (hash3(cx, cy, cz, seed ^ SALT_VARIANT) % np.uint64(params.variants)).astype(np.int64)
    return {"cell": (cx, cy, cz), "lo": lo, "hi": hi, "id": room_id(cx, cy, cz), "lit": lit, "variant": variant}


def trace(p: np.ndarray, d: np.ndarray, n: np.ndarray, mass: BuildingMass, params: InteriorParams) -> tuple[np.ndarray, ...]:
    """Per ray (facade point p, unit direction d, normal n; object space): face code, room id,
    distance t from the facade, whether the room is lit and its texture variant, as the interior
    shader decides them."""
    room = find_room(p, n, mass, params)
    lo, hi = room["lo"], room["hi"]
    size = hi - lo
    with np.errstate(divide="ignore", invalid="ignore"):
        far = np.where(d >= 0, hi, lo)
        tt = (far - p) / d
    ty_wins = (tt[:, 1] <= tt[:, 0]) & (tt[:, 1] <= tt[:, 2])
    tx_wins = ~ty_wins & (tt[:, 0] <= tt[:, 2])
    face = np.where(ty_wins, np.where(d[:, 1] > 0, FACE_CEILING, FACE_FLOOR), np.where(tx_wins, FACE_WALL_X, FACE_WALL_Z))
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


def relief_entry(maps, local: np.ndarray, d: np.ndarray, n: np.ndarray, facade: np.ndarray, floor_height: float):
    """Relief facades (docs/relief.md, the city): the window bay `maps` repeats across the wall, one
    bay (facade[:, 2] metres) wide and one floor high; each ray is traced through it by the
    reference tracer. Returns, per ray, whether it meets glass and where (object space): the
    point from which it continues into the room."""
    rows, cols = maps.shape
    up = np.array([0.0, 1.0, 0.0])
    along = np.stack([-n[:, 2], np.zeros(len(n)), n[:, 0]], axis=1)  # the way facade u grows: n x up
    scale = np.stack([cols / facade[:, 2], np.full(len(n), rows / floor_height), np.full(len(n), 1 / maps.depth_unit)], axis=1)
    start = np.stack([facade[:, 0], facade[:, 1], np.zeros(len(n))], axis=1) * scale
    direction = np.stack([np.sum(d * along, axis=1), d[:, 1], -np.sum(d * n, axis=1)], axis=1) * scale
    # The bay tiled over the wall, with a bay and a floor to spare on every side: a ray entering
    # near a corner or the roof line meets the repeat the GPU samples there.
    bays = int(np.ceil(np.max(start[:, 0]) / cols)) + 3
    floors = int(np.ceil(np.max(start[:, 1]) / rows)) + 3
    wall = DetailMaps(np.tile(maps.depth, (floors, bays)), np.tile(maps.material, (floors, bays)), maps.texel, maps.depth_unit)
    margin = np.array([cols, rows, 0.0])
    hits = trace_reference(wall, start + margin, direction)
    offset = np.nan_to_num(hits.point - margin - start) / scale
    point = local + along * offset[:, :1] + up * offset[:, 1:2] - n * offset[:, 2:]
    return hits.material == GLASS, point


def reference_ids(masses: list[BuildingMass], camera, size: tuple[int, int], params: InteriorParams,
                  facade_alpha: np.ndarray, ground_bounds: tuple[float, float, float, float],
                  relief: dict | None = None) -> np.ndarray:
    """The id AOV with room state (face, room, building + 1, room_state(lit, variant)) of the
    building and ground passes, per pixel centre: the masses' own solids ray-cast (_solids.py),
    glass decided by the facade texel (or, for the buildings whose index maps to a window bay in
    `relief`, by the relief met along the ray, `relief_entry`) unless a door stands there
    (`cityshade.scene.door_hit`), rooms by `trace` (none behind the
    glass of a mass without an interior). The ground is the
    plane y = 0 inside `ground_bounds` (x0, z0, x1, z1), cut by the camera's far plane."""
    relief = relief or {}
    width, height = size
    dirs = camera.pixel_rays(size).reshape(-1, 3)
    eye = camera.eye
    hits = cast_masses(masses, eye, dirs)
    out = np.zeros((len(dirs), 4), dtype=np.uint32)
    with np.errstate(divide="ignore", invalid="ignore"):
        tg = -eye[1] / dirs[:, 1]
    gp = eye + dirs * tg[:, None]
    x0, z0, x1, z1 = ground_bounds
    ground = (tg > 0) & (gp[:, 0] > x0) & (gp[:, 0] < x1) & (gp[:, 2] > z0) & (gp[:, 2] < z1) & (tg < hits.t)
    ground &= tg * np.abs(dirs @ camera.forward) < camera.far
    out[ground, 0] = FACE_GROUND
    th, tw = facade_alpha.shape
    for b, mass in enumerate(masses):
        sel = np.nonzero((hits.building == b) & ~ground)[0]
        if not len(sel):
            continue
        facade, roof = hits.facade[sel], hits.roof[sel]
        entry = hits.local.copy()
        if b in relief:
            glass = np.zeros(len(sel), dtype=bool)
            walls = sel[~roof]
            if len(walls):
                glass[~roof], entry[walls] = relief_entry(relief[b], hits.local[walls], hits.direction[walls],
                                                          hits.normal[walls], hits.facade[walls], mass.room_size[1])
        else:
            col = (np.mod(facade[:, 0] / facade[:, 2], 1.0) * tw).astype(np.int64).clip(0, tw - 1)
            row = (np.mod(facade[:, 1] / mass.room_size[1], 1.0) * th).astype(np.int64).clip(0, th - 1)
            glass = ~roof & (facade_alpha[row, col] < 0.5)
        if mass.doors:  # a door stands in front of whatever the facade has there
            glass &= roof | ~door_hit(hits.local[sel], hits.normal[sel], mass.doors)[0]
        out[sel, 0] = np.where(roof, FACE_ROOF, FACE_EXTERIOR)
        out[sel, 2] = b + 1
        if glass.any() and mass.interior:  # without an interior the glass stays an exterior face
            rays = sel[glass]
            face, room, _, lit, variant = trace(entry[rays], hits.direction[rays], hits.normal[rays], mass, params)
            out[rays, 0], out[rays, 1], out[rays, 3] = face, room, room_state(lit, variant)
    return out.reshape(height, width, 4)
