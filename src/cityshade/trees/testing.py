"""What the tests use of cityshade.trees's internals: its numpy twins and the parts they check one by one."""

from ._tree_cells import TreeCells
from ._tree_pass import INSTANCE_BYTES, PARTS

__all__ = ["INSTANCE_BYTES", "PARTS", "TreeCells"]
