"""The tree pass's and shadow pass's cost with impostor cards on and off, taking turns (on, off,
off, on) in one process so both see the same machine load: the 100,000-building generator city
(default_city(blocks=102)) walking the street, per pass (Renderer.draw(profile=True), as
`cityshade render --profile`), at a given internal size with the viewer's first `--level` quality
steps taken. Medians over 4 blocks of 4 frames after one block of warm-up.

    python scripts/impostor-cost.py --size 256x192 --level 4
"""

from __future__ import annotations

import argparse
import statistics
from dataclasses import replace

from cityshade.render import Renderer, RenderSettings, with_quality_steps
from cityshade.scene import PATHS, default_city


def main():
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--size", default="256x192", help="internal size (the viewer's smallest scale at 1024x768)")
    parser.add_argument("--level", type=int, default=4, help="quality steps taken (render.QUALITY_STEPS)")
    parser.add_argument("--blocks", type=int, default=102, help="default_city(blocks=N): 102 gives 100,349 buildings")
    args = parser.parse_args()
    size = tuple(int(v) for v in args.size.split("x"))
    city = default_city(blocks=args.blocks)
    renderer = Renderer(size, RenderSettings(samples=0))
    renderer.set_city(city)
    settings, trees = with_quality_steps(renderer.settings, renderer.trees.settings, args.level)
    renderer.set_settings(settings)
    times = {True: [], False: []}
    drawn = {}
    for block in range(5):
        camera = PATHS["walk"](city, block / 50)
        for on in (True, False, False, True):
            renderer.trees.settings = replace(trees, impostors=on)
            renderer.draw(camera, profile=True)
            if block:  # block 0 warms up (programs, atlases)
                times[on].append(dict(renderer.last_pass_seconds))
            meshes = sum(count for _, count in renderer.trees.instances.values())
            drawn[on] = (meshes, sum(card.count for card in renderer.trees.impostors.values()))
    print(f"{len(city.masses)} buildings, {len(renderer.trees.trees)} trees, {args.size}, quality steps {args.level}")
    for on in (False, True):
        frames = times[on]
        median = {name: 1000 * statistics.median(f[name] for f in frames) for name in frames[0]}
        frame = 1000 * statistics.median(sum(f.values()) for f in frames)
        print(
            f"impostors {'on ' if on else 'off'}: trees {median['trees']:.1f} ms, shadows {median.get('shadows', 0):.1f} ms,"
            f" frame {frame:.1f} ms ({len(frames)} frames); last frame: {drawn[on][0]} mesh instances, {drawn[on][1]} cards"
        )
    renderer.release()


if __name__ == "__main__":
    main()
