"""`cityshade bench facades`: fig. 11 of Krecklau & Kobbelt 2011 and the grammar texture's size (§6).

A city of 20,000 box buildings (2,000 with --quick), every facade from one grammar at a time:
simple (subdivisions and static textures, fig. 13a), random (fig. 12), full (dusk.grammar:
randomisation, layers, masks and Intrusion rooms) and conditions (conditions.grammar: simple's
layout with its window choices made by Case conditions on rule parameters, split.index and
parity), seen from a distance, at street level and in
close-up; each by the forward (depth prepass) and the deferred path. The city is drawn by the
city's own frame (render.Renderer, FIG11_SETTINGS: no MSAA, trees, shadows, god rays or rooms
behind the glass; SSAO on). Median frame times.
Also: windows that show more than one room, over the built-in district's and the Helsinki
extract's viewpoints (windows_straddling_rooms_district, windows_straddling_rooms_osm).
"""

from __future__ import annotations

import math
from pathlib import Path

import numpy as np
from matplotlib.figure import Figure

from .._files import write_figure, write_png
from ..gl import create_context, describe_context
from ..grammar import BUILDING_STYLES, compile_grammars, library_path, load, load_library
from ..interior import windows_straddling_rooms
from ..maps import load_map, map_city
from ..render import Renderer, RenderSettings, styles_with_relief
from ..scene import Camera, City, Layer, box, make_city
from ..trees import TREE_DTYPE
from ._harness import BenchResult, Timing, method_record, time_interleaved, timing_record
from .osm import HELSINKI

GRAMMARS = {"simple": "simple", "random": "fig12", "full": "dusk", "conditions": "conditions"}  # -> grammar name
PATHS = ("forward", "deferred")
# fig. 11 measures the facades: the frame without what the paper's city lacks (MSAA, trees, shadows,
# god rays, rooms behind the glass); buildings not culled; SSAO as in the paper's deferred pipeline;
# daylight. The grammars not in the library are compiled after it.
FIG11_SETTINGS = RenderSettings(
    samples=0,
    trees=False,
    shadows=False,
    god_rays=False,
    interior_mapping=False,
    culling="off",
    ssao=True,
    time_of_day=14.0,
    grammar_files=tuple(str(library_path(f"{name}.grammar")) for name in ("simple", "conditions")),
)
# forward: depth prepass, then the grammar where the depth test passes; deferred: G-buffer, the
# grammar once per pixel, then the buildings pass reads it back
PATH_SETTINGS = {
    "forward": dict(grammar_deferred=False, depth_prepass=True),
    "deferred": dict(grammar_deferred=True, depth_prepass=False),
}
GRAMMAR_STYLE = {name: number for number, name in BUILDING_STYLES.items()}["office"]  # any grammar style
# Fig. 11: frames per second / ms per frame at 1024x768 on a GeForce GTX 470.
PAPER_FIG11 = {
    "distance": {"simple": (79, 12), "random": (66, 15), "full": (18, 55)},
    "street": {"simple": (130, 7), "random": (110, 9), "full": (39, 25)},
    "closeup": {"simple": (82, 12), "random": (70, 14), "full": (25, 40)},
}
PAPER_RULES, PAPER_BYTES = 330, 5928  # §6: the grammar of fig. 10
TARGETS = {
    "random_over_simple": "<= 1.1 (paper ~1.2)",
    "full_over_simple": "<= 2.0 (paper ~4.4)",
    "conditions_over_simple": "<= 1.3",
    "bytes_per_rule": "<= 16 (paper 18)",
    "deferred_over_forward": "report (< 1: deferred is faster)",
    "city_deferred_over_forward": "report (the city's default follows the faster)",
    "windows_straddling_rooms_district": "0",
    "windows_straddling_rooms_osm": "0",
    "styles_with_relief_fraction": "1.0",
    "relief_everywhere_over_off": "<= 1.3",
}
PITCH = 32.0
CITY_SIZE = (640, 360)
WINDOWS_SIZE = (960, 540)  # piers between windows stay a pixel wide or more in the street views


def city_masses(count: int, seed: int = 11):
    """Boxes on a square grid of PITCH-metre lots, 16-24 m wide, 10-60 m tall, with grammar facades."""
    rng = np.random.default_rng(seed)
    side = math.ceil(math.sqrt(count))
    sizes = rng.uniform(16.0, 24.0, (count, 2))
    heights = rng.choice(np.arange(3.2, 60.0, 3.2), count)
    seeds = rng.integers(0, 1 << 30, count)
    return [
        box(
            (float(k % side) * PITCH, float(k // side) * PITCH),
            float(sizes[k, 0]),
            float(sizes[k, 1]),
            float(heights[k]),
            seed=int(seeds[k]),
            style=GRAMMAR_STYLE,
        )
        for k in range(count)
    ], side


def fig11_city(count: int) -> tuple[City, int]:
    """The grid city of city_masses as a City without trees; and its side in lots."""
    masses, side = city_masses(count)
    extent = side * PITCH
    return City(
        "fig. 11", 0, masses, [], (0.0, 0.0, extent, extent), layers=(Layer("trees", trees=np.zeros(0, TREE_DTYPE)),)
    ), side


def fig11_settings(path: str, grammar: str) -> RenderSettings:
    """FIG11_SETTINGS drawing every facade with GRAMMARS[grammar] by `path`."""
    return FIG11_SETTINGS.with_(grammar_start=GRAMMARS[grammar], **PATH_SETTINGS[path])


def views(side: int) -> dict[str, Camera]:
    """Fig. 10's three views of the grid city."""
    extent = side * PITCH
    mid = (side // 2) * PITCH
    street_x = mid + 28.0  # between two columns of lots
    return {
        "distance": Camera(
            (-0.15 * extent, 0.12 * extent + 60.0, -0.15 * extent),
            (0.45 * extent, 0.0, 0.45 * extent),
            fov_y=55.0,
            near=2.0,
            far=4.0 * extent + 500.0,
        ),
        "street": Camera((street_x, 1.7, mid - 60.0), (street_x - 6.0, 14.0, mid + 80.0), fov_y=66.0, far=4000.0),
        "closeup": Camera((mid + 6.0, 4.0, mid - 7.0), (mid + 12.0, 6.5, mid), fov_y=60.0, far=4000.0),
    }


def city_frame_ms(ctx, size, frames: int) -> dict[str, Timing]:
    """The whole frame of the default city with the grammar facades forward or deferred."""
    city = make_city("default")
    camera = city.camera("street")
    renderers = {path: Renderer(size, RenderSettings(grammar_deferred=path == "deferred"), ctx=ctx) for path in PATHS}
    for renderer in renderers.values():
        renderer.set_city(city)
    try:
        return time_interleaved(ctx, {p: (lambda i, r=r: r.draw(camera)) for p, r in renderers.items()}, frames)
    finally:
        for renderer in renderers.values():
            renderer.release()


def relief_frame_ms(ctx, size, frames: int) -> dict[str, float]:
    """The default city's frame with relief on every style that has it and with relief off, the two
    taking turns frame by frame, at the street and close-up viewpoints: (camera, on|off) -> median ms."""
    city = make_city("default")
    renderers = {on: Renderer(size, RenderSettings(relief=on == "on"), ctx=ctx) for on in ("on", "off")}
    for renderer in renderers.values():
        renderer.set_city(city)
    out = {}
    try:
        for name in ("street", "closeup"):
            camera = city.camera(name)
            timed = time_interleaved(
                ctx, {k: (lambda i, r=r, camera=camera: r.draw(camera)) for k, r in renderers.items()}, frames
            )
            out.update({(name, k): v.ms()[0] for k, v in timed.items()})
    finally:
        for renderer in renderers.values():
            renderer.release()
    return out


def straddling_windows(ctx, city, size=WINDOWS_SIZE) -> dict[str, int]:
    """Windows that show more than one room, over the city's viewpoints (the id AOV with window
    keys, cityshade.interior.windows_straddling_rooms), summed."""
    renderer = Renderer(size, RenderSettings(), ctx=ctx)
    renderer.set_city(city)
    total = dict.fromkeys(("windows", "straddling", "patches_with_rooms", "patches_of_touching_windows"), 0)
    try:
        for camera in city.viewpoints.values():
            count = windows_straddling_rooms(renderer.render_ids(camera, windows=True))
            for key in total:
                total[key] += getattr(count, key)
    finally:
        renderer.release()
    return total


def library_bytes_per_rule() -> tuple[int, int, float]:
    """The whole library in one texture: (rules as written, bytes, bytes per rule)."""
    grammars = load_library()
    grammars["simple"] = load(library_path("simple.grammar"))
    grammars["conditions"] = load(library_path("conditions.grammar"))
    compiled = compile_grammars(grammars)
    written = {
        (r.source.definition.location.path, r.source.definition.location.line)
        for g in grammars.values()
        for r in g.rules.values()
    }
    return len(written), compiled.nbytes, compiled.nbytes / len(written)


def run(quick: bool, out_dir: Path) -> BenchResult:
    ctx = create_context()
    count = 2_000 if quick else 20_000
    size = (512, 384) if quick else (1024, 768)
    frames = 9 if quick else 11
    city, side = fig11_city(count)
    renderer = Renderer(size, FIG11_SETTINGS, ctx=ctx)
    renderer.set_city(city)
    cameras = views(side)
    ms: dict[tuple[str, str, str], float] = {}
    iqr: dict[tuple[str, str, str], float] = {}

    def draw(settings: RenderSettings, camera: Camera):
        renderer.set_settings(settings)
        renderer.draw(camera)

    try:
        for view, camera in cameras.items():
            for grammar in GRAMMARS:
                settings = {path: fig11_settings(path, grammar) for path in PATHS}
                timed = time_interleaved(
                    ctx, {path: (lambda i, s=settings[path], camera=camera: draw(s, camera)) for path in PATHS}, frames
                )
                for path, value in timed.items():
                    ms[(view, grammar, path)], iqr[(view, grammar, path)] = value.ms()
                # the last frame drawn (deferred)
                write_png(renderer.targets["display"].read()[..., :3].copy(), out_dir / f"facades_{view}_{grammar}.png")
    finally:
        renderer.release()

    city_ms = city_frame_ms(ctx, CITY_SIZE, frames)
    relief_ms = relief_frame_ms(ctx, CITY_SIZE, frames)
    with_relief, styles_used = styles_with_relief(make_city("default").masses)
    straddling = {
        "district": straddling_windows(ctx, make_city("default")),
        "osm": straddling_windows(ctx, map_city(load_map(HELSINKI))),
    }
    result = BenchResult("facades", describe_context(ctx), timing=timing_record(frames))
    for path in PATHS:
        result.methods[f"fig. 11 {path}"] = method_record(
            cull_back_faces=True,  # the buildings pass culls them (render/_frame.py)
            depth_prepass=path == "forward",
            frustum_culling=False,
            msaa=0,
            size=size,
            grammar_deferred=path == "deferred",
            ssao=True,
            note="the city's frame without trees, shadows, god rays or rooms behind the glass (ground and sky "
            "drawn, tone mapped); forward: depth prepass, then the grammar where the depth test passes; "
            "deferred: G-buffer, grammar once per pixel, buildings pass reading it back",
        )
        result.methods[f"city frame, grammar {path}"] = method_record(
            cull_back_faces=True,  # the buildings pass culls them (render/_frame.py)
            depth_prepass=True,
            frustum_culling=True,
            msaa=RenderSettings().samples,
            size=CITY_SIZE,
            grammar_deferred=path == "deferred",
        )
    rows = []
    for view in cameras:
        for grammar in GRAMMARS:
            fps, paper_ms = PAPER_FIG11[view].get(grammar, ("-", "-"))  # the paper has no conditions
            fwd, dfr = ms[(view, grammar, "forward")], ms[(view, grammar, "deferred")]
            rows.append(
                [
                    view,
                    grammar,
                    fwd,
                    iqr[(view, grammar, "forward")],
                    dfr,
                    iqr[(view, grammar, "deferred")],
                    round(dfr / fwd, 3),
                    paper_ms,
                    fps,
                ]
            )
    result.add_table(
        f"Fig. 11: ms per frame, {count} buildings at {size[0]}x{size[1]} (paper: GTX 470, 1024x768)",
        [
            "view",
            "grammar",
            "forward ms",
            "forward IQR ms",
            "deferred ms",
            "deferred IQR ms",
            "deferred/forward",
            "paper ms",
            "paper fps",
        ],
        rows,
    )
    best = {key[:2]: min(ms[(*key[:2], p)] for p in PATHS) for key in ms}

    def over_simple(grammar):
        return _geomean([best[(v, grammar)] / best[(v, "simple")] for v in cameras])

    result.add_table(
        "The city's frame (default city, street camera, 640x360, interiors on): grammar facades by path",
        ["path", "ms per frame", "IQR ms"],
        [[p, *v.ms()] for p, v in city_ms.items()],
    )
    result.add_table(
        "The city's frame (default city, 640x360): relief on every style that has it vs relief off",
        ["camera", "relief on ms", "relief off ms", "on/off"],
        [
            [c, relief_ms[(c, "on")], relief_ms[(c, "off")], round(relief_ms[(c, "on")] / relief_ms[(c, "off")], 3)]
            for c in ("street", "closeup")
        ],
    )
    rules, nbytes, per_rule = library_bytes_per_rule()
    result.add_table(
        "§6: grammar texture of the whole library",
        ["", "rules", "bytes", "bytes per rule"],
        [
            ["ours", rules, nbytes, round(per_rule, 2)],
            ["paper (fig. 10)", PAPER_RULES, PAPER_BYTES, round(PAPER_BYTES / PAPER_RULES, 2)],
        ],
    )
    result.ratios = {
        "random_over_simple": round(over_simple("random"), 3),
        "full_over_simple": round(over_simple("full"), 3),
        "conditions_over_simple": round(over_simple("conditions"), 3),
        "bytes_per_rule": round(per_rule, 2),
        "deferred_over_forward": round(
            _geomean([ms[(v, g, "deferred")] / ms[(v, g, "forward")] for v in cameras for g in GRAMMARS]), 3
        ),
        "city_deferred_over_forward": round(city_ms["deferred"].median / city_ms["forward"].median, 3),
        "windows_straddling_rooms_district": straddling["district"]["straddling"],
        "windows_straddling_rooms_osm": straddling["osm"]["straddling"],
        "styles_with_relief_fraction": round(len(with_relief) / len(styles_used), 3),
        "relief_everywhere_over_off": round(
            _geomean([relief_ms[(c, "on")] / relief_ms[(c, "off")] for c in ("street", "closeup")]), 3
        ),
    }
    result.add_table(
        f"Windows showing more than one room, over each city's viewpoints at {WINDOWS_SIZE[0]}x{WINDOWS_SIZE[1]}",
        [
            "city",
            "windows",
            "showing two or more rooms",
            "glass patches showing several rooms",
            "of them: touching windows",
        ],
        [
            [name, *counts.values()]
            for name, counts in (
                ("district (default city)", straddling["district"]),
                ("Helsinki extract", straddling["osm"]),
            )
        ],
    )
    result.targets = dict(TARGETS)
    faster = "deferred" if result.ratios["deferred_over_forward"] < 1 else "forward"
    result.notes += [
        "Ratios over simple use each configuration's faster path and the geometric mean over the three views.",
        "A window is the glass of one grammar window or window bay (the id AOV's window key); a glass patch is "
        "4-connected glass on the screen, which joins windows that touch (a curtain wall's panes, a glazed front).",
        f"The faster path on this device: {faster} (deferred/forward = {result.ratios['deferred_over_forward']}).",
        "The paper's bytes count the 330 rules of fig. 10's grammar; ours count every rule written in the library "
        "files (rules reused through namespaces share texels and are counted once).",
        f"Frame times are medians (and interquartile ranges) of {frames} frames after one warm-up, with "
        "ctx.finish(); the two paths take turns frame by frame.",
    ]
    result.notes.append(
        f"Styles with relief (default city): {with_relief} of {styles_used}; relief on/off is the geometric mean "
        "over the street and close-up viewpoints."
    )
    result.plots.append(str(_plot(ms, cameras, out_dir)))
    return result


def _geomean(values) -> float:
    return float(np.exp(np.mean(np.log(values))))


def _plot(ms, cameras, out_dir: Path) -> Path:
    fig = Figure(figsize=(8, 3.6))
    ax = fig.add_subplot(1, 1, 1)
    labels = [f"{v}\n{g}" for v in cameras for g in GRAMMARS]
    x = np.arange(len(labels))
    for offset, path in ((-0.2, "forward"), (0.2, "deferred")):
        ax.bar(x + offset, [ms[(v, g, path)] for v in cameras for g in GRAMMARS], 0.4, label=path)
    ax.plot(
        x,
        [PAPER_FIG11[v].get(g, (0, np.nan))[1] for v in cameras for g in GRAMMARS],
        "k_",
        markersize=18,
        label="paper (GTX 470)",
    )
    ax.set_xticks(x, labels, fontsize=7)
    ax.set_ylabel("ms per frame")
    ax.legend(fontsize=8)
    fig.tight_layout()
    out_dir.mkdir(parents=True, exist_ok=True)
    path = out_dir / "facades.png"
    write_figure(fig, path, dpi=110)
    return path
