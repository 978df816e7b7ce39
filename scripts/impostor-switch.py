"""Where a tree's mesh should give way to its impostor: each species drawn as its mesh (the LOD the
distance gives) and as its impostor card, at a range of sizes on screen (the image rows its
height spans), in the street viewer's pixel scale; prints how the two differ, beside how the
mesh's own two LODs differ at the same size (a difference the renderer already fades across),
and writes the docs picture of both at the switch (docs/images/trees_impostor_switch.png).

Four measures over the pixels where either picture has the tree: pixels whose colour differs by
more than DIFFERS levels; pixels that are tree in one picture and sky in the other (silhouette);
the mean colour difference of 4x4-pixel blocks (what is left when leaf-sized detail is averaged
away), in 8-bit levels; and the difference of the two trees' mean colours (each over its own tree
pixels, largest channel), in 8-bit levels: positive where the first picture is the brighter.

    python scripts/impostor-switch.py --out docs/images/trees_impostor_switch.png
"""

from __future__ import annotations

import argparse
from dataclasses import replace
from pathlib import Path

import moderngl
import numpy as np
from PIL import Image

from cityshade.gl import FRAME_BLOCK, RenderTarget, create_context, programs
from cityshade.render import Daylight, TreePass, TreeSettings
from cityshade.scene import Camera
from cityshade.trees import SPECIES_ORDER, tree_instances

ROWS = (240, 160, 120, 90, 70, 60, 50, 40, 30, 20, 12)
FOCAL = 768 / (2 * np.tan(np.radians(30.0)))  # rows per metre at a metre: 1024x768, 60 degrees (the table's metres)
BACKGROUND = np.array([0.45, 0.6, 0.8])
DIFFERS = 24  # 8-bit display levels (any channel) a pixel must change by to count


def display(hdr: np.ndarray) -> np.ndarray:
    x = np.clip(hdr, 0, None)
    x = np.clip((x * (2.51 * x + 0.03)) / (x * (2.43 * x + 0.59) + 0.14), 0, 1) ** (1 / 2.2)
    return (x * 255).astype(np.uint8)


def draw(ctx, tree: TreePass, camera: Camera, size: int, focal_rows: float, samples: int) -> np.ndarray:
    daylight = Daylight.at(16.0)
    FRAME_BLOCK.write(
        ctx,
        u_inv_view_proj=np.linalg.inv(camera.view_projection(1.0)),
        u_camera=camera.eye,
        u_time=0.0,
        u_sun_dir=daylight.sun_direction,
        u_exposure=daylight.exposure,
        u_sun_color=daylight.sun_color,
        u_sky_ambient=daylight.sky_ambient,
        u_ground_ambient=daylight.ground_ambient,
    )
    tree.prepare(camera.eye, focal_rows=focal_rows)
    hdr = RenderTarget(ctx, (size, size), (("f2", 4),), samples=samples)
    out = RenderTarget(ctx, (size, size), (("f2", 4),))
    hdr.use()
    ctx.clear(*BACKGROUND, 1.0, depth=1.0)
    ctx.enable(moderngl.DEPTH_TEST)
    tree.draw({"u_view_proj": camera.view_projection(1.0)}, camera.view(), None)
    ctx.copy_framebuffer(out.fbo, hdr.fbo)
    image = display(out.read()[..., :3].astype(np.float32))
    hdr.release()
    out.release()
    return image


def differences(a: np.ndarray, b: np.ndarray) -> str:
    """The three measures (see the module's text) as a table cell."""
    sky = display(BACKGROUND[None, None, :].astype(np.float32))[0, 0].astype(int)
    a, b = a.astype(int), b.astype(int)
    in_a, in_b = (np.abs(x - sky).max(axis=2) > 2 for x in (a, b))
    tree = in_a | in_b
    colour = np.count_nonzero((np.abs(a - b).max(axis=2) > DIFFERS) & tree) / tree.sum()
    outline = np.count_nonzero(in_a != in_b) / tree.sum()
    n = a.shape[0] // 4 * 4

    def blocks(x):
        return x[:n, :n].reshape(n // 4, 4, n // 4, 4, 3).mean(axis=(1, 3))

    touched = tree[:n, :n].reshape(n // 4, 4, n // 4, 4).any(axis=(1, 3))
    blurred = np.abs(blocks(a) - blocks(b)).mean(axis=2)[touched].mean()
    shift = a[in_a].mean(axis=0) - b[in_b].mean(axis=0)
    mean = shift[np.argmax(np.abs(shift))]
    return f"{colour:6.1%} {outline:6.1%} {blurred:5.1f} {mean:+6.1f}"


def main():
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--out", type=Path, help="the docs picture (mesh above, impostor below, at the switch)")
    parser.add_argument("--samples", type=int, default=4, choices=(0, 4))
    args = parser.parse_args()
    ctx = create_context(headless=True)
    cache = programs(ctx)
    switch_rows = TreeSettings().impostor_rows[0]
    print(
        f"pixels differing by more than {DIFFERS}/255 over the tree's pixels, {args.samples}x MSAA, at 1024x768 60 deg"
    )
    print("                                impostor vs mesh                 far LOD vs near LOD")
    print("species  rows  metres  mesh LOD  colour  outline  4x4   mean     colour  outline  4x4   mean")
    pictures = []
    for name in SPECIES_ORDER:
        trees = tree_instances([(0.0, 0.0, 0.0)], name, np.random.default_rng(0))
        trees["yaw"], trees["scale"] = 0.0, 1.0
        tree = TreePass(ctx, cache, trees, TreeSettings(fins=False))
        height = tree.models[next(iter(tree.models))].height
        for rows in ROWS:
            distance = height * FOCAL / rows
            size = int(max(64, rows * 1.5))
            fov = 2 * np.degrees(np.arctan(size / 2 / FOCAL))
            camera = Camera((0.0, 1.7, distance), (0.0, height / 2, 0.0), fov_y=fov, near=0.5, far=distance * 3)
            never, always = (1e-6, 0.9e-6), (1e9, 0.9e9)
            tree.settings = replace(tree.settings, impostor_rows=never)
            mesh = draw(ctx, tree, camera, size, FOCAL, args.samples)
            tree.settings = replace(tree.settings, impostor_rows=always)
            impostor = draw(ctx, tree, camera, size, FOCAL, args.samples)
            lods = []
            for band in ((1e6, 2e6), (0.0, 1e-3)):  # the near LOD, the far LOD
                tree.settings = replace(tree.settings, impostor_rows=never, lod_band=band)
                lods.append(draw(ctx, tree, camera, size, FOCAL, args.samples))
            tree.settings = replace(tree.settings, lod_band=TreeSettings().lod_band)
            if rows == switch_rows:
                pictures.append((mesh, impostor))
            lod = "near" if distance < TreeSettings().lod_band[0] else "far"
            print(
                f"{name:7s} {rows:5.0f} {distance:7.1f}  {lod:8s}  {differences(mesh, impostor)}"
                f"    {differences(lods[0], lods[1])}"
            )
        tree.release()
    if args.out:
        scale = 3  # nearest-neighbour enlargement, so the pixels can be seen
        size = max(m.shape[0] for m, _ in pictures)

        def padded(image):
            pad = size - image.shape[0]
            out = np.pad(image, ((pad, 0), (pad // 2, pad - pad // 2), (0, 0)), mode="edge")
            return out.repeat(scale, 0).repeat(scale, 1)

        top = np.hstack([padded(m) for m, _ in pictures])
        bottom = np.hstack([padded(i) for _, i in pictures])
        Image.fromarray(np.vstack([top, bottom])).save(args.out)
        print(f"wrote {args.out} (mesh above, impostor below, at {switch_rows:g} rows)")


if __name__ == "__main__":
    main()
