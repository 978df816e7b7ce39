"""The buildings' vertices as the GPU holds them, 24 bytes: the object-space position, facade u and
v, and a row of the face table. What every vertex of a face repeats (normal, bay width and storey
height, the face's width, base, top and room depth, the ids) is one row of the face table, which
the vertex stage reads by the vertex's row index (shaders/common/building_vertex.glsl, a storage
buffer BuildingFaces); the world position is placed there from the object-space one by the
building's placement (cos and sin of its yaw, its origin: float64, BuildingPlacements) with the
float64 arithmetic of `world_positions`, which gives the meshed float32 bits exactly (face_table
checks that every vertex was placed so). The rows hold the very bits of the meshed VERTEX_DTYPE
records, so every program sees the values it saw before, bit for bit. `shared_vertices` then
stores each distinct vertex once, drawn through an index buffer (a quad's triangles share corners).

A row is FACE_WORDS 32-bit words in FACE_DTYPE's order; a new per-face value is a new field at the
end of FACE_DTYPE and a matching read in building_vertex.glsl."""

from __future__ import annotations

import numpy as np

from ._mass_table import MassTable
from ._meshes import VERTEX_DTYPE, world_positions

GPU_VERTEX_DTYPE = np.dtype(
    [
        ("local", "<f4", 3),  # object space (metres)
        ("facade", "<f4", 2),  # u along the face, v up (metres)
        ("face", "<u4"),  # its row in the face table
    ]
)
GPU_VERTEX_FORMAT = "3f 2f 1u"
GPU_VERTEX_ATTRIBUTES = ("in_local", "in_facade", "in_face_row")

FACE_DTYPE = np.dtype(
    [
        ("normal", "<f4", 3),  # per vertex on curved walls and domes: such faces get a row per normal
        ("spacing", "<f4", 2),  # bay width, storey height (metres)
        ("face", "<f4", 4),  # the face's width, base, top, room depth (metres)
        ("ids", "<i4", 4),  # building index, surface kind, room column of the face's first and last bay
    ]
)
FACE_WORDS = FACE_DTYPE.itemsize // 4
# per building: cos and sin of its yaw, its origin's world x and z (a dvec4 in the shader)
PLACEMENT_DTYPE = np.dtype([("rotation", "<f8", 2), ("origin", "<f8", 2)])
FACE_TABLE_CONSTANTS = {"FACE_WORDS": f"{FACE_WORDS}u"}
FNV_PRIME = np.uint64(0x100000001B3)  # the rows' hash (FNV-1a over their words)

# the words of a VERTEX_DTYPE record that FACE_DTYPE's fields come from, in FACE_DTYPE's order
_WORDS = np.r_[
    VERTEX_DTYPE.fields["normal"][1] // 4 : VERTEX_DTYPE.fields["normal"][1] // 4 + 3,
    VERTEX_DTYPE.fields["facade"][1] // 4 + 2 : VERTEX_DTYPE.itemsize // 4,
]


def placements(masses) -> np.ndarray:
    """The masses' PLACEMENT_DTYPE rows, with the values scene.batch places their vertices by."""
    if isinstance(masses, MassTable):  # its columns: no mass objects built
        yaw, origin = masses.column("yaw"), masses.column("position")
    else:
        yaw = np.array([m.yaw for m in masses], np.float64)
        origin = np.array([m.position for m in masses], np.float64).reshape(-1, 2)
    out = np.zeros(len(masses), PLACEMENT_DTYPE)
    out["rotation"] = np.column_stack([np.cos(yaw), np.sin(yaw)]) if len(masses) else np.zeros((0, 2))
    out["origin"] = origin
    return out


def _placed(local: np.ndarray, building: np.ndarray, placement: np.ndarray) -> np.ndarray:
    rows = placement[building]
    return world_positions(local, rows["rotation"][:, 0], rows["rotation"][:, 1], rows["origin"]).astype(np.float32)


def face_table(vertices: np.ndarray, placement: np.ndarray, first_row: int = 0) -> tuple[np.ndarray, np.ndarray]:
    """VERTEX_DTYPE records as (GPU_VERTEX_DTYPE vertices, FACE_DTYPE rows): a row per distinct
    combination of face-table words (a face, or one normal of a curved face), compared bit for bit;
    the vertices' row indices start at `first_row` (a table made of several parts). `placement`:
    the PLACEMENT_DTYPE rows of the buildings the vertices' ids name; a vertex they do not place
    at its very position is an error (the GPU would draw it elsewhere)."""
    building = vertices["ids"][:, 0]
    placed = _placed(vertices["local"], building, placement)
    moved = np.any(placed.view(np.uint32) != np.ascontiguousarray(vertices["position"]).view(np.uint32), axis=1)
    if moved.any():
        first = int(np.argmax(moved))
        raise ValueError(
            f"{int(moved.sum())} vertices are not where their building's placement puts them "
            f"(vertex {first} of building {int(building[first])}): mesh them with scene.world_positions"
        )
    words = np.ascontiguousarray(vertices).view(np.uint32).reshape(len(vertices), VERTEX_DTYPE.itemsize // 4)
    words = words[:, _WORDS]
    # runs of consecutive vertices alike first (a face's vertices are neighbours), then the runs' distinct rows
    starts = np.ones(len(vertices), bool)
    starts[1:] = np.any(words[1:] != words[:-1], axis=1)
    runs = words[starts]
    first, run_row = _distinct(runs)
    out = np.empty(len(vertices), GPU_VERTEX_DTYPE)
    out["local"] = vertices["local"]
    out["facade"] = vertices["facade"][:, :2]
    out["face"] = run_row[np.cumsum(starts) - 1] + first_row
    return out, runs[first].view(FACE_DTYPE).ravel()


def expand_face_table(vertices: np.ndarray, table: np.ndarray, placement: np.ndarray, first_row: int = 0) -> np.ndarray:
    """face_table's inverse: the VERTEX_DTYPE records back, every value as the vertex stage gets it."""
    out = np.zeros(len(vertices), VERTEX_DTYPE)
    rows = table[vertices["face"].astype(np.int64) - first_row]
    out["position"] = _placed(vertices["local"], rows["ids"][:, 0], placement)
    out["local"], out["normal"] = vertices["local"], rows["normal"]
    out["facade"][:, :2], out["facade"][:, 2:] = vertices["facade"], rows["spacing"]
    out["face"], out["ids"] = rows["face"], rows["ids"]
    return out


def shared_vertices(vertices: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """GPU_VERTEX_DTYPE vertices as (their distinct vertices in order of first use, uint32 indices
    into those, one per vertex given): an index buffer that draws the same triangles in the same
    order, each corner a face's triangles share stored once."""
    first, inverse = _distinct(
        np.ascontiguousarray(vertices).view(np.uint32).reshape(len(vertices), GPU_VERTEX_DTYPE.itemsize // 4)
    )
    order = np.argsort(first)
    rank = np.empty(len(order), np.uint32)
    rank[order] = np.arange(len(order), dtype=np.uint32)
    return vertices[first[order]], rank[inverse]


def _distinct(rows: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """(index of each distinct row's first occurrence, each row's distinct index) of uint32 rows:
    grouped by a 64-bit hash (sorting the rows' bytes is several times slower), each group
    checked to hold one row; where a hash collides, by the bytes."""
    key = np.zeros(len(rows), np.uint64)
    for column in rows.T:
        key = (key ^ column) * FNV_PRIME
    _, first, inverse = np.unique(key, return_index=True, return_inverse=True)
    inverse = inverse.ravel()
    if not np.array_equal(rows[first[inverse]], rows):
        void = rows.view(np.dtype((np.void, rows.shape[1] * 4))).ravel()
        _, first, inverse = np.unique(void, return_index=True, return_inverse=True)
        inverse = inverse.ravel()
    return first, inverse
