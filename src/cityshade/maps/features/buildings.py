"""Buildings (`building=*` outlines and `building:part=*` parts): the Simple 3D Buildings tags read
with their defaults (maps/_tags.py), a record per polygon, and what `cityshade info` says of them.
The buildings are meshed as the city's masses (maps/_masses.py), not as a layer: every renderer
path draws them. `building=roof` (or `building:part=roof`) has no walls."""

from __future__ import annotations

from collections import Counter

from .._model import BUILDING_ATTRIBUTES, MapBuilding, MapData
from .._tags import building_attributes
from ._feature import Feature
from .trees import origin_counts

CONFIDENT = ("levels", "height", "roof_shape")  # the guessed values that carry a confidence


def is_building(tags: dict[str, str]) -> bool:
    return tags.get("building", "no") != "no" or tags.get("building:part", "no") != "no"


def add_buildings(data: MapData, source_id: str, outlines, tags: dict[str, str], fixed: dict) -> list[MapBuilding]:
    """A record per outline with what the tags say; `fixed`: attributes a reader measured (CityJSON)."""
    is_part = tags.get("building", "no") == "no"
    kind = tags.get("building:part" if is_part else "building", "yes")
    records = []
    for outline in outlines:
        building = MapBuilding(
            index=len(data.buildings),
            source_id=source_id,
            outline=outline,
            kind=kind,
            is_part=is_part,
            has_walls=kind != "roof",
            tags=tags,
        )
        building_attributes(building, tags, data.report)
        for name, value in fixed.items():
            setattr(building, name, value)
            if name in BUILDING_ATTRIBUTES:
                building.tagged.add(name)
        data.buildings.append(building)
        records.append(building)
    return records


class Buildings(Feature):
    name = "buildings"

    def summary(self, data):
        outlines = [b for b in data.buildings if not b.is_part]
        tagged_roofs = Counter(b.roof_shape for b in data.buildings if "roof_shape" in b.tagged)
        return {
            "buildings": len(outlines),
            "parts": len(data.buildings) - len(outlines),
            "outlines_replaced_by_parts": sum(b.replaced_by_parts for b in outlines),
            "outlines_cut_by_parts": sum(b.remainder is not None for b in outlines),
            "roofs_without_walls": sum(not b.has_walls for b in data.buildings),
            "roof_shapes": dict(Counter(b.roof_shape or "none" for b in data.buildings).most_common()),
            "roof_shapes_tagged": dict(tagged_roofs.most_common()),
            "building_attributes": origin_counts(data.buildings, BUILDING_ATTRIBUTES),
            "guess_confidence": confidence_summary(data.buildings),
            "guess_forms": dict(Counter(b.form for b in data.buildings if b.form).most_common()),
        }


def confidence_summary(buildings: list[MapBuilding]) -> dict[str, dict]:
    """Per value the guessing model estimates: how many got a confidence, its mean, and how many are
    below one half (levels within one storey, height within 3 m, roof flat or pitched)."""
    summary = {}
    for name in CONFIDENT:
        values = [b.confidence[name] for b in buildings if name in b.confidence]
        summary[name] = {
            "guessed": len(values),
            "mean": round(sum(values) / len(values), 4) if values else None,
            "below_half": sum(v < 0.5 for v in values),
        }
    return summary
