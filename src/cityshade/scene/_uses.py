"""What a building is used for, and the share of its rooms lit at each hour of the day.

A building's use is a small integer, `BuildingMass.use`, one of USES:

| code | name | lit |
|---|---|---|
| 0 | mixed (unknown, the built-in cities) | a blend: few by day, most in the evening, some after midnight |
| 1 | home (flats, houses, hotels) | mornings before work and the evening; dark in the small hours |
| 2 | office | the working day, 8 to 17; nearly dark at night |
| 3 | shop (retail, commercial) | opening hours, 9 to 21; dark when closed |
| 4 | industry (factories, warehouses) | the working shifts, 7 to 17 |
| 5 | public (schools, civic, churches, stations) | the day and the early evening |

The record carries the use in the bits of its flags above USE_SHIFT (the shaders' `building_use`).
Per frame the renderer turns the hour into one share per use (`lit_shares`) and a room is lit when
its hash (interior mapping's per-room randomness) is below share x the building's own `lights`.
"""

from __future__ import annotations

import numpy as np

USE_MIXED, USE_HOME, USE_OFFICE, USE_SHOP, USE_INDUSTRY, USE_PUBLIC = range(6)
USES = {
    "mixed": USE_MIXED,
    "home": USE_HOME,
    "office": USE_OFFICE,
    "shop": USE_SHOP,
    "industry": USE_INDUSTRY,
    "public": USE_PUBLIC,
}
USE_COUNT = len(USES)
USE_SHIFT = 8  # the flags' low bits are FLAG_*; the use sits above them
USE_MASK = 0xF
# for the shaders (cityshade.shader_constants)
USE_CODES = {
    **{f"USE_{name.upper()}": code for name, code in USES.items()},
    "USE_COUNT": USE_COUNT,
    "USE_SHIFT": USE_SHIFT,
    "USE_MASK": USE_MASK,
}

# Per use: (hour, share of lit rooms) points; linear between them, wrapping around midnight.
LIT_SCHEDULE: dict[int, tuple[tuple[float, float], ...]] = {
    USE_MIXED: ((0, 0.5), (3, 0.2), (6, 0.15), (9, 0.12), (16, 0.12), (18.5, 0.45), (21, 0.78), (23, 0.72)),
    USE_HOME: (
        (0, 0.3),
        (1.5, 0.1),
        (5, 0.05),
        (6.5, 0.4),
        (8, 0.3),
        (9, 0.08),
        (16, 0.08),
        (18, 0.5),
        (21, 0.8),
        (23, 0.55),
    ),
    USE_OFFICE: ((0, 0.02), (6, 0.03), (7.5, 0.45), (8.5, 0.85), (16.5, 0.85), (18, 0.4), (20, 0.1), (22, 0.03)),
    USE_SHOP: ((0, 0.0), (8, 0.0), (9, 0.95), (20.5, 0.95), (21.5, 0.0)),
    USE_INDUSTRY: ((0, 0.08), (6, 0.1), (7, 0.75), (16.5, 0.75), (17.5, 0.2), (22, 0.08)),
    USE_PUBLIC: ((0, 0.02), (7, 0.05), (8, 0.7), (16, 0.6), (18.5, 0.45), (21, 0.05)),
}
assert sorted(LIT_SCHEDULE) == list(range(USE_COUNT))


def lit_share(use: int, hours: float) -> float:
    """The share of a building's rooms lit at clock time `hours` (0..24) for a use code."""
    points = np.asarray(LIT_SCHEDULE[use], dtype=np.float64)
    return float(np.interp(hours % 24.0, points[:, 0], points[:, 1], period=24.0))


def lit_shares(hours: float, override: float | None = None) -> np.ndarray:
    """One share per use code at `hours`: the frame's `u_lit_share`; `override` (--lights) replaces them all."""
    if override is not None:
        return np.full(USE_COUNT, float(override))
    return np.array([lit_share(use, hours) for use in range(USE_COUNT)])
