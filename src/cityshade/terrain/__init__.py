"""The ground's relief: a DEM read under a map (`read_terrain`) as one `Terrain` that every stage
places things on (`Terrain.height_at`, vectorised over map metres)."""

from ._grid import Terrain
from ._read import TerrainWarning, read_terrain

__all__ = ["Terrain", "TerrainWarning", "read_terrain"]
