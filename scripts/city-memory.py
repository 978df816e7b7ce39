"""Resident memory a built-in city adds, per building, counted as `cityshade bench scale` counts it
(bench.scale.loaded_city), and the GL buffers of its buildings by owner: one city size, without
drawing a frame. On llvmpipe the GL buffers live in the process, so they are part of the resident
bytes. Usage: python scripts/city-memory.py BLOCKS (default_city(blocks=BLOCKS); 102: 100,349
buildings, 32: 9,865)."""

import sys
import warnings

import moderngl

from cityshade.bench.scale import SIZE, loaded_city
from cityshade.render import Renderer, RenderSettings
from cityshade.scene import default_city


def _buffers(owner, prefix: str = "") -> list[tuple[str, int]]:
    out = []
    for name, value in vars(owner).items():
        if isinstance(value, moderngl.Buffer):
            out.append((prefix + name, value.size))
        elif name == "visibility":
            out += _buffers(value, f"{name}.")
    return out


def main(blocks: int):
    warnings.simplefilter("ignore")
    renderer = Renderer(SIZE, RenderSettings(samples=0))
    city, seconds, resident = loaded_city(renderer, lambda: default_city(blocks=blocks))
    n = len(city.masses)
    print(f"default_city(blocks={blocks}): {n:,} buildings, loaded in {seconds:.1f} s")
    print(f"resident bytes per building (bench scale's count): {resident / n:,.0f}")
    for name, size in sorted(_buffers(renderer.city), key=lambda item: -item[1]):
        print(f"  GL buffer {name}: {size / n:,.0f}")
    trees = renderer.trees
    drawn = sum(buffer.size for buffer, _ in trees.instances.values()) + sum(b.size for b in trees.commands.values())
    print(f"  GL buffers of tree instances and draw commands (grow to the trees drawn): {drawn / n:,.1f}")
    print(f"  masses ({city.masses!r}): {city.masses.nbytes / n:,.0f}")
    print(f"  tree records ({len(trees.trees):,} trees): {trees.trees.nbytes / n:,.0f}")
    renderer.release()


if __name__ == "__main__":
    main(int(sys.argv[1]) if len(sys.argv) > 1 else 32)
