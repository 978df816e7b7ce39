"""`cityshade bench interior`: the experiments of interior-mapping §3.

(a) fig. 9: frame time against the number of buildings, interior mapping against polygonised
    interiors (real floors, ceilings and walls; cityshade.interior.polygonised_vertices);
(b) §3.1 z-cull: depth prepass on and off, camera orbiting a grid of buildings;
(c) §3.2 room texture resolution 256 / 64 / 16;
(d) §3.2 rooms per building from 1,000 to 4,000,000 (same masses, smaller rooms);
(e) §3.2 interior mapping against reflective-only windows.

Every comparison alternates its variants frame by frame in one run (the harness's
time_interleaved), so load on the machine hits them alike; times are medians with their
interquartile range. All variants draw at the same size without MSAA, with the paper's interior
version (four textures, no furniture, no distance LOD) and without shadows, trees and god rays,
which the paper's scenes did not have. The polygonised baseline culls back faces and has its own
depth prepass for the rooms (render/_frame.py); the result's `methods` records both.
"""

from __future__ import annotations

from dataclasses import dataclass, replace
from pathlib import Path

import numpy as np
from matplotlib.figure import Figure

from .._files import write_figure, write_png
from ..render import Renderer, RenderSettings
from ..scene import Camera, City, grid_city
from ._harness import MIN_TIMED_FRAMES, BenchResult, Timing, method_record, time_interleaved, timing_record

SETTINGS = RenderSettings(
    samples=0,
    furniture=False,
    curtains=False,
    lod=False,
    shadows=False,
    trees=False,
    god_rays=False,
    grammar_deferred=False,
    culling="frustum",
)  # the same chunks as the rooms
BUILDING_COUNTS = (1, 10, 100, 500, 1000)
TEXTURE_SIZES = (256, 64, 16)
ROOM_COUNTS = (1_000, 10_000, 100_000, 1_000_000, 4_000_000)
PAPER_SECONDS = 5.0  # the paper counts frames rendered in five seconds
PAPER = {
    "zcull_off": 881,
    "zcull_on": 1265,
    "textures": {256: 999, 64: 1032, 16: 1053},
    "reflective": 5100,
    "interior_mapping": 999,
}
TARGETS = {
    "rooms_4m_over_1k": "<= 1.02",
    "im_over_reflective": "<= 2.0 (paper 5.1)",
    "prepass_speedup": ">= 1.5 (paper 1.44)",
    "polygonised_over_im_at_10": "> 1",
    "polygonised_over_im_at_1000": ">= 5",
}


def frames_in(seconds_per_frame: float) -> float:
    """The paper's measure: frames rendered in five seconds."""
    return PAPER_SECONDS / seconds_per_frame


def method(settings: RenderSettings, size) -> dict:
    """What a variant runs with: both cull back faces (render/_frame.py) and by chunk against the
    frustum."""
    return method_record(
        cull_back_faces=True,
        depth_prepass=settings.depth_prepass,
        frustum_culling=True,
        msaa=settings.samples,
        size=size,
        interior=(
            "polygonised"
            if settings.polygonised_interiors
            else "interior mapping"
            if settings.interior_mapping
            else "reflective only"
        ),
        furniture=settings.furniture and settings.interior_mapping,
        room_texture_size=settings.room_texture_size,
    )


def timed(renderer: Renderer, camera: Camera, variants: dict[str, RenderSettings], frames: int) -> dict[str, Timing]:
    """The variants' frames on one renderer, taking turns frame by frame."""

    def draw(settings):
        renderer.set_settings(settings)
        renderer.draw(camera)

    return time_interleaved(renderer.ctx, {k: (lambda i, s=s: draw(s)) for k, s in variants.items()}, frames)


def _renderer_for(base: Renderer, settings: RenderSettings, city: City) -> Renderer:
    """A renderer on the same context and programs as `base`, with its own settings and city."""
    renderer = Renderer(base.size, settings, ctx=base.ctx)
    renderer.programs = base.programs
    renderer.set_city(city)
    return renderer


def overview_camera(city: City) -> Camera:
    """The whole grid from above one corner: every building in view (fig. 9)."""
    x0, z0, x1, z1 = city.bounds
    half = max(x1 - x0, 60.0) / 2
    return Camera((half * 1.3, half * 0.8 + 60.0, half * 1.3), (0.0, 35.0, 0.0), fov_y=55.0)


def street_camera(city: City) -> Camera:
    """From a street corner into the grid: facades fill most of the picture."""
    x0, z0, _, _ = city.bounds
    return Camera((x0 - 6.0, 12.0, z0 - 6.0), (x0 + 60.0, 40.0, z0 + 45.0), fov_y=60.0)


def scaled_rooms(city: City, rooms: int) -> City:
    """The same masses with room size scaled so each building has about `rooms` rooms."""
    mass = city.masses[0]
    scale = (np.prod(np.rint(mass.extent / mass.room_size)) / rooms) ** (1 / 3)
    masses = [replace(m, room_width=m.room_width * scale, floor_height=m.floor_height * scale) for m in city.masses]
    return replace(city, masses=masses)


def _rooms(city: City) -> int:
    mass = city.masses[0]
    return int(np.prod(np.rint(mass.extent / mass.room_size)))


def _fig9(result: BenchResult, renderer: Renderer, rounds: int, counts) -> dict[int, dict[str, float]]:
    im, poly = SETTINGS, SETTINGS.with_(polygonised_interiors=True)
    rows, times = [], {}
    for n in counts:
        city = grid_city(n)
        renderer.set_city(city)
        timing = timed(renderer, overview_camera(city), {"im": im, "poly": poly}, rounds)
        t = times[n] = {k: v.median for k, v in timing.items()}
        im_triangles = renderer.city.building_vertex_count // 3
        rows.append(
            [
                n,
                *timing["im"].ms(),
                *timing["poly"].ms(),
                round(frames_in(t["im"])),
                round(frames_in(t["poly"])),
                round(t["poly"] / t["im"], 2),
                im_triangles,
                im_triangles + renderer.city.polygonised().triangle_count,
                10 * n,
                158 * n,
            ]
        )
    result.add_table(
        "(a) fig. 9: buildings vs frame time, interior mapping (IM) vs polygonised interiors (P)",
        [
            "buildings",
            "IM ms",
            "IM IQR ms",
            "P ms",
            "P IQR ms",
            "IM frames/5 s",
            "P frames/5 s",
            "P / IM time",
            "IM triangles",
            "P triangles",
            "paper IM polys",
            "paper P polys",
        ],
        rows,
    )
    for n in (10, 1000):
        if n in times:
            result.ratios[f"polygonised_over_im_at_{n}"] = times[n]["poly"] / times[n]["im"]
    return times


def _plot_fig9(result: BenchResult, times: dict[int, dict[str, float]], out_dir: Path):
    counts = sorted(times)
    fig = Figure(figsize=(6, 4))
    ax = fig.add_subplot()
    for key, label in (("im", "interior mapping"), ("poly", "polygonised interiors")):
        ax.plot(counts, [frames_in(times[n][key]) for n in counts], marker="o", label=label)
    ax.set_xscale("log")
    ax.set_yscale("log")
    ax.set_xlabel("buildings in the scene")
    ax.set_ylabel("frames in 5 s")
    ax.set_title(f"fig. 9 ({result.device})", fontsize=8)
    ax.grid(True, which="both", alpha=0.3)
    ax.legend()
    path = out_dir / "interior_fig9.png"
    write_figure(fig, path, dpi=100, bbox_inches="tight")
    result.plots.append(str(path))


def _prepass(result: BenchResult, renderer: Renderer, rounds: int, angles, buildings: int):
    city = grid_city(buildings)
    renderer.set_city(city)
    x0, _, x1, _ = city.bounds
    orbit = Camera((x1 + 20.0, 25.0, x1 + 20.0), (0.0, 30.0, 0.0), fov_y=60.0)
    on, off = SETTINGS, SETTINGS.with_(depth_prepass=False)
    rows, sums = [], {"on": 0.0, "off": 0.0}
    for angle in angles:
        timing = timed(renderer, orbit.orbit(angle), {"off": off, "on": on}, rounds)
        t = {k: v.median for k, v in timing.items()}
        sums["on"] += t["on"]
        sums["off"] += t["off"]
        rows.append([angle, *timing["off"].ms(), *timing["on"].ms(), round(t["off"] / t["on"], 2)])
    speedup = sums["off"] / sums["on"]
    rows.append(["sum", round(sums["off"] * 1e3, 2), "", round(sums["on"] * 1e3, 2), "", round(speedup, 2)])
    rows.append(
        [
            "paper (frames/5 s)",
            PAPER["zcull_off"],
            "",
            PAPER["zcull_on"],
            "",
            round(PAPER["zcull_on"] / PAPER["zcull_off"], 2),
        ]
    )
    result.add_table(
        f"(b) z-cull: depth prepass off vs on, camera orbiting a grid of {buildings} buildings",
        ["orbit angle", "off ms", "off IQR ms", "on ms", "on IQR ms", "speed-up"],
        rows,
    )
    result.ratios["prepass_speedup"] = speedup


def _textures(result: BenchResult, base: Renderer, city: City, camera: Camera, rounds: int):
    renderers = {size: _renderer_for(base, SETTINGS.with_(room_texture_size=size), city) for size in TEXTURE_SIZES}
    timing = time_interleaved(
        base.ctx, {size: (lambda i, r=r: r.draw(camera)) for size, r in renderers.items()}, rounds
    )
    t = {k: v.median for k, v in timing.items()}
    rows = [
        [
            size,
            *timing[size].ms(),
            round(frames_in(t[size])),
            round(t[256] / t[size], 3),
            PAPER["textures"][size],
            round(PAPER["textures"][size] / PAPER["textures"][256], 3),
        ]
        for size in TEXTURE_SIZES
    ]
    result.add_table(
        "(c) room texture resolution (four textures)",
        ["texels", "ms", "IQR ms", "frames/5 s", "speed vs 256", "paper frames/5 s", "paper speed vs 256"],
        rows,
    )
    result.ratios["texture16_speedup"] = t[256] / t[16]
    for r in renderers.values():
        r.release()


def _rooms_table(result: BenchResult, base: Renderer, city: City, camera: Camera, rounds: int, counts):
    renderers = {}
    for rooms in counts:
        scaled = scaled_rooms(city, rooms)
        renderers[_rooms(scaled)] = _renderer_for(base, SETTINGS, scaled)
    timing = time_interleaved(base.ctx, {k: (lambda i, r=r: r.draw(camera)) for k, r in renderers.items()}, rounds)
    t = {k: v.median for k, v in timing.items()}
    first, last = min(t), max(t)
    rows = [[rooms, *timing[rooms].ms(), round(frames_in(t[rooms])), round(t[rooms] / t[first], 3)] for rooms in t]
    result.add_table(
        "(d) rooms per building (paper: no change from 1,000 to 4,000,000)",
        ["rooms per building", "ms", "IQR ms", "frames/5 s", f"time / {first} rooms"],
        rows,
    )
    result.ratios["rooms_4m_over_1k"] = t[last] / t[first]
    for r in renderers.values():
        r.release()


def _reflective(result: BenchResult, renderer: Renderer, city: City, camera: Camera, rounds: int):
    renderer.set_city(city)
    timing = timed(renderer, camera, VARIANTS, rounds)
    t = {k: v.median for k, v in timing.items()}
    base = t["reflective-only windows"]
    paper = {
        "reflective-only windows": PAPER["reflective"],
        "interior mapping (paper's version)": PAPER["interior_mapping"],
    }
    rows = [
        [
            k,
            *timing[k].ms(),
            round(frames_in(v)),
            round(v / base, 2),
            paper.get(k, ""),
            round(PAPER["reflective"] / paper[k], 2) if k in paper else "",
        ]
        for k, v in t.items()
    ]
    result.add_table(
        "(e) cost of interior mapping against reflective-only windows (street view)",
        ["windows", "ms", "IQR ms", "frames/5 s", "time / reflective", "paper frames/5 s", "paper time / reflective"],
        rows,
    )
    result.ratios["im_over_reflective"] = t["interior mapping (paper's version)"] / base
    renderer.set_settings(SETTINGS)


VARIANTS = {
    "reflective-only windows": SETTINGS.with_(interior_mapping=False),
    "interior mapping (paper's version)": SETTINGS,
    "interior mapping, furniture + curtains": SETTINGS.with_(furniture=True, curtains=True),
    "polygonised interiors": SETTINGS.with_(polygonised_interiors=True),
}


def comparison_picture(renderer: Renderer, city: City, camera: Camera) -> np.ndarray:
    """Interior mapping (left) and polygonised interiors (right) of the same buildings."""
    renderer.set_city(city)
    renderer.set_settings(SETTINGS)
    left = renderer.render(camera)
    renderer.set_settings(SETTINGS.with_(polygonised_interiors=True))
    right = renderer.render(camera)
    renderer.set_settings(SETTINGS)
    gap = np.full((left.shape[0], 4, 3), 255, np.uint8)
    return np.concatenate([left, gap, right], axis=1)


def comparison_camera() -> Camera:
    """A few blocks of grid_city(4) from across the street, windows large enough to see into."""
    return Camera((-70.0, 22.0, -80.0), (-10.0, 34.0, -8.0), fov_y=50.0)


@dataclass(frozen=True)
class Plan:
    """How big each experiment is."""

    size: tuple[int, int]
    rounds: int
    building_counts: tuple[int, ...]
    orbit_angles: tuple[float, ...]
    orbit_buildings: int
    street_buildings: int
    room_counts: tuple[int, ...]


FULL = Plan((1024, 768), 11, BUILDING_COUNTS, tuple(range(0, 360, 45)), 100, 36, ROOM_COUNTS)
QUICK = Plan(
    (320, 240), MIN_TIMED_FRAMES, BUILDING_COUNTS, (0, 90, 180, 270), 64, 16, (ROOM_COUNTS[0], ROOM_COUNTS[-1])
)


def run(quick: bool, out_dir: Path) -> BenchResult:
    return run_plan(QUICK if quick else FULL, out_dir)


def run_plan(plan: Plan, out_dir: Path) -> BenchResult:
    renderer = Renderer(plan.size, SETTINGS)
    result = BenchResult("interior", renderer.device, targets=dict(TARGETS), timing=timing_record(plan.rounds))
    result.methods = {
        name: method(settings, plan.size)
        for name, settings in {
            **VARIANTS,
            "interior mapping without prepass": SETTINGS.with_(depth_prepass=False),
        }.items()
    }
    out_dir.mkdir(parents=True, exist_ok=True)
    picture = comparison_picture(renderer, grid_city(4), comparison_camera())
    path = out_dir / "interior_vs_polygonised.png"
    write_png(picture, path)
    result.plots.append(str(path))

    times = _fig9(result, renderer, plan.rounds, plan.building_counts)
    _plot_fig9(result, times, out_dir)
    _prepass(result, renderer, plan.rounds, plan.orbit_angles, plan.orbit_buildings)
    street = grid_city(plan.street_buildings)
    camera = street_camera(street)
    _textures(result, renderer, street, camera, plan.rounds)
    _rooms_table(result, renderer, street, camera, plan.rounds, plan.room_counts)
    _reflective(result, renderer, street, camera, plan.rounds)
    result.notes += [
        f"{plan.size[0]}x{plan.size[1]}, no MSAA, median (and interquartile range) of {plan.rounds} frames per "
        "variant after one warm-up frame, variants alternating frame by frame.",
        "Paper: frames rendered in 5 s at 1024x768 on a GeForce 6600GT; ours: 5 s / median frame time.",
        "Polygonised interiors: per building one floor and one ceiling quad per storey and a full-height quad on "
        "each side of every room wall line; exteriors drawn first with the glass cut out, then floors, ceilings, "
        "walls (after a depth-only pass of the same three layers), then the glass's reflection blended; back "
        "faces culled throughout, frustum-culled in the same chunks as interior mapping; its fragments find their "
        "room as the cell of the regular room grid (no wall search).",
        "Interior mapping as in the paper's tests: four textures, no furniture or curtains, no distance LOD.",
    ]
    renderer.release()
    return result
