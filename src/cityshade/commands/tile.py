"""`cityshade tile FILE --out DIR`, and the options that stream a city in `render` and `view`
(--tiles DIR, --memory-budget SIZE): docs/scale.md, "Streaming"."""

from __future__ import annotations

import contextlib
import math
import sys
import tempfile
import time
from pathlib import Path

from rich.console import Console
from rich.progress import Progress

from ..errors import UsageError
from ..render import (
    TILE_SIZE,
    CacheProblem,
    TileCache,
    check_cache_folder,
    format_bytes,
    on_ray,
    open_tiles,
    run_here,
    source_identity,
    write_tiles,
)
from .arguments import add_terrain_option, parse_memory_size

MAX_WORKERS = 4096  # Ray tasks at once


def _map_city(path: Path, terrain: Path | None = None):
    from ..maps import load_map, map_city

    return map_city(load_map(path, terrain=terrain))


def _identity(path: Path, terrain: Path | None = None) -> dict:
    """The source's identity (and its terrain's: another DEM is another city); a file that cannot be
    read fails as the map or DEM reader says."""
    try:
        identity = source_identity(path)
        return identity if terrain is None else {**identity, "terrain": source_identity(terrain)}
    except OSError:
        _map_city(path, terrain)  # raises load_map's one-line error
        raise


def _tile_size(text: str) -> float:
    try:
        size = float(text)
    except ValueError:
        size = math.nan
    if not 1.0 <= size <= 100_000.0:
        raise UsageError(f"invalid --tile-size {text!r}; give metres from 1 to 100000")
    return size


def register(subparsers):
    parser = subparsers.add_parser(
        "tile", help="cut a map's buildings into a tile cache for streaming (render/view --tiles DIR)"
    )
    parser.add_argument(
        "file", type=Path, metavar="FILE", help="a map: OpenStreetMap (.osm.pbf, .osm), GeoJSON or CityJSON"
    )
    parser.add_argument("--out", type=Path, required=True, metavar="DIR", help="the cache folder (replaced whole)")
    add_terrain_option(parser)
    parser.add_argument(
        "--tile-size",
        type=_tile_size,
        default=TILE_SIZE,
        metavar="METRES",
        help=f"side of the square tiles (default {TILE_SIZE:g})",
    )
    parser.add_argument(
        "--workers",
        type=_workers,
        default=1,
        metavar="K",
        help="mesh tiles in K Ray tasks at once (default 1: in this process, no Ray); this process "
        "writes every file, and a build that was stopped resumes from the tiles it finished",
    )
    parser.add_argument(
        "--address",
        default=None,
        metavar="A",
        help="run the tasks on the Ray cluster at A (host:port or auto) instead of a local runtime",
    )
    parser.set_defaults(run=run)


def _workers(text: str) -> int:
    try:
        workers = int(text)
    except ValueError:
        workers = 0
    if not 1 <= workers <= MAX_WORKERS:
        raise UsageError(f"invalid --workers {text!r}; give a whole number from 1 to {MAX_WORKERS}")
    return workers


def run(args) -> int:
    start = time.perf_counter()
    check_cache_folder(args.out)  # before the map is read
    if args.address is not None:
        from ..dataset import check_address

        check_address(args.address)
    source = _identity(args.file, args.terrain)
    city = _map_city(args.file, args.terrain)
    with _runner(args.workers, args.address) as runner, Progress(console=Console(stderr=True), transient=True) as bar:
        task = bar.add_task(f"meshing tiles of {args.out.name}", total=None)
        summary = write_tiles(
            city,
            args.out,
            source,
            args.tile_size,
            runner,
            lambda done, total: bar.update(task, completed=done, total=total),
        )
    resumed = f", {summary['resumed']} of them kept from the build that was stopped" if summary["resumed"] else ""
    print(
        f"wrote {args.out}: {summary['tiles']} tiles, {summary['buildings']} buildings, "
        f"{format_bytes(summary['bytes'])} in {time.perf_counter() - start:.1f} s{resumed}"
    )
    return 0


@contextlib.contextmanager
def _runner(workers: int, address: str | None):
    """run_here for one local worker; else Ray tasks, `workers` at once, on a local runtime started
    here (and stopped after) or on the cluster at `address`."""
    if workers == 1 and address is None:
        yield run_here
        return
    import ray

    from ..dataset import start_ray

    started = start_ray(workers, address)
    try:
        yield on_ray(workers)
    finally:
        if started:
            ray.shutdown()


def add_streaming_arguments(parser):
    parser.add_argument(
        "--tiles",
        type=Path,
        default=None,
        metavar="DIR",
        help="the city from a tile cache (`cityshade tile`); with --map, the cache of that map, "
        "made or remade from it when missing, stale or damaged",
    )
    parser.add_argument(
        "--memory-budget",
        default=None,
        metavar="SIZE",
        help="stream the buildings in tiles around the camera, at most SIZE of them resident "
        "(e.g. 512MB, 1GB); a still waits for the tiles its view needs, the viewer never waits",
    )


def _notice(text: str):
    print(f"cityshade: {text}", file=sys.stderr)


@contextlib.contextmanager
def streamed_tiles(args, city=None):
    """The TileCache that args.tiles / args.memory_budget ask for, with the budget in bytes (None:
    every tile); (None, None) when neither is given. `city`: the built-in City to stream (no --map,
    no --tiles). A cache made for this run only lives in a temporary folder until the block ends."""
    if args.tiles is None and args.memory_budget is None:
        yield None, None
        return
    budget = None if args.memory_budget is None else parse_memory_size(args.memory_budget)
    terrain = getattr(args, "terrain", None)  # commands without --terrain stream flat maps
    with contextlib.ExitStack() as stack:
        start = time.perf_counter()
        if args.map is None and args.tiles is not None:
            try:
                cache = open_tiles(args.tiles)
            except CacheProblem as problem:
                raise UsageError(f"{problem}; make it again with `cityshade tile SOURCE --out {args.tiles}`") from None
            how = "read"
        else:
            source = _identity(args.map, terrain) if args.map is not None else None
            folder = args.tiles
            if folder is None:
                folder = Path(stack.enter_context(tempfile.TemporaryDirectory(prefix="cityshade-tiles-"))) / "tiles"
            cache, how = _open_or_make(folder, args.map, source, city, terrain)
        print(f"tile cache {how} in {time.perf_counter() - start:.1f} s: {_describe(cache, budget)}")
        yield cache, budget


def _open_or_make(folder: Path, path: Path | None, source: dict | None, city, terrain=None) -> tuple[TileCache, str]:
    check_cache_folder(folder)  # a folder of something else is refused, not replaced
    if folder.exists() and path is not None:
        try:
            return open_tiles(folder, source), "read"
        except CacheProblem as problem:
            _notice(f"{problem}; making it again from {path}")
    write_tiles(_map_city(path, terrain) if path is not None else city, folder, source)
    return open_tiles(folder, source), "made"


def _describe(cache: TileCache, budget: int | None) -> str:
    held = "all resident" if budget is None or budget >= cache.total_bytes else f"budget {format_bytes(budget)}"
    return f"{len(cache.tiles)} tiles, {format_bytes(cache.total_bytes)} of tiles, {held}"
