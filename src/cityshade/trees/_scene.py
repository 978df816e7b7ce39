"""The trees' own scene: a park at low sun, looking toward the sun through the trees, with a row
of buildings behind (back-lit leaves, god rays, long cascaded shadows; `cityshade render --scene trees`)."""

from __future__ import annotations

from ..scene import GROUND_GRASS, GROUND_PAVEMENT, Camera, City, box

SCENE_TIME = "18:20"  # low sun in the west (-x), about 10 degrees up


def park_scene(seed: int = 3) -> City:
    park = (-45.0, -40.0, 45.0, 40.0)
    ground = [(-60.0, -55.0, 60.0, 55.0, GROUND_PAVEMENT), (*park, GROUND_GRASS)]
    # Buildings along the park's north and south sides, in the low sun's long shadows.
    masses = [
        box((x, -70.0), 18.0, 14.0, h, seed=seed + i, style=i % 8)
        for i, (x, h) in enumerate(zip(range(-60, 60, 20), (22, 35, 18, 40, 26, 30)))
    ]
    masses += [
        box((x, 56.0), 18.0, 14.0, h, seed=seed + 10 + i, style=(i + 3) % 8)
        for i, (x, h) in enumerate(zip(range(-60, 60, 20), (28, 20, 45, 24, 32, 19)))
    ]
    viewpoints = {
        "park": Camera((30.0, 1.8, 4.0), (-20.0, 7.0, 0.0), fov_y=60.0, near=0.2, far=1500.0),
        "closeup": Camera((12.0, 2.5, 9.0), (0.0, 4.0, 2.0), fov_y=55.0, near=0.1, far=1500.0),
    }
    return City("park", seed, masses, ground, (-60.0, -75.0, 60.0, 75.0), viewpoints, parks=[park], streets=[])
