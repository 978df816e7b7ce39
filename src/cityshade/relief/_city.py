"""Relief facades in the city: the buildings that can take them, and the shared window bay on the GPU."""

from __future__ import annotations

import moderngl

from ._compress import compress
from ._gpu import GpuFacade
from ._layout import generate_bay

FACADE_RELIEF = 2  # the record's facade.x for relief facades (shaders/relief/building.glsl)
RELIEF_STYLES = (2, 7)  # building styles drawn with relief: two of eight, a quarter of the box buildings
RELIEF_SHAPES = ("prism",)  # flat walls only


class CityRelief:
    """The city's window bay, BMF-compressed, ready to bind for the buildings' program."""

    def __init__(self, ctx: moderngl.Context):
        maps = generate_bay()
        self.facade = GpuFacade(ctx, maps, {"bmf": compress(maps, "bmf", source="city window bay")})

    def bind(self, program: moderngl.Program):
        if "u_relief_depth_unit" in program:
            program["u_relief_depth_unit"].value = self.facade.maps.depth_unit
        self.facade.bind(program, "bmf")

    def release(self):
        self.facade.release()
