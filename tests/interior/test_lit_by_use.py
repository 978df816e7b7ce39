"""Lit windows by use and hour: the schedule (cityshade.scene.LIT_SCHEDULE) and, on the GPU against
the numpy twin, which rooms of an office and a home are lit at 10:00 and at 22:00."""

from __future__ import annotations

import numpy as np
import pytest
import shapely
from PIL import Image

from cityshade.maps import MapBuilding, ReadReport
from cityshade.maps.testing import building_attributes, use_code
from cityshade.render import Renderer, RenderSettings
from cityshade.scene import FLAGS, LIT_SCHEDULE, USE_CODES, USE_COUNT, USES, Camera, City, box, lit_share, lit_shares
from render_checks import interior_twin

HOME, OFFICE, SHOP, MIXED = USES["home"], USES["office"], USES["shop"], USES["mixed"]
MINUTES = np.arange(24 * 60) / 60.0
LIT, SEEN = 2, 1  # room state bits (cityshade.interior.room_state)


def _shares(use: int) -> np.ndarray:
    return np.array([lit_share(use, h) for h in MINUTES])


@pytest.mark.parametrize("use", range(USE_COUNT))
def test_every_share_is_a_probability_and_the_day_wraps_at_midnight(use):
    shares = _shares(use)
    assert shares.min() >= 0.0 and shares.max() <= 1.0
    assert abs(lit_share(use, 23.9999) - lit_share(use, 0.0)) < 1e-3, "a jump at midnight"
    assert lit_share(use, 24.0 + 7.5) == pytest.approx(lit_share(use, 7.5)), "the clock wraps"
    assert np.abs(np.diff(shares)).max() < 0.1, "no share jumps within a minute"


def test_offices_are_lit_in_the_working_day_and_dark_at_night():
    office = _shares(OFFICE)
    day, night = (MINUTES >= 9) & (MINUTES <= 16), (MINUTES >= 21) | (MINUTES <= 5)
    assert office[day].min() >= 0.7 and office[night].max() <= 0.1


def test_homes_light_up_in_the_evening_and_early_morning():
    home = _shares(HOME)
    working_day = home[(MINUTES >= 10) & (MINUTES <= 15)]
    assert home[(MINUTES >= 19.5) & (MINUTES <= 22)].min() > 4 * working_day.max()
    assert home[(MINUTES >= 6.5) & (MINUTES <= 7)].min() > 3 * working_day.max(), "breakfast"
    assert home[(MINUTES >= 2) & (MINUTES <= 4.5)].max() <= 0.1, "asleep"


def test_shops_are_lit_while_open_only():
    shop = _shares(SHOP)
    assert shop[(MINUTES >= 9) & (MINUTES <= 20.5)].min() >= 0.9
    assert shop[(MINUTES >= 21.5) | (MINUTES <= 8)].max() == 0.0


def test_lights_override_every_use_and_the_table_covers_every_code():
    assert np.array_equal(lit_shares(13.0, override=0.3), np.full(USE_COUNT, 0.3))
    assert lit_shares(13.0)[OFFICE] == lit_share(OFFICE, 13.0)
    assert sorted(LIT_SCHEDULE) == sorted(USES.values()) == list(range(USE_COUNT))
    assert USE_CODES["USE_MASK"] >= USE_COUNT - 1


def test_the_use_sits_above_the_flags_and_unknown_codes_are_refused():
    plain, office = box((0, 0), 10, 10, 10), box((0, 0), 10, 10, 10, use=OFFICE)
    assert office.flags >> USE_CODES["USE_SHIFT"] == OFFICE
    assert office.flags & ((1 << USE_CODES["USE_SHIFT"]) - 1) == plain.flags
    assert box((0, 0), 10, 10, 10, shop_front=True).flags & FLAGS["FLAG_SHOP_FRONT"]
    with pytest.raises(ValueError, match="use code"):
        box((0, 0), 10, 10, 10, use=USE_COUNT)


# --- GPU against the twin ---------------------------------------------------------------------

SIZE = (160, 120)
MASSES = [
    box((0.0, 0.0), 16.0, 10.0, 15.0, seed=11, room_width=4.0, floor_height=3.0, use=OFFICE),
    box((18.0, 0.0), 16.0, 10.0, 15.0, seed=12, room_width=4.0, floor_height=3.0, use=HOME, shop_front=True),
]
BOUNDS = (-30.0, -30.0, 50.0, 30.0)
CAMERA = Camera((17.0, 7.5, -22.0), (17.0, 7.5, 5.0), fov_y=70.0)


def _lit_rooms(ids: np.ndarray, building: int, ground: bool) -> tuple[set[int], set[int]]:
    """(lit, all) room ids of a building (index + 1 in the id AOV) seen in a picture, on the ground
    floor or above it."""
    floor = ids[..., 1] >> 22  # cityshade.interior.room_id
    seen = (ids[..., 2] == building) & (ids[..., 3] & SEEN).astype(bool) & ((floor == 0) == ground)
    lit = seen & (ids[..., 3] & LIT).astype(bool)
    return set(ids[..., 1][lit].tolist()), set(ids[..., 1][seen].tolist())


def test_office_home_and_shop_rooms_lit_by_hour_match_the_twin(gl_context, output_dir):
    renderer = Renderer(SIZE, RenderSettings(samples=0, god_rays=False), ctx=gl_context)
    counts = {}
    try:
        renderer.set_city(City("uses", 0, MASSES, [], BOUNDS))
        for hours in (10.0, 22.0):
            renderer.set_settings(renderer.settings.with_(time_of_day=hours))
            gpu = renderer.render_ids(CAMERA, room_state=True)
            Image.fromarray(renderer.render(CAMERA)).save(output_dir / f"lit_by_use_{hours:02.0f}h.png")
            ref = interior_twin(renderer, MASSES, CAMERA, SIZE, BOUNDS, lights=tuple(lit_shares(hours)))
            same = np.all(gpu[..., :3] == ref[..., :3], axis=-1) & (ref[..., 3] & SEEN).astype(bool)
            pixels_differ = same & ((gpu[..., 3] ^ ref[..., 3]) & LIT).astype(bool)
            for name, building, ground in (("office", 1, False), ("home", 2, False), ("shop", 2, True)):
                gpu_lit, gpu_rooms = _lit_rooms(np.where(same[..., None], gpu, 0), building, ground)
                ref_lit, _ = _lit_rooms(np.where(same[..., None], ref, 0), building, ground)
                counts[name, hours] = (len(gpu_lit), len(gpu_rooms), len(gpu_lit ^ ref_lit))
            print(
                f"{hours:05.2f}h: {same.sum()} room pixels compared, {pixels_differ.sum()} differ in light; "
                + ", ".join(
                    f"{n}: {lit} of {rooms} rooms lit, {wrong} lit differently"
                    for (n, h), (lit, rooms, wrong) in counts.items()
                    if h == hours
                )
            )
            assert same.sum() > 1000, "the view must look into both buildings' rooms"
            assert not pixels_differ.any(), f"{pixels_differ.sum()} room pixels differ in light"
    finally:
        renderer.release()
    assert all(wrong == 0 for _, _, wrong in counts.values())
    share = {key: lit / rooms for key, (lit, rooms, _) in counts.items()}
    assert share["office", 10.0] > 0.6 and share["office", 22.0] < 0.15
    assert share["home", 22.0] > 0.4 and share["home", 10.0] < 0.25
    assert share["shop", 10.0] >= 0.75 and share["shop", 22.0] == 0.0, "the shops below the flats keep their hours"


@pytest.mark.parametrize(
    "tags, use",
    [
        ({"building": "office"}, "office"),
        ({"building": "apartments"}, "home"),
        ({"building": "yes", "shop": "bakery"}, "shop"),
        ({"building": "yes", "amenity": "school"}, "public"),
        ({"building": "warehouse"}, "industry"),
        ({"building": "yes"}, "mixed"),
    ],
)
def test_map_buildings_take_their_use_from_the_tags(tags, use):
    building = MapBuilding(0, "way/1", shapely.box(0, 0, 10, 10), kind=tags["building"])
    building_attributes(building, tags, ReadReport())
    assert use_code(building) == USES[use]
