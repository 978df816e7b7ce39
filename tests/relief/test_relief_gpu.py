"""GPU relief against the numpy reference: exact decoding of every codec, FDM hits per pixel, RM errors counted."""

import numpy as np
import pytest
from PIL import Image

from cityshade.gl import programs
from cityshade.relief import (
    RENDERERS,
    FacadeView,
    GpuFacade,
    MeshFacade,
    decode_on_gpu,
    detail_matrices,
    facade_camera,
    generate_facade,
    paper_facade,
    trace_view,
)
from cityshade.relief.testing import MISS, SINGLE_FACADE
from render_checks import assert_finite, hit_edges

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
        assert np.array_equal(decoded[name], matrix), (
            f"{codec}: {name} differs at {np.argwhere(decoded[name] != matrix)[:3]}"
        )
    gpu.release()


def read(view, what):
    """The view's images, after checking that the colour is finite."""
    images = view.read()
    assert_finite(images.color, what)
    return images


def save(output_dir, name, image):
    Image.fromarray((np.clip(image.color, 0, 1) * 255).astype(np.uint8)).save(output_dir / f"relief_{name}.png")


@pytest.mark.parametrize("view", sorted(VIEWS))
def test_fdm_matches_reference(gl, facade, view, output_dir):
    ctx, programs = gl
    camera = facade_camera(facade.maps, *VIEWS[view])
    ref = trace_view(facade.maps, camera, SIZE)
    assert (ref.material != MISS).mean() > 0.3, "the view must show the facade"
    renderer = FacadeView(ctx, SIZE, programs)
    for name in ("fdm", "cfdm", "bcfdm"):
        renderer.draw(facade, camera, name)
        gpu = read(renderer, f"{name} {view}")
        save(output_dir, f"{name}_{view}", gpu)
        differ = (gpu.material != ref.material) | (gpu.face != ref.face)
        edges = hit_edges(ref)
        print(
            f"{name} {view}: {differ.sum()} of {differ.size} pixels differ, all on edges: {not (differ & ~edges).any()}"
        )
        assert not (differ & ~edges).any(), f"{name}: off-edge mismatches at {np.argwhere(differ & ~edges)[:5]}"
        assert differ.mean() < 0.005
        both = (gpu.material != MISS) & ~differ
        assert np.abs(gpu.point[both] - ref.point[both]).max() < 0.02, "hit depth and position"
    renderer.release()


def test_rm_errors_are_counted(gl, facade, output_dir):
    ctx, programs = gl
    camera = facade_camera(facade.maps, *VIEWS["grazing"])
    ref = trace_view(facade.maps, camera, SIZE)
    renderer = FacadeView(ctx, SIZE, programs)
    counts = {}
    for name in ("rm", "crm", "bcrm"):
        renderer.draw(facade, camera, name)
        gpu = read(renderer, f"{name} grazing")
        save(output_dir, f"{name}_grazing", gpu)
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
        assert (read(renderer, name).material != MISS).mean() > 0.3, name
    renderer.release()


def test_triangulated_relief_matches_reference(gl, facade, output_dir):
    ctx, programs = gl
    camera = facade_camera(facade.maps, *VIEWS["oblique"])
    ref = trace_view(facade.maps, camera, SIZE)
    view = FacadeView(ctx, SIZE, programs)
    mesh = MeshFacade(ctx, facade.maps)
    view.target.use()
    ctx.clear(0.0, 0.0, 0.0, 0.0, depth=1.0)
    mesh.draw(ctx, programs, camera, SINGLE_FACADE, 1.0)
    gpu = read(view, "mesh")
    save(output_dir, "mesh_oblique", gpu)
    differ = (gpu.material != ref.material) | (gpu.face != ref.face)
    print(f"mesh: {differ.sum()} of {differ.size} pixels differ ({mesh.triangles} triangles)")
    assert differ.mean() < 0.01, "the geometry baseline shows the same relief"
    mesh.release()
    view.release()
