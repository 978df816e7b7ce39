"""The buildings' vertices as the GPU holds them: what varies per vertex (world and object position,
facade u and v) stays in the vertex, 36 bytes; what every vertex of a face repeats (normal, bay
width and storey height, the face's width, base, top and room depth, the ids) is one row of a face
table, which the vertex stage reads by the vertex's row index (shaders/common/building_vertex.glsl,
a storage buffer at FACES_BINDING). The rows hold the very bits of the meshed VERTEX_DTYPE records,
so every program sees the values it saw before, bit for bit.

A row is FACE_WORDS 32-bit words in FACE_DTYPE's order; a new per-face value is a new field at the
end of FACE_DTYPE and a matching read in building_vertex.glsl's `face_row`."""

from __future__ import annotations

import numpy as np

from ._meshes import VERTEX_DTYPE

GPU_VERTEX_DTYPE = np.dtype(
    [
        ("position", "<f4", 3),
        ("local", "<f4", 3),
        ("facade", "<f4", 2),  # u along the face, v up (metres)
        ("face", "<u4"),  # its row in the face table
    ]
)
GPU_VERTEX_FORMAT = "3f 3f 2f 1u"
GPU_VERTEX_ATTRIBUTES = ("in_position", "in_local", "in_facade", "in_face_row")

FACE_DTYPE = np.dtype(
    [
        ("normal", "<f4", 3),  # per vertex on curved walls and domes: such faces get a row per normal
        ("spacing", "<f4", 2),  # bay width, storey height (metres)
        ("face", "<f4", 4),  # the face's width, base, top, room depth (metres)
        ("ids", "<i4", 4),  # building index, surface kind, room column of the face's first and last bay
    ]
)
FACE_WORDS = FACE_DTYPE.itemsize // 4
FACES_BINDING = 11  # the storage buffer of the face table (common/building_vertex.glsl)
FACE_TABLE_CONSTANTS = {"FACE_WORDS": f"{FACE_WORDS}u", "FACES_BINDING": FACES_BINDING}
FNV_PRIME = np.uint64(0x100000001B3)  # the rows' hash (FNV-1a over their words)

# the words of a VERTEX_DTYPE record that FACE_DTYPE's fields come from, in FACE_DTYPE's order
_WORDS = np.r_[
    VERTEX_DTYPE.fields["normal"][1] // 4 : VERTEX_DTYPE.fields["normal"][1] // 4 + 3,
    VERTEX_DTYPE.fields["facade"][1] // 4 + 2 : VERTEX_DTYPE.itemsize // 4,
]


def face_table(vertices: np.ndarray, first_row: int = 0) -> tuple[np.ndarray, np.ndarray]:
    """VERTEX_DTYPE records as (GPU_VERTEX_DTYPE vertices, FACE_DTYPE rows): a row per distinct
    combination of face-table words (a face, or one normal of a curved face), compared bit for bit;
    the vertices' row indices start at `first_row` (a table made of several parts)."""
    words = np.ascontiguousarray(vertices).view(np.uint32).reshape(len(vertices), VERTEX_DTYPE.itemsize // 4)
    words = words[:, _WORDS]
    # runs of consecutive vertices alike first (a face's vertices are neighbours), then the runs' distinct rows
    starts = np.ones(len(vertices), bool)
    starts[1:] = np.any(words[1:] != words[:-1], axis=1)
    runs = words[starts]
    first, run_row = _distinct(runs)
    out = np.empty(len(vertices), GPU_VERTEX_DTYPE)
    for field in ("position", "local"):
        out[field] = vertices[field]
    out["facade"] = vertices["facade"][:, :2]
    out["face"] = run_row[np.cumsum(starts) - 1] + first_row
    return out, runs[first].view(FACE_DTYPE).ravel()


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


def expand_face_table(vertices: np.ndarray, table: np.ndarray, first_row: int = 0) -> np.ndarray:
    """face_table's inverse: the VERTEX_DTYPE records back (facade's bay width and storey height
    from the row, as the vertex stage reads them)."""
    out = np.zeros(len(vertices), VERTEX_DTYPE)
    rows = table[vertices["face"].astype(np.int64) - first_row]
    out["position"], out["local"], out["normal"] = vertices["position"], vertices["local"], rows["normal"]
    out["facade"][:, :2], out["facade"][:, 2:] = vertices["facade"], rows["spacing"]
    out["face"], out["ids"] = rows["face"], rows["ids"]
    return out
