"""Relief in the city: one atlas of detail maps for every facade that has relief, on the GPU.

Region 0 is the window bay of the relief-bay buildings (repeated over their walls); region 1 the
window of the textured window bay (style 0, `window_bay_opening`); then, per grammar style the city uses, the window openings of its glazed terminals
and holes (`style_openings`, docs/relief.md). Each part is factorised once, BMF or SVD whichever is smaller,
and cached on disk (`_cache.py`); the atlas stacks the parts' BMF factorisations (exact: block rows
of X, the parts' terms side by side), so nothing is factorised again when the city loads.
"""

from __future__ import annotations

import hashlib
import math
from dataclasses import dataclass
from functools import lru_cache

import moderngl
import numpy as np

from ._bay_opening import window_bay_opening
from ._cache import cached_arrays, cached_compress, smallest_compression
from ._compress import MAP_NAMES, CompressedFacade, digest
from ._factor import Factors
from ._gpu import GpuFacade
from ._grammar_source import OPENING_DEPTH, PROFILE, StyleOpenings, style_openings
from ._layout import DEPTH_UNIT, generate_bay
from ._maps import DetailMaps

FACADE_RELIEF = 2  # the record's facade.x for relief-bay facades (shaders/relief/building.glsl)
RELIEF_STYLES = (2,)  # building styles drawn with the relief bay (no grammar style of their own)
RELIEF_SHAPES = ("prism",)  # flat walls only
MAX_OPENINGS = 64  # shaders/relief/openings.glsl RELIEF_MAX_OPENINGS


def switch_distance(height_px: int, fov_y: float) -> float:
    """Metres from the eye beyond which a pixel spans more than the pane's depth behind the wall:
    there the recess moves what a window shows by under a pixel (seen at 45 degrees), and the
    city draws the flat grammar instead of tracing (docs/relief.md, bench relief)."""
    pane = OPENING_DEPTH["glass"] * 0.01  # cm -> m
    return pane * height_px / (2.0 * math.tan(math.radians(fov_y) / 2.0))


@dataclass(frozen=True)
class ReliefAtlas:
    maps: DetailMaps  # the atlas's D and M (regions stacked in rows, zero-padded to the widest)
    bmf: CompressedFacade  # its factorisation, stacked from the parts'
    bay: tuple[int, int, int, int]  # the bay's region: first row, columns, rows, 1 (repeats)
    window_bay: tuple[int, int, int, int]  # the window bay's opening: first row, columns, rows (ring included), 0
    terminals: dict[int, int]  # glazed terminal's or hole's rule address -> first row of its opening
    colours: dict[int, tuple]  # glazed terminal's or hole's rule address -> sRGB (frame, reveal), StyleOpenings.colours
    styles: dict[str, str]  # grammar style -> the method its openings were compressed with


def stack_bmf(parts: list[CompressedFacade]) -> CompressedFacade:
    """BMF factorisations of maps stacked bottom to top as one: X is block-diagonal (each part's
    rows use only its own terms), Y holds every part's terms side by side (narrower parts padded
    with zero columns, never read); the free boxes move to the atlas rows and A's indices shift by
    the boxes before, as one more term per part whose value is that shift."""
    cols = max(p.shape[1] for p in parts)
    factors, boxes, row, shift = {}, [], 0, 0
    for p in parts:
        b = p.boxes.astype(np.int64) + [0, row, 0, row]
        boxes.append(b)
        row, shift = row + p.shape[0], shift + len(b)
    rows = row
    for name in MAP_NAMES:
        xs, ys, ss, row, shift = [], [], [], 0, 0
        for p in parts:
            f = p.factors[name]
            r = p.shape[0]
            extra = name == "boxes" and shift > 0
            x = np.zeros((rows, f.terms + extra), bool)
            x[row : row + r, : f.terms] = f.x
            y = np.zeros((cols, f.terms + extra), bool)
            y[: f.y.shape[0], : f.terms] = f.y
            s = list(f.s)
            if extra:
                x[row : row + r, -1] = True
                y[:, -1] = True
                s.append(shift)
            xs.append(x), ys.append(y), ss.append(np.asarray(s, np.float32))
            row, shift = row + r, shift + len(p.boxes)
        factors[name] = Factors("bmf", np.concatenate(xs, 1), np.concatenate(ss), np.concatenate(ys, 1))
    first = parts[0]
    digests = {name: digest(f.reconstruct()) for name, f in factors.items()}
    return CompressedFacade(
        "bmf", first.texel, first.depth_unit, factors, np.concatenate(boxes).astype(np.uint16), digests
    )


def _stack_maps(parts: list[DetailMaps]) -> DetailMaps:
    cols = max(m.shape[1] for m in parts)
    pad = [((0, 0), (0, cols - m.shape[1])) for m in parts]
    depth = np.concatenate([np.pad(m.depth, p) for m, p in zip(parts, pad)])
    material = np.concatenate([np.pad(m.material, p) for m, p in zip(parts, pad)])
    return DetailMaps(depth, material, parts[0].texel, parts[0].depth_unit)


_OPENING_ARRAYS = ("terminals", "depth", "material", "colours", "holes")


def cached_openings(compiled, style: str, number: int) -> StyleOpenings:
    """style_openings, cached on disk by a hash of its inputs: the compiled grammar texture, the
    tiles, the style's start rule and number, the profile and its depths."""
    from ..assets import tile_array

    digest = hashlib.sha256()
    for part in (compiled.texels.tobytes(), tile_array(128).layers.tobytes()):
        digest.update(part)
    digest.update(repr((compiled.address(style), number, PROFILE, sorted(OPENING_DEPTH.items()), 2)).encode())

    def build():
        o = style_openings(compiled, style, number)
        return {
            "terminals": np.array(o.terminals, np.int64),
            "depth": o.maps.depth,
            "material": o.maps.material,
            "colours": np.array(o.colours, np.float64).reshape(-1, 2, 3),
            "holes": np.array(o.holes, np.int64),
        }

    a = cached_arrays(f"openings-{style}", digest.hexdigest()[:32], _OPENING_ARRAYS, build)
    colours = tuple(tuple(tuple(float(c) for c in rgb) for rgb in pair) for pair in a["colours"])
    maps = DetailMaps(a["depth"].astype(np.uint16), a["material"].astype(np.uint16), 1.0, DEPTH_UNIT)
    return StyleOpenings(tuple(int(t) for t in a["terminals"]), maps, colours, tuple(int(t) for t in a["holes"]))


@lru_cache(maxsize=1)
def relief_atlas() -> ReliefAtlas:
    """The city's relief atlas (built once per process; the factorisations come from the disk cache)."""
    from ..grammar import BUILDING_STYLES, library_texture

    compiled = library_texture()
    bay, window = generate_bay(), window_bay_opening()
    parts = [bay, window]
    packed = [cached_compress(bay, "bmf", "city relief bay")[0], cached_compress(window, "bmf", "city window bay")[0]]
    terminals, colours, styles, row = {}, {}, {}, bay.shape[0] + window.shape[0]
    for number, style in BUILDING_STYLES.items():
        openings = cached_openings(compiled, style, number)  # every style has windows to recess
        best = smallest_compression(openings.maps, f"{style} window openings")
        styles[style] = best.method
        # the GPU decodes BMF: a style whose SVD is smaller is also factorised (and cached) with BMF
        packed.append(best if best.method == "bmf" else cached_compress(openings.maps, "bmf", style)[0])
        parts.append(openings.maps)
        for k, terminal in enumerate(openings.terminals):
            if terminal not in terminals:
                terminals[terminal] = row + k * openings.region_shape[0]
                colours[terminal] = openings.colours[k]
        row += openings.maps.shape[0]
    if len(terminals) > MAX_OPENINGS:
        raise ValueError(f"{len(terminals)} glazed terminals and holes; the city's shader holds {MAX_OPENINGS}")
    return ReliefAtlas(
        _stack_maps(parts),
        stack_bmf(packed),
        (0, bay.shape[1], bay.shape[0], 1),
        (bay.shape[0], window.shape[1], window.shape[0], 0),
        terminals,
        colours,
        styles,
    )


class CityRelief:
    """The relief atlas on the GPU, ready to bind for the buildings' program."""

    def __init__(self, ctx: moderngl.Context):
        self.atlas = relief_atlas()
        self.facade = GpuFacade(ctx, self.atlas.maps, {"bmf": self.atlas.bmf})
        # metres: the deepest point of the relief bay, and of the openings (the rows after it)
        depth, unit, bay_rows = self.atlas.maps.depth, self.atlas.maps.depth_unit, self.atlas.bay[2]
        self.deepest = (float(depth[:bay_rows].max()) * unit, float(depth[bay_rows:].max()) * unit)

    def bind(self, program: moderngl.Program, range_m: float):
        """range_m: metres within which grammar windows are traced (RenderSettings.relief_range)."""
        a = self.atlas
        terminals = sorted(a.terminals.items())
        _set_present(
            program,
            u_relief_depth_unit=a.maps.depth_unit,
            u_relief_bay=a.bay,
            u_relief_window_bay=a.window_bay,
            u_relief_profile=(PROFILE[0] + 2, PROFILE[1] + 2),
            u_relief_range=range_m,
        )
        self.bind_openings(program)
        if "u_relief_colours" in program:
            uniform = program["u_relief_colours"]
            flat = [c for terminal, _ in terminals for c in a.colours[terminal]]
            flat += [(0.0, 0.0, 0.0)] * (uniform.array_length - len(flat))
            uniform.value = flat[: uniform.array_length]
        self.facade.bind(program, "bmf")

    def bind_openings(self, program: moderngl.Program):
        """Which glazed terminals and holes have an opening, and its first row (shaders/relief/openings.glsl)."""
        terminals = sorted(self.atlas.terminals.items())
        _set_present(program, u_relief_openings=len(terminals))
        if "u_relief_terminals" in program:
            uniform = program["u_relief_terminals"]
            padded = terminals + [(-1, -1)] * (uniform.array_length - len(terminals))
            uniform.value = padded[: uniform.array_length]

    def bind_depth_bound(self, program: moderngl.Program, range_m: float):
        """For a depth-only program with RELIEF_DEPTH_BOUND (shaders/relief/depth.glsl): the switch
        distance and the deepest recesses."""
        _set_present(program, u_relief_range=range_m, u_relief_depths=self.deepest)

    def release(self):
        self.facade.release()


def _set_present(program: moderngl.Program, **values):
    """Sets the uniforms the program uses (the compiler drops those a variant does not read)."""
    for name, value in values.items():
        if name in program:
            program[name].value = value
