"""The sun's and the moon's discs, drawn per pixel by the sky pass (shaders/frame/sky.glsl) against
their numpy twin (render/_sky_discs.py): inside a disc the frame is the disc's radiance, outside
it nothing of the disc leaks (as the texels of a disc baked into the cube map did), and the
antialiased edge is where the twin puts it."""

from __future__ import annotations

import numpy as np
import pytest
from PIL import Image

from cityshade.render import Daylight, Renderer, RenderSettings
from cityshade.render.testing import sky_disc_uniforms, sky_discs_reference
from cityshade.scene import GROUND_PAVEMENT, Camera, City, box

SIZE = (160, 120)
FOV = 8.0  # degrees: a narrow lens, so each disc spans many pixels
CASES = {
    "sun": dict(time_of_day=12.0, sun=(20.0, 200.0)),
    # the sun just below the horizon: the moon lights the night, the stars are not out yet
    "moon": dict(time_of_day=23.0, sun=(-4.2, 20.0), moon=(35.0, 140.0, 0.8)),
}


def _city() -> City:
    return City(
        "open sky",
        1,
        [box((0.0, 0.0), 4.0, 4.0, 3.0)],
        [(-50.0, -50.0, 50.0, 50.0, GROUND_PAVEMENT)],
        (-50.0, -50.0, 50.0, 50.0),
        {},
    )


def _directions(camera: Camera) -> np.ndarray:
    """Each pixel's unit view direction, top row first."""
    aspect = SIZE[0] / SIZE[1]
    inverse = np.linalg.inv(camera.view_projection(aspect))
    x = (np.arange(SIZE[0]) + 0.5) / SIZE[0] * 2 - 1
    y = 1 - (np.arange(SIZE[1]) + 0.5) / SIZE[1] * 2
    ndc = np.stack([*np.meshgrid(x, y), np.ones((SIZE[1], SIZE[0])), np.ones((SIZE[1], SIZE[0]))], axis=-1)
    far = ndc @ inverse.T
    d = far[..., :3] / far[..., 3:] - camera.eye
    return d / np.linalg.norm(d, axis=-1, keepdims=True)


@pytest.mark.parametrize("case", sorted(CASES))
def test_the_sky_pass_draws_round_discs_as_the_twin(gl_context, case, output_dir):
    settings = RenderSettings(samples=0, god_rays=False, trees=False, shadows=False, **CASES[case])
    daylight = Daylight.at(settings.time_of_day, settings.sun, settings.moon)
    toward = daylight.sky_sun if case == "sun" else daylight.moon_direction
    eye = np.array([0.0, 2.0, 30.0])
    camera = Camera(tuple(eye), tuple(eye + 100.0 * np.asarray(toward)), fov_y=FOV)
    renderer = Renderer(SIZE, settings, ctx=gl_context)
    try:
        renderer.set_city(_city())
        renderer.draw(camera)
        hdr = renderer.read_hdr().astype(np.float64)
        sky = renderer.depth() == 1.0
    finally:
        renderer.release()
    uniforms = sky_disc_uniforms(daylight, SIZE[1], FOV)
    radiance = np.asarray(uniforms["u_disc_radiance"])[0 if case == "sun" else 1]
    # the twin's coverage of each pixel: its mix of a white disc over a black sky
    plain = {
        **uniforms,
        "u_disc_radiance": [(1.0, 1.0, 1.0) if np.any(r) else (0.0, 0.0, 0.0) for r in uniforms["u_disc_radiance"]],
    }
    cover = sky_discs_reference(np.zeros((*SIZE[::-1], 3)), _directions(camera), plain)[..., 0]
    inside, outside, edge = sky & (cover == 1.0), sky & (cover == 0.0), sky & (cover > 0.0) & (cover < 1.0)
    luma = np.array([0.2126, 0.7152, 0.0722])
    wrong_inside = np.abs(hdr[inside] - radiance).max(axis=-1) > 0.01 * radiance.max()
    leaked = hdr[outside] @ luma > 0.5 * (radiance @ luma)
    expected_edge = cover[edge][:, None] * radiance  # at least the disc's share of the pixel
    wrong_edge = (hdr[edge] < 0.98 * expected_edge - 1e-3).any(axis=-1) | (hdr[edge] > radiance * 1.01).any(axis=-1)
    print(
        f"{case}: {inside.sum()} pixels inside the disc, {int(wrong_inside.sum())} not its radiance; "
        f"{int(leaked.sum())} of {outside.sum()} outside it bright; {int(wrong_edge.sum())} of {edge.sum()} edge pixels off"
    )
    Image.fromarray(np.clip(hdr / radiance.max() * 255, 0, 255).astype(np.uint8)).save(
        output_dir / f"sky_disc_{case}.png"
    )
    assert inside.sum() > 50 and edge.sum() > 10
    assert not wrong_inside.any() and not leaked.any() and not wrong_edge.any()
