"""`cityshade bench relief`: the paper's Tables 1-3 for compressed facade displacement maps.

Table 1: KB per map (D, M, A) of the four test facades, uncompressed, zlib and lzma (standing in
for WinRAR), SVD and BMF. Table 2: frame time of the six renderers per facade. Table 3: a
fly-over of a city of boxes with BCFDM facades against the same relief as instanced triangles
(wound consistently and drawn with back faces culled); both draw only the buildings of the
chunks inside the view frustum. Renderers compared with each other are timed frame by frame in
turn (the harness's time_interleaved); the result's `methods` records what each ran with.
"""

from __future__ import annotations

import lzma
import math
import time
import zlib
from collections.abc import Callable
from pathlib import Path

import numpy as np
from matplotlib.figure import Figure

from .._files import write_figure
from ..frame import boxes_visible, frustum_planes
from ..gl import ProgramCache, RenderTarget, create_context, describe_context
from ..relief import (
    FRAME_DTYPE,
    MAP_NAMES,
    PAPER_FACADES,
    PROFILE,
    RENDERERS,
    DetailMaps,
    FacadeView,
    GpuFacade,
    MeshFacade,
    compress,
    detail_matrices,
    draw_facades,
    facade_camera,
    paper_facade,
    relief_atlas,
    slab_faces,
    switch_distance,
    trace_view,
)
from ..render import Renderer, RenderSettings
from ..scene import Camera, make_city
from ._harness import BenchResult, method_record, time_interleaved, timing_record

# Paper Table 1 (KB): NOCOMP, WINRAR, SVD, BIN for heightfield, material, acceleration, total.
PAPER_TABLE1 = {
    "F1": {"nocomp": (586, 586, 2344, 3516), "rar": (4, 4, 7, 15), "svd": (63, 63, 150, 276), "bmf": (8, 5, 96, 109)},
    "F2": {
        "nocomp": (3072, 3072, 12378, 18522),
        "rar": (7, 7, 33, 47),
        "svd": (195, 195, 616, 1006),
        "bmf": (30, 30, 141, 201),
    },
    "F3": {"nocomp": (768, 768, 3072, 4608), "rar": (3, 3, 7, 13), "svd": (72, 72, 252, 1208), "bmf": (9, 9, 36, 140)},
    "F4": {"nocomp": (1059, 1059, 4236, 6354), "rar": (4, 4, 9, 17), "svd": (73, 73, 90, 236), "bmf": (4, 4, 78, 86)},
}
# Paper Table 2: frames per second at 1600x1200 on a GeForce 8800 GTX, F1..F4.
PAPER_TABLE2 = {
    "rm": (443, 94, 360, 209),
    "fdm": (730, 387, 712, 369),
    "crm": (30, 28, 34, 35),
    "bcrm": (110, 67, 111, 43),
    "cfdm": (219, 82, 137, 116),
    "bcfdm": (213, 124, 230, 104),
}
# Paper Table 3: fps ours / geometry per screen size, and sizes in GB.
PAPER_TABLE3 = {"1600x1200": (21.5, 0.5), "1200x900": (30.2, 0.6), "800x600": (46, 0.6)}
PAPER_MEMORY_GB = {"uncompressed": (138, 23.93), "compressed": (1.62, None)}

FRAMES = {True: 9, False: 11}  # timed frames per point, --quick or not
TARGETS = {
    "bmf_over_svd_size": "<= 0.35",
    "fdm_speed_over_rm": ">= 2",
    "bcfdm_speed_over_crm": ">= 4",
    "geometry_over_bcfdm_time": ">= 40",
    "fdm_mismatch_fraction": "== 0 (edges only)",
    "f2_bmf_factorisation_s": "< 10",
    "city_switch_over_exact_everywhere": "report (< 1: the switch saves time)",
}


def _raw_bytes(matrix: np.ndarray) -> bytes:
    """The paper's uncompressed storage: the narrowest integer width that holds the map."""
    dtype = np.uint8 if matrix.max() < 256 else np.uint16 if matrix.max() < 65536 else np.uint32
    return np.ascontiguousarray(matrix, dtype).tobytes()


def _table1(result: BenchResult, facades: dict) -> dict:
    rows, totals, timings = [], {}, {}
    for name, maps in facades.items():
        matrices, boxes = detail_matrices(maps)
        raw = {
            "depth": _raw_bytes(matrices["depth"]),
            "material": _raw_bytes(matrices["material"]),
            "boxes": np.ascontiguousarray(matrices["boxes"], np.uint32).tobytes() + boxes.astype("<u2").tobytes(),
        }
        compressed = {}
        for method in ("svd", "bmf"):
            start = time.perf_counter()
            compressed[method] = compress(maps, method, source=name)
            timings[(name, method)] = time.perf_counter() - start
        facades[name] = (maps, compressed)
        sizes = {
            "nocomp": {n: len(raw[n]) for n in MAP_NAMES},
            "zlib": {n: len(zlib.compress(raw[n], 9)) for n in MAP_NAMES},
            "lzma": {n: len(lzma.compress(raw[n], preset=9)) for n in MAP_NAMES},
            "svd": compressed["svd"].nbytes(),
            "bmf": compressed["bmf"].nbytes(),
        }
        paper = PAPER_TABLE1[name]
        for k, label in enumerate(("D", "M", "A")):
            m = MAP_NAMES[k]
            rows.append(
                [name, label]
                + [round(sizes[c][m] / 1024, 1) for c in sizes]
                + [compressed["svd"].factors[m].terms, compressed["bmf"].factors[m].terms]
                + [paper[c][k] for c in ("nocomp", "rar", "svd", "bmf")]
            )
        total = {c: sum(sizes[c].values()) / 1024 for c in sizes}
        totals[name] = total
        rows.append(
            [name, "total"]
            + [round(total[c], 1) for c in sizes]
            + ["", ""]
            + [paper[c][3] for c in ("nocomp", "rar", "svd", "bmf")]
        )
    result.add_table(
        "Table 1: KB per map (ours: NOCOMP, zlib, lzma, SVD, BMF; terms; paper: NOCOMP, WinRAR, SVD, BIN)",
        [
            "facade",
            "map",
            "nocomp",
            "zlib",
            "lzma",
            "svd",
            "bmf",
            "svd terms",
            "bmf terms",
            "paper nocomp",
            "paper rar",
            "paper svd",
            "paper bin",
        ],
        rows,
    )
    result.ratios["bmf_over_svd_size"] = max(t["bmf"] / t["svd"] for t in totals.values())
    result.ratios["f2_bmf_factorisation_s"] = timings[("F2", "bmf")] if ("F2", "bmf") in timings else float("nan")
    result.notes.append(
        "Table 1 sizes: NOCOMP stores D and M in the narrowest integer width (1 byte here) and A in "
        "4 bytes per texel plus the box list (8 bytes per box), which SVD and BMF sizes include too; "
        "SVD stores float32 X, S, Y; BMF stores X and Y as 32 bits per R32UI texel and S as float32."
    )
    result.notes.append(
        "Factorisation time (A built, then D, M, A factorised), seconds: "
        + ", ".join(f"{n} {m} {t:.2f}" for (n, m), t in timings.items())
    )
    return totals


def _orbit_camera(maps, frame: int, frames: int) -> Camera:
    width, height = maps.size_m
    distance = 0.6 * max(width, height) / math.tan(math.radians(20))
    azimuth = -35 + 70 * (frame % frames) / max(frames - 1, 1)
    return facade_camera(maps, azimuth, 8, distance)


def _table2(result: BenchResult, ctx, programs, facades: dict, quick: bool) -> dict:
    size = (320, 240) if quick else (1600, 1200)
    frames = FRAMES[quick]
    view = FacadeView(ctx, size, programs)
    times: dict[str, dict[str, float]] = {r: {} for r in [*RENDERERS, "bcfdm (mod 37)"]}
    spreads: dict[str, dict[str, float]] = {r: {} for r in times}
    for name, (maps, compressed) in facades.items():
        gpu = GpuFacade(ctx, maps, compressed)

        def draw(renderer: str, gpu=gpu, maps=maps) -> Callable[[int], None]:
            base, mod37 = renderer.split(" ")[0], renderer.endswith("(mod 37)")
            return lambda i: view.draw(gpu, _orbit_camera(maps, i, frames), base, lsb_mod37=mod37)

        timing = time_interleaved(ctx, {renderer: draw(renderer) for renderer in times}, frames)
        for renderer, t in timing.items():
            times[renderer][name], spreads[renderer][name] = t.median, t.iqr
        gpu.release()
    view.release()
    for renderer in times:
        result.methods[f"table 2 {renderer}"] = method_record(
            cull_back_faces=True,
            depth_prepass=False,
            frustum_culling=False,
            msaa=0,
            size=size,
            note="one facade in view; the traced volume's faces facing away from the eye are dropped",
        )
    names = list(facades)
    rows = []
    for renderer, per in times.items():
        paper = PAPER_TABLE2.get(renderer.split(" ")[0]) if " " not in renderer else None
        rows.append(
            [renderer.upper()]
            + [round(per[n] * 1000, 2) for n in names]
            + [round(spreads[renderer][n] * 1000, 2) for n in names]
            + [round(1 / per[n], 1) for n in names]
            + (list(paper) if paper else ["", "", "", ""])
        )
    result.add_table(
        f"Table 2: ms per frame at {size[0]}x{size[1]} (ours), fps (ours; paper F1-F4 fps at 1600x1200)",
        ["renderer"]
        + [f"{n} ms" for n in names]
        + [f"{n} IQR ms" for n in names]
        + [f"{n} fps" for n in names]
        + [f"paper {n} fps" for n in ("F1", "F2", "F3", "F4")],
        rows,
    )

    def gmean(a, b):
        return float(np.exp(np.mean([np.log(times[a][n] / times[b][n]) for n in names])))

    result.ratios["fdm_speed_over_rm"] = gmean("rm", "fdm")
    result.ratios["bcfdm_speed_over_crm"] = gmean("crm", "bcfdm")
    result.ratios["bcfdm_findlsb_speed_over_mod37"] = gmean("bcfdm (mod 37)", "bcfdm")
    result.notes.append(
        "Table 2 ratios are geometric means over the four facades of per-facade time ratios; the camera "
        f"orbits the facade (azimuth -35..35 degrees) over {frames} frames, the seven renderers taking "
        "turns frame by frame; median frame time and interquartile range."
    )
    return times


def _mismatch(result: BenchResult, ctx, programs, facades: dict, quick: bool):
    """FDM against the reference tracer on each facade, oblique and grazing, every pixel counted."""
    size, differing, total, rows = (64, 48) if quick else (128, 96), 0, 0, []
    view = FacadeView(ctx, size, programs)
    for name, (maps, compressed) in facades.items():
        gpu = GpuFacade(ctx, maps, compressed)
        for label, (az, el, dist) in {"oblique": (30, 15, 1.0), "grazing": (75, 5, 0.6)}.items():
            camera = facade_camera(maps, az, el, dist * max(maps.size_m), target=(0.5, 0.35))
            ref = trace_view(maps, camera, size)
            counts = []
            for renderer in ("fdm", "bcfdm", "rm"):
                view.draw(gpu, camera, renderer)
                out = view.read()
                counts.append(int(((out.material != ref.material) | (out.face != ref.face)).sum()))
            differing += counts[0] + counts[1]
            total += 2 * ref.material.size
            rows.append([name, label, *counts, ref.material.size])
        gpu.release()
    view.release()
    result.add_table(
        f"Pixels whose hit material or face differs from the reference tracer ({size[0]}x{size[1]})",
        ["facade", "view", "FDM", "BCFDM", "RM", "pixels"],
        rows,
    )
    result.ratios["fdm_mismatch_fraction"] = differing / total
    result.notes.append(
        "RM counts include its face: RM has no side normals, so every side-wall pixel counts; the "
        "FDM/BCFDM counts are rays grazing an edge where two surfaces meet within 0.05 texel."
    )


def city_frames(count: int, width: float, spacing: float) -> np.ndarray:
    """Four facade frames per building on a square grid of box buildings `width` wide."""
    side = math.ceil(math.sqrt(count))
    gx, gz = np.divmod(np.arange(count), side)
    x, z = gx * spacing, gz * spacing
    frames = np.zeros((count, 4), FRAME_DTYPE)
    one, zero = np.ones(count), np.zeros(count)
    sides = (
        ((x, z + width), (one, zero, zero), (zero, zero, one)),  # facing +z
        ((x + width, z + width), (zero, zero, -one), (one, zero, zero)),  # facing +x
        ((x + width, z), (-one, zero, zero), (zero, zero, -one)),  # facing -z
        ((x, z), (zero, zero, one), (-one, zero, zero)),
    )  # facing -x
    for k, ((ox, oz), along, out) in enumerate(sides):
        frames["origin"][:, k] = np.column_stack([ox, zero, oz])
        frames["along"][:, k] = np.column_stack(along)
        frames["out"][:, k] = np.column_stack(out)
    return frames.reshape(-1)


class CityChunks:
    """The fly-over city's buildings grouped into square chunks of `side` x `side` buildings, each
    with its bounding box, so a frame draws only the facades of the chunks inside the frustum."""

    def __init__(self, count: int, width: float, spacing: float, height: float, side: int = 8):
        grid = math.ceil(math.sqrt(count))
        gx, gz = np.divmod(np.arange(count), grid)
        key = (gx // side) * grid + gz // side
        self.facades = [np.flatnonzero(np.repeat(key == k, 4)) for k in np.unique(key)]
        members = [np.flatnonzero(key == k) for k in np.unique(key)]
        margin = 2.0  # metres: relief and rounding stay inside the box
        self.lo = np.array([[gx[m].min() * spacing - margin, 0.0, gz[m].min() * spacing - margin] for m in members])
        self.hi = np.array(
            [
                [gx[m].max() * spacing + width + margin, height + margin, gz[m].max() * spacing + width + margin]
                for m in members
            ]
        )

    def visible(self, frames: np.ndarray, view_projection: np.ndarray) -> np.ndarray:
        keep = boxes_visible(frustum_planes(view_projection), self.lo, self.hi)
        chosen = [f for f, k in zip(self.facades, keep) if k]
        return frames[np.concatenate(chosen)] if chosen else frames[:0]


def flyover_camera(extent: float, frame: int) -> Camera:
    t = 0.15 + 0.05 * frame
    eye = np.array([t * extent, 70.0, t * extent])
    return Camera(tuple(eye), tuple(eye + np.array([60.0, -40.0, 60.0])), fov_y=60.0, near=1.0, far=4000.0)


def _table3(result: BenchResult, ctx, programs, facades: dict, quick: bool):
    maps, compressed = facades["F1"]
    buildings = 500 if quick else 30000
    size = (320, 240) if quick else (800, 600)
    width, height = maps.size_m
    frames = city_frames(buildings, width, width + 8.0)
    extent = math.ceil(math.sqrt(buildings)) * (width + 8.0)
    target = RenderTarget(ctx, size, colors=(("f2", 4), ("u4", 4), ("f4", 4)))
    gpu = GpuFacade(ctx, maps, compressed)
    mesh = MeshFacade(ctx, maps)
    quad = slab_faces(maps.shape[1], maps.shape[0], gpu.slab_depth, sides=False)
    aspect = size[0] / size[1]

    chunks = CityChunks(buildings, width, width + 8.0, height)
    drawn = []

    def visible(camera: Camera) -> np.ndarray:
        shown = chunks.visible(frames, camera.view_projection(aspect))
        drawn.append(len(shown))
        return shown

    def draw_relief(i):
        target.use()
        ctx.clear(0.5, 0.6, 0.7, 1.0, depth=1.0)
        camera = flyover_camera(extent, i)
        shown = visible(camera)
        ctx.depth_func = "<"
        draw_facades(ctx, programs, gpu, camera, "bcfdm", quad, shown, aspect, depth_only=True)
        ctx.depth_func = "<="  # the prepass leaves only the visible facade's fragments to trace
        target.fbo.depth_mask = False
        draw_facades(ctx, programs, gpu, camera, "bcfdm", quad, shown, aspect, after_prepass=True)
        target.fbo.depth_mask = True
        ctx.depth_func = "<"

    def draw_mesh(i):
        target.use()
        ctx.clear(0.5, 0.6, 0.7, 1.0, depth=1.0)
        camera = flyover_camera(extent, i)
        mesh.draw(ctx, programs, camera, visible(camera), aspect)

    n = FRAMES[quick]
    timing = time_interleaved(ctx, {"bcfdm": draw_relief, "geometry": draw_mesh}, n)
    t_relief, t_mesh = timing["bcfdm"].median, timing["geometry"].median
    result.methods["table 3 bcfdm"] = method_record(
        cull_back_faces=True,
        depth_prepass=True,
        frustum_culling=True,
        msaa=0,
        size=size,
        note="facade quads; the traced volume's faces facing away from the eye are dropped",
    )
    result.methods["table 3 geometry"] = method_record(
        cull_back_faces=True,
        depth_prepass=False,
        frustum_culling=True,
        msaa=0,
        size=size,
        note="instanced triangles, wound counter-clockwise seen from outside; drawn once with the depth test",
    )
    facades_n = len(frames)
    bcfdm_bytes = sum(compressed["bmf"].nbytes().values()) + frames.nbytes + quad.nbytes
    mesh_bytes = mesh.nbytes + frames.nbytes
    raw_per_facade = sum(compressed["bmf"].raw_nbytes().values())
    gb = 1024**3
    result.add_table(
        f"Table 3: fly-over of {buildings} buildings ({facades_n} facades) at {size[0]}x{size[1]}",
        ["", "BCFDM", "geometry (instanced)", "paper ours", "paper geometry"],
        [
            ["ms per frame", round(t_relief * 1000, 1), round(t_mesh * 1000, 1), "", ""],
            ["IQR ms", round(timing["bcfdm"].iqr * 1000, 1), round(timing["geometry"].iqr * 1000, 1), "", ""],
            ["facades drawn per frame (mean; chunks in the frustum)", *[round(float(np.mean(drawn)))] * 2, "", ""],
            ["fps", round(1 / t_relief, 2), round(1 / t_mesh, 2), *PAPER_TABLE3["800x600"]],
            ["triangles in the city", 2 * facades_n, mesh.triangles * facades_n, "", "180 million"],
            ["GPU memory, shared facade (MB)", round(bcfdm_bytes / 2**20, 2), round(mesh_bytes / 2**20, 2), "", ""],
            [
                "every facade its own maps/mesh (GB)",
                round(sum(compressed["bmf"].nbytes().values()) * facades_n / gb, 2),
                round(mesh.nbytes * facades_n / gb, 2),
                PAPER_MEMORY_GB["compressed"][0],
                PAPER_MEMORY_GB["uncompressed"][1],
            ],
            [
                "uncompressed maps, every facade (GB)",
                round(raw_per_facade * facades_n / gb, 2),
                "",
                PAPER_MEMORY_GB["uncompressed"][0],
                "",
            ],
        ],
    )
    result.ratios["geometry_over_bcfdm_time"] = t_mesh / t_relief
    result.notes.append(
        f"Table 3 uses facade F1 ({mesh.triangles} triangles as geometry) on every wall; both draw one "
        "instanced call of the facades of the chunks (8 x 8 buildings) inside the view frustum, with "
        "the same procedural materials and lighting; roofs and ground are not drawn. BCFDM first "
        "draws the facade quads' depth (the paper's z-buffer initialisation), so only visible pixels "
        "are traced; the geometry, wound consistently, is drawn once with back faces culled and the "
        f"depth test. The two take turns frame by frame over {n} frames."
    )
    gpu.release()
    mesh.release()
    target.release()


def run(quick: bool, out_dir: Path) -> BenchResult:
    ctx = create_context()
    programs = ProgramCache(ctx)
    result = BenchResult("relief", describe_context(ctx), targets=dict(TARGETS))
    facades = {name: paper_facade(name) for name in PAPER_FACADES}
    result.timing = timing_record(FRAMES[quick])
    _table1(result, facades)
    _table2(result, ctx, programs, facades, quick)
    _mismatch(result, ctx, programs, facades, quick)
    _table3(result, ctx, programs, facades, quick)
    _opening_renderers(result, ctx, programs, quick)
    _city_switch(result, ctx, quick)
    _plot(result, out_dir)
    return result


OPENING_DISTANCES = (4.0, 8.0, 16.0, 32.0, 64.0)  # metres from the facade


def opening_wall(windows: tuple[int, int] = (4, 2)) -> DetailMaps:
    """A wall of one grammar window opening (the first of the city's atlas, `relief_atlas`),
    repeated with wall between, at the texel a 1.3 m window gives the profile."""
    atlas = relief_atlas()
    row = min(atlas.terminals.values())
    rows, cols = PROFILE[1] + 2, PROFILE[0] + 2
    pad = ((24, 30), (22, 22))  # wall below, above, left and right of the opening, in texels
    depth = np.tile(np.pad(atlas.maps.depth[row : row + rows, :cols], pad), windows[::-1])
    material = np.tile(np.pad(atlas.maps.material[row : row + rows, :cols], pad), windows[::-1])
    return DetailMaps(depth, material, 1.3 / PROFILE[0], atlas.maps.depth_unit)


def _opening_renderers(result: BenchResult, ctx, programs, quick: bool):
    """The six renderers on a wall of grammar window openings by distance: ms per frame, and the
    pixels whose material differs from the reference tracer's; 'flat' is the material where the ray
    meets the wall plane (no relief), what the city draws beyond the switch."""
    maps = opening_wall()
    size = (160, 120) if quick else (640, 480)
    frames = FRAMES[quick]
    gpu = GpuFacade(ctx, maps)
    view = FacadeView(ctx, size, programs)
    flat_maps = DetailMaps(np.zeros_like(maps.depth), maps.material, maps.texel, maps.depth_unit)
    rows = []
    for distance in OPENING_DISTANCES:
        camera = facade_camera(maps, 35, 10, distance, target=(0.3, 0.4), fov_y=50.0)
        timed = time_interleaved(
            ctx, {r: (lambda i, r=r, camera=camera: view.draw(gpu, camera, r)) for r in RENDERERS}, frames
        )
        ref = trace_view(maps, camera, size)
        on = ref.material != -1
        errors = {}
        for renderer in RENDERERS:
            view.draw(gpu, camera, renderer)
            errors[renderer] = int(((view.read().material != ref.material) & on).sum())
        flat = int(((trace_view(flat_maps, camera, size).material != ref.material) & on).sum())
        rows.append(
            [distance, int(on.sum()), *(round(timed[r].median * 1000, 2) for r in RENDERERS), *errors.values(), flat]
        )
    view.release()
    gpu.release()
    names = [r.upper() for r in RENDERERS]
    result.add_table(
        f"Grammar window openings ({maps.shape[1]}x{maps.shape[0]} texels, {maps.size_m[0]:.1f} x "
        f"{maps.size_m[1]:.1f} m) by distance at {size[0]}x{size[1]}, 35 degrees off the normal: ms per frame, "
        "and pixels whose material differs from the reference tracer",
        ["distance m", "facade pixels", *(f"{n} ms" for n in names), *(f"{n} wrong" for n in names), "flat wrong"],
        rows,
    )


SWITCH_SIZE = {True: (480, 270), False: (960, 540)}
EXACT_EVERYWHERE = 1e9  # metres: grammar windows traced at every distance
# switch distances measured (0: flat everywhere; None: the city's own, relief.switch_distance of the view)
SWITCH_SWEEP = (0.0, 15.0, 30.0, None, 60.0, 120.0, EXACT_EVERYWHERE)


def _city_switch(result: BenchResult, ctx, quick: bool):
    """Where the distance switch should sit: the default city's frame with grammar windows traced by
    BCFDM nearer than each switch distance and flat beyond, against the exact tracer at every
    distance; per distance the frame time (all taking turns frame by frame) and the pixels whose
    colour differs from the exact tracer's (the switch's error). The city's own distance
    (RenderSettings.relief_range None: switch_distance) gives the ratio."""
    city, size = make_city("default"), SWITCH_SIZE[quick]
    chosen = None
    renderers = {m: Renderer(size, RenderSettings(samples=0, relief_range=m), ctx=ctx) for m in SWITCH_SWEEP}
    rows, ratios = [], []
    try:
        for renderer in renderers.values():
            renderer.set_city(city)
        for name in ("street", "closeup"):
            camera = city.camera(name)
            timed = time_interleaved(
                ctx, {m: (lambda i, r=r, camera=camera: r.draw(camera)) for m, r in renderers.items()}, FRAMES[quick]
            )
            images = {m: r.targets["display"].read()[..., :3].astype(int) for m, r in renderers.items()}
            exact = images[EXACT_EVERYWHERE]
            for m in SWITCH_SWEEP:
                differ = np.abs(images[m] - exact).max(axis=-1) > 2
                label = (
                    "exact everywhere"
                    if m == EXACT_EVERYWHERE
                    else "flat everywhere"
                    if m == 0
                    else f"{switch_distance(size[1], camera.fov_y):.0f} m (the city's: a pixel spans the pane's depth)"
                    if m is None
                    else f"{m:g} m"
                )
                rows.append(
                    [name, label, round(timed[m].median * 1000, 1), int(differ.sum()), round(float(differ.mean()), 4)]
                )
            ratios.append(timed[chosen].median / timed[EXACT_EVERYWHERE].median)
    finally:
        for renderer in renderers.values():
            renderer.release()
    result.add_table(
        f"City: grammar windows traced (BCFDM) nearer than the switch distance, flat beyond, default city at "
        f"{size[0]}x{size[1]}: ms per frame and pixels whose colour differs from the exact tracer everywhere",
        ["camera", "switch at", "ms per frame", "pixels that differ", "share"],
        rows,
    )
    result.ratios["city_switch_over_exact_everywhere"] = round(math.prod(ratios) ** (1 / len(ratios)), 3)


def _plot(result: BenchResult, out_dir: Path):
    table = result.tables[1]
    renderers = [row[0] for row in table["rows"]]
    fig = Figure(figsize=(8, 4))
    ax = fig.add_subplot()
    for k in range(4):
        ax.bar(
            np.arange(len(renderers)) + k * 0.2,
            [row[1 + k] for row in table["rows"]],
            0.2,
            label=table["columns"][1 + k],
        )
    ax.set_xticks(np.arange(len(renderers)) + 0.3, renderers)
    ax.set_ylabel("ms per frame")
    ax.set_title(f"relief renderers ({result.device})", fontsize=8)
    ax.legend()
    out_dir.mkdir(parents=True, exist_ok=True)
    path = out_dir / "relief.png"
    write_figure(fig, path, dpi=100, bbox_inches="tight")
    result.plots.append(str(path))
