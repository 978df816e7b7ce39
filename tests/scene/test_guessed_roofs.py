"""Roofs the map is silent about: flat ones get one of GUESSED_FLAT_ROOFS building by building (by
use), every guessed one a varied brightness; a tagged roof keeps its material and colour."""

from __future__ import annotations

from collections import Counter

import numpy as np
import pytest

from cityshade.scene import USES, BuildingMass, Roof, building_records, roof_material
from cityshade.scene.testing import GUESSED_FLAT_ROOFS, GUESSED_ROOF_SPREAD, guessed_roof, linear

SQUARE = ((0.0, 0.0), (10.0, 0.0), (10.0, 10.0), (0.0, 10.0))


def test_flat_roofs_vary_by_building_with_the_weights_of_their_use():
    homes = Counter(guessed_roof(seed, True, True, "roofing_felt", None)[0] for seed in range(4000))
    offices = Counter(guessed_roof(seed, False, True, "roofing_felt", None)[0] for seed in range(4000))
    for weights, counts in ((0, homes), (1, offices)):
        expected = Counter()
        for row in GUESSED_FLAT_ROOFS:
            expected[row[2]] += row[weights] / sum(r[weights] for r in GUESSED_FLAT_ROOFS)
        for material, share in expected.items():
            assert counts[material] / 4000 == pytest.approx(share, abs=0.03), (material, counts)
    assert offices["concrete"] > 2 * homes["concrete"]  # membranes on offices and shops
    assert guessed_roof(7, True, True, "roofing_felt", None) == guessed_roof(7, True, True, "roofing_felt", None)


def test_a_guessed_pitched_roof_keeps_its_material_and_varies_its_brightness():
    colours = np.array([guessed_roof(seed, True, False, "roof_tiles", None)[1] for seed in range(500)])
    base = np.array(roof_material("roof_tiles")[1])
    gain = colours / base
    assert {guessed_roof(s, True, False, "roof_tiles", None)[0] for s in range(50)} == {"roof_tiles"}
    assert np.allclose(gain, gain[:, :1], atol=1e-6)  # the hue kept
    assert gain.min() >= 1 - GUESSED_ROOF_SPREAD - 1e-6 and gain.max() <= 1 + GUESSED_ROOF_SPREAD + 1e-6
    assert gain.std() > GUESSED_ROOF_SPREAD / 3


def test_records_vary_only_the_roofs_the_map_did_not_give():
    guessed = {"roof_material", "roof_colour"}
    silent = [
        BuildingMass(
            "prism",
            (0.0, 0.0),
            SQUARE,
            10.0,
            seed=s,
            use=USES["home"],
            roof=Roof("flat", material="roofing_felt", colour=(0.4, 0.4, 0.41)),
            guessed=frozenset(guessed),
        )
        for s in range(40)
    ]
    tagged = [
        BuildingMass(
            "prism",
            (0.0, 0.0),
            SQUARE,
            10.0,
            seed=s,
            roof=Roof("flat", material="roofing_felt", colour=(0.3, 0.2, 0.1)),
        )
        for s in range(40)
    ]
    roofs = building_records(silent + tagged)["roof"]
    assert len({tuple(r) for r in roofs[:40]}) > 10, "silent roofs vary"
    assert np.allclose(roofs[40:, :3], linear((0.3, 0.2, 0.1))) and (roofs[40:, 3] == 0).all(), "tagged ones kept"
