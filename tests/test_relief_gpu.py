"""GPU relief against the numpy reference: exact decoding of every codec, FDM hits per pixel, RM errors counted."""

import numpy as np
import pytest
from PIL import Image

from cityshade.gl import programs
from cityshade.relief import detail_matrices, generate_facade, paper_facade
from cityshade.relief._gpu import RENDERERS, GpuFacade, decode_on_gpu
from cityshade.relief._reference import MISS
from cityshade.relief._view import SINGLE_FACADE, FacadeView, MeshFacade, facade_camera, trace_view

SIZE = (96, 96)
VIEWS = {  # azimuth, elevation, distance, target
    "oblique": (35, 20, 14, (0.5, 0.4)),
    "grazing": (78, 5, 9, (0.3, 0.3)),
    "corner": (-60, -25, 6, (0.0, 0.1)),  # sees the left and bottom side quads
}


@pytest.fixture(scope="module")
def gl(gl_context):
    return gl_context, programs(gl_context)


@pytest.fixture(scope="module")
def facade(gl):
    return GpuFacade(gl[0], generate_facade(120, 180, texel=0.1))


@pytest.mark.parametrize("codec,mod37", [("raw", False), ("svd", False), ("bmf", False), ("bmf", True)])
def test_gpu_decodes_every_texel_exactly(gl, codec, mod37):
    ctx, programs = gl
    maps = paper_facade("F1")
    gpu = GpuFacade(ctx, maps)
    decoded = decode_on_gpu(ctx, gpu, codec, programs, lsb_mod37=mod37)
    matrices, _ = detail_matrices(maps)
    for name, matrix in matrices.items():
        assert np.array_equal(decoded[name], matrix), f"{codec}: {name} differs at {np.argwhere(decoded[name] != matrix)[:3]}"
    gpu.release()


def edge_pixels(gpu, ref):
    """Pixels where two surfaces meet under the ray (both hit the same point, on an edge) or at the
    facade's outline (a miss next to the pixel): the only places a mismatch is allowed."""
    same_point = np.linalg.norm(np.nan_to_num(gpu.point - ref.point, nan=1e9), axis=-1) < 0.05
    miss = np.pad((ref.material == MISS) | (gpu.material == MISS), 1, mode="edge")
    near_miss = np.zeros_like(ref.material, bool)
    for dy in range(3):
        for dx in range(3):
            near_miss |= miss[dy:dy + SIZE[1], dx:dx + SIZE[0]]
    return same_point | near_miss


def save(name, image):
    Image.fromarray((np.clip(image.color, 0, 1) * 255).astype(np.uint8)).save(f"tests/output/relief_{name}.png")


@pytest.mark.parametrize("view", sorted(VIEWS))
def test_fdm_matches_reference(gl, facade, view):
    ctx, programs = gl
    camera = facade_camera(facade.maps, *VIEWS[view])
    ref = trace_view(facade.maps, camera, SIZE)
    assert (ref.material != MISS).mean() > 0.3, "the view must show the facade"
    renderer = FacadeView(ctx, SIZE, programs)
    for name in ("fdm", "cfdm", "bcfdm"):
        renderer.draw(facade, camera, name)
        gpu = renderer.read()
        save(f"{name}_{view}", gpu)
        differ = (gpu.material != ref.material) | (gpu.face != ref.face)
        edges = edge_pixels(gpu, ref)
        print(f"{name} {view}: {differ.sum()} of {differ.size} pixels differ, all on edges: {not (differ & ~edges).any()}")
        assert not (differ & ~edges).any(), f"{name}: off-edge mismatches at {np.argwhere(differ & ~edges)[:5]}"
        assert differ.mean() < 0.005
        both = (gpu.material != MISS) & ~differ
        assert np.abs(gpu.point[both] - ref.point[both]).max() < 0.02, "hit depth and position"
    renderer.release()


def test_rm_errors_are_counted(gl, facade):
    ctx, programs = gl
    camera = facade_camera(facade.maps, *VIEWS["grazing"])
    ref = trace_view(facade.maps, camera, SIZE)
    renderer = FacadeView(ctx, SIZE, programs)
    counts = {}
    for name in ("rm", "crm", "bcrm"):
        renderer.draw(facade, camera, name)
        gpu = renderer.read()
        save(f"{name}_grazing", gpu)
        counts[name] = int((gpu.material != ref.material).sum())
    print("relief mapping material mismatches (grazing view):", counts)
    assert counts["rm"] == counts["crm"] == counts["bcrm"], "compression must not change what RM hits"
    assert counts["rm"] > 0, "RM's fixed steps miss thin features at grazing angles (paper fig. 3)"
    renderer.release()


def test_all_six_renderers_draw(gl, facade):
    ctx, programs = gl
    renderer = FacadeView(ctx, (48, 48), programs)
    camera = facade_camera(facade.maps, *VIEWS["oblique"])
    for name in RENDERERS:
        renderer.draw(facade, camera, name)
        assert (renderer.read().material != MISS).mean() > 0.3, name
    renderer.release()


def test_triangulated_relief_matches_reference(gl, facade):
    ctx, programs = gl
    camera = facade_camera(facade.maps, *VIEWS["oblique"])
    ref = trace_view(facade.maps, camera, SIZE)
    view = FacadeView(ctx, SIZE, programs)
    mesh = MeshFacade(ctx, facade.maps)
    view.target.use()
    ctx.clear(0.0, 0.0, 0.0, 0.0, depth=1.0)
    mesh.draw(ctx, programs, camera, SINGLE_FACADE, 1.0)
    gpu = view.read()
    save("mesh_oblique", gpu)
    differ = (gpu.material != ref.material) | (gpu.face != ref.face)
    print(f"mesh: {differ.sum()} of {differ.size} pixels differ ({mesh.triangles} triangles)")
    assert differ.mean() < 0.01, "the geometry baseline shows the same relief"
    mesh.release()
    view.release()
