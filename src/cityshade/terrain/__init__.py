"""The ground's relief: a DEM read under a map (`read_terrain`) as one `Terrain` that every stage
places things on (`Terrain.height_at`, vectorised over map metres), its chunked mesh with levels of
detail (`terrain_mesh`), and ground laid on it (`draped`, `raised`)."""

from ._drape import draped, raised, subdivided
from ._grid import Terrain
from ._mesh import terrain_mesh
from ._normals import face_normals
from ._read import TerrainWarning, read_terrain

__all__ = [
    "Terrain",
    "TerrainWarning",
    "draped",
    "face_normals",
    "raised",
    "read_terrain",
    "subdivided",
    "terrain_mesh",
]
