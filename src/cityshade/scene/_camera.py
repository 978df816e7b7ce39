"""Perspective camera with look-at, and the math shared by the GPU path and the numpy twins."""

from __future__ import annotations

from dataclasses import dataclass, replace

import numpy as np


def look_at(eye: np.ndarray, target: np.ndarray, up: np.ndarray) -> np.ndarray:
    """World-to-view matrix (4x4, column vectors, OpenGL convention: camera looks down -z)."""
    forward = target - eye
    forward = forward / np.linalg.norm(forward)
    side = np.cross(forward, up)
    side = side / np.linalg.norm(side)
    true_up = np.cross(side, forward)
    m = np.identity(4)
    m[0, :3], m[1, :3], m[2, :3] = side, true_up, -forward
    m[:3, 3] = -m[:3, :3] @ eye
    return m


def perspective(fov_y_degrees: float, aspect: float, near: float, far: float) -> np.ndarray:
    f = 1.0 / np.tan(np.radians(fov_y_degrees) / 2.0)
    m = np.zeros((4, 4))
    m[0, 0] = f / aspect
    m[1, 1] = f
    m[2, 2] = (far + near) / (near - far)
    m[2, 3] = 2.0 * far * near / (near - far)
    m[3, 2] = -1.0
    return m


@dataclass(frozen=True)
class Camera:
    position: tuple[float, float, float]
    target: tuple[float, float, float]
    fov_y: float = 60.0
    near: float = 0.5
    far: float = 4000.0
    up: tuple[float, float, float] = (0.0, 1.0, 0.0)
    shadow_far: float | None = None  # metres of cascaded shadows ahead; None: the renderer's default

    @property
    def eye(self) -> np.ndarray:
        return np.asarray(self.position, dtype=np.float64)

    @property
    def forward(self) -> np.ndarray:
        f = np.asarray(self.target, float) - self.eye
        return f / np.linalg.norm(f)

    def view(self) -> np.ndarray:
        return look_at(self.eye, np.asarray(self.target, float), np.asarray(self.up, float))

    def projection(self, aspect: float) -> np.ndarray:
        return perspective(self.fov_y, aspect, self.near, self.far)

    def view_projection(self, aspect: float) -> np.ndarray:
        return self.projection(aspect) @ self.view()

    def pixel_rays(self, size: tuple[int, int]) -> np.ndarray:
        """World-space unit ray directions through pixel centres, (H, W, 3), top row first."""
        width, height = size
        inv = np.linalg.inv(self.view_projection(width / height))
        xs = (np.arange(width) + 0.5) / width * 2 - 1
        ys = 1 - (np.arange(height) + 0.5) / height * 2
        gx, gy = np.meshgrid(xs, ys)
        clip = np.stack([gx, gy, np.ones_like(gx), np.ones_like(gx)], axis=-1)
        world = clip @ inv.T
        points = world[..., :3] / world[..., 3:4]
        dirs = points - self.eye
        return dirs / np.linalg.norm(dirs, axis=-1, keepdims=True)

    def orbit(self, angle_degrees: float) -> "Camera":
        """The camera rotated about the vertical axis through its target."""
        a = np.radians(angle_degrees)
        offset = self.eye - np.asarray(self.target, float)
        c, s = np.cos(a), np.sin(a)
        rotated = np.array([c * offset[0] + s * offset[2], offset[1], -s * offset[0] + c * offset[2]])
        return replace(self, position=tuple(np.asarray(self.target, float) + rotated))
