"""A single tree drawn by the tree pass on a plain background, for the tree tests."""

import moderngl
import numpy as np
from PIL import Image

from cityshade.frame import Daylight
from cityshade.gl import FRAME_BLOCK, RenderTarget
from cityshade.trees import TreePass, TreeSettings, tree_instances
from render_checks import assert_finite

SIZE = (128, 128)


def one_tree(ctx, programs, species="oak", **settings):
    trees = tree_instances([(0, 0, 0)], species, np.random.default_rng(0))
    trees["yaw"], trees["scale"] = 0.0, 1.0
    return TreePass(ctx, programs, trees, TreeSettings(**settings))


def write_frame_block(ctx, camera, daylight, time=0.0, aspect=1.0):
    FRAME_BLOCK.write(
        ctx,
        u_inv_view_proj=np.linalg.inv(camera.view_projection(aspect)),
        u_camera=camera.eye,
        u_time=time,
        u_sun_dir=daylight.sun_direction,
        u_exposure=daylight.exposure,
        u_sun_color=daylight.sun_color,
        u_sky_ambient=daylight.sky_ambient,
        u_ground_ambient=daylight.ground_ambient,
    )


def render(
    ctx,
    tree_pass,
    camera,
    samples=4,
    shadows=None,
    parts=("trunks", "fins", "leaves", "fronds", "impostors"),
    background=(0.0, 0.0, 0.0),
    fade=None,
    time=0.0,
    focal_rows=None,
):
    """The tree pass's HDR colour; `focal_rows` as TreePass.prepare's (impostors need it)."""
    daylight = Daylight.at(16.0)
    tree_pass.prepare(camera.eye, focal_rows=focal_rows)
    write_frame_block(ctx, camera, daylight, time)
    if fade is not None:  # only the near LOD, at this alpha
        for (species, lod), (buffer, count) in tree_pass.instances.items():
            data = np.frombuffer(buffer.read(), np.float32).reshape(-1, 8)[:count].copy()
            data[:, 5] = fade
            buffer.write(data.tobytes())
            tree_pass.instances[species, lod] = (buffer, count if lod == 0 else 0)
    if shadows is not None:
        shadows.update(0, camera, 1.0, daylight.sun_direction, tree_pass.draw_shadow)
    hdr = RenderTarget(ctx, SIZE, (("f2", 4),), samples=samples)
    out = RenderTarget(ctx, SIZE, (("f2", 4),))
    hdr.use()
    ctx.clear(*background, 1.0, depth=1.0)
    tree_pass.draw({"u_view_proj": camera.view_projection(1.0)}, camera.view(), shadows, parts=parts)
    ctx.copy_framebuffer(out.fbo, hdr.fbo)
    image = out.read()[..., :3].astype(np.float32)
    assert_finite(image, "tree HDR colour")
    hdr.release()
    out.release()
    return image


def render_ids(ctx, tree_pass, camera, parts=("trunks", "fins", "leaves", "fronds")):
    """The tree pass's id AOV (HxWx4 uint32, top row first) and its depth buffer (HxW, 0..1)."""
    tree_pass.prepare(camera.eye)
    write_frame_block(ctx, camera, Daylight.at(16.0))
    target = RenderTarget(ctx, SIZE, (("u4", 4),))
    target.use()
    target.fbo.clear(0.0, 0.0, 0.0, 0.0, depth=1.0)
    ctx.enable(moderngl.DEPTH_TEST)
    ctx.depth_func = "<="
    tree_pass.draw({"u_view_proj": camera.view_projection(1.0)}, camera.view(), parts=parts, ids=True)
    ids = target.read().copy()
    depth = np.frombuffer(target.depth.read(), np.float32).reshape(SIZE[1], SIZE[0])[::-1].copy()
    target.release()
    return ids, depth


def display(image):
    """HDR -> 8-bit with the ACES curve and a 2.2 gamma, for looking at and for golden images."""
    x = np.clip(image, 0, None)
    x = np.clip((x * (2.51 * x + 0.03)) / (x * (2.43 * x + 0.59) + 0.14), 0, 1) ** (1 / 2.2)
    return (x * 255).astype(np.uint8)


def save(image, name, output_dir):
    Image.fromarray(display(image)).save(output_dir / f"{name}.png")
