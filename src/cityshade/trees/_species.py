"""Tree species: the parameters of the branching generator, one frozen record per species."""

from __future__ import annotations

from dataclasses import dataclass


@dataclass(frozen=True)
class Species:
    name: str
    trunk_length: float  # metres
    trunk_radius: float  # metres at the base
    children: tuple[int, ...]  # branches per parent, one entry per branching level
    spread: tuple[float, ...]  # angle between child and parent, radians, per level
    length_ratio: tuple[float, ...]  # child length / parent length, per level
    branch_start: float  # fraction of the parent's length where children begin
    cone: float  # 1 = children shorten linearly toward the parent's tip (conifer), 0 = no shaping
    tropism: float  # bend per metre: + up, - droop
    gnarl: float  # random bend per segment, radians
    leaves_per_branch: int  # leaf cards on each branch of the last level
    leaf_size: float  # half the edge of a leaf card, metres
    leaf_cell: int  # cell of the leaf atlas used by the cards
    fronds: bool  # conifers carry frond ribbons along their last-level branches
    bark_layer: int  # layer of the bark texture array
    bark_tile: float  # metres of bark per texture repeat along a branch
    relief_depth: float  # metres: height of the bark relief (and width of the silhouette fins)


OAK = Species(
    name="oak",
    trunk_length=4.2,
    trunk_radius=0.30,
    children=(7, 4),
    spread=(0.95, 0.75),
    length_ratio=(0.62, 0.5),
    branch_start=0.45,
    cone=0.2,
    tropism=0.04,
    gnarl=0.16,
    leaves_per_branch=9,
    leaf_size=0.55,
    leaf_cell=0,
    fronds=False,
    bark_layer=0,
    bark_tile=0.7,
    relief_depth=0.06,
)
FIR = Species(  # a spruce or fir: a narrow cone of whorled boughs, each with side shoots in flat sprays
    name="fir",
    trunk_length=12.0,
    trunk_radius=0.26,
    children=(60, 6),
    spread=(1.6, 1.0),
    length_ratio=(0.3, 0.45),
    branch_start=0.08,
    cone=1.0,
    tropism=0.01,
    gnarl=0.05,
    leaves_per_branch=4,
    leaf_size=0.36,
    leaf_cell=2,
    fronds=True,
    bark_layer=1,
    bark_tile=0.6,
    relief_depth=0.03,
)
POPLAR = Species(
    name="poplar",
    trunk_length=11.0,
    trunk_radius=0.2,
    children=(18, 3),
    spread=(0.38, 0.45),
    length_ratio=(0.36, 0.5),
    branch_start=0.25,
    cone=0.6,
    tropism=0.05,
    gnarl=0.1,
    leaves_per_branch=6,
    leaf_size=0.45,
    leaf_cell=1,
    fronds=False,
    bark_layer=2,
    bark_tile=0.6,
    relief_depth=0.025,
)

PINE = Species(  # a Scots pine: a tall bare trunk under a high, open crown of upturned boughs
    name="pine",
    trunk_length=15.0,
    trunk_radius=0.28,
    children=(22, 6),
    spread=(1.2, 0.8),
    length_ratio=(0.28, 0.5),
    branch_start=0.55,
    cone=0.6,
    tropism=0.06,
    gnarl=0.12,
    leaves_per_branch=6,
    leaf_size=0.5,
    leaf_cell=2,
    fronds=True,
    bark_layer=1,
    bark_tile=0.6,
    relief_depth=0.03,
)

SPECIES = {s.name: s for s in (OAK, FIR, POPLAR, PINE)}  # the order numbers the instance records' species
