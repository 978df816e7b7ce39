"""Relief in the city: the repeating window bay traced on the GPU matches the reference on the
repeated maps, a share of the default city's buildings gets relief facades, and the fly-over's
chunk culling keeps its picture."""

import numpy as np

from cityshade.bench.relief import CityChunks, city_frames, flyover_camera
from cityshade.gl import programs as gl_programs
from cityshade.relief import (DetailMaps, FacadeView, GpuFacade, compress, draw_facades, facade_camera, generate_bay,
                              paper_facade, slab_faces, trace_view)
from cityshade.relief import FACADE_RELIEF, RELIEF_SHAPES, RELIEF_STYLES
from cityshade.render import assign_facades
from cityshade.relief._reference import MISS
from cityshade.relief._view import SINGLE_FACADE
from cityshade.scene import batch, default_city

SIZE = (96, 96)


def test_repeated_bay_matches_reference(gl_context):
    ctx = gl_context
    programs = gl_programs(ctx)
    bay = generate_bay(texel=0.1)
    wall = DetailMaps(np.tile(bay.depth, (2, 3)), np.tile(bay.material, (2, 3)), bay.texel, bay.depth_unit)
    gpu = GpuFacade(ctx, bay, {"bmf": compress(bay, "bmf")})
    camera = facade_camera(wall, 35, 15, 6.0)
    view = FacadeView(ctx, SIZE, programs)
    view.target.use()
    ctx.clear(0.0, 0.0, 0.0, 0.0, depth=1.0)
    rows, cols = wall.shape
    draw_facades(ctx, programs, gpu, camera, "bcfdm", slab_faces(cols, rows, gpu.slab_depth, sides=False),
                 SINGLE_FACADE, 1.0, tiled=True)
    out, ref = view.read(), trace_view(wall, camera, SIZE)
    # Away from the wall's border (where the repeat goes on but the reference's maps end)...
    x, y = ref.point[..., 0], ref.point[..., 1]
    inner = (ref.material != MISS) & (x > 2) & (x < cols - 2) & (y > 2) & (y < rows - 2)
    assert inner.mean() > 0.5
    differ = inner & ((out.material != ref.material) | (out.face != ref.face))
    on_edge = np.linalg.norm(np.nan_to_num(out.point - ref.point, nan=1e9), axis=-1) < 0.05
    print(f"repeated bay: {differ.sum()} of {inner.sum()} inner pixels differ")
    assert not (differ & ~on_edge).any()
    view.release()
    gpu.release()


def test_a_quarter_of_the_box_buildings_gets_relief():
    city = default_city()
    _, records = batch(city.masses)
    count = assign_facades(records, city.masses)["relief bay"]
    marked = np.flatnonzero(records["facade"][:, 0] == FACADE_RELIEF)
    boxes = [i for i, m in enumerate(city.masses) if m.shape in RELIEF_SHAPES]
    due = [i for i in boxes if city.masses[i].style in RELIEF_STYLES]
    assert count == len(marked) and list(marked) == due  # every box building of a relief style, nothing else
    print(f"relief on {count} of {len(boxes)} box buildings ({count / len(boxes):.3f})")
    assert 0.2 < count / len(boxes) < 0.3  # styles are uniform over 0..7: two of eight


def test_flyover_chunk_culling_keeps_the_picture(gl_context):
    """`bench relief` Table 3 draws only the chunks inside the frustum: the same picture, fewer facades."""
    ctx = gl_context
    programs = gl_programs(ctx)
    maps = paper_facade("F1")
    gpu = GpuFacade(ctx, maps, {"bmf": compress(maps, "bmf")})
    width, height = maps.size_m
    buildings, size = 400, (128, 96)
    frames = city_frames(buildings, width, width + 8.0)
    chunks = CityChunks(buildings, width, width + 8.0, height, side=4)
    camera = flyover_camera(20 * (width + 8.0), 5)
    view = FacadeView(ctx, size, programs)
    quad = slab_faces(maps.shape[1], maps.shape[0], gpu.slab_depth, sides=False)
    pictures, drawn = [], []
    for shown in (frames, chunks.visible(frames, camera.view_projection(size[0] / size[1]))):
        view.target.use()
        ctx.clear(0.0, 0.0, 0.0, 0.0, depth=1.0)
        draw_facades(ctx, programs, gpu, camera, "bcfdm", quad, shown, size[0] / size[1])
        pictures.append(view.read())
        drawn.append(len(shown))
    print(f"chunk culling drew {drawn[1]} of {drawn[0]} facades")
    assert drawn[1] < 0.9 * drawn[0]
    assert (pictures[0].material != MISS).mean() > 0.2
    assert np.array_equal(pictures[0].material, pictures[1].material) and np.array_equal(pictures[0].face, pictures[1].face)
    view.release()
    gpu.release()
