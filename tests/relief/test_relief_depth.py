"""The relief writes its traced depth (shaders/relief/depth.glsl): where a grammar window is
recessed the depth buffer holds the recessed surface, as the interior twin's distance says, with
the depth prepass on and off and with the forward and deferred grammar paths; and a building whose
front lies inside the recess (7 cm behind the wall: behind the wall's plane, in front of the frame
and the pane) shows through the windows exactly where the twin's recessed surface lies behind it."""

from __future__ import annotations

import dataclasses

import numpy as np
import pytest

from cityshade import assets
from cityshade.dataset import linear_depth
from cityshade.grammar import BUILDING_STYLES
from cityshade.interior import reference_surfaces
from cityshade.relief import relief_atlas
from cityshade.render import Renderer, RenderSettings
from cityshade.render.testing import GROUND_MARGIN
from cityshade.scene import Camera, City, box
from render_checks import grammar_facades, id_edges, interior_params

SIZE = (160, 120)
SWITCH_M = 60.0  # every window in the view traced
TOLERANCE_M = 0.01  # the recess is 10 cm (frame) to 14 cm (pane) behind the wall
NOTHING_M = 1e9  # the distance where a ray meets nothing (inf), so that differences stay finite
BUILDING_NUMBER = {name: number for number, name in BUILDING_STYLES.items()}
OFFICE = box((0.0, 0.0), 18.0, 12.0, 16.0, style=BUILDING_NUMBER["office"], seed=32)
# inside the office, its front 7 cm behind the office's: between the wall's plane and the frame
INSIDE = box((2.0, 0.07), 14.0, 6.0, 12.0, style=0, seed=41)
CAMERA = Camera((-3.0, 5.5, -9.0), (12.0, 7.0, 2.0), fov_y=60.0)
RECESS_STREET = City("building inside a recess", 0, [OFFICE, INSIDE], [], (-30.0, -30.0, 50.0, 30.0), {})


def distances(renderer: Renderer, aov: bool = False) -> np.ndarray:
    """Metres along each pixel's ray to the surface the depth buffer holds (NOTHING_M: nothing)."""
    z = linear_depth(renderer.depth(aov=aov), CAMERA.near, CAMERA.far)
    forward = CAMERA.forward / np.linalg.norm(CAMERA.forward)
    return np.nan_to_num(z / (CAMERA.pixel_rays(SIZE) @ forward), posinf=NOTHING_M)


@pytest.fixture(scope="module")
def twin(gl_context):
    """The twin's (ids, distance) of each building alone, recessed and flat (by name), and the GPU's
    id AOV and its distances."""
    renderer = Renderer(
        SIZE, RenderSettings(lights=0.6, animation_time=1.3, relief_range=SWITCH_M, samples=0), ctx=gl_context
    )
    renderer.set_city(RECESS_STREET)
    gpu_ids = renderer.render_ids(CAMERA)
    gpu_distance = distances(renderer, aov=True)
    params = interior_params(renderer)
    renderer.release()
    alpha = assets.facade_texture()[0][..., 3] / 255.0
    x0, z0, x1, z1 = RECESS_STREET.bounds
    ground = (x0 - GROUND_MARGIN, z0 - GROUND_MARGIN, x1 + GROUND_MARGIN, z1 + GROUND_MARGIN)

    def surfaces(mass, relief: bool):
        atlas = relief_atlas() if relief else None
        grammar = dataclasses.replace(grammar_facades([mass]), relief=atlas, relief_range=SWITCH_M)
        ids, distance = reference_surfaces(
            [mass], CAMERA, SIZE, params, alpha, ground, grammar=grammar, labels=True, window_bay_relief=atlas
        )
        return ids, np.nan_to_num(distance, posinf=NOTHING_M)

    recessed = {"office": surfaces(OFFICE, True), "inside": surfaces(INSIDE, True)}
    flat = {"office": surfaces(OFFICE, False), "inside": surfaces(INSIDE, False)}
    return recessed, flat, gpu_ids, gpu_distance


def combined(twins: dict):
    """The two buildings together: the nearer surface per pixel (the inner one as building 2), and
    where the inner one is nearer."""
    (ids, distance), (inner_ids, inner_distance) = twins["office"], twins["inside"]
    nearer = (inner_ids[..., 2] > 0) & (inner_distance < distance)
    inner_ids = inner_ids + np.array([0, 0, 1, 0], np.uint32) * (inner_ids[..., 2:3] > 0)
    return np.where(nearer[..., None], inner_ids, ids), np.where(nearer, inner_distance, distance), nearer


def test_the_inner_building_shows_through_the_recess_where_the_twin_says(twin):
    recessed_twin, flat, gpu_ids, gpu_distance = twin
    ids, distance, shown = combined(recessed_twin)
    _, _, shown_flat = combined(flat)
    office, office_flat = recessed_twin["office"], flat["office"]
    recessed = (office[0][..., 2] > 0) & (office[1] - office_flat[1] > TOLERANCE_M)
    gpu_shown = gpu_ids[..., 2] == 2
    differ = gpu_shown != shown
    wrong_depth = (ids[..., 2] > 0) & (np.abs(gpu_distance - distance) > TOLERANCE_M)
    edges = id_edges(ids)
    error = np.abs(gpu_distance - distance)[recessed & ~shown]
    print(
        f"{recessed.sum()} recessed office pixels (twin), depth error median {np.median(error) * 1000:.3f} mm, "
        f"max {error.max() * 1000:.3f} mm; inner building seen through the recess on {shown.sum()} pixels "
        f"(twin), {gpu_shown.sum()} (GPU), {differ.sum()} differ ({(differ & ~edges).sum()} away from edges); "
        f"with the wall's depth it would show on {shown_flat.sum()}; {wrong_depth.sum()} building pixels "
        f"more than {TOLERANCE_M * 100:.0f} cm off the twin's distance ({(wrong_depth & ~edges).sum()} away from edges)"
    )
    assert recessed.sum() > 2000, "the view must show recessed windows"
    assert shown.sum() > 500 and not shown_flat.any(), "the inner building must show only through the recess"
    assert not (differ & ~edges).any() and differ.sum() <= 0.001 * differ.size
    assert not (wrong_depth & ~edges).any() and wrong_depth.sum() <= 0.001 * wrong_depth.size


@pytest.mark.parametrize(
    "prepass, deferred, culling, relief",
    [
        (True, True, "gpu", True),
        (True, False, "off", True),
        (False, True, "off", True),
        (False, False, "gpu", True),
        (True, True, "gpu", False),
    ],
)
def test_the_frame_depth_is_the_recessed_depth(gl_context, twin, prepass, deferred, culling, relief):
    """The colour frame's depth buffer (single-sample) against the twin's nearer surface: the
    recessed one with relief on, with the depth prepass (its bound) and without, forward and
    deferred grammar, GPU culling (its occluders bounded too) and none; the wall's with relief off."""
    ids, distance, _ = combined(twin[0] if relief else twin[1])
    settings = RenderSettings(
        lights=0.6,
        animation_time=1.3,
        relief_range=SWITCH_M,
        samples=0,
        trees=False,
        depth_prepass=prepass,
        grammar_deferred=deferred,
        culling=culling,
        relief=relief,
    )
    renderer = Renderer(SIZE, settings, ctx=gl_context)
    renderer.set_city(RECESS_STREET)
    renderer.render(CAMERA)
    got = distances(renderer)
    renderer.release()
    buildings = ids[..., 2] > 0
    wrong = buildings & ~(np.abs(got - distance) <= TOLERANCE_M)
    edges = id_edges(ids)
    print(f"{wrong.sum()} of {buildings.sum()} building pixels off the twin ({(wrong & ~edges).sum()} away from edges)")
    assert not (wrong & ~edges).any() and wrong.sum() <= 0.001 * wrong.size


CLOSEUP_SIZE = (480, 270)


@pytest.fixture(scope="module")
def closeup_frames(gl_context):
    """The default city's close-up at 480x270 (4x MSAA), relief on, with the depth prepass and
    without: (colour, depth) by prepass."""
    from cityshade.scene import make_city

    city = make_city("default")
    frames = {}
    for prepass in (True, False):
        renderer = Renderer(CLOSEUP_SIZE, RenderSettings(depth_prepass=prepass), ctx=gl_context)
        renderer.set_city(city)
        image = renderer.render(city.camera("closeup")).astype(int)
        frames[prepass] = image, np.frombuffer(renderer.targets["resolved"].depth.read(), np.float32)
        renderer.release()
    return frames


def test_the_depth_prepass_changes_no_pixel(closeup_frames):
    """The prepass writes the relief's bound, the buildings pass the traced depth; with back faces
    culled and "<=" in both frames, a tie between two surfaces goes the same way, so the frame's
    depth is the same to the bit and no pixel takes another surface's colour. (One did: a line of
    pixels along a building's silhouette, where its back face met its front face at one depth,
    took the back face's colour, up to 53 levels off.) A few pixels, each at an edge between two
    buildings or a building and the ground, differ by 1 to 3 levels: most likely a 2x2 quad whose
    other pixels the prepass rejects before shading, which moves a texture's footprint."""
    (on, depth_on), (off, depth_off) = closeup_frames[True], closeup_frames[False]
    difference = np.abs(on - off).max(axis=-1)
    print(
        f"prepass on vs off: {(difference > 0).sum()} of {difference.size} pixels differ at all, "
        f"{(difference > 2).sum()} by more than 2/255 (at most {difference.max()}); "
        f"{(depth_on != depth_off).sum()} depths differ"
    )
    assert on.std() > 10, "not an empty picture"
    assert (depth_on == depth_off).all()
    assert (difference <= 4).all() and (difference > 0).sum() <= 0.0002 * difference.size


def test_the_two_relief_programs_draw_what_one_would(gl_context, monkeypatch):
    """The buildings pass draws the buildings a relief may be traced on by the program that writes
    the traced depth and the others by one that does not (render._buildings.relief_parts): in the
    close-up (single-sample, no prepass) depth and ids are those of one program drawing every
    building, and colour but for a pixel or two at an edge, by a few levels. (At 320x180 the first draws the relief-bay buildings in view, 18,884 pixels of
    them, the second the grammar buildings, all beyond the 22 m switch.)"""
    from cityshade.render import _buildings
    from cityshade.scene import make_city

    city = make_city("default")
    camera = city.camera("closeup")
    split = _buildings.relief_parts
    frames = {}
    for parts in ("two", "one"):
        monkeypatch.setattr(_buildings, "relief_parts", split if parts == "two" else lambda f: ({},))
        renderer = Renderer((320, 180), RenderSettings(depth_prepass=False, samples=0), ctx=gl_context)
        renderer.set_city(city)
        frames[parts] = renderer.render(camera), renderer.depth(), renderer.render_ids(camera)
        renderer.release()
    (image, depth, ids), (image_one, depth_one, ids_one) = frames["two"], frames["one"]
    difference = np.abs(image.astype(int) - image_one).max(axis=-1)
    print(
        f"two programs vs one: colour {(difference > 0).sum()} pixels differ (at most {difference.max()}), "
        f"depth {(depth != depth_one).sum()}, ids {(ids != ids_one).any(axis=-1).sum()}"
    )
    assert image.std() > 10
    assert (depth == depth_one).all() and (ids == ids_one).all()
    # as with the prepass: a quad at an edge whose other pixels one program rejects before shading
    assert (difference <= 4).all() and (difference > 0).sum() <= 0.0002 * difference.size
