"""What every map feature module is: the tags it reads (its defaults beside them), the records it
adds to MapData, what `cityshade info` says of it, and the layer of the city it builds.

Flat ground is shared: each feature names the surfaces it claims with a rank, and the ground is cut
in rank order (maps/_ground.py), each surface losing what ranks above it claims, so no two
surfaces overlap. Ranks so far: carriageways 10, ballast 20, pavements beside roads 30, water 40,
paved squares 50, sand 60, green 70.
"""

from __future__ import annotations

from dataclasses import dataclass, field

import shapely

from ...scene import Layer
from .._model import MapData


@dataclass(frozen=True)
class Surface:
    """Flat ground at y = 0 that a feature claims: map-metre geometry, its ground material, its rank."""

    geometry: shapely.Geometry
    material: int
    rank: int


@dataclass(frozen=True)
class Built:
    """A feature's layer (with whatever ground it draws raised above or below the flat ground) and the
    flat surfaces it claims; the cut surfaces' triangles go before the layer's own ground."""

    layer: Layer
    surfaces: list[Surface] = field(default_factory=list)


class Feature:
    """One kind of map data. Every hook has a default that does nothing, so a module overrides only
    what its data needs."""

    name = ""
    # (key, value) -> area kind (AREA_KINDS) of the polygons this feature reads; the first of a
    # polygon's tags found in any feature's table decides its kind
    area_tags: dict[tuple[str, str], str] = {}

    def point_kind(self, tags: dict[str, str]) -> str | None:
        """What a tagged node is to this feature (named in reports), None: not its node."""
        return None

    def wants_line(self, tags: dict[str, str]) -> bool:
        return False

    def read_point(self, source_id: str, point: tuple[float, float], tags: dict[str, str], data: MapData) -> None:
        """Adds the node's records to `data` (called for every node some feature wants)."""

    def read_line(self, source_id: str, lines: list, tags: dict[str, str], data: MapData) -> bool:
        """Adds the line's records to `data`; True if the line was this feature's."""
        return False

    def link(self, data: MapData) -> None:
        """After everything is read: ties this feature's records to the others (doors onto walls)."""

    def summary(self, data: MapData) -> dict:
        """This feature's entries of `cityshade info` (JSON keys), guessing done."""
        return {}

    def build(self, data: MapData) -> Built:
        """This feature's layer of the city (map_city's last stage)."""
        return Built(Layer(self.name))
