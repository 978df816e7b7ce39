"""A city's building masses as NumPy columns: what a City keeps of its buildings.

A BuildingMass as a Python object (a frozen dataclass, its footprint a tuple of tuples) costs about
a kilobyte; a city of 100,000 buildings held them for its whole life. The table keeps each number
in a column (float64, so every value reads back bit for bit), the footprints as one array of points
with each mass's first row, and the rarer values that are whole objects (roofs, courtyards, doors,
tags) in pools of distinct values indexed per mass: most masses share the same few. It reads as a
sequence of BuildingMass, each built when asked for (by index, or one after another).
"""

from __future__ import annotations

import operator
from array import array
from collections.abc import Iterable, Sequence
from dataclasses import fields

import numpy as np

from ._buildings import BuildingMass
from ._records import SHAPES

SHAPE_NAMES = tuple(SHAPES)
# integer columns (np.integer) take the narrowest integer type their values fit: a seed below 2**32
# needs no eight bytes; floats stay float64, so that every value reads back bit for bit
NUMBERS = {  # field -> dtype of its column
    "height": np.float64,
    "yaw": np.float64,
    "floor_height": np.float64,
    "room_width": np.float64,
    "seed": np.integer,
    "style": np.integer,
    "lights": np.float64,
    "use": np.integer,
    "shop_front": np.bool_,
    "wall_jitter": np.float64,
    "furniture": np.bool_,
    "curtains": np.bool_,
    "interior": np.bool_,
    "base": np.float64,
    "first_level": np.integer,
    "walls": np.bool_,
}
MASS_POOLS = (
    "holes",
    "roof",
    "wall_colour",
    "wall_material",
    "doors",
    "guessed",
    "given",
)  # objects: index into a pool
MASS_COLUMNS = {  # every column: dtype and shape past the first axis
    "shape": (np.uint8, ()),
    "position": (np.float64, (2,)),
    "footprint_start": (np.integer, ()),  # one more row than masses: the last is the points' count
    "footprint_points": (np.float64, (2,)),
    **{name: (dtype, ()) for name, dtype in NUMBERS.items()},
    **{name: (np.integer, ()) for name in MASS_POOLS},
}
ROW_COLUMNS = {name for name in MASS_COLUMNS if not name.startswith("footprint_")}  # one row per mass
VALUE_FIELDS = (*NUMBERS, *MASS_POOLS)  # a mass's fields besides shape, position and footprint, in column order
READ_CHUNK = 4096  # masses read at a time when iterating: their Python values are made a chunk at a time
TYPECODES = {np.float64: "d", np.integer: "q", np.uint8: "B", np.bool_: "B"}  # array.array's, while adding
STORED_FIELDS = {"shape", "position", "footprint", *NUMBERS, *MASS_POOLS}
if STORED_FIELDS != {f.name for f in fields(BuildingMass)}:  # a new field of BuildingMass needs a column
    raise ImportError(f"MassTable stores {sorted(STORED_FIELDS)}, not BuildingMass's fields")


class _Pool:
    """Distinct values in first-seen order; equal values (by repr: 0.0 and -0.0 stay apart) share a slot."""

    def __init__(self):
        self.values: list = []
        self._by_repr: dict[str, int] = {}
        self._by_id: dict[int, tuple[object, int]] = {}  # the value kept: its id is not reused meanwhile

    def index(self, value) -> int:
        seen = self._by_id.get(id(value))
        if seen is not None:
            return seen[1]
        key = f"{type(value).__qualname__}:{value!r}"
        slot = self._by_repr.setdefault(key, len(self.values))
        if slot == len(self.values):
            self.values.append(value)
        self._by_id[id(value)] = (value, slot)
        return slot


class MassColumns:
    """Masses added one at a time into growing C arrays (no Python object per number): a city built
    mass by mass, each mass dropped once added, leaves no heap of freed objects behind, which the
    allocator could not hand back while the city's other objects lie scattered among them."""

    def __init__(self):
        self._columns = {name: array(TYPECODES[dtype]) for name, (dtype, _) in MASS_COLUMNS.items()}
        self._columns["footprint_start"].append(0)
        self._pools = {name: _Pool() for name in MASS_POOLS}

    def append(self, mass: BuildingMass):
        c = self._columns
        c["shape"].append(SHAPES[mass.shape])
        c["position"].extend(mass.position)
        for point in mass.footprint:
            c["footprint_points"].extend(point)
        c["footprint_start"].append(len(c["footprint_points"]) // 2)
        for name, dtype in NUMBERS.items():
            value = getattr(mass, name)
            c[name].append(bool(value) if dtype is np.bool_ else value)
        for name, pool in self._pools.items():
            c[name].append(pool.index(getattr(mass, name)))

    def table(self) -> MassTable:
        return MassTable.from_columns(*self.arrays())

    def arrays(self) -> tuple[dict[str, np.ndarray], dict[str, list]]:
        """(columns, pools) as MassTable.from_columns takes them."""
        columns = {}
        for name, (dtype, shape) in MASS_COLUMNS.items():
            values = np.asarray(self._columns[name])
            values = _narrowest(values) if dtype is np.integer else values.astype(dtype)
            columns[name] = values.reshape(-1, *shape)
        return columns, {name: pool.values for name, pool in self._pools.items()}


class MassTable(Sequence):
    """Building masses in columns (MASS_COLUMNS), read back as BuildingMass objects equal bit for bit to
    those stored. Build one from masses (`MassTable(masses)`) or from checked columns (`from_columns`)."""

    __hash__ = None

    def __init__(self, masses: Iterable[BuildingMass] = ()):
        columns = MassColumns()
        for mass in masses:
            columns.append(mass)
        self._set(*columns.arrays())

    @classmethod
    def from_columns(cls, columns: dict[str, np.ndarray], pools: dict[str, list]) -> MassTable:
        """A table of these columns (MASS_COLUMNS, each as its dtype and shape) and pools (MASS_POOLS, the values
        the pooled columns index); ValueError naming the first column that does not fit."""
        table = cls.__new__(cls)
        table._set(columns, pools)
        return table

    def _set(self, columns: dict[str, np.ndarray], pools: dict[str, list]):
        _check(columns, pools)
        self._columns = {
            name: _one_if_constant(columns[name]) if name in ROW_COLUMNS else columns[name] for name in MASS_COLUMNS
        }
        self._pools = {name: list(pools[name]) for name in MASS_POOLS}

    def __setstate__(self, state: dict):  # unpickled (a tile cache's city): checked as from_columns
        self._set(state["_columns"], state["_pools"])

    def column(self, name: str) -> np.ndarray:
        """One column (MASS_COLUMNS), read only."""
        view = self._columns[name].view()
        view.flags.writeable = False
        return view

    def pool(self, name: str) -> tuple:
        """The distinct values a pooled column (MASS_POOLS) indexes."""
        return tuple(self._pools[name])

    @property
    def nbytes(self) -> int:
        """Bytes of the columns (the pools' objects not counted: a few shared values in most cities)."""
        return sum(
            column.itemsize * (column[:1].size if _constant(column) else column.size)
            for column in self._columns.values()
        )

    def __len__(self) -> int:
        return len(self._columns["shape"])

    def __getitem__(self, index):
        if isinstance(index, slice):
            start, stop, step = index.indices(len(self))
            if step == 1:
                return list(self._masses(start, max(start, stop)))
            return [self[i] for i in range(start, stop, step)]
        i = operator.index(index)
        if i < 0:
            i += len(self)
        if not 0 <= i < len(self):
            raise IndexError(f"mass index {index} out of range for {len(self)} masses")
        return next(self._masses(i, i + 1))

    def __iter__(self):
        for start in range(0, len(self), READ_CHUNK):
            yield from self._masses(start, min(start + READ_CHUNK, len(self)))

    def _masses(self, start: int, end: int):
        """Masses start..end-1, made from their rows as Python values."""
        c = self._columns
        first, last = c["footprint_start"][[start, end]].tolist()
        points = c["footprint_points"][first:last].tolist()
        corners = (c["footprint_start"][start : end + 1] - first).tolist()
        shapes, positions = c["shape"][start:end].tolist(), c["position"][start:end].tolist()
        numbers = [c[name][start:end].tolist() for name in NUMBERS]
        pooled = [[self._pools[name][k] for k in c[name][start:end].tolist()] for name in MASS_POOLS]
        for k, values in enumerate(zip(*numbers, *pooled)):
            yield BuildingMass(
                shape=SHAPE_NAMES[shapes[k]],
                position=tuple(positions[k]),
                footprint=tuple(map(tuple, points[corners[k] : corners[k + 1]])),
                **dict(zip(VALUE_FIELDS, values)),
            )

    def __eq__(self, other) -> bool:
        if not isinstance(other, (MassTable, list, tuple)):
            return NotImplemented
        return len(self) == len(other) and all(a == b for a, b in zip(self, other))

    def __add__(self, other) -> list[BuildingMass]:
        return list(self) + list(other)

    def __radd__(self, other) -> list[BuildingMass]:
        return list(other) + list(self)

    def __repr__(self) -> str:
        return f"MassTable({len(self)} masses, {self.nbytes:,} bytes of columns)"


def _constant(column: np.ndarray) -> bool:
    return column.ndim > 0 and column.strides[0] == 0


def _one_if_constant(column: np.ndarray) -> np.ndarray:
    """A column whose rows all hold the same bits (a district's yaws, its flags, its flat roofs) as
    that one row, broadcast (read only) to every mass; other columns as they are."""
    if len(column) < 2 or _constant(column):
        return column
    bits = column.reshape(len(column), -1).view(np.uint8)
    if not np.all(bits == bits[0]):
        return column
    return np.broadcast_to(column[:1].copy(), column.shape)


def _narrowest(values: np.ndarray) -> np.ndarray:
    """Integers (int64) as the narrowest integer type that holds them all."""
    if not len(values):
        return values.copy()
    low, high = int(values.min()), int(values.max())
    for dtype in (np.uint8, np.uint16, np.uint32) if low >= 0 else (np.int8, np.int16, np.int32):
        if np.iinfo(dtype).min <= low and high <= np.iinfo(dtype).max:
            return values.astype(dtype)
    return values.copy()


def _fits(dtype: np.dtype, wanted) -> bool:
    return np.issubdtype(dtype, np.integer) if wanted is np.integer else dtype == wanted


def _check(columns: dict[str, np.ndarray], pools: dict[str, list]):
    if set(columns) != set(MASS_COLUMNS):
        raise ValueError(f"mass table columns {sorted(columns)} are not {sorted(MASS_COLUMNS)}")
    if set(pools) != set(MASS_POOLS):
        raise ValueError(f"mass table pools {sorted(pools)} are not {sorted(MASS_POOLS)}")
    count = len(columns["shape"])
    for name, (dtype, shape) in MASS_COLUMNS.items():
        column = columns[name]
        rows = {"footprint_start": count + 1, "footprint_points": None}.get(name, count)
        if not isinstance(column, np.ndarray) or not _fits(column.dtype, dtype) or column.shape[1:] != shape:
            got = f"{column.dtype} {column.shape}" if isinstance(column, np.ndarray) else type(column).__name__
            wanted = "integers" if dtype is np.integer else np.dtype(dtype)
            raise ValueError(f"mass table column {name!r} holds {got}, not {wanted} (rows, *{shape})")
        if rows is not None and len(column) != rows:
            raise ValueError(f"mass table column {name!r} has {len(column)} rows, not {rows}")
    start = columns["footprint_start"]
    if start[0] != 0 or start[-1] != len(columns["footprint_points"]) or np.any(start[1:] < start[:-1]):
        raise ValueError("mass table column 'footprint_start' does not step through 'footprint_points' in order")
    if np.any(columns["shape"] >= len(SHAPE_NAMES)):
        raise ValueError(f"mass table column 'shape' holds a code beyond {len(SHAPE_NAMES) - 1}")
    for name in MASS_POOLS:
        index = columns[name]
        if len(index) and (index.min() < 0 or index.max() >= len(pools[name])):
            raise ValueError(f"mass table column {name!r} points outside its pool of {len(pools[name])} values")
