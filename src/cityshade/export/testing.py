"""What the tests use of cityshade.export's internals: its numpy twins and the parts they check one by one."""

from ._bake import check_size
from ._content import BuildingWriter, Stats
from ._gltf import Document

__all__ = ["BuildingWriter", "Document", "Stats", "check_size"]
