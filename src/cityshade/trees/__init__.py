"""Procedural trees: species, generator, textures, placement, and the numpy twins of the fin
extrusion, cascade scheduling and LOD fade used by the tree renderer."""

from ._cascades import (
    SHADOW_CASTERS,
    EVERY_FRAME,
    PAPER_RATES,
    CascadeRate,
    cascade_view_projection,
    cascades_due,
    light_basis,
    slowed_rates,
    split_distances,
    texture_matrix,
)
from ._fins import extrude_fins, fin_width
from ._generator import (
    BRANCH_ATTRIBUTES,
    BRANCH_LAYOUT,
    CARD_ATTRIBUTES,
    CARD_LAYOUT,
    FROND_ATTRIBUTES,
    FROND_LAYOUT,
    TreeMesh,
    TreeModel,
    generate_tree,
    skeleton,
)
from ._lod import lod_alphas, vanish_alphas
from ._placement import SPECIES_ORDER, TREE_DTYPE, city_trees, park_trees, street_trees, tree_instances
from ._scene import SCENE_TIME, park_scene
from ._species import FIR, OAK, POPLAR, SPECIES, Species
from ._textures import BarkTextures, LeafTextures, bark_textures, leaf_textures

__all__ = [
    "SHADOW_CASTERS",
    "EVERY_FRAME",
    "PAPER_RATES",
    "CascadeRate",
    "cascade_view_projection",
    "cascades_due",
    "light_basis",
    "slowed_rates",
    "split_distances",
    "texture_matrix",
    "extrude_fins",
    "fin_width",
    "BRANCH_ATTRIBUTES",
    "BRANCH_LAYOUT",
    "CARD_ATTRIBUTES",
    "CARD_LAYOUT",
    "FROND_ATTRIBUTES",
    "FROND_LAYOUT",
    "TreeMesh",
    "TreeModel",
    "generate_tree",
    "skeleton",
    "lod_alphas",
    "vanish_alphas",
    "SPECIES_ORDER",
    "TREE_DTYPE",
    "city_trees",
    "park_trees",
    "street_trees",
    "tree_instances",
    "SCENE_TIME",
    "park_scene",
    "FIR",
    "OAK",
    "POPLAR",
    "SPECIES",
    "Species",
    "BarkTextures",
    "LeafTextures",
    "bark_textures",
    "leaf_textures",
]
