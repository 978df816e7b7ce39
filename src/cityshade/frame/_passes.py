"""A pass of the frame, the check that each pass's targets come from earlier passes, and the
runner that allocates the targets the passes declare and runs them in order."""

from __future__ import annotations

import time
from collections.abc import Callable, Sequence
from dataclasses import dataclass

from ..errors import UsageError
from ._context import Frame
from ._state import GLState
from ._targets import Target


@dataclass(frozen=True)
class Pass:
    """One step of the frame. `writes` is what it draws into: a Target, which the runner binds (and
    clears to `clear` if given) before `draw`, or the name of something the pass binds itself (the
    shadow maps, the depth pyramid). `reads` names what it draws from: Targets, which an earlier
    pass of the frame must write, and the names of the frame's other inputs. `scratch` holds
    targets only the pass itself draws into and reads."""

    name: str
    draw: Callable[[Frame], object]
    reads: tuple[Target | str, ...]
    writes: Target | str
    state: GLState = GLState()
    clear: tuple[float, float, float, float] | None = None
    scratch: tuple[Target, ...] = ()


def declared_targets(passes: Sequence[Pass]) -> list[Target]:
    """The targets the passes write, read or draw into on their own, each once; refused when a pass
    reads a target no earlier pass writes, or two passes declare one name differently."""
    written: dict[str, Target] = {}
    for p in passes:
        for read in p.reads:
            if isinstance(read, Target) and written.get(read.name) != read:
                earlier = "as declared" if read.name in written else "at all"
                raise UsageError(f"pass {p.name!r} reads target {read.name!r}, which no earlier pass writes {earlier}")
        for target in (*p.scratch, *((p.writes,) if isinstance(p.writes, Target) else ())):
            if written.setdefault(target.name, target) != target:
                raise UsageError(f"pass {p.name!r} declares target {target.name!r} unlike an earlier pass")
    return list(written.values())


def run_passes(f: Frame, passes: Sequence[Pass], times: dict[str, float] | None = None) -> None:
    """Makes the targets the passes declare, then runs them in order. With `times`, each pass's wall
    time in seconds is stored under its name, measured with ctx.finish() before and after it."""
    f.targets.allocate(declared_targets(passes), f.view.size, f.view.settings.samples)
    start = 0.0
    for p in passes:
        if times is not None:
            f.ctx.finish()
            start = time.perf_counter()
        if isinstance(p.writes, Target):
            target = f.targets[p.writes.name]
            target.use()
            if p.clear is not None:
                f.ctx.color_mask, f.ctx.depth_mask = (True,) * 4, True  # a clear writes only through the masks
                target.fbo.clear(*p.clear, depth=1.0)
        p.state.apply(f.ctx)
        p.draw(f)
        if times is not None:
            f.ctx.finish()
            times[p.name] = time.perf_counter() - start
