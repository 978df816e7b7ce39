"""Detail maps from a facade grammar: the grammar's numpy evaluator rasterised at texel centres,
each terminal given the depth and material of its semantic label (glass texels of a terminal
sink to the glass depth)."""

from __future__ import annotations

from dataclasses import dataclass
from pathlib import Path
from typing import Callable

import numpy as np

from ..assets import LABELS, tile_array
from ..grammar import compile_grammars, evaluate, hole_cut, load, seed_vector
from ._layout import CORNICE, DEPTH_UNIT, DOOR_D, FRAME, FRAME_D, GLASS, GLASS_D, SILL, STONE, WALL, WALL_D, WOOD
from ._maps import DetailMaps

# label -> (depth in cm behind the outermost surface, material)
LABEL_RELIEF = {
    "none": (WALL_D, WALL),
    "wall": (WALL_D, WALL),
    "window": (FRAME_D, FRAME),
    "door": (DOOR_D, WOOD),
    "balcony": (SILL, STONE),
    "shop": (FRAME_D, FRAME),
    "roof": (CORNICE, STONE),
    "room": (GLASS_D, GLASS),
    "cornice": (CORNICE, STONE),
}
_DEPTH = np.array([LABEL_RELIEF[name][0] for name in LABELS], np.uint16)
_MATERIAL = np.array([LABEL_RELIEF[name][1] for name in LABELS], np.uint16)


def grammar_maps(
    path: Path,
    rule: str | None,
    facade: tuple[float, float],
    texel: float,
    seed: int = 1,
    on_rows: Callable[[int], None] | None = None,
) -> DetailMaps:
    """D and M of a grammar facade `facade` metres wide and high; on_rows(n) reports progress."""
    grammar = load(path)
    if rule is not None:
        grammar.rule(rule)
    compiled = compile_grammars({"g": grammar})
    start = compiled.address("g", rule)
    cols, rows = max(1, round(facade[0] / texel)), max(1, round(facade[1] / texel))
    tiles = tile_array(128)
    x = (np.arange(cols, dtype=np.float32) + 0.5) * texel
    label = np.empty((rows, cols), np.int64)
    glass = np.empty((rows, cols), bool)
    chunk = max(1, 20000 // cols)
    for r0 in range(0, rows, chunk):
        y = (np.arange(r0, min(rows, r0 + chunk), dtype=np.float32) + 0.5) * texel
        uv = np.stack(np.meshgrid(x, y), axis=-1).reshape(-1, 2)
        result = evaluate(compiled, start, uv, facade, seed_vector(seed), tiles)
        label[r0 : r0 + len(y)] = result.label.reshape(len(y), cols)
        glass[r0 : r0 + len(y)] = result.glass.reshape(len(y), cols)
        if on_rows:
            on_rows(len(y))
    depth = np.where(glass, GLASS_D, _DEPTH[label]).astype(np.uint16)
    material = np.where(glass, GLASS, _MATERIAL[label]).astype(np.uint16)
    return DetailMaps(depth, material, texel, DEPTH_UNIT)


# Window openings (the city's relief on grammar facades, docs/relief.md): each glazed terminal of a
# style is rasterised over its own scope at PROFILE texels, normalised, so one profile fits every
# window that terminal draws whatever the scope's size (Fit tiles stretch with the scope). A ring of
# wall texels at depth 0 around it is the opening's reveal. A window that is a hole (a SkipMask cutting
# through the wall to what a layer below shows, dusk's rooms) is its mask over the SkipMask's scope.
PROFILE = (48, 48)  # columns, rows inside the ring
OPENING_DEPTH = {"frame": 10, "glass": 14}  # cm behind the wall: the window frame and mullions, the pane
# faces (width, height) and building (levels, use) the numpy evaluator is run over to find a
# style's glazed terminals: narrow, wide, low and tall faces, homes, offices and shops
_PROBE_FACES = ((14.0, 16.0), (7.0, 22.0), (26.0, 7.5))
_PROBE_USES = (0, 1, 2)
_PROBE_SEEDS = (1, 2, 3)


@dataclass(frozen=True)
class StyleOpenings:
    """A style's window openings: its glazed terminals' and holes' profiles stacked bottom to top,
    region k at rows [k * rows, (k + 1) * rows) of `maps`, each PROFILE plus the ring."""

    terminals: tuple[int, ...]  # rule addresses in the compiled texture (a Mat, or a hole's SkipMask), one per region
    maps: DetailMaps
    # per region, the sRGB colour of the terminal's frame and of the style's wall (the reveal), as
    # the flat grammar shows them, so the recessed window keeps the flat one's colours
    colours: tuple[tuple[tuple[float, float, float], tuple[float, float, float]], ...]
    holes: tuple[int, ...] = ()  # the terminals that are holes (SkipMasks)

    @property
    def region_shape(self) -> tuple[int, int]:
        return PROFILE[1] + 2, PROFILE[0] + 2


def _grid(shape: tuple[int, int], scope: np.ndarray) -> np.ndarray:
    """Texel centres (rows * cols, 2) over a scope (x, y, w, h), row 0 at the bottom."""
    cols, rows = shape
    x = scope[0] + (np.arange(cols) + 0.5) / cols * scope[2]
    y = scope[1] + (np.arange(rows) + 0.5) / rows * scope[3]
    return np.stack(np.meshgrid(x, y), axis=-1).reshape(-1, 2).astype(np.float32)


def _profile(compiled, tiles, result, terminal: int, hole: bool, reveal) -> tuple[np.ndarray, np.ndarray, tuple]:
    """D, M (ring included) and (frame, reveal) colours of one opening from the evaluation over its
    scope's PROFILE grid: a glazed terminal's glass at the pane's depth and the rest of it at the
    frame's; a hole (its mask's own shape, grammar.hole_cut) open at the pane's depth in the wall.
    Frames layered over a hole stay on the flat grammar's wall plane: they are not traced."""

    def grid(values):
        return values.reshape(PROFILE[1], PROFILE[0], *values.shape[1:])[:, ::-1]

    colour = grid(result.color)
    if hole:
        glass = grid(hole_cut(compiled, tiles, terminal, _grid(PROFILE, np.array([0.0, 0.0, 1.0, 1.0]))))
        frame = np.zeros_like(glass)
        depth = np.where(glass, OPENING_DEPTH["glass"], 0)
    else:
        own = grid(result.terminal == terminal)
        glass = grid(result.glass) & own
        frame = own & ~glass if (own & ~glass).any() else own
        depth = np.where(glass, OPENING_DEPTH["glass"], np.where(own, OPENING_DEPTH["frame"], 0))
    shade = tuple(float(c) for c in colour[frame].mean(axis=0)) if frame.any() else reveal
    material = np.where(glass, GLASS, np.where(frame, FRAME, WALL))
    return np.pad(depth, 1), np.pad(material, 1, constant_values=WALL), (shade, reveal)


def style_openings(compiled, style: str, style_number: int, probe_texel: float = 0.25) -> StyleOpenings:
    """The glazed terminals and holes of library style `style` (compiled: the city's grammar texture)
    and a profile of each (_profile): texels another terminal covers (a rail layered over a window)
    stand at the wall. Columns follow the wall mesh's u, which runs right to left seen from outside:
    the profile is mirrored."""
    start = compiled.address(style)
    tiles = tile_array(128)
    found: dict[int, tuple] = {}
    walls = []  # sRGB colours of the wall texels seen on the probes
    for face in _PROBE_FACES:
        cols, rows = round(face[0] / probe_texel), round(face[1] / probe_texel)
        uv = _grid((cols, rows), np.array([0.0, 0.0, *face]))
        for use in _PROBE_USES:
            for seed in _PROBE_SEEDS:
                building = (round(face[1] / 3.2), style_number, use, face[1])
                result = evaluate(compiled, start, uv, face, seed_vector(seed), tiles, building=building)
                walls.append(result.color[(result.label == LABELS.index("wall")) & (result.hole < 0)])
                glazed = result.glass & (result.terminal >= 0)
                holes = (result.hole >= 0) & ~glazed  # what a hole shows, not a glazed terminal's glass
                for which, terminals, scopes, hole in (
                    (glazed, result.terminal, result.scope, False),
                    (holes, result.hole, result.hole_scope, True),
                ):
                    for terminal in np.unique(terminals[which]):
                        if int(terminal) not in found:
                            first = np.flatnonzero(which & (terminals == terminal))[0]
                            found[int(terminal)] = (face, seed, building, scopes[first].copy(), hole)
    wall = np.concatenate(walls)
    reveal = tuple(float(c) for c in (wall.mean(axis=0) if len(wall) else np.full(3, 0.6)))
    regions, colours = [], []
    for terminal, (face, seed, building, scope, hole) in sorted(found.items()):
        result = evaluate(compiled, start, _grid(PROFILE, scope), face, seed_vector(seed), tiles, building=building)
        depth, material, colour = _profile(compiled, tiles, result, terminal, hole, reveal)
        regions.append((depth, material))
        colours.append(colour)
    if not regions:
        raise ValueError(f"grammar style {style!r} has no glazed terminal nor hole on the probe faces")
    depth = np.concatenate([d for d, _ in regions]).astype(np.uint16)
    material = np.concatenate([m for _, m in regions]).astype(np.uint16)
    holes = tuple(terminal for terminal, found_at in sorted(found.items()) if found_at[-1])
    return StyleOpenings(tuple(sorted(found)), DetailMaps(depth, material, 1.0, DEPTH_UNIT), tuple(colours), holes)
