"""What one frame shows (FrameView) and what it hands every pass (Frame): the GL context and
programs, the view, the targets, the city's buildings, the sky, the shadow maps, and each
technique's own state on the GPU, found by its type."""

from __future__ import annotations

from dataclasses import dataclass, field
from typing import Any, Protocol, TypeVar

import moderngl
import numpy as np

from ..gl import ProgramCache
from ..scene import Camera
from ._daylight import Daylight
from ._settings import RenderSettings
from ._targets import FrameTargets

T = TypeVar("T")


@dataclass
class FrameView:
    """What this frame shows: from where, when, how, at what size, and which frame it is."""

    camera: Camera
    settings: RenderSettings
    daylight: Daylight
    size: tuple[int, int]
    frame_index: int = 0  # the shadow cascades update at their own rates (SpeedTree §4.3.2)

    @property
    def view_projection(self) -> np.ndarray:
        return self.camera.view_projection(self.size[0] / self.size[1])

    @property
    def focal_rows(self) -> float:
        """The rows of the image one metre spans at one metre's distance."""
        return float(self.size[1] / (2.0 * np.tan(np.radians(self.camera.fov_y) / 2.0)))


class FrameCity(Protocol):
    """The city on the GPU, as passes draw it (render/_city_gpu.py)."""

    records: moderngl.Buffer  # the buildings' attributes (binding Buildings)
    visibility: Any  # render's BuildingVisibility: the cull passes' buffers, frustum tests and pyramid
    relief: Any  # relief.CityRelief: the openings and bays relief traces
    street_lights: Any  # the lamps the ground and facades are lit by

    def draw_buildings(
        self, program: moderngl.Program, view_projection: np.ndarray | None = None, draws: moderngl.Buffer | None = None
    ) -> None: ...

    def bind_lod_colours(self) -> None: ...

    def polygonised(self) -> Any: ...  # interior.PolygonisedGPU, made when first drawn


class ShadowMaps(Protocol):
    """The cascaded shadow maps, as a receiving program binds them."""

    def bind(self, program: moderngl.Program) -> None: ...


@dataclass
class Frame:
    """What one frame needs, handed to every pass. `camera_draws` and `depth_pyramid` are this
    frame's GPU culling of the camera's view, set by its cull passes (None without them)."""

    ctx: moderngl.Context
    programs: ProgramCache
    view: FrameView
    targets: FrameTargets
    city: FrameCity
    env: moderngl.TextureCube  # the sky's radiance with the sun and moon discs, for reflections
    sky: moderngl.TextureCube  # the same without the discs, which the sky pass draws per pixel
    shadows: ShadowMaps | None = None  # None: shadows off
    room_textures: dict[str, moderngl.Texture] = field(default_factory=dict)  # by sampler name
    techniques: dict[type, object] = field(default_factory=dict)  # a technique's GPU state, by its type
    camera_draws: moderngl.Buffer | None = None
    depth_pyramid: moderngl.Texture | None = None

    def technique(self, kind: type[T]) -> T | None:
        """The frame's `kind` (trees.TreePass, grammar.DeferredGrammarPass, ...); None where it draws none."""
        found = self.techniques.get(kind)
        return found if isinstance(found, kind) else None

    def draw_buildings(self, program: moderngl.Program, view_projection: np.ndarray | None = None) -> None:
        """The buildings seen through `view_projection` (default: the camera's), culled as
        settings.culling says: "gpu", the cull pass's commands for the camera and a frustum test on
        the GPU for any other view; "frustum", chunks on the CPU; "off", all."""
        city, culling = self.city, self.view.settings.culling
        view = self.view.view_projection if view_projection is None else view_projection
        if culling == "off":
            city.draw_buildings(program)
        elif culling == "frustum":
            city.draw_buildings(program, view)
        elif view_projection is None and self.camera_draws is not None:
            city.draw_buildings(program, draws=self.camera_draws)
        else:
            city.draw_buildings(program, draws=city.visibility.frustum(view))
