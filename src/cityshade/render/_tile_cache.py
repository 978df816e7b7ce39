"""A city's buildings and ground cut into square tiles on disk, for streaming (docs/scale.md,
"Streaming").

A cache folder holds `manifest.json` (format, cityshade version and a hash of its source code,
vertex, face, ground and record layouts, the source file's name, size and SHA-256, and per tile
its file, bounds, counts, bytes and SHA-256), `city.pickle` (the City without the tiles' geometry:
masses, the ground no tile holds, trees, lamps, viewpoints; the building records with their
facades assigned; the cull pass's boxes in the whole city's order, each box's first vertex counted
within its tile) and `tiles/NNNNN.npz` (each tile's vertices as the GPU holds them, its buildings
one after another in box order; its own face table, scene/_face_table.py, the vertices' rows
counted from the tile's first; its ground triangles). A tile is the buildings whose masses stand
in one square of `tile_size` metres and the ground of that square; render/_tile_writer.py meshes
the city tile by tile, so cutting it never holds more than one tile's vertices.
The folder also carries cityshade's output marker (_files.atomic_folder), so that only a cache is
ever replaced by one.

Anything that does not match (another format, cityshade version or source code, vertex layout or
source file; a missing, truncated or altered file) raises CacheProblem with one line saying what;
the caller rebuilds the cache from the source or reports the line.
"""

from __future__ import annotations

import functools
import hashlib
import io
import json
import math
import os
import pickle
import re
import stat
import zipfile
import zlib
from dataclasses import dataclass
from pathlib import Path

import numpy as np

from .._files import InputError, read_input_bytes
from .._json import nesting_depth
from .._version import __version__
from ..errors import CityshadeError
from ..scene import BUILDING_DTYPE, FACE_DTYPE, GPU_VERTEX_DTYPE, City
from ._visibility import BOX_DTYPE

FORMAT = 2  # 2: each tile holds its own face table (1: one table for the city, in city.pickle)
TILE_SIZE = 256.0  # metres: about a district of a dozen blocks
MANIFEST = "manifest.json"
CITY_FILE = "city.pickle"
TILE_FOLDER = "tiles"
KIND = "tile-cache"  # its marker's kind (_files.OUTPUT_MARKER)
MANIFEST_LIMIT = 64 << 20  # bytes: about 200,000 tiles' entries
MAX_BYTES = 1 << 40  # the most a city file or tile may have (a TiB): bounds the manifest's counts
MANIFEST_NESTING = 4  # lists and objects: the manifest, its tiles, a tile, its bounds
SHA256 = re.compile("[0-9a-f]{64}")
TILE_NAME = re.compile(rf"{TILE_FOLDER}/[0-9]{{5,9}}\.npz")  # the names write_tiles gives
HASH_BLOCK = 1 << 20
GROUND_DTYPE = np.dtype((np.float32, 4))  # a ground vertex: x, y, z, material (render/_city_gpu.py)
# A resident tile's slot of the streaming arena holds its building vertices, its face rows from the
# first whole row after them, then its ground vertices likewise; slots start at multiples of
# SLOT_UNIT bytes, so that each part starts at a whole row of its own
SLOT_UNIT = int(np.lcm.reduce([GPU_VERTEX_DTYPE.itemsize, FACE_DTYPE.itemsize, GROUND_DTYPE.itemsize]))


def _whole(size: int, row: int) -> int:
    return -(-size // row) * row


def face_offset(vertices: int) -> int:
    """Bytes from a slot's start to its first face row."""
    return _whole(vertices * GPU_VERTEX_DTYPE.itemsize, FACE_DTYPE.itemsize)


def ground_offset(vertices: int, faces: int) -> int:
    """Bytes from a slot's start to its first ground vertex."""
    return _whole(face_offset(vertices) + faces * FACE_DTYPE.itemsize, GROUND_DTYPE.itemsize)


def slot_bytes(vertices: int, faces: int, ground: int) -> int:
    """The bytes of the slot that holds `vertices`, `faces` rows and `ground` vertices (whole SLOT_UNITs)."""
    return _whole(ground_offset(vertices, faces) + ground * GROUND_DTYPE.itemsize, SLOT_UNIT)


class CacheProblem(CityshadeError):
    """A tile cache that cannot be used as it is; the message names the folder and the reason."""

    def __init__(self, folder: Path, reason: str):
        super().__init__(f"tile cache {folder}: {reason}", exit_code=2)
        self.reason = reason


@dataclass(frozen=True)
class Tile:
    file: str
    bounds: tuple[float, float, float, float]  # x0, z0, x1, z1 of its buildings' boxes (metres)
    buildings: int
    vertices: int
    faces: int  # rows of its face table
    ground: int  # vertices of its ground triangles
    bytes: int  # the file's size
    sha256: str

    @property
    def resident_bytes(self) -> int:
        """What the tile holds once loaded: its slot of vertices, face rows and ground (on the GPU,
        or on the CPU on the way there)."""
        return slot_bytes(self.vertices, self.faces, self.ground)

    def distance(self, x: float, z: float) -> float:
        """Metres from (x, z) to the tile's bounds on the ground (0 inside)."""
        x0, z0, x1, z1 = self.bounds
        return float(np.hypot(max(x0 - x, 0.0, x - x1), max(z0 - z, 0.0, z - z1)))


@dataclass
class TileCache:
    """An opened (checked) cache: the city without its buildings' geometry, and the tiles' list."""

    folder: Path
    tiles: list[Tile]
    city: City
    records: np.ndarray  # BUILDING_DTYPE, facades assigned
    boxes: np.ndarray  # render/_visibility.py's BOX_DTYPE, whole-city order; draw[:, 1] within the tile
    box_tile: np.ndarray  # the tile of each box
    facades: dict
    lod_faces: np.ndarray  # SAMPLE_FACE_DTYPE, by building
    source: dict

    @property
    def total_bytes(self) -> int:
        return sum(t.resident_bytes for t in self.tiles)


def _sha256(data: bytes) -> str:
    return hashlib.sha256(data).hexdigest()


def source_identity(path: Path) -> dict:
    """The source file's name, size and SHA-256 (read in blocks)."""
    digest, size = hashlib.sha256(), 0
    with open(path, "rb") as handle:
        while block := handle.read(HASH_BLOCK):
            digest.update(block)
            size += len(block)
    return {"name": Path(path).name, "bytes": size, "sha256": digest.hexdigest()}


@functools.cache
def _code_hash() -> str:
    """A hash of cityshade's Python source: any change to how maps are read and meshed (which a
    version number does not follow between releases) makes caches from before it stale."""
    package = Path(__file__).resolve().parent.parent
    digest = hashlib.sha256()
    for path in sorted(package.rglob("*.py")):
        digest.update(path.relative_to(package).as_posix().encode() + b"\0" + path.read_bytes() + b"\0")
    return digest.hexdigest()[:16]


def _layouts() -> dict:
    """What must match for a cache to be read: its format, cityshade's version and source code, and
    the layouts."""
    return {
        "format": FORMAT,
        "cityshade": __version__,
        "meshing_code": _code_hash(),
        "vertex": str(GPU_VERTEX_DTYPE.descr),
        "faces": str(FACE_DTYPE.descr),
        "ground": str(GROUND_DTYPE.descr),
        "record": str(BUILDING_DTYPE.descr),
    }


def _damaged(folder: Path, what: str) -> CacheProblem:
    return CacheProblem(folder, f"{MANIFEST} is damaged ({what}); make the cache again")


def _inside(folder: Path, name: str) -> Path:
    """The file `name` (a name write_tiles gives) in the cache; one that a symbolic link takes out
    of the folder is refused, and nothing about it is said."""
    real = Path(os.path.realpath(folder))
    path = Path(os.path.realpath(real / name))
    if real not in path.parents:
        raise CacheProblem(folder, f"{name} leads outside the cache (a symbolic link); make the cache again")
    return path


def _read_checked(folder: Path, name: str, size: int, sha256: str) -> bytes:
    try:
        data = read_input_bytes(_inside(folder, name), size, "cache file")
    except InputError as exc:
        raise CacheProblem(folder, f"{name} is missing or damaged ({exc.reason})") from None
    if len(data) != size:
        raise CacheProblem(folder, f"{name} is damaged ({len(data)} bytes, the manifest says {size})")
    if _sha256(data) != sha256:
        raise CacheProblem(folder, f"{name} is damaged (its SHA-256 is not the manifest's)")
    return data


def _manifest(folder: Path) -> dict:
    if not folder.is_dir():
        raise CacheProblem(folder, "no such folder")
    if not (folder / MANIFEST).exists():
        raise CacheProblem(folder, f"no {MANIFEST}")
    try:
        data = read_input_bytes(_inside(folder, MANIFEST), MANIFEST_LIMIT, "tile manifest")
        if nesting_depth(data) > MANIFEST_NESTING:  # measured before json.loads recurses into it
            raise _damaged(folder, "nested too deeply")
        manifest = json.loads(data)
    except InputError as exc:
        raise CacheProblem(folder, f"{MANIFEST}: {exc.reason}") from None
    except (UnicodeDecodeError, ValueError) as exc:
        raise _damaged(folder, type(exc).__name__) from None
    if not isinstance(manifest, dict):
        raise _damaged(folder, "not an object")
    return manifest


def _shown(value) -> str:
    """A manifest's value for a message: short plain values only, never a whole structure."""
    text = repr(value) if isinstance(value, (str, int, float, type(None))) else "of another kind"
    return text if len(text) <= 80 else "another"


def _count(folder: Path, what: str, value) -> int:
    if isinstance(value, bool) or not isinstance(value, int) or not 0 <= value <= MAX_BYTES:
        raise _damaged(folder, f"{what} is not a whole number from 0 to {MAX_BYTES}")
    return value


def _tile(folder: Path, index: int, entry) -> Tile:
    """Tile `index` of the manifest, every field checked: a file name write_tiles gives, finite
    bounds, counts from 0 to MAX_BYTES, a SHA-256."""
    where = f"tile {index}"
    if not isinstance(entry, dict):
        raise _damaged(folder, f"{where} is not an object")
    bounds = entry.get("bounds")
    if not (
        isinstance(bounds, list)
        and len(bounds) == 4
        and all(isinstance(v, (int, float)) and not isinstance(v, bool) and math.isfinite(v) for v in bounds)
    ):
        raise _damaged(folder, f"{where}'s bounds are not four finite numbers")
    name, digest = entry.get("file"), entry.get("sha256")
    if not isinstance(name, str) or not TILE_NAME.fullmatch(name):
        raise _damaged(folder, f"{where}'s file is not a name like {TILE_FOLDER}/00000.npz")
    if not isinstance(digest, str) or not SHA256.fullmatch(digest):
        raise _damaged(folder, f"{where}'s sha256 is not 64 hexadecimal digits")
    counts = [_count(folder, f"{where}'s {key}", entry.get(key)) for key in _TILE_COUNTS]
    tile = Tile(name, tuple(float(v) for v in bounds), *counts, digest)
    if sum(rows * dtype.itemsize for rows, dtype in _parts(tile).values()) > tile.bytes:
        # np.savez stores the arrays as they are: a file never holds less than its arrays' bytes
        raise _damaged(folder, f"{where}'s counts need more bytes than its file has")
    return tile


def _parts(tile: Tile) -> dict:
    """The arrays of a tile's file: name -> (rows, row dtype)."""
    return {
        "vertices": (tile.vertices, GPU_VERTEX_DTYPE),
        "faces": (tile.faces, FACE_DTYPE),
        "ground": (tile.ground, GROUND_DTYPE),
    }


_TILE_COUNTS = ("buildings", "vertices", "faces", "ground", "bytes")


def _city_entry(folder: Path, entry) -> tuple[int, str]:
    if not isinstance(entry, dict) or entry.get("file") != CITY_FILE:
        raise _damaged(folder, f"its city is not {CITY_FILE}")
    digest = entry.get("sha256")
    if not isinstance(digest, str) or not SHA256.fullmatch(digest):
        raise _damaged(folder, "the city's sha256 is not 64 hexadecimal digits")
    return _count(folder, "the city's bytes", entry.get("bytes")), digest


def _file_size(folder: Path, name: str) -> int | None:
    """The size of a regular file in the cache, None for anything else."""
    try:
        info = os.stat(_inside(folder, name))
    except OSError:
        return None
    return info.st_size if stat.S_ISREG(info.st_mode) else None


def open_tiles(folder: Path, source: dict | None = None) -> TileCache:
    """The checked cache in `folder`; with `source` (source_identity), made from that file."""
    folder = Path(folder)
    manifest = _manifest(folder)
    for key, wanted in _layouts().items():
        if manifest.get(key) != wanted:
            raise CacheProblem(folder, f"made with {key} {_shown(manifest.get(key))}, this cityshade needs {wanted!r}")
    if source is not None and manifest.get("source") != source:
        made = manifest.get("source")
        made = made if isinstance(made, dict) else {}
        raise CacheProblem(
            folder, f"made from another file ({_shown(made.get('name'))}, {_shown(made.get('bytes'))} bytes)"
        )
    if not isinstance(manifest.get("tiles"), list):
        raise _damaged(folder, "its tiles are not a list")
    tiles = [_tile(folder, i, entry) for i, entry in enumerate(manifest["tiles"])]
    data = _read_checked(folder, CITY_FILE, *_city_entry(folder, manifest.get("city")))
    for tile in tiles:
        size = _file_size(folder, tile.file)
        if size != tile.bytes:
            raise CacheProblem(
                folder, f"{tile.file} is missing or damaged ({size} bytes, the manifest says {tile.bytes})"
            )
    try:
        rest = _CityUnpickler(io.BytesIO(data)).load()  # checked against the manifest's SHA-256 first
    except _ForeignObject as exc:
        raise CacheProblem(
            folder, f"{CITY_FILE} {exc}; a tile cache never holds that: rebuild it with cityshade tile"
        ) from None
    except Exception as exc:  # noqa: BLE001 - any unpickling failure means a damaged file
        raise CacheProblem(folder, f"{CITY_FILE} cannot be read ({type(exc).__name__})") from None
    _check_rest(folder, rest, tiles)
    return TileCache(
        folder,
        tiles,
        rest["city"],
        rest["records"],
        rest["boxes"],
        rest["box_tile"],
        rest["facades"],
        rest["lod_faces"],
        manifest.get("source"),
    )


def _check_rest(folder: Path, rest, tiles: list[Tile]):
    """The unpickled city's parts and the tile indices and vertex ranges its boxes name, which the
    streamer indexes with."""
    kinds = {"city": City, "records": np.ndarray, "boxes": np.ndarray, "box_tile": np.ndarray, "facades": dict}
    kinds["lod_faces"] = np.ndarray
    if not isinstance(rest, dict) or not all(isinstance(rest.get(k), kind) for k, kind in kinds.items()):
        raise CacheProblem(folder, f"{CITY_FILE} is not a tile cache's city; make the cache again")
    boxes, box_tile, records = rest["boxes"], rest["box_tile"], rest["records"]
    if (
        boxes.dtype != BOX_DTYPE
        or records.dtype != BUILDING_DTYPE
        or box_tile.dtype.kind not in "iu"
        or box_tile.shape != boxes.shape
    ):
        raise CacheProblem(folder, f"{CITY_FILE} holds boxes or records of another layout")
    if len(box_tile) and not (0 <= box_tile.min() and box_tile.max() < len(tiles)):
        raise CacheProblem(folder, f"{CITY_FILE} has boxes of tiles the manifest does not list")
    vertices = np.array([t.vertices for t in tiles] or [0], np.int64)[box_tile]
    draw = boxes["draw"].astype(np.int64)
    if np.any(draw[:, 0] + draw[:, 1] > vertices) or (len(draw) and draw[:, 2].max() >= len(records)):
        raise CacheProblem(folder, f"{CITY_FILE} has boxes of vertices or buildings its tiles do not hold")


class _ForeignObject(pickle.UnpicklingError):
    pass


# what the pickled City is made of besides cityshade's own classes: numpy arrays and builtins
_NUMPY_GLOBALS = {
    ("numpy", "ndarray"),
    ("numpy", "dtype"),
    ("numpy.core.multiarray", "_reconstruct"),
    ("numpy._core.multiarray", "_reconstruct"),
    ("numpy.core.multiarray", "scalar"),
    ("numpy._core.multiarray", "scalar"),
    ("numpy.core.numeric", "_frombuffer"),
    ("numpy._core.numeric", "_frombuffer"),
    ("builtins", "set"),
    ("builtins", "frozenset"),
    ("collections", "Counter"),
    ("collections", "OrderedDict"),
}


class _CityUnpickler(pickle.Unpickler):
    """Unpickles only cityshade's own classes, numpy arrays and plain containers: a cache folder
    can come from elsewhere, and a pickle naming any other function (os.system, ...) could run it."""

    def find_class(self, module: str, name: str):
        if (module, name) in _NUMPY_GLOBALS:
            return super().find_class(module, name)
        if module == "cityshade" or module.startswith("cityshade."):
            found = super().find_class(module, name)
            if isinstance(found, type):  # a class, never a function
                return found
        raise _ForeignObject(f"refers to {module}.{name}")


def read_tile(cache: TileCache, index: int) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """Tile `index`'s vertices, face rows and ground vertices, checked against the manifest (size,
    SHA-256, layouts)."""
    tile = cache.tiles[index]
    data = _read_checked(cache.folder, tile.file, tile.bytes, tile.sha256)
    arrays = {}
    try:
        with zipfile.ZipFile(io.BytesIO(data)) as archive:
            for name, (rows, dtype) in _parts(tile).items():
                with archive.open(f"{name}.npy") as member:  # the header first: nothing larger is allocated
                    shape, fortran, stored = _NPY_HEADERS[np.lib.format.read_magic(member)](member)
                    if stored != dtype.base or shape != (rows, *dtype.shape) or fortran:
                        raise CacheProblem(
                            cache.folder, f"{tile.file} holds {name} of another layout or count than its tile's"
                        )
                    array = np.empty(shape, dtype.base)  # then the data, read once into its array
                    if member.readinto(memoryview(array.reshape(-1)).cast("B")) != array.nbytes:
                        raise EOFError(f"{name}.npy is cut short")
                    arrays[name] = array
    except (ValueError, KeyError, OSError, EOFError, NotImplementedError, zipfile.BadZipFile, zlib.error) as exc:
        raise CacheProblem(cache.folder, f"{tile.file} cannot be read ({type(exc).__name__}: {exc})") from None
    vertices, faces, ground = arrays["vertices"], arrays["faces"], arrays["ground"]
    if len(vertices) and int(vertices["face"].max()) >= len(faces):
        raise CacheProblem(cache.folder, f"{tile.file} has vertices of face rows it does not hold")
    return vertices, faces, ground


_NPY_HEADERS = {(1, 0): np.lib.format.read_array_header_1_0, (2, 0): np.lib.format.read_array_header_2_0}
