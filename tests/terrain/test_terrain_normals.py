"""The terrain's slopes are shaded with the normal of the triangle under each pixel
(shaders/city/ground_normal.glsl); the GPU's normals match their numpy twin (terrain.face_normals)."""

from __future__ import annotations

import numpy as np

from cityshade.maps import to_scene
from cityshade.scene import Camera
from cityshade.terrain import Terrain, face_normals, terrain_mesh

SIZE = (256, 192)


def test_the_gpu_face_normals_match_their_numpy_twin(gl_context):
    import moderngl

    from cityshade.gl import ProgramCache, RenderTarget

    rows, cols = np.mgrid[0:65, 0:65]
    heights = 30 + 8 * np.sin(cols / 6.0) * np.cos(rows / 9.0) + 0.3 * cols  # ridges and a tilt
    terrain = Terrain(heights.astype(np.float32), 0.0, 128.0, 2.0)
    points = terrain_mesh(terrain, terrain.bounds())
    scene = np.column_stack([to_scene(points[:, :2])[:, 0], points[:, 2], to_scene(points[:, :2])[:, 1]])
    triangles = scene.reshape(-1, 3, 3)
    lying = np.abs(np.cross(triangles[:, 1] - triangles[:, 0], triangles[:, 2] - triangles[:, 0])[:, 1]) > 1e-6
    vertices = triangles[lying].reshape(-1, 3).astype(np.float32)  # skirts, seen edge on, left out
    camera = Camera((-40.0, 140.0, 40.0), (64.0, 30.0, -64.0), fov_y=50.0, near=1.0, far=1000.0)
    program = ProgramCache(gl_context).get("city/ground_normal_probe.glsl")
    program["u_view_proj"].write(camera.view_projection(SIZE[0] / SIZE[1]).T.astype("f4").tobytes())
    target = RenderTarget(gl_context, SIZE, colors=(("f4", 4),))
    buffer = gl_context.buffer(vertices.tobytes())
    vao = gl_context.vertex_array(program, [(buffer, "3f", "in_position")])
    try:
        target.use()
        target.fbo.clear(0.0, 0.0, 0.0, 0.0, depth=1.0)
        gl_context.disable(moderngl.BLEND | moderngl.CULL_FACE)
        gl_context.enable(moderngl.DEPTH_TEST)
        vao.render()
        gpu = target.read(0).reshape(-1, 4)
    finally:
        vao.release()
        buffer.release()
        target.release()
    drawn = gpu[:, 3] > 0
    index = gpu[drawn, 3].astype(np.int64) - 1
    reference = face_normals(vertices)[index]
    error = np.linalg.norm(gpu[drawn, :3] - reference, axis=1)
    differs = error > 1e-3
    print(f"{differs.sum()} of {drawn.sum()} terrain pixels differ (worst {error.max():.2e})")
    assert drawn.mean() > 0.25 and differs.mean() <= 0.01, f"{differs.sum()} of {drawn.sum()} pixels differ"
    assert np.ptp(reference[:, 0]) > 0.3, "the probe's slopes face many ways"
