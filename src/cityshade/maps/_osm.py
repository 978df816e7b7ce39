"""OpenStreetMap `.osm.pbf` and `.osm` XML (also gzip or bzip2 compressed) through pyosmium: its area
assembler builds multipolygons.

One streaming pass: nodes give trees, street lamps, entrances and shops; ways give roads, railways, tree rows, the
coastline, and (closed) building outlines, `building:part`s and land use; the area assembler gives
multipolygon relations with their inner rings. What cannot be built (an unclosed building way, a
way with a missing node, a relation with open rings) is counted and skipped.

XML is checked before libosmium sees it: a document type declaration (the carrier of entity bombs
and external entities) is refused outright, so nothing is expanded and no local file is read
(libosmium refuses entities too: "XML entities are not supported").
"""

from __future__ import annotations

import contextlib
import os
import re
import tempfile
import zlib
from pathlib import Path

import numpy as np
import osmium
import shapely

from .._files import InputError, open_input_stream
from ..errors import UsageError
from ._assemble import Raw, assemble
from ._model import MapData, ReadReport
from .features import area_kind, is_building, point_kind, wanted_line

PROLOG_BYTES = 65536
# Node locations are kept in memory (libosmium's flex_mem index) unless the index would take more
# than this share of the memory available: then in a sparse index in a temporary file on disk. A
# PBF holds about 10 bytes per node and the sparse index 16 (id and location), so a file is taken
# to need 1.6 times its size of index.
INDEX_BYTES_PER_FILE_BYTE = 1.6
INDEX_MEMORY_SHARE = 0.25
SNIFF = 64
_WKB = osmium.geom.WKBFactory()
SCAN_BYTES = 1 << 24
# XML is about ten times its .osm.pbf: a city's extract (Berlin, 80 MB as PBF) is about 1 GiB of it,
# and libosmium keeps every node's location while reading. 4 GiB of XML, however small its .gz,
# is a region, which belongs in a .osm.pbf; beyond it a file is refused before libosmium reads it.
MAX_XML_BYTES = 4 << 30
# The scan holds one line: exports write an element a line, under 2 MB even for a relation of
# 30,000 members, so 16 MiB leaves room for small files written without line breaks.
MAX_XML_LINE = 16 << 20
_EXPONENT = re.compile(rb'\bl(?:at|on)="\s*[-+]?[0-9.]*[eE][-+]?[0-9]+\s*"')
LINE_KEYS = ("highway", "railway", "natural")


def osm_format(path: Path) -> str | None:
    """libosmium's name for the file's format by its first bytes: 'pbf', 'osm' (XML), 'osm.gz',
    'osm.bz2'; None if it is none of them."""
    with open(path, "rb") as stream:
        head = stream.read(SNIFF)
    for magic, compression in ((b"\x1f\x8b", "gz"), (b"BZh", "bz2")):
        if head.startswith(magic):
            try:
                with _open(path, f"osm.{compression}", (SNIFF, SNIFF)) as stream:
                    head = stream.read(SNIFF)
            except (OSError, EOFError, ValueError):
                return f"osm.{compression}"  # damaged: reading it says so
            return f"osm.{compression}" if _is_xml(head) else None
    if _is_xml(head):
        return "osm"
    return "pbf" if b"OSMHeader" in head[:32] else None


def _is_xml(head: bytes) -> bool:
    return head.lstrip(b"\xef\xbb\xbf \t\r\n").startswith(b"<")


def _open(path: Path, kind: str, limits: tuple[int, int] = (MAX_XML_BYTES, MAX_XML_LINE)):
    """The file's XML as a capped stream: (uncompressed bytes, bytes of one line) at most."""
    compression = kind.rpartition(".")[2] if "." in kind else None
    return open_input_stream(path, *limits, "map", compression)


def check_xml(path: Path, kind: str = "osm", limits: tuple[int, int] = (MAX_XML_BYTES, MAX_XML_LINE)) -> None:
    """Refuse XML that declares a document type (entities) before its first element, that writes a
    coordinate with an exponent (libosmium reads an overflowing `lat="1e308"` as 0 without a word),
    or that is larger, uncompressed, than `limits` (bytes in all, bytes of one line) allow."""
    try:
        with _open(path, kind, limits) as stream:
            _scan_xml(path, stream)
    except InputError as exc:
        raise UsageError(f"{exc}; give a smaller extract, or the map as .osm.pbf, written one element a line") from None
    except (OSError, EOFError, zlib.error) as exc:
        raise UsageError(
            f"{path}: not a readable OpenStreetMap file ({kind} data damaged or cut short: "
            f"{str(exc)[:80] or type(exc).__name__}); check that the download is complete"
        ) from None


def _scan_xml(path: Path, stream) -> None:
    """The checks of `check_xml` on an open stream of the file."""
    head = stream.read(PROLOG_BYTES)
    start = head.find(b"<osm")
    prolog = head if start < 0 else head[:start]
    if b"<!DOCTYPE" in prolog.upper() or b"<!ENTITY" in prolog.upper():
        raise UsageError(
            f"{path}: the XML declares a document type or entities, which OpenStreetMap files "
            "never need; refusing it (entities could expand without bound or read local files)"
        )
    line, chunk = 1, head + stream.readline()
    while chunk:
        match = _EXPONENT.search(chunk)
        if match:
            node = re.search(rb'id="(-?\d+)"', chunk[chunk.rfind(b"<", 0, match.start()) : match.start()])
            at = line + chunk.count(b"\n", 0, match.start())
            where = f"{path}:{at}" + (f": node/{node.group(1).decode()}" if node else "")
            raise UsageError(
                f"{where}: coordinate {match.group(0).decode('ascii', 'replace')[:40]} has an "
                "exponent; write latitude and longitude as plain decimals within ±90 and ±180"
            )
        line += chunk.count(b"\n")
        chunk = stream.read(SCAN_BYTES) + stream.readline()


def _coordinates(way) -> np.ndarray | None:
    """(n, 2) lon/lat of a way's nodes (repeated nodes once) built by libosmium; None if a node is
    missing or has a bad location, or fewer than two distinct nodes remain. (libosmium passes over
    missing nodes at the very start of a way, so the caller checks the first node itself.)"""
    try:
        return shapely.get_coordinates(shapely.from_wkb(_WKB.create_linestring(way)))
    except (osmium.InvalidLocationError, RuntimeError):
        return None


def _ring(nodes) -> list[tuple[float, float] | None]:
    """(lon, lat) of each node; None where the node is missing or its location is not valid."""
    points = []
    for node in nodes:
        location = node.location
        points.append((location.lon, location.lat) if location.valid() else None)
    return points


def _area_polygon(area) -> shapely.Geometry:
    polygons = [
        shapely.Polygon(_ring(outer), [_ring(inner) for inner in area.inner_rings(outer)])
        for outer in area.outer_rings()
    ]
    return polygons[0] if len(polygons) == 1 else shapely.MultiPolygon(polygons)


def _runs(ring: list) -> list[list[tuple[float, float]]]:
    """The stretches of a way whose nodes all have a location, each with at least two nodes."""
    runs, run = [], []
    for point in ring:
        if point is not None:
            run.append(point)
        else:
            runs.append(run)
            run = []
    runs.append(run)
    return [run for run in runs if len(run) >= 2]


def _line_kind(tags) -> str:
    return next((key for key in LINE_KEYS if key in tags), "way")


class _Collector:
    """Turns the stream of OSM objects into raw features and counts what cannot be used."""

    def __init__(self, report: ReadReport):
        self.report = report
        self.raws: list[Raw] = []
        self.last_node = None
        self.areas_from_relations: set[int] = set()
        self.area_relations: dict[int, str] = {}
        self.outer_ways: dict[int, int] = {}  # way id -> the building relation it is an outer ring of

    def node(self, node) -> None:
        if self.last_node is not None and node.id <= self.last_node:
            self.report.repair("node", "duplicate or unsorted node id (the last one is used)", f"node/{node.id}")
        self.last_node = node.id
        tags = node.tags
        what = point_kind(tags)
        if what is None:
            return
        if not node.location.valid():
            self.report.skip(what, "location missing or out of range", f"node/{node.id}")
            return
        self.raws.append(Raw(f"node/{node.id}", shapely.Point(node.location.lon, node.location.lat), dict(tags)))

    def way(self, way) -> None:
        tags = way.tags
        building = is_building(tags)
        polygon = building or (way.is_closed() and area_kind(dict(tags)) is not None)
        if not polygon and not wanted_line(tags):
            return
        element = f"way/{way.id}"
        coords = _coordinates(way)
        missing = (coords is None or not way.nodes[0].location.valid()) and any(
            point is None for point in _ring(way.nodes)
        )
        if polygon:
            # closed ways are built here rather than by the assembler, which drops a self-intersecting
            # ring without a word; `assemble` repairs it with make_valid and counts it
            what = "building" if building else "area"
            if missing:
                self.report.skip(what, "refers to a missing node or a bad location", element)
            elif coords is None or len(coords) < 4:
                self.report.skip(what, "fewer than 3 corners", element)
            elif not way.is_closed():
                self.report.skip(what, "way is not closed", element)
            else:
                self.raws.append(Raw(element, shapely.polygons(coords), dict(tags)))
            if building or not wanted_line(tags):
                return
        if way.is_closed() and tags.get("area") == "yes":
            return
        runs = _runs(_ring(way.nodes)) if missing else [coords] if coords is not None else []
        if missing:
            self.report.repair(_line_kind(tags), "cut where it refers to missing nodes (the extract's edge)", element)
        if not runs:
            self.report.skip(_line_kind(tags), "fewer than 2 nodes with a location", element)
            return
        line = shapely.LineString(runs[0]) if len(runs) == 1 else shapely.MultiLineString(runs)
        self.raws.append(Raw(element, line, dict(tags)))

    def relation(self, relation) -> None:
        tags = relation.tags
        if tags.get("type") == "multipolygon" and (is_building(tags) or area_kind(dict(tags))):
            self.area_relations[relation.id] = "building" if is_building(tags) else "area"
            if is_building(tags):
                for member in relation.members:
                    if member.type == "w" and member.role in ("outer", ""):
                        self.outer_ways[member.ref] = relation.id

    def area(self, area) -> None:
        if area.from_way():
            return  # built from the way itself (see `way`)
        tags = dict(area.tags)
        if not is_building(tags) and area_kind(tags) is None:
            return
        element = f"relation/{area.orig_id()}"
        self.areas_from_relations.add(area.orig_id())
        polygon = _area_polygon(area)
        if polygon.is_empty:
            self.report.skip("building" if is_building(tags) else "area", "no rings", element)
            return
        self.raws.append(Raw(element, polygon, tags))

    def finish(self) -> None:
        for relation, what in self.area_relations.items():
            if relation not in self.areas_from_relations:
                self.report.skip(
                    what, "multipolygon could not be assembled (open or missing members)", f"relation/{relation}"
                )
        self.raws = [raw for raw in self.raws if not self._drawn_by_relation(raw)]

    def _drawn_by_relation(self, raw: Raw) -> bool:
        """A building way that is also the outer ring of a building relation (old-style tagging on
        both): the relation, which has the courtyards, is kept."""
        kind, _, number = raw.source_id.partition("/")
        outline = kind == "way" and raw.tags.get("building", "no") != "no"  # parts stay: they are drawn
        relation = self.outer_ways.get(int(number)) if outline else None
        if relation is None or relation not in self.areas_from_relations:
            return False
        self.report.skip("building", "outer ring of a building relation, which is drawn instead", raw.source_id)
        return True


def _where(path: Path, kind: str, message: str) -> str:
    """`path:LINE:COLUMN` of an XML syntax error, `path:LINE: node/ID` for libosmium's "wrong format
    for coordinate: 'X'" in XML, else `path`."""
    position = re.search(r"at line (\d+), column (\d+)", message)
    if position:  # expat counts columns from 0, editors from 1
        return f"{path}:{position.group(1)}:{int(position.group(2)) + 1}"
    match = re.search(r"coordinate: '([^']*)'", message)
    if not match:
        return str(path)
    value = f'"{match.group(1)}"'
    with _open(path, kind) as stream:
        for number, line in enumerate(stream, 1):
            text = line.decode("utf-8", "replace")
            if value in text:
                node = re.search(r'<node\s[^>]*id="(-?\d+)"[^>]*' + re.escape(value), text)
                return f"{path}:{number}" + (f": node/{node.group(1)}" if node else "")
    return str(path)


def _available_memory() -> int:
    try:
        return os.sysconf("SC_AVPHYS_PAGES") * os.sysconf("SC_PAGE_SIZE")
    except (ValueError, OSError):
        return 1 << 62  # unknown: in memory


def _location_index(path: Path, stack: contextlib.ExitStack) -> str:
    """libosmium's node location index for `path`: in memory, or in a temporary file on disk for a
    file whose index would not fit the memory available (INDEX_MEMORY_SHARE of it)."""
    wanted = path.stat().st_size * INDEX_BYTES_PER_FILE_BYTE
    if wanted <= INDEX_MEMORY_SHARE * _available_memory():
        return "flex_mem"
    folder = stack.enter_context(tempfile.TemporaryDirectory(prefix="cityshade-nodes-"))
    return f"sparse_file_array,{Path(folder) / 'locations.idx'}"


def read_osm(path: Path) -> MapData:
    """MapData of an OpenStreetMap extract (.osm.pbf, or .osm XML, also gzip or bzip2 compressed)."""
    kind = osm_format(path) or "pbf"  # not recognisably anything: let libosmium say what is wrong
    xml = kind != "pbf"
    if xml:
        check_xml(path, kind)
    report = ReadReport()
    collector = _Collector(report)
    dispatch = {"n": collector.node, "w": collector.way, "r": collector.relation, "a": collector.area}
    try:
        with contextlib.ExitStack() as stack:
            # the format by content, not by name (libosmium would go by the file's extension)
            source = osmium.io.File(str(path), kind)
            processor = osmium.FileProcessor(source).with_areas().with_locations(_location_index(path, stack))
            if not xml:  # PBF writers sort and deduplicate nodes; skipping untagged ones saves half the time
                processor.with_filter(osmium.filter.EmptyTagFilter())
            for item in processor:
                dispatch[item.type_str()](item)
    except (RuntimeError, ValueError, osmium.InvalidLocationError) as exc:
        message = str(exc).strip().splitlines()[0] if str(exc).strip() else type(exc).__name__
        raise UsageError(
            f"{_where(path, kind, message)}: not a readable OpenStreetMap file ({message}); "
            "check that it is a complete .osm.pbf or .osm XML export"
        ) from None
    collector.finish()
    box = processor.header.box()  # the extract's <bounds> (XML) or header bbox (PBF), when it says
    declared = (box.bottom_left.lon, box.bottom_left.lat, box.top_right.lon, box.top_right.lat) if box.valid() else None
    return assemble(path, collector.raws, report, declared=declared)
