"""The frame's targets: each declared once, by name and spec, by the passes that write or read it;
the frame makes them from those declarations and keeps them until their spec, the frame's size or
its samples change."""

from __future__ import annotations

from collections.abc import Iterable
from dataclasses import dataclass

import moderngl

from ..errors import UsageError
from ..gl import RenderTarget

Attachments = tuple[tuple[str, int], ...]  # (dtype, components) of each colour attachment


@dataclass(frozen=True)
class Target:
    """A target of the frame: colour attachments and a depth buffer, at the frame's size divided by
    `divisor` (rounded up), multisampled at the frame's samples or single-sample, sampled with
    nearest or linear filtering (linear: clamped at the edges)."""

    name: str
    colours: Attachments = (("f2", 4),)
    multisampled: bool = False
    divisor: int = 1
    linear: bool = False

    def size(self, frame_size: tuple[int, int]) -> tuple[int, int]:
        d = self.divisor
        return ((frame_size[0] + d - 1) // d, (frame_size[1] + d - 1) // d)

    def make(self, ctx: moderngl.Context, frame_size: tuple[int, int], samples: int) -> RenderTarget:
        target = RenderTarget(ctx, self.size(frame_size), self.colours, samples=samples if self.multisampled else 0)
        if self.linear:
            for texture in target.colors:
                texture.filter = (moderngl.LINEAR, moderngl.LINEAR)
                texture.repeat_x = texture.repeat_y = False
        return target


class FrameTargets:
    """The targets the frame's passes declared, by name."""

    def __init__(self, ctx: moderngl.Context):
        self.ctx = ctx
        self._made: dict[str, tuple[tuple[Target, tuple[int, int], int], RenderTarget]] = {}

    def allocate(self, targets: Iterable[Target], frame_size: tuple[int, int], samples: int) -> None:
        """Makes each target not yet made as declared at this size and samples (remaking a stale one).
        Targets not declared now are kept while the size and samples stay (the frame and the id AOV
        take turns), released when those change."""
        for name, ((_, size, made_samples), stale) in list(self._made.items()):
            if (size, made_samples) != (frame_size, samples):
                stale.release()
                del self._made[name]
        for target in targets:
            key = (target, frame_size, samples)
            made = self._made.get(target.name)
            if made is not None and made[0] == key:
                continue
            if made is not None:
                made[1].release()
            self._made[target.name] = (key, target.make(self.ctx, frame_size, samples))

    def get(self, name: str) -> RenderTarget | None:
        made = self._made.get(name)
        return None if made is None else made[1]

    def __getitem__(self, name: str) -> RenderTarget:
        made = self._made.get(name)
        if made is None:
            raise UsageError(f"no target {name!r} in this frame: no pass that ran declared it")
        return made[1]

    def release(self) -> None:
        for _, target in self._made.values():
            target.release()
        self._made.clear()


HDR = Target("hdr", multisampled=True)  # the frame's linear colour, which every shading pass draws into
IDS = Target("ids", (("u4", 4),))  # the id AOV: face, room, building + 1, label per pixel
