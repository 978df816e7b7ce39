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
from ._bake import (
    Atlas,
    atlas_uv,
    bake_atlas,
    canvases_of,
    check_size,
    has_grammar,
    wall_sides,
)
from ._gltf import Document

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


class BuildingWriter:
    """Bakes the facades of a set of masses and adds one node per building to a document."""

    def __init__(self, doc: Document, masses, metadata, texel: float, stats: Stats):
        self.doc, self.masses, self.metadata, self.texel, self.stats = doc, masses, metadata, texel, stats
        self.vertices, self.canvases = [], {}
        if not masses:
            return
        vertices = [building_vertices(m, i) for i, m in enumerate(masses)]
        # as the renderer: grammar buildings tinted to their style's wall colour, faces too narrow for
        # their grammar marked plain walls (with the renderer's counted warning)
        self.records = building_records(masses)
        every = np.concatenate(vertices)
        assign_facades(self.records, masses, every)
        self.vertices = np.split(every, np.cumsum([len(v) for v in vertices])[:-1])
        for i, (mass, verts) in enumerate(zip(masses, self.vertices)):
            walls = verts[verts["ids"][:, 1] == SURFACE_WALL]  # not roofs, plain walls nor dormer fronts
            if has_grammar(mass) and len(walls):
                self.canvases[i] = canvases_of(i, mass, walls, texel)
        check_size([c for cs in self.canvases.values() for c in cs], texel)

    def write(self):
        if not self.masses:
            return
        atlas = bake_atlas([c for cs in self.canvases.values() for c in cs], self.texel)
        self.stats.atlas_sizes += atlas.sizes
        pages = self._page_materials(atlas)
        image, _ = facade_texture()
        bays = self.doc.material("window bays", base_texture=self.doc.texture(image[::-1, :, :3].copy(), repeat=True))
        roofs = self.doc.material("roofs", roughness=0.8, double_sided=True)
        plain_walls = self.doc.material("plain walls", roughness=0.9)
        for i, (mass, verts) in enumerate(zip(self.masses, self.vertices)):
            self._building(i, mass, verts, atlas, pages, (bays, roofs, plain_walls))

    def _page_materials(self, atlas: Atlas) -> list[int]:
        doc = self.doc
        return [
            doc.material(
                f"facades {p}",
                base_texture=doc.texture(atlas.base_colour[p], name=f"facade colour {p}"),
                mr_texture=doc.texture(atlas.metallic_roughness[p]),
                roughness=1.0,
                normal_texture=doc.texture(atlas.normal[p]),
                emissive_texture=doc.texture(atlas.emissive[p]),
            )
            for p in range(len(atlas.sizes))
        ]

    def _building(self, i, mass, verts, atlas, pages, materials):
        bays, roofs, plain_walls = materials
        rot = rotation_y(mass.yaw)
        roof = verts["ids"][:, 1] == SURFACE_ROOF
        record = self.records[i]
        primitives = []
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
                tangents = np.column_stack([-n[:, 2], np.zeros(len(n)), n[:, 0]]) @ rot.T  # along mesh u
                tangents /= np.linalg.norm(tangents, axis=1, keepdims=True)  # a dome's tilted rings: shorter
                tangents = np.column_stack([tangents, -np.ones(len(n))])  # bitangent = cross(n, t) * -1 = up
                for side, canvas in enumerate(self.canvases[i]):
                    sel = sides == side
                    uv = atlas_uv(canvas, walls["facade"][sel], atlas.sizes[canvas.page], self.texel)
                    primitives.append(
                        self.doc.primitive(
                            pages[canvas.page], walls["position"][sel], normals[sel], uv, tangents=tangents[sel]
                        )
                    )
                if len(plain):
                    colour = np.append(np.minimum(bay_mean()[:3] * bay_tint(record), 1.0), 1.0)
                    primitives.append(
                        self.doc.primitive(
                            plain_walls,
                            plain["position"],
                            plain["normal"] @ rot.T,
                            colours=np.tile(colour, (len(plain), 1)),
                        )
                    )
            if len(bay_walls):
                facade = bay_walls["facade"]
                uv = np.column_stack([facade[:, 0] / facade[:, 2], -facade[:, 1] / mass.room_size[1]])
                tint = bay_tint(record)
                primitives.append(
                    self.doc.primitive(
                        bays,
                        bay_walls["position"],
                        bay_walls["normal"] @ rot.T,
                        uv,
                        colours=np.tile(np.append(tint, 1.0), (len(bay_walls), 1)),
                    )
                )
        if roof.any():
            colour = np.append(record["roof"][:3], 1.0)
            primitives.append(
                self.doc.primitive(
                    roofs,
                    verts["position"][roof],
                    verts["normal"][roof] @ rot.T,
                    colours=np.tile(colour, (int(roof.sum()), 1)),
                )
            )
        if not primitives:
            return
        self.stats.buildings += 1
        self.stats.triangles += len(verts) // 3
        style = BUILDING_STYLES[mass.style] if i in self.canvases else "window bays"
        metadata = dict(self.metadata[i], facade=style)
        self.doc.feature(
            metadata, primitives, [self.doc.gltf.accessors[p.attributes.POSITION].count for p in primitives]
        )
        self.doc.node(f"building {metadata['source_id']}", primitives, extras=metadata)


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


def add_ground(doc: Document, city, stats: Stats):
    ground = ground_triangles(city)
    primitives = []
    for material in np.unique(ground[:, 3]).astype(int):
        rows = ground[:, 3] == material
        colour = (*GROUND_COLOURS.get(int(material), (0.2, 0.2, 0.2)), 1.0)
        index = doc.material(f"ground {material}", colour=colour, double_sided=True)
        up = np.tile([0.0, 1.0, 0.0], (int(rows.sum()), 1))
        primitives.append(doc.primitive(index, ground[rows, :3], up))
    if primitives:
        stats.triangles += len(ground) // 3
        doc.node("ground", primitives, extras={"kind": "ground"})


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
        primitives = [doc.indexed_primitive(m, p, n, i) for m, p, n, i in parts if len(i)]
        stats.triangles += sum(len(i) // 3 for *_, i in parts)
        mine = trees[trees["species"] == index]
        yaw = mine["yaw"].astype(np.float64)
        rotations = np.column_stack([np.zeros(len(yaw)), np.sin(yaw / 2), np.zeros(len(yaw)), np.cos(yaw / 2)])
        scales = np.repeat(mine["scale"][:, None], 3, axis=1)
        doc.instanced(
            f"trees {name}",
            primitives,
            mine["position"],
            rotations,
            scales,
            extras={"kind": "trees", "species": name, "count": len(mine)},
        )
        stats.tree_instances += len(mine)
