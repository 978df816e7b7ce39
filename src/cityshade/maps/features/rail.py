"""Railways and tram lines (`railway=rail|tram|light_rail|subway|...` lines): the tags read with
their defaults, and the tracks as surfaces: ballast under every line but trams (which run in the
street), two rails a gauge apart, and bridge decks lifted by their layer. Tunnels are left out.

Gauge from `gauge` (millimetres, 300..3000), else Railway's default (Finnish broad gauge)."""

from __future__ import annotations

import numpy as np
import shapely

from ...scene import GROUND_BALLAST, GROUND_RAIL, Layer
from .._ground import PAINT_LIFT, triangles, union_of
from .._model import Railway
from .._tags import layer, number, yes
from ._feature import Built, Feature, Surface
from .streets import BRIDGE_STOREY, lengths_km

RAILWAYS = {"rail", "tram", "light_rail", "subway", "narrow_gauge", "monorail", "funicular", "preserved"}
BALLAST_WIDTH = 3.2
RAIL_WIDTH = 0.08
BALLAST_RANK = 20


def rail_strips(railways) -> np.ndarray:
    """Two thin strips per railway, its gauge apart."""
    if not railways:
        return np.zeros(0, dtype=object)
    lines = np.array([r.line for r in railways for _ in (0, 1)], dtype=object)
    offsets = np.array([side * r.gauge / 2 for r in railways for side in (-1, 1)])
    return shapely.buffer(shapely.offset_curve(lines, offsets), RAIL_WIDTH / 2, cap_style="flat")


def tracks(railways) -> tuple[shapely.Geometry, shapely.Geometry]:
    """(ballast, rails) of the railways at ground level."""
    on_ground = [r for r in railways if not r.tunnel and not r.bridge]
    tracked = [r.line for r in on_ground if r.kind != "tram"]
    ballast = union_of(shapely.buffer(np.array(tracked, dtype=object), BALLAST_WIDTH / 2, quad_segs=2))
    return ballast, shapely.GeometryCollection(list(rail_strips(on_ground)))  # overlaps at switches: no union


class Rail(Feature):
    name = "rail"

    def wants_line(self, tags):
        return tags.get("railway") in RAILWAYS

    def read_line(self, source_id, lines, tags, data):
        kind = tags.get("railway")
        if kind not in RAILWAYS:
            return False
        gauge = number(tags.get("gauge", "").split(";")[0])  # millimetres
        tagged_gauge = {"gauge": gauge / 1000.0} if gauge and 300.0 <= gauge <= 3000.0 else {}
        where = {"layer": layer(tags), "bridge": yes(tags, "bridge"), "tunnel": yes(tags, "tunnel")}
        data.railways += [Railway(source_id, line, kind, **where, tags=tags, **tagged_gauge) for line in lines]
        return True

    def summary(self, data):
        return {"railways_km": lengths_km(data.railways)}

    def build(self, data):
        ballast, rails = tracks(data.railways)
        raised = [triangles(rails, PAINT_LIFT, GROUND_RAIL)]
        for railway in (r for r in data.railways if r.bridge and not r.tunnel):
            lift = BRIDGE_STOREY * max(railway.layer, 1)
            deck = shapely.buffer(railway.line, BALLAST_WIDTH / 2, cap_style="flat")
            raised.append(triangles(deck, lift, GROUND_BALLAST))
            raised.append(triangles(shapely.GeometryCollection(list(rail_strips([railway]))), lift + 0.03, GROUND_RAIL))
        return Built(Layer(self.name, np.concatenate(raised)), [Surface(ballast, GROUND_BALLAST, BALLAST_RANK)])
