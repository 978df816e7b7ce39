"""Procedural trees: species, generator, textures, fin and cascade references, placement."""

from ._generator import TreeMesh, TreeModel, generate_tree, skeleton
from ._species import FIR, OAK, POPLAR, SPECIES, Species
from ._textures import BarkTextures, LeafTextures, bark_textures, leaf_textures

__all__ = [
    "TreeMesh", "TreeModel", "generate_tree", "skeleton",
    "FIR", "OAK", "POPLAR", "SPECIES", "Species",
    "BarkTextures", "LeafTextures", "bark_textures", "leaf_textures",
]
