"""The viewer's quality steps: what it gives up, one step at a time, when even its smallest
internal resolution misses the target frame rate (render/_resolution.py takes and releases them).

Each step is cheaper where the frame's cost does not shrink with the resolution: the shadow
cascades (their tree casters above all), the far trees, relief tracing. Steps add up:
step 3 keeps steps 1 and 2. At full quality (no step) the settings are the ones given.
"""

from __future__ import annotations

from dataclasses import dataclass, field, replace

from ..frame import RenderSettings
from ..trees import TreeSettings


@dataclass(frozen=True)
class QualityStep:
    name: str  # shown in the viewer's status line
    settings: dict = field(default_factory=dict)  # RenderSettings fields it sets
    trees: dict = field(default_factory=dict)  # TreeSettings fields it sets
    vanish: float = 1.0  # far trees fade out at this many times the image rows (TreeSettings.vanish_rows)


QUALITY_STEPS = (
    # the shadow pass is mostly trees cast into three cascades: redraw them half as often
    QualityStep("shadows every 2nd frame", settings={"shadow_refresh": 2}),
    # far trees are impostor cards (two triangles each) but still cost each tree's preparation and
    # pixels, in the view and in every cascade
    QualityStep("far trees fade sooner", vanish=2.0),
    # relief tracing of facades and bark, and the trunks' silhouette fins
    QualityStep("flat facades and bark", settings={"relief": False}, trees={"relief": False, "fins": False}),
    QualityStep("far trees fade much sooner", vanish=4.0),
    QualityStep("no shadows", settings={"shadows": False}),
)


def with_quality_steps(
    settings: RenderSettings, trees: TreeSettings, level: int, steps=QUALITY_STEPS
) -> tuple[RenderSettings, TreeSettings]:
    """The render and tree settings with the first `level` steps taken."""
    vanish = 1.0
    for step in steps[:level]:
        settings = replace(settings, **step.settings)
        trees = replace(trees, **step.trees)
        vanish = max(vanish, step.vanish)
    return settings, replace(trees, vanish_rows=tuple(rows * vanish for rows in trees.vanish_rows))


def quality_status(level: int, steps=QUALITY_STEPS) -> str:
    """The steps taken, for the status line ('' at full quality)."""
    return f"  quality -{level}: {', '.join(step.name for step in steps[:level])}" if level else ""
