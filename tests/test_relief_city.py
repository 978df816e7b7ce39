"""Relief in the city: the repeating window bay traced on the GPU matches the reference on the
repeated maps, a share of the default city's buildings gets relief facades, and the fly-over's
chunk culling keeps its picture."""

import numpy as np

from cityshade.bench.relief import CityChunks, city_frames, flyover_camera
from cityshade.gl import ProgramCache, create_context
from cityshade.relief import (DetailMaps, FacadeView, GpuFacade, compress, draw_facades, facade_camera, generate_bay,
                              paper_facade, slab_faces, trace_view)
from cityshade.relief._city import FACADE_RELIEF, RELIEF_SHAPES, RELIEF_STYLES, assign_relief
from cityshade.relief._reference import MISS
from cityshade.relief._view import SINGLE_FACADE
from cityshade.scene import batch, default_city

SIZE = (96, 96)


def test_repeated_bay_matches_reference():
    ctx = create_context()
    programs = ProgramCache(ctx)
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


def test_a_share_of_the_city_gets_relief():
    city = default_city()
    _, records = batch(city.masses)
    count = assign_relief(records, city.masses)
    marked = np.flatnonzero(records["facade"][:, 0] == FACADE_RELIEF)
    assert count == len(marked) and 0.1 < count / len(city.masses) < 0.4
    assert all(city.masses[i].style in RELIEF_STYLES and city.masses[i].shape in RELIEF_SHAPES for i in marked)


def test_flyover_chunk_culling_keeps_the_picture():
    """`bench relief` Table 3 draws only the chunks inside the frustum: the same picture, fewer facades."""
    ctx = create_context()
    programs = ProgramCache(ctx)
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
