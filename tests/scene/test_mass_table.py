"""The city's columnar store of building masses (scene.MassTable): every mass reads back bit for bit
as it was stored, and columns that do not fit are refused."""

import dataclasses
import pickle
from pathlib import Path

import numpy as np
import pytest

from cityshade.maps import building_masses, guess_missing, load_map
from cityshade.scene import (
    MASS_COLUMNS,
    MASS_POOLS,
    BuildingMass,
    City,
    MassColumns,
    MassTable,
    Roof,
    box,
    default_city,
    dome,
    make_city,
)

MAPS = Path(__file__).parents[1] / "data" / "maps"


def _bits(value):
    """`value` as comparable parts, each float as its 8 bytes (0.0 and -0.0, one ulp apart: different)."""
    if isinstance(value, (bool, np.bool_, str)) or value is None:
        return (type(value).__name__ if value is not None else None, value)
    if isinstance(value, (float, np.floating)):
        return ("float", np.float64(value).tobytes())
    if isinstance(value, (int, np.integer)):
        return ("int", int(value))
    if isinstance(value, (tuple, list)):
        return tuple(_bits(v) for v in value)
    if isinstance(value, frozenset):
        return ("set", tuple(sorted(value)))
    if dataclasses.is_dataclass(value):
        return (type(value).__name__, tuple(_bits(getattr(value, f.name)) for f in dataclasses.fields(value)))
    raise TypeError(f"no bits for {type(value)}")


def _odd_masses() -> list[BuildingMass]:
    """Masses with every field away from its default, values that compare equal but differ in bits."""
    roof = Roof("gabled", 4.5, direction=-0.0, colour=(0.5, 0.25, 0.125), material="tiles", seed=9, attic_storey=2.5)
    return [
        BuildingMass(
            "prism",
            (np.float64(-3.25), 1e-300),
            ((0.0, 0.0), (12.0, 0.0), (12.0, 9.0), (6.0, 11.5), (0.0, 9.0)),
            21.5,
            yaw=np.nextafter(0.6, 1.0),
            floor_height=3.1,
            room_width=4.25,
            seed=2**40 + 3,
            style=5,
            lights=0.0,
            use=3,
            shop_front=True,
            wall_jitter=0.0,
            furniture=False,
            curtains=False,
            interior=False,
            holes=(((3.0, 3.0), (3.0, 5.0), (5.0, 5.0), (5.0, 3.0)),),
            base=2.0,
            first_level=2,
            roof=roof,
            wall_colour=(0.9, 0.8, 0.7),
            wall_material="brick",
            doors=((6.0, 0.0, 0.0, -1.0), (12.0, 4.0, 1.0, -0.0)),
            guessed=frozenset({"height", "roof_shape"}),
        ),
        dataclasses.replace(box((1.0, 2.0), 8.0, 6.0, 9.0), roof=dataclasses.replace(roof, direction=0.0)),
        dome((-0.0, 5.0), 14.0, walls=True, seed=-7),
        box((0.0, 0.0), 5.0, 5.0, 3.0, walls=False, base=1.0),
    ]


def _map_masses(name: str) -> list[BuildingMass]:
    data = load_map(MAPS / name)
    data = guess_missing(data)
    return building_masses(data)


@pytest.mark.parametrize(
    "masses",
    [
        pytest.param(_odd_masses, id="every-field"),
        pytest.param(lambda: list(default_city(blocks=3).masses), id="district"),
        pytest.param(lambda: list(make_city("outlines").masses), id="outlines"),
        pytest.param(lambda: _map_masses("tagged.osm"), id="tagged-map"),
        pytest.param(lambda: _map_masses("roofs_dormers.osm"), id="roofs-map"),
        pytest.param(lambda: _map_masses("entrances.osm"), id="doors-map"),
    ],
)
def test_masses_read_back_bit_for_bit(masses):
    masses = masses()
    table = MassTable(masses)
    assert len(table) == len(masses) > 0
    for read in (list(table), [table[i] for i in range(len(table))], table[:]):
        differing = [i for i, (a, b) in enumerate(zip(read, masses)) if _bits(a) != _bits(b)]
        assert not differing, f"{len(differing)} of {len(masses)} masses differ, first {differing[:5]}"
    assert _bits(table[-1]) == _bits(masses[-1])
    unpickled = pickle.loads(pickle.dumps(table))  # as a tile cache stores the city
    assert [_bits(m) for m in unpickled] == [_bits(m) for m in masses]


def _columns(table: MassTable) -> tuple[dict, dict]:
    """Copies of a table's columns and pools, to change."""
    return {name: table.column(name).copy() for name in MASS_COLUMNS}, {
        name: list(table.pool(name)) for name in MASS_POOLS
    }


def test_one_ulp_in_a_column_is_seen():
    """The comparison above can fail: a height one ulp up, a yaw of -0.0 for 0.0, read back as other masses."""
    masses = _odd_masses()
    columns, pools = _columns(MassTable(masses))
    columns["height"][0] = np.nextafter(columns["height"][0], np.inf)
    columns["yaw"][1] = -0.0
    changed = MassTable.from_columns(columns, pools)
    assert _bits(changed[0]) != _bits(masses[0])
    assert changed[1] == masses[1] and _bits(changed[1]) != _bits(masses[1])  # equal numbers, other bits
    assert [_bits(m) for m in changed[2:]] == [_bits(m) for m in masses[2:]]


def _wrong_dtype(columns, pools):
    columns["height"] = columns["height"].astype(np.float32)


def _wrong_rows(columns, pools):
    columns["seed"] = columns["seed"][:-1]


def _wrong_shape(columns, pools):
    columns["position"] = columns["position"][:, 0]


def _missing(columns, pools):
    del columns["roof"]


def _unknown(columns, pools):
    columns["colour"] = columns["height"]


def _footprints_out_of_step(columns, pools):
    columns["footprint_start"][2] = columns["footprint_start"][3] + 1


def _shape_code(columns, pools):
    columns["shape"][0] = 7


def _outside_pool(columns, pools):
    columns["doors"][1] = len(pools["doors"])


def _float_seeds(columns, pools):
    columns["seed"] = columns["seed"].astype(np.float64)


def _not_an_array(columns, pools):
    columns["walls"] = list(columns["walls"])


@pytest.mark.parametrize(
    "damage, named",
    [
        (_wrong_dtype, "'height' holds float32"),
        (_wrong_rows, "'seed' has 3 rows, not 4"),
        (_wrong_shape, "'position' holds float64 (4,)"),
        (_missing, "columns"),
        (_unknown, "columns"),
        (_footprints_out_of_step, "'footprint_start'"),
        (_shape_code, "'shape' holds a code"),
        (_outside_pool, "'doors' points outside its pool"),
        (_float_seeds, "'seed' holds float64 (4,), not integers"),
        (_not_an_array, "'walls' holds list"),
    ],
)
def test_a_wrong_column_is_refused(damage, named):
    columns, pools = _columns(MassTable(_odd_masses()))
    damage(columns, pools)
    with pytest.raises(ValueError, match="mass table") as refused:
        MassTable.from_columns(columns, pools)
    assert named in str(refused.value)


def test_a_damaged_pickle_is_refused():
    """A pickled table (a tile cache's city) is checked as it is read back."""
    table = MassTable(_odd_masses())
    table._columns["yaw"] = table._columns["yaw"].astype(np.float32)
    with pytest.raises(ValueError, match="'yaw' holds float32"):
        pickle.loads(pickle.dumps(table))


def test_columns_added_mass_by_mass_are_the_table():
    """default_city adds its masses one by one (MassColumns); integers narrowed where they fit."""
    masses = _odd_masses() + list(default_city(blocks=2).masses)
    columns = MassColumns()
    for mass in masses:
        columns.append(mass)
    table = columns.table()
    assert [_bits(m) for m in table] == [_bits(m) for m in MassTable(masses)] == [_bits(m) for m in masses]
    assert table.column("seed").dtype == np.int64  # 2**40 + 3 and -7
    assert table.column("use").dtype == table.column("roof").dtype == np.uint8
    assert MassTable(masses[4:]).column("seed").dtype == np.uint32


def test_a_column_of_one_value_is_stored_once():
    """A district's yaws, flags and roofs are the same for every mass: one row each, broadcast;
    0.0 and -0.0 are not the same value."""
    city = default_city(blocks=3)
    masses = list(city.masses)
    assert city.masses.column("yaw").strides[0] == city.masses.column("roof").strides[0] == 0
    assert city.masses.column("seed").strides[0] > 0
    assert city.masses.nbytes < sum(city.masses.column(name).nbytes for name in MASS_COLUMNS) - 20 * len(masses)
    turned = [box((0.0, 0.0), 4.0, 4.0, 9.0, yaw=yaw) for yaw in (0.0, -0.0, 0.0)]
    table = MassTable(turned)
    assert table.column("yaw").strides[0] > 0
    assert [_bits(m) for m in table] == [_bits(m) for m in turned]


def test_a_city_keeps_its_masses_as_a_table():
    city = default_city(blocks=2)
    assert isinstance(city.masses, MassTable)
    masses = list(city.masses)
    moved = dataclasses.replace(city, masses=[dataclasses.replace(m, style=1) for m in masses])
    assert isinstance(moved.masses, MassTable) and {m.style for m in moved.masses} == {1}
    assert City("list", 0, masses, [], city.bounds).masses == masses
    assert city.masses + masses[:1] == masses + masses[:1] == masses[:0] + city.masses + masses[:1]
    assert np.array_equal(city.masses.column("position"), [m.position for m in masses])
    with pytest.raises(IndexError):
        city.masses[len(masses)]
