"""Entrances and shops mapped as points: `entrance=*` nodes within ENTRANCE_SNAP of a building's
wall become its doors (the main entrance first; ENTRANCE_ORDER), and a shop mapped as a point
(`shop=*`) gives the building it stands in shop fronts. The doors are drawn with the buildings
(maps/_masses.py); buildings without a mapped entrance get one guessed (maps/_doors.py)."""

from __future__ import annotations

import numpy as np
import shapely

from .._doors import on_ground
from .._model import Entrance, MapData
from ._feature import Feature

ENTRANCE_SNAP = 0.5  # metres: an entrance this near a building's wall stands on it
# Entrances in the order they get one of a building's few doors (cityshade.scene.MAX_DOORS); others after.
ENTRANCE_ORDER = ("main", "yes", "staircase", "shop", "secondary", "home", "side", "service", "garage")


def link_entrances(data: MapData) -> None:
    """Each entrance becomes a door of the buildings (and parts) whose wall it stands on, main entrances
    first; entrances on no wall are counted. Buildings that hold a mapped shop get shop fronts."""
    if not data.buildings:
        return
    outlines = np.array([b.outline for b in data.buildings], dtype=object)
    tree = shapely.STRtree(outlines)
    if data.entrances:
        points = shapely.points([e.position for e in data.entrances])
        entrance, building = tree.query(points, predicate="dwithin", distance=ENTRANCE_SNAP)
        on_wall = shapely.distance(points[entrance], shapely.boundary(outlines[building])) <= ENTRANCE_SNAP
        entrance, building = entrance[on_wall], building[on_wall]

        def rank(i: int) -> tuple[int, int]:
            kind = data.entrances[i].kind
            return (ENTRANCE_ORDER.index(kind) if kind in ENTRANCE_ORDER else len(ENTRANCE_ORDER), i)

        for i, b in sorted(zip(entrance.tolist(), building.tolist()), key=lambda pair: rank(pair[0])):
            data.buildings[b].doors.append(data.entrances[i].position)
            data.buildings[b].tagged.add("doors")
        for i in sorted(set(range(len(data.entrances))) - set(entrance.tolist())):
            data.report.skip(
                "entrance", f"not on a building's wall (within {ENTRANCE_SNAP} m)", data.entrances[i].source_id
            )
    if data.shops:
        _, building = tree.query(shapely.points(data.shops), predicate="within")
        for b in set(building.tolist()):
            data.buildings[b].shop_front = True


class Entrances(Feature):
    name = "entrances"

    def point_kind(self, tags):
        if tags.get("entrance", "no") != "no":
            return "entrance"
        return "shop" if "shop" in tags else None

    def read_point(self, source_id, point, tags, data):
        position = (float(point[0]), float(point[1]))
        if tags.get("entrance", "no") != "no":
            data.entrances.append(Entrance(source_id, position, tags["entrance"]))
        if "shop" in tags:
            data.shops.append(position)

    def link(self, data):
        link_entrances(data)

    def summary(self, data):
        """Door points of the drawn buildings whose walls reach the ground: at mapped entrances, or
        guessed on the street side; and how many drawn buildings have shop fronts."""
        drawn = [b for b in data.buildings if b.drawn]
        grounded = [b for b in drawn if on_ground(b)]
        doors = {
            "entrances": len(data.entrances),
            "from_entrances": sum(len(b.doors) for b in grounded if "doors" in b.tagged),
            "guessed": sum(len(b.doors) for b in grounded if "doors" in b.guessed),
            "buildings_with_shop_fronts": sum(b.shop_front for b in drawn),
        }
        return {"doors": doors}
