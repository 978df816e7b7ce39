"""A dataset's cameras for reconstruction tools: nerfstudio's `transforms.json` at the root and a
COLMAP text model in `colmap/` (cameras.txt, images.txt, points3D.txt), from the samples' camera
JSON (K and world_to_camera in OpenCV's axes, pixel centres at integer coordinates).

Both formats put pixel centres at half-integers (the image's corner is (0, 0)), so their principal
point is K's + 0.5. nerfstudio's transform_matrix is camera-to-world in OpenGL's camera axes (x
right, y up, z backward): OpenCV's camera-to-world with its y and z columns negated. COLMAP's
images.txt holds world-to-camera in OpenCV's axes as the unit quaternion (QW, QX, QY, QZ) and the
translation; points3D.txt is empty (no triangulated points). The world is the scene's: metres, x
east, y up, z south, origin at the map's origin.
"""

from __future__ import annotations

import numpy as np
from scipy.spatial.transform import Rotation

CV_TO_GL = np.diag([1.0, -1.0, -1.0, 1.0])  # camera axes: OpenCV (y down, z forward) <-> OpenGL (y up, z back)


def _intrinsics(meta: dict) -> dict:
    k = np.asarray(meta["K"], float)
    return {
        "fl_x": float(k[0, 0]),
        "fl_y": float(k[1, 1]),
        "cx": float(k[0, 2]) + 0.5,
        "cy": float(k[1, 2]) + 0.5,
        "w": int(meta["width"]),
        "h": int(meta["height"]),
    }


def camera_to_world_gl(world_to_camera) -> np.ndarray:
    """nerfstudio's transform_matrix from an OpenCV world_to_camera."""
    return np.linalg.inv(np.asarray(world_to_camera, float)) @ CV_TO_GL


def transforms_document(metas: list[dict], depth_scale: float | None = None) -> dict:
    """transforms.json of the samples (their camera JSON, in index order). With `depth_scale`
    (metres per unit of the 16-bit depth PNGs), frames name their depth file too."""
    first = _intrinsics(metas[0]) if metas else {}
    document = {"camera_model": "OPENCV", **first, "k1": 0.0, "k2": 0.0, "p1": 0.0, "p2": 0.0}
    if depth_scale is not None:
        document["depth_unit_scale_factor"] = depth_scale
    frames = []
    for meta in metas:
        frame = {
            "file_path": f"samples/{meta['files']['rgb']}",
            "transform_matrix": camera_to_world_gl(meta["world_to_camera"]).tolist(),
        }
        own = _intrinsics(meta)
        frame.update({key: value for key, value in own.items() if value != first[key]})  # per frame where it differs
        if depth_scale is not None:
            frame["depth_file_path"] = f"samples/{meta['files']['kitti_depth']}"
        frames.append(frame)
    document["frames"] = frames
    return document


def colmap_model(metas: list[dict]) -> dict[str, str]:
    """File name -> text of a COLMAP text model: one PINHOLE camera per distinct K, one image per sample
    (IMAGE_ID = sample index + 1, NAME relative to the dataset folder)."""
    cameras, camera_lines, image_lines = {}, [], []
    for meta in metas:
        own = _intrinsics(meta)
        key = tuple(own.values())
        if key not in cameras:
            cameras[key] = len(cameras) + 1
            camera_lines.append(
                f"{cameras[key]} PINHOLE {own['w']} {own['h']} "
                f"{own['fl_x']!r} {own['fl_y']!r} {own['cx']!r} {own['cy']!r}"
            )
        pose = np.asarray(meta["world_to_camera"], float)
        qx, qy, qz, qw = Rotation.from_matrix(pose[:3, :3]).as_quat()
        if qw < 0:  # the same rotation; COLMAP writes w >= 0
            qw, qx, qy, qz = -qw, -qx, -qy, -qz
        tx, ty, tz = pose[:3, 3]
        values = " ".join(repr(float(v)) for v in (qw, qx, qy, qz, tx, ty, tz))
        image_lines += [f"{meta['index'] + 1} {values} {cameras[key]} samples/{meta['files']['rgb']}", ""]
    return {
        "cameras.txt": "# Camera list with one line of data per camera:\n"
        "#   CAMERA_ID, MODEL, WIDTH, HEIGHT, PARAMS[]\n"
        f"# Number of cameras: {len(cameras)}\n" + "".join(line + "\n" for line in camera_lines),
        "images.txt": "# Image list with two lines of data per image:\n"
        "#   IMAGE_ID, QW, QX, QY, QZ, TX, TY, TZ, CAMERA_ID, NAME\n"
        "#   POINTS2D[] as (X, Y, POINT3D_ID)\n"
        f"# Number of images: {len(metas)}, mean observations per image: 0\n"
        + "".join(line + "\n" for line in image_lines),
        "points3D.txt": "# 3D point list with one line of data per point:\n"
        "#   POINT3D_ID, X, Y, Z, R, G, B, ERROR, TRACK[] as (IMAGE_ID, POINT2D_IDX)\n"
        "# Number of points: 0, mean track length: 0\n",
    }
