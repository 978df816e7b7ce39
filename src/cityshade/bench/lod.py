"""`cityshade bench lod`: building level of detail (docs/frame.md), off against on.

One city, `default_city(blocks=10)` (948 buildings; --quick: blocks=4 at 320x240), drawn at
1024x768 without MSAA by one renderer whose settings switch frame by frame, so that both see the
same machine load:
- frame time of the street and aerial views, LOD off and on (time_interleaved), after a still of
  each (a still evaluates every cheap colour its view needs, so the timed frames evaluate none);
- the cheap colours each still evaluated, and how long they took;
- a walk down the street (WALK_STEP metres a frame) with LOD on and no colour evaluated yet: the
  colours each frame evaluates under `building_lod_budget`, and how long they take.
Ratios: `on_over_off_street`, `on_over_off_aerial` (frame time; under 1: the LOD pays).
"""

from __future__ import annotations

from dataclasses import replace
from pathlib import Path

import numpy as np

from ..render import Renderer, RenderSettings
from ..scene import Camera, default_city
from ._harness import MIN_TIMED_FRAMES, BenchResult, method_record, time_interleaved, timing_record

BLOCKS = {True: 4, False: 10}
SIZE = {True: (320, 240), False: (1024, 768)}
FRAMES = {True: MIN_TIMED_FRAMES, False: 11}
VIEWS = ("street", "aerial")
WALK_FRAMES, WALK_STEP = 12, 3.0


def _walk(street: Camera, frames: int) -> list[Camera]:
    """The street camera moved WALK_STEP metres a frame toward where it looks, level."""
    eye, target = np.array(street.position), np.array(street.target)
    step = (target - eye) * np.array([1.0, 0.0, 1.0])
    step *= WALK_STEP / np.linalg.norm(step)
    return [replace(street, position=tuple(eye + i * step), target=tuple(target + i * step)) for i in range(frames)]


def run(quick: bool, out_dir: Path) -> BenchResult:
    size, frames = SIZE[quick], FRAMES[quick]
    city = default_city(blocks=BLOCKS[quick])
    settings = {
        "off": RenderSettings(samples=0, building_lod=False),
        "on": RenderSettings(samples=0, building_lod=True),
    }
    renderer = Renderer(size, settings["on"])
    try:
        renderer.set_city(city)
        result = BenchResult("lod", renderer.device, timing=timing_record(frames))
        for name, s in settings.items():
            result.methods[f"building LOD {name}"] = method_record(
                cull_back_faces=False,
                depth_prepass=s.depth_prepass,
                frustum_culling=True,
                msaa=0,
                size=size,
                building_lod=s.building_lod,
                building_lod_pixels=list(s.building_lod_pixels),
                building_lod_budget=s.building_lod_budget,
            )
        walk = []
        for camera in _walk(city.camera("street"), WALK_FRAMES):  # nothing evaluated yet: the viewer's path
            renderer.draw(camera)
            walk.append([len(walk), renderer.last_lod_colours, round(renderer.last_lod_seconds * 1e3, 2)])
        stills, rows = [], []
        for view in VIEWS:
            camera = city.camera(view)
            for name in ("off", "on"):
                renderer.set_settings(settings[name])
                renderer.render(camera)
                if name == "on":
                    stills.append([view, renderer.last_lod_colours, round(renderer.last_lod_seconds * 1e3, 1)])

            def draw(name: str, camera=camera):
                def frame(i: int):
                    renderer.set_settings(settings[name])
                    renderer.draw(camera)

                return frame

            timing = time_interleaved(renderer.ctx, {name: draw(name) for name in settings}, frames)
            ratio = timing["on"].median / timing["off"].median
            result.ratios[f"on_over_off_{view}"] = ratio
            rows.append([view, *timing["off"].ms(), *timing["on"].ms(), round(ratio, 3)])
        lod = renderer.city.lod_colours()
        grammar = len(lod.faces)
        evaluated = int(np.count_nonzero(~lod.pending))
    finally:
        renderer.release()
    title = f"Frame time, default_city(blocks={BLOCKS[quick]}) ({len(city.masses)} buildings), {size[0]}x{size[1]}"
    result.add_table(title, ["view", "off (ms)", "off IQR (ms)", "on (ms)", "on IQR (ms)", "on / off"], rows)
    result.add_table("Cheap colours a still evaluated (after the street walk's)", ["view", "colours", "ms"], stills)
    result.add_table(
        f"Street walk, {WALK_STEP:g} m a frame, LOD on from no colour evaluated",
        ["frame", "colours evaluated", "ms"],
        walk,
    )
    result.notes.append(f"{evaluated} of the city's {grammar} grammar buildings' colours evaluated in all.")
    return result
