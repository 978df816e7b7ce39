"""The shadow pass: three cascaded shadow maps redrawn at their own rates (§4.3.2).

Which cascade is redrawn on which frame, and with which casters, comes from
`trees.cascades_due`; each cascade keeps the light matrix it was last drawn with, so a cascade
that is not redrawn this frame is still looked up consistently. Receivers sample all three
(shaders/shadow/csm.glsl).
"""

from __future__ import annotations

from dataclasses import dataclass, field
from typing import Callable

import moderngl
import numpy as np

from ..frame import Frame
from ..gl import RenderTarget, bind_textures, set_uniforms
from ..scene import Camera
from ..trees import (
    PAPER_RATES,
    TreePass,
    cascade_view_projection,
    cascades_due,
    slowed_rates,
    split_distances,
    texture_matrix,
)

SHADOW_BIAS = 0.0008  # texture-depth units, every cascade

# Until a cascade is first drawn, its matrix sends every point outside [0, 1]: no shadow from it.
_OUTSIDE = np.array([[0, 0, 0, -1.0], [0, 0, 0, -1.0], [0, 0, 0, -1.0], [0, 0, 0, 1.0]])

# draw_casters(light view-projection, sun direction, casters) -> number of draw calls
DrawCasters = Callable[[np.ndarray, np.ndarray, frozenset], int]


@dataclass
class ShadowStats:
    """What the last update drew: (cascade, caster names, draw calls) per redrawn cascade."""

    redrawn: list[tuple[int, tuple[str, ...], int]] = field(default_factory=list)

    @property
    def draw_calls(self) -> int:
        return sum(calls for _, _, calls in self.redrawn)


class CascadedShadows:
    def __init__(
        self,
        ctx: moderngl.Context,
        resolution: int = 1024,
        shadow_far: float = 160.0,
        rates=PAPER_RATES,
        caster_reach: float = 120.0,
    ):
        self.ctx = ctx
        self.resolution = resolution
        self.shadow_far = shadow_far
        self.rates = rates
        self.caster_reach = caster_reach
        self.targets = [RenderTarget(ctx, (resolution, resolution), colors=()) for _ in rates]  # depth only
        self.maps = [target.depth for target in self.targets]
        for depth in self.maps:
            depth.compare_func = "<="
            depth.filter = (moderngl.LINEAR, moderngl.LINEAR)  # hardware 2x2 PCF per tap
            depth.repeat_x = depth.repeat_y = False
        self.matrices = [_OUTSIDE.copy() for _ in rates]
        self.drawn = [False for _ in rates]
        self.stats = ShadowStats()

    def splits(self, camera: Camera) -> np.ndarray:
        reach = self.shadow_far if camera.shadow_far is None else camera.shadow_far
        return split_distances(camera.near, min(reach, camera.far), len(self.rates))

    def update(
        self, frame: int, camera: Camera, aspect: float, sun_dir, draw_casters: DrawCasters, slower: int = 1
    ) -> ShadowStats:
        """Redraws the cascades due on this frame, at their rates made `slower` times less frequent.
        Leaves a shadow framebuffer bound: run it before the frame's target is bound."""
        ctx = self.ctx
        sun = np.asarray(sun_dir, float)
        inv = np.linalg.inv(camera.view_projection(aspect))
        splits = self.splits(camera)
        stats = ShadowStats()
        ctx.enable(moderngl.DEPTH_TEST)
        ctx.disable(moderngl.CULL_FACE)
        ctx.depth_func = "<"
        ctx.polygon_offset = (1.5, 4.0)
        due = dict(cascades_due(frame, slowed_rates(self.rates, slower)))
        # a cascade never drawn yet (new maps: a new resolution) is drawn now, not at its turn
        due.update({i: rate.casters for i, rate in enumerate(self.rates) if not self.drawn[i]})
        for index, casters in sorted(due.items()):
            view_proj = cascade_view_projection(
                inv, camera.near, camera.far, splits[index], splits[index + 1], sun, self.resolution, self.caster_reach
            )
            self.targets[index].use()
            self.targets[index].fbo.clear(depth=1.0)
            calls = draw_casters(view_proj, sun, casters)
            self.matrices[index] = texture_matrix(view_proj)
            self.drawn[index] = True
            stats.redrawn.append((index, tuple(sorted(casters)), calls))
        ctx.polygon_offset = (0.0, 0.0)
        self.stats = stats
        return stats

    def bind(self, program):
        """Binds the maps to their units and sets the receiver uniforms of shadow/csm.glsl."""
        if "u_shadow_matrix" not in program:
            return
        bind_textures(program, {f"u_shadow_map{i}": depth for i, depth in enumerate(self.maps)})
        # a variant that reads only the first cascades has a shorter array after compilation
        matrices = program["u_shadow_matrix"]
        matrices.write(np.stack([m.T for m in self.matrices[: matrices.array_length]]).astype("f4").tobytes())
        if "u_shadow_bias" in program:
            bias = program["u_shadow_bias"]
            bias.write(np.full(bias.array_length, SHADOW_BIAS, "f4").tobytes())

    def release(self):
        for target in self.targets:
            target.release()


def shadow_pass(f: Frame):
    """The frame's first pass: redraws the cascades due on f.view.frame_index with their casters
    (buildings as depth-only, trees through the tree pass)."""
    shadows, trees = f.shadows, f.technique(TreePass)
    if not isinstance(shadows, CascadedShadows):
        return

    def draw_casters(view_proj, sun, casters) -> int:
        calls = 0
        if "buildings" in casters:
            program = f.programs.get("city/building.glsl", {"DEPTH_ONLY": True})
            set_uniforms(program, u_view_proj=view_proj)
            f.draw_buildings(program, view_proj)
            calls += 1
        if trees is not None:
            trees.prepare(f.view.camera.eye, view_proj, f.view.focal_rows)  # the cascade's casters, as seen
            if f.view.settings.culling == "gpu":
                trees.cull(view_proj)  # the cascade's frustum
            calls += trees.draw_shadow(view_proj, sun, casters)
        return calls

    aspect = f.view.size[0] / f.view.size[1]
    shadows.update(
        f.view.frame_index,
        f.view.camera,
        aspect,
        f.view.daylight.sun_direction,
        draw_casters,
        f.view.settings.shadow_refresh,
    )
