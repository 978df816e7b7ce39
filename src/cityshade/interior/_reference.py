"""numpy twin of interior mapping (shaders/interior/interior.glsl): the same rooms, faces and room
ids per pixel, vectorised over pixels, in float64. Used by tests to check the GPU pixel by pixel."""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from ..scene import FLAG_CURTAINS, FLAG_FURNITURE, FLAG_ROOM_VARIATION, rotation_y
from ._faces import FACE_CEILING, FACE_CURTAIN, FACE_FLOOR, FACE_FURNITURE, FACE_WALL_X, FACE_WALL_Z
from ._hash import hash3, unit_float

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

    lights: float
    time: float
    variants: int
    glass_rect: tuple[float, float, float, float]
    sprite_alpha: np.ndarray      # (kinds, frames, H, W) alpha, row 0 at the bottom
    feature_mask: int = FLAG_FURNITURE | FLAG_CURTAINS | FLAG_ROOM_VARIATION


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


def find_room(p: np.ndarray, n: np.ndarray, record, params: InteriorParams) -> dict:
    """The room entered at facade points p (N, 3) with normals n: cell, box, id, lit, variant."""
    size = record["room"][:3].astype(np.float64)
    seed = int(record["ids"][0])
    flags = int(record["ids"][2]) & params.feature_mask
    jitter = float(record["room"][3]) if flags & FLAG_ROOM_VARIATION else 0.0
    lines = np.round(record["extent"][:3].astype(np.float64) / size).astype(np.int64)
    q = p - n * (1e-3 * size.min())
    cy = np.floor(q[:, 1] / size[1]).astype(np.int64)
    cx, x0, x1 = _room_interval(q[:, 0], size[0], lines[0], cy, seed ^ SALT_WALL_X, jitter)
    cz, z0, z1 = _room_interval(q[:, 2], size[2], lines[2], cy, seed ^ SALT_WALL_Z, jitter)
    lo = np.stack([x0, cy * size[1], z0], axis=1)
    hi = np.stack([x1, (cy + 1) * size[1], z1], axis=1)
    lit = unit_float(hash3(cx, cy, cz, seed ^ SALT_LIGHT)) < params.lights * float(record["extent"][3])
    variant = (hash3(cx, cy, cz, seed ^ SALT_VARIANT) % np.uint64(params.variants)).astype(np.int64)
    return {"cell": (cx, cy, cz), "lo": lo, "hi": hi, "id": room_id(cx, cy, cz), "lit": lit, "variant": variant}


def trace(p: np.ndarray, d: np.ndarray, n: np.ndarray, record, params: InteriorParams) -> tuple[np.ndarray, ...]:
    """Per ray (facade point p, unit direction d, normal n; object space): face code, room id,
    distance t from the facade and whether the room is lit, exactly as the interior shader decides
    them."""
    room = find_room(p, n, record, params)
    lo, hi = room["lo"], room["hi"]
    size = hi - lo
    with np.errstate(divide="ignore", invalid="ignore"):
        far = np.where(d >= 0, hi, lo)
        tt = (far - p) / d
    ty_wins = (tt[:, 1] <= tt[:, 0]) & (tt[:, 1] <= tt[:, 2])
    tx_wins = ~ty_wins & (tt[:, 0] <= tt[:, 2])
    face = np.where(ty_wins, np.where(d[:, 1] > 0, FACE_CEILING, FACE_FLOOR), np.where(tx_wins, FACE_WALL_X, FACE_WALL_Z))
    t = np.where(ty_wins, tt[:, 1], np.where(tx_wins, tt[:, 0], tt[:, 2]))

    seed = int(record["ids"][0])
    flags = int(record["ids"][2]) & params.feature_mask
    cx, cy, cz = room["cell"]
    facing = np.maximum(-np.sum(n * d, axis=1), 1e-4)
    if flags & FLAG_FURNITURE:
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
    if flags & FLAG_CURTAINS:
        pick = unit_float(hash3(cx, cy, cz, seed ^ SALT_CURTAIN))
        closed = 0.15 + 0.8 * pick / CURTAIN_SHARE
        tc = CURTAIN_DEPTH / facing
        v = (p[:, 1] + d[:, 1] * tc - lo[:, 1]) / size[:, 1]
        g = params.glass_rect
        hit = (pick < CURTAIN_SHARE) & (v >= g[3] - closed * (g[3] - g[1]))
        face = np.where(hit, FACE_CURTAIN, face)
        t = np.where(hit, tc, t)
    return face, room["id"], t, room["lit"]


def reference_ids(masses, camera, size: tuple[int, int], params: InteriorParams, facade_alpha: np.ndarray,
                  ground_bounds: tuple[float, float, float, float]) -> np.ndarray:
    """The id AOV (face, room, building + 1, 0) of the building and ground passes, per pixel centre:
    triangles ray-cast, attributes interpolated as the rasteriser does, glass decided by the facade
    texel, rooms by `trace`. The ground is the plane y = 0 inside `ground_bounds` (x0, z0, x1, z1)."""
    return reference_pixels(masses, camera, size, params, facade_alpha, ground_bounds)[0]


def reference_pixels(masses, camera, size: tuple[int, int], params: InteriorParams, facade_alpha: np.ndarray,
                     ground_bounds: tuple[float, float, float, float]) -> tuple[np.ndarray, np.ndarray]:
    """reference_ids and, per pixel, whether the room seen there is lit (False off the rooms)."""
    from ..scene import SURFACE_ROOF, batch, intersect
    from ._faces import FACE_EXTERIOR, FACE_GROUND, FACE_ROOF

    vertices, records = batch(masses)
    width, height = size
    dirs = camera.pixel_rays(size).reshape(-1, 3)
    eye = camera.eye
    tris = vertices["position"].astype(np.float64).reshape(-1, 3, 3)
    t, tri, bary = intersect(eye, dirs, tris)
    out = np.zeros((len(dirs), 4), dtype=np.uint32)
    lit = np.zeros(len(dirs), dtype=bool)
    # ground plane y = 0 where no building is nearer
    with np.errstate(divide="ignore", invalid="ignore"):
        tg = -eye[1] / dirs[:, 1]
    gp = eye + dirs * tg[:, None]
    x0, z0, x1, z1 = ground_bounds
    ground = (tg > 0) & (gp[:, 0] > x0) & (gp[:, 0] < x1) & (gp[:, 2] > z0) & (gp[:, 2] < z1) & (tg < t)
    ground &= tg * np.abs(dirs @ camera.forward) < camera.far  # the far clipping plane
    out[ground, 0] = FACE_GROUND
    hit = (tri >= 0) & ~ground
    corners = vertices.reshape(-1, 3)
    for b, record in enumerate(records):
        sel = hit & (corners[np.maximum(tri, 0), 0]["ids"][:, 0] == b)
        if not sel.any():
            continue
        verts = corners[tri[sel]]
        w = bary[sel][:, :, None]
        local = np.sum(verts["local"].astype(np.float64) * w, axis=1)
        normal = np.sum(verts["normal"].astype(np.float64) * w, axis=1)
        normal /= np.linalg.norm(normal, axis=1, keepdims=True)
        facade = np.sum(verts["facade"].astype(np.float64) * w, axis=1)
        roof = verts["ids"][:, 0, 1] == SURFACE_ROOF
        rot = rotation_y(float(record["origin_yaw"][3]))
        cam_local = rot.T @ (eye - record["origin_yaw"][:3].astype(np.float64))
        d = local - cam_local
        d /= np.linalg.norm(d, axis=1, keepdims=True)
        bay = np.stack([facade[:, 0] / facade[:, 2], facade[:, 1] / float(record["room"][1])], axis=1)
        th, tw = facade_alpha.shape
        col = (np.mod(bay[:, 0], 1.0) * tw).astype(np.int64).clip(0, tw - 1)
        row = (np.mod(bay[:, 1], 1.0) * th).astype(np.int64).clip(0, th - 1)
        glass = ~roof & (facade_alpha[row, col] < 0.5)
        face = np.where(roof, FACE_ROOF, FACE_EXTERIOR).astype(np.int64)
        room = np.zeros(len(face), dtype=np.int64)
        room_lit = np.zeros(len(face), dtype=bool)
        if glass.any():
            gface, groom, _, glit = trace(local[glass], d[glass], normal[glass], record, params)
            face[glass], room[glass], room_lit[glass] = gface, groom, glit
        idx = np.nonzero(sel)[0]
        lit[idx] = room_lit
        out[idx, 0] = face
        out[idx, 1] = room
        out[idx, 2] = b + 1
    return out.reshape(height, width, 4), lit.reshape(height, width)
