"""The city's content as glTF: buildings with their baked facades, the ground, and trees (one mesh
per species, instanced). Everything is in the scene's frame: metres, x east, y up, z south."""

from __future__ import annotations

from dataclasses import dataclass, field, replace

import numpy as np

from ..assets import facade_texture
from ..grammar import BUILDING_STYLES
from ..interior import pcg_hash
from ..render import assign_facades, bay_mean
from ..scene import (
    GROUND_TABLE,
    GROUND_TERRAIN,
    SURFACE_DORMER,
    SURFACE_PLAIN_WALL,
    SURFACE_ROOF,
    SURFACE_WALL,
    TINT_GAIN,
    Roof,
    building_records,
    building_vertices,
    rotation_y,
)
from ..terrain import face_normals
from ._bake import (
    Atlas,
    atlas_uv,
    bake_atlas,
    canvases_of,
    check_size,
    face_extents,
    finest_texel,
    has_grammar,
    wall_sides,
)
from ._gltf import Document
from ._merge import Pieces

GROUND_Y = (0.0, 0.02, 0.04)  # the built-in city's asphalt plane, pavements and grass, stacked
GROUND_COLOURS = {material: colour for material, (_, colour) in GROUND_TABLE.items()}  # linear, by material id
BARK_COLOUR = (0.12, 0.08, 0.05, 1.0)
LEAF_COLOUR = (0.08, 0.18, 0.04, 1.0)


@dataclass
class Stats:
    buildings: int = 0
    triangles: int = 0  # buildings, ground and one copy of each tree species
    tree_instances: int = 0
    facade_area: float = 0.0  # square metres of wall
    atlas_sizes: list = field(default_factory=list)  # (cols, rows) per page
    leaf: bool = False  # a 3D Tiles leaf: full detail
    draw_calls: int = 0  # primitives (an instanced mesh's primitive is one draw call for all its instances)

    @property
    def atlas_texels(self) -> int:
        return int(sum(w * h for w, h in self.atlas_sizes))


def simplified(mass):
    """A coarse level's building: the same outline as a flat-topped prism to the roof's top."""
    return (
        replace(mass, roof=Roof(colour=mass.roof.colour, material=mass.roof.material))
        if mass.shape == "prism"
        else mass
    )


def bay_tint(record) -> np.ndarray:
    """The linear tint the renderer multiplies the window-bay texture by (shaders/city/building.glsl
    building_tint): a tagged colour or material brightened TINT_GAIN times, else a per-building variation;
    clamped to 1 (glTF vertex colours)."""
    if record["tint"][3] > 0:
        tint = np.asarray(record["tint"][:3], np.float64) * TINT_GAIN
    else:
        h = int(pcg_hash(int(record["ids"][0]) ^ 0x9E37))
        tint = 0.8 + 0.35 * np.array([h & 255, (h >> 8) & 255, (h >> 16) & 255]) / 255.0 - 0.17
    return np.minimum(tint, 1.0)


def _triangle_area(positions: np.ndarray) -> float:
    a, b, c = positions[0::3], positions[1::3], positions[2::3]
    return float(0.5 * np.linalg.norm(np.cross(b - a, c - a), axis=1).sum())


def grammar_walls(masses):
    """(records, vertices per mass, {mass index: its grammar walls}) as the renderer has them:
    grammar buildings tinted to their style's wall colour, faces too narrow for their grammar marked
    plain walls (with the renderer's counted warning); grammar walls are neither roofs, plain walls
    nor dormer fronts."""
    vertices = [building_vertices(m, i) for i, m in enumerate(masses)]
    records = building_records(masses)
    every = np.concatenate(vertices)
    assign_facades(records, masses, every)
    vertices = np.split(every, np.cumsum([len(v) for v in vertices])[:-1])
    walls = {}
    for i, (mass, verts) in enumerate(zip(masses, vertices)):
        mine = verts[verts["ids"][:, 1] == SURFACE_WALL]
        if has_grammar(mass) and len(mine):
            walls[i] = mine
    return records, vertices, walls


def finest_city_texel(masses, finest: float) -> float:
    """The finest texel (no finer than `finest`) at which these masses' facades fit the atlas."""
    if not masses:
        return finest
    walls = grammar_walls(masses)[2].values()
    return finest_texel(np.concatenate([face_extents(w) for w in walls] or [np.zeros((0, 2))]), finest)


class BuildingWriter:
    """Bakes the facades of a set of masses and adds them to a document: one node per building with
    its origin at its base (one primitive per material), or with `merged` (a 3D Tiles tile) one node
    for all, one primitive per material; buildings stay apart as features either way."""

    def __init__(self, doc: Document, masses, metadata, texel: float, stats: Stats, merged: bool = False):
        self.doc, self.masses, self.metadata, self.texel, self.stats = doc, masses, metadata, texel, stats
        self.merged = merged
        self.vertices, self.canvases = [], {}
        if not masses:
            return
        self.records, self.vertices, walls = grammar_walls(masses)
        self.canvases = {i: canvases_of(i, masses[i], w, texel) for i, w in walls.items()}
        check_size([c for cs in self.canvases.values() for c in cs], texel)

    def write(self):
        if not self.masses:
            return
        atlas = bake_atlas([c for cs in self.canvases.values() for c in cs], self.texel)
        self.stats.atlas_sizes += atlas.sizes
        pages = self._page_materials(atlas)
        image, _ = facade_texture()
        bays = self.doc.material(
            "window bays", base_texture=self.doc.texture(image[::-1, :, :3].copy(), repeat=True, colour=True)
        )
        roofs = self.doc.material("roofs", roughness=0.8, double_sided=True)
        plain_walls = self.doc.material("plain walls", roughness=0.9)
        every = Pieces()
        for i, (mass, verts) in enumerate(zip(self.masses, self.vertices)):
            pieces = every if self.merged else Pieces()
            if not self._building(i, mass, verts, atlas, pages, (bays, roofs, plain_walls), pieces):
                continue
            if not self.merged:
                metadata = self.doc.features[-1]
                self._node(f"building {metadata['source_id']}", pieces, metadata)
        if self.merged and every:
            self._node("buildings", every, {"kind": "buildings"})

    def _node(self, name: str, pieces: Pieces, extras: dict):
        """A node whose origin is the middle of its base (where Blender puts an object's handle)."""
        lo, hi = pieces.bounds()
        origin = np.array([(lo[0] + hi[0]) / 2, lo[1], (lo[2] + hi[2]) / 2])
        primitives, scale = pieces.primitives(self.doc, origin)
        self.doc.node(name, primitives, extras=extras, translation=origin, scale=scale)

    def _page_materials(self, atlas: Atlas) -> list[int]:
        doc = self.doc
        out = []
        for p in range(len(atlas.sizes)):
            maps = {
                "base_texture": doc.texture(atlas.base_colour[p], name=f"facade colour {p}", colour=True),
                "mr_texture": doc.texture(atlas.metallic_roughness[p]),
                "roughness": 1.0,
                "normal_texture": doc.texture(atlas.normal[p]),
            }
            day = doc.material(f"facades {p}", **maps)  # the default: no window glows in daylight
            night = doc.material(f"facades {p} night", **maps, emissive_texture=doc.texture(atlas.emissive[p]))
            doc.night_variant(day, night)
            out.append(day)
        return out

    def _building(self, i, mass, verts, atlas, pages, materials, pieces: Pieces) -> bool:
        """Adds building i's triangles to `pieces` (in the document's frame) and its property
        table row; False when it has none."""
        if not len(verts):
            return False
        doc = self.doc
        row = doc.feature_row(
            dict(self.metadata[i], facade=BUILDING_STYLES[mass.style] if i in self.canvases else "window bays")
        )
        bays, roofs, plain_walls = materials
        rot = rotation_y(mass.yaw)
        record = self.records[i]

        def add(material, part, normals, **arrays):
            n = len(part)
            pieces.add(
                material,
                positions=doc.world(part["position"]),
                normals=doc.turn(normals),
                features=np.full(n, row, np.float64),
                **arrays,
            )

        roof = verts["ids"][:, 1] == SURFACE_ROOF
        walls = verts[~roof]
        if len(walls):
            self.stats.facade_area += _triangle_area(walls["position"].astype(np.float64))
            bay_walls = walls
            if i in self.canvases:
                surface = walls["ids"][:, 1]
                plain = walls[surface == SURFACE_PLAIN_WALL]  # too narrow for the grammar: its wall colour
                walls, bay_walls = walls[surface == SURFACE_WALL], walls[surface == SURFACE_DORMER]
                normals = walls["normal"] @ rot.T
                sides = wall_sides(walls)
                n = walls["normal"]
                along = np.column_stack([-n[:, 2], np.zeros(len(n)), n[:, 0]]) @ rot.T  # along mesh u
                along = doc.turn(along)
                along /= np.linalg.norm(along, axis=1, keepdims=True)  # a dome's tilted rings: shorter
                tangents = np.column_stack([along, -np.ones(len(n))])  # bitangent = cross(n, t) * -1 = up
                for side, canvas in enumerate(self.canvases[i]):
                    sel = sides == side
                    uv = atlas_uv(canvas, walls["facade"][sel], atlas.sizes[canvas.page], self.texel)
                    add(pages[canvas.page], walls[sel], normals[sel], uv=uv, tangents=tangents[sel])
                if len(plain):
                    colour = np.append(np.minimum(bay_mean()[:3] * bay_tint(record), 1.0), 1.0)
                    add(plain_walls, plain, plain["normal"] @ rot.T, colours=np.tile(colour, (len(plain), 1)))
            if len(bay_walls):
                facade = bay_walls["facade"]
                uv = np.column_stack([facade[:, 0] / facade[:, 2], -facade[:, 1] / mass.room_size[1]])
                colours = np.tile(np.append(bay_tint(record), 1.0), (len(bay_walls), 1))
                add(bays, bay_walls, bay_walls["normal"] @ rot.T, uv=uv, colours=colours)
        if roof.any():
            colour = np.append(record["roof"][:3], 1.0)
            add(roofs, verts[roof], verts["normal"][roof] @ rot.T, colours=np.tile(colour, (int(roof.sum()), 1)))
        self.stats.buildings += 1
        self.stats.triangles += len(verts) // 3
        return True


def ground_triangles(city) -> np.ndarray:
    """(N*3, 4) vertices (x, y, z, material): the map's ground mesh, or the built-in city's rectangles
    over an asphalt plane covering its bounds."""
    if city.ground_mesh is not None:
        return np.asarray(city.ground_mesh, np.float32)
    x0, z0, x1, z1 = city.bounds
    rects = [(x0, z0, x1, z1, 0)] + list(city.ground)
    out = []
    for a0, b0, a1, b1, material in rects:
        y = GROUND_Y[min(material, 2)]
        corners = [
            (a0, y, b0),
            (a0, y, b1),
            (a1, y, b1),
            (a0, y, b0),
            (a1, y, b1),
            (a1, y, b0),
        ]  # counter-clockwise from above
        out += [(*c, material) for c in corners]
    return np.asarray(out, np.float32)


def _ground_node(doc: Document, ground: np.ndarray, name: str, extras: dict, normals=None):
    """One node of ground triangles, a primitive per material; `normals` per vertex (default: up)."""
    pieces = Pieces()
    for material in np.unique(ground[:, 3]).astype(int):
        rows = ground[:, 3] == material
        colour = (*GROUND_COLOURS.get(int(material), (0.2, 0.2, 0.2)), 1.0)
        index = doc.material(f"ground {material}", colour=colour, double_sided=True)
        up = np.tile([0.0, 1.0, 0.0], (int(rows.sum()), 1)) if normals is None else normals[rows]
        pieces.add(index, positions=doc.world(ground[rows, :3]), normals=doc.turn(up))
    if pieces:
        lo, hi = pieces.bounds()
        origin = np.array([(lo[0] + hi[0]) / 2, 0.0, (lo[2] + hi[2]) / 2])
        primitives, scale = pieces.primitives(doc, origin)
        doc.node(name, primitives, extras=extras, translation=origin, scale=scale)


def add_ground(doc: Document, city, stats: Stats):
    """The ground (streets, water, land, ...) and, apart, a DEM's terrain with its face normals and
    its relief in the extras."""
    ground = ground_triangles(city)
    relief = ground[:, 3] == GROUND_TERRAIN
    stats.triangles += len(ground) // 3
    _ground_node(doc, ground[~relief], "ground", {"kind": "ground"})
    if relief.any():
        terrain = ground[relief]
        normals = np.repeat(face_normals(terrain), 3, axis=0)
        extras = {
            "kind": "terrain",
            "triangles": len(terrain) // 3,
            "lowest_m": round(float(terrain[:, 1].min()), 3),
            "highest_m": round(float(terrain[:, 1].max()), 3),
            "heights": "metres above the vertical datum of the DEM (the mesh lies 0.3 m below the ground on it)",
        }
        _ground_node(doc, terrain, "terrain", extras, normals)


def _card_quads(cards: np.ndarray, indices: np.ndarray):
    """Leaf cards (camera-facing in the renderer) as fixed quads turned by their spin about +y."""
    centre, corner, size, spin = cards[:, 0:3], cards[:, 3:5], cards[:, 5], cards[:, 8]
    right = np.column_stack([np.cos(spin), np.zeros(len(spin)), np.sin(spin)])
    positions = centre + (right * corner[:, :1] + np.array([0.0, 1.0, 0.0]) * corner[:, 1:2]) * size[:, None]
    normals = np.column_stack([-np.sin(spin), np.zeros(len(spin)), np.cos(spin)])
    return positions, normals, indices


def add_trees(doc: Document, trees, stats: Stats, seed: int = 0):
    """One mesh per species (trunk and branches, leaf cards, fronds) drawn at every tree of it."""
    from ..trees import SPECIES, SPECIES_ORDER, generate_tree

    if trees is None or not len(trees):
        return
    bark = doc.material("bark", colour=BARK_COLOUR)
    leaves = doc.material("leaves", colour=LEAF_COLOUR, double_sided=True)
    for index in sorted({int(s) for s in trees["species"]}):
        name = SPECIES_ORDER[index]
        mesh = generate_tree(SPECIES[name], seed + index).lods[0]
        parts = [
            (bark, mesh.branches[:, 0:3], mesh.branches[:, 3:6], mesh.branch_indices),
            (leaves, *_card_quads(mesh.cards, mesh.card_indices)),
        ]
        if len(mesh.frond_indices):
            parts.append((leaves, mesh.fronds[:, 0:3], mesh.fronds[:, 3:6], mesh.frond_indices))
        primitives = [doc.primitive(m, p, n, indices=i) for m, p, n, i in parts if len(i)]
        stats.triangles += sum(len(i) // 3 for *_, i in parts)
        mine = trees[trees["species"] == index]
        yaw = mine["yaw"].astype(np.float64) + (0.0 if doc.place is None else -doc.place.convergence)
        rotations = np.column_stack([np.zeros(len(yaw)), np.sin(yaw / 2), np.zeros(len(yaw)), np.cos(yaw / 2)])
        scales = np.repeat(mine["scale"][:, None], 3, axis=1)
        doc.instanced(
            f"trees {name}",
            primitives,
            doc.world(mine["position"]),
            rotations,
            scales,
            extras={"kind": "trees", "species": name, "count": len(mine)},
        )
        stats.tree_instances += len(mine)
