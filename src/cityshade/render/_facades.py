"""The one facade registry: every facade technique of the city registered once, with an explicit
precedence, and `choose_facade` picking one per building from the building's own data.

Today the choice reads the building's style number and shape; later choosers (OpenStreetMap tags,
for instance) replace `accepts` without touching the frame. The polygonised-interiors baseline is
not a kind of facade but a frame mode (RenderSettings.polygonised_interiors): it replaces the
interior mapping of every window-bay facade at once.
"""

from __future__ import annotations

import warnings
from collections import Counter
from dataclasses import dataclass

import numpy as np

from ..grammar import BUILDING_STYLES, FACADE_GRAMMAR, GRAMMAR_SHAPES, library_min_widths, library_texture, seed_cells
from ..relief import FACADE_RELIEF, RELIEF_SHAPES, RELIEF_STYLES, relief_atlas
from ..scene import SHAPES, SURFACE_PLAIN_WALL, SURFACE_WALL, TINT_GAIN, BuildingMass, vertex_face_levels
from ._building_lod import bay_mean, style_wall_colours

NARROW_FACES = "plain wall (face narrower than its grammar)"  # the count assign_facades keeps of them


class GrammarFitWarning(UserWarning):
    """Wall faces narrower than their building's grammar fits were drawn as plain walls."""


WINDOW_BAY = 0  # the record's facade.x of the textured window bay with interior-mapped rooms


@dataclass(frozen=True)
class FacadeKind:
    name: str
    precedence: int  # the lowest accepting kind wins
    code: int  # the record's facade.x, read by shaders/city/building.glsl
    styles: frozenset[int] | None  # building style numbers it takes; None: any
    shapes: tuple[str, ...]
    grammar_style: str | None = None  # the library style of a grammar facade

    def accepts(self, mass: BuildingMass) -> bool:
        return (self.styles is None or mass.style in self.styles) and mass.shape in self.shapes


FACADE_KINDS = tuple(
    sorted(
        (
            # relief first: its styles are a quarter of the style numbers, so a quarter of the box buildings
            FacadeKind("relief bay", 10, FACADE_RELIEF, frozenset(RELIEF_STYLES), RELIEF_SHAPES),
            *(
                FacadeKind(f"grammar {style}", 20, FACADE_GRAMMAR, frozenset({number}), GRAMMAR_SHAPES, style)
                for number, style in BUILDING_STYLES.items()
            ),
            FacadeKind("window bay", 100, WINDOW_BAY, None, SHAPES),
        ),
        key=lambda kind: kind.precedence,
    )
)


def choose_facade(mass: BuildingMass) -> FacadeKind:
    """The facade of one building: the accepting kind of lowest precedence."""
    return next(kind for kind in FACADE_KINDS if kind.accepts(mass))


def assign_facades(records: np.ndarray, masses, vertices: np.ndarray | None = None) -> Counter:
    """Writes each building's facade into records['facade'] (code, grammar start rule, seed cells);
    returns how many buildings each kind got. A grammar building's tint becomes its style's wall
    colour (grammar_tints). With the buildings' `vertices` (scene.batch), the wall faces too narrow
    for their grammar become plain walls (surface SURFACE_PLAIN_WALL): counted under NARROW_FACES,
    with a GrammarFitWarning (dormer fronts are window bays: never counted)."""
    kinds = [choose_facade(m) for m in masses]
    records["facade"][:, 0] = [kind.code for kind in kinds]
    grammar = [i for i, kind in enumerate(kinds) if kind.grammar_style is not None]
    counts = Counter(kind.name for kind in kinds)
    if grammar:
        compiled = library_texture()
        records["facade"][grammar, 1] = [compiled.address(kinds[i].grammar_style) for i in grammar]
        records["facade"][grammar, 2:] = seed_cells([masses[i].seed for i in grammar])
        records["tint"][grammar] = grammar_tints([masses[i].style for i in grammar])
        if vertices is not None:
            styles = np.array([kind.grammar_style or "" for kind in kinds], dtype=object)
            narrow = _plain_narrow_faces(vertices, _needed_widths(vertices, records, styles))
            if narrow:
                counts[NARROW_FACES] = narrow
                warnings.warn(
                    f"{narrow} wall faces are narrower than their building's grammar fits "
                    f"(the narrowest face each library style fits at the ground: {_widths()}): drawn as plain walls",
                    GrammarFitWarning,
                    stacklevel=2,
                )
    return counts


def grammar_tints(styles: list[int]) -> np.ndarray:
    """(n, 4) building tints for grammar buildings of `styles`: what the grammar does not draw (plain
    walls, dormer fronts' window bays) takes the grammar's wall colour, not the building's mapped or
    guessed colour, which the grammar does not show."""
    wall = np.array([style_wall_colours()[style] for style in styles]).reshape(-1, 3)
    return np.column_stack([wall / (TINT_GAIN * bay_mean()[:3]), np.ones(len(wall))])


def _needed_widths(vertices: np.ndarray, records: np.ndarray, styles: np.ndarray) -> np.ndarray:
    """Per vertex, the narrowest face its building's grammar style (`styles` per building, "" for
    none) fits at the level of the vertex's face (facade.level: a ground floor may need a door's
    width where the storeys above do not); 0 off grammar walls."""
    needs = np.zeros(len(vertices))
    names, style = np.unique(styles, return_inverse=True)
    walls = np.flatnonzero((vertices["ids"][:, 1] == SURFACE_WALL) & (styles != "")[vertices["ids"][:, 0]])
    levels = vertex_face_levels(vertices, records, walls)
    for level in np.unique(levels).tolist():
        widths = np.array([library_min_widths(level).get(name, 0.0) for name in names])
        at = walls[levels == level]
        needs[at] = widths[style[vertices["ids"][at, 0]]]
    return needs


def _plain_narrow_faces(vertices: np.ndarray, needs: np.ndarray) -> int:
    """Marks the wall vertices of faces narrower than they need (`needs` per vertex) as plain walls;
    returns how many faces (building, room columns) that was."""
    building = vertices["ids"][:, 0]
    narrow = (vertices["ids"][:, 1] == SURFACE_WALL) & (vertices["face"][:, 0] < needs - 1e-6)
    vertices["ids"][narrow, 1] = SURFACE_PLAIN_WALL
    faces = np.column_stack([building[narrow], vertices["ids"][narrow, 2:], vertices["face"][narrow, 1:3]])
    return len(np.unique(faces, axis=0))


def _widths() -> str:
    return ", ".join(f"{style} {width:g} m" for style, width in library_min_widths().items())


def styles_with_relief(masses) -> tuple[list[int], list[int]]:
    """(the building styles that have relief, every style the buildings use): a style has relief when
    its buildings take the relief bay, the window bay (its window has an opening in the atlas), or a
    grammar style whose windows have openings in the atlas."""
    used = sorted({m.style for m in masses})
    atlas = relief_atlas()
    relief = []
    for style in used:
        kinds = [choose_facade(m) for m in masses if m.style == style]
        if any(
            k.code == FACADE_RELIEF
            or (k.code == WINDOW_BAY and atlas.window_bay[2] > 0)
            or (k.grammar_style is not None and atlas.styles.get(k.grammar_style))
            for k in kinds
        ):
            relief.append(style)
    return relief, used
