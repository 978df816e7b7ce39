"""Generating a dataset on Ray: a local runtime started here (or a cluster joined with `address`),
one actor per worker owning a headless renderer and the loaded city, views dealt in batches.

Exactly once: a sample is complete when its files exist and its manifest row is written; only the
driver writes the manifest, from the rows the actors return. An actor that dies is restarted by Ray
and its batch retried (the same views give the same bytes); temporary files a killed actor leaves
are removed at the end. The same actors render the frames of `cityshade video --workers`.
"""

from __future__ import annotations

import functools
import os
import socket
import time
from pathlib import Path

from ..errors import CityshadeError, UsageError
from ._config import DatasetConfig
from ._manifest import check_record, read_manifest, write_manifest
from ._views import sample_view

MANIFEST_EVERY = 2.0  # seconds between manifest rewrites while samples arrive


def check_output(out: Path):
    """Fails with one line if `out` cannot be a dataset folder (nothing is created)."""
    probe = Path(out)
    while not probe.exists():
        probe = probe.parent
    if not probe.is_dir():
        raise UsageError(f"cannot write dataset to {str(out)!r}: {str(probe)!r} is not a directory")
    if not os.access(probe, os.W_OK | os.X_OK):
        raise UsageError(f"cannot write dataset to {str(out)!r}: permission denied; choose another --out")


def check_address(address: str):
    """A host:port that does not answer within 5 s is one line, not a long hang in ray.init."""
    if address == "auto":
        return
    host, _, port = address.removeprefix("ray://").rpartition(":")
    try:
        socket.create_connection((host, int(port)), timeout=5.0).close()
    except (OSError, ValueError):
        raise UsageError(
            f"--address {address}: no Ray cluster answers there; start one with `ray start --head` "
            "or leave out --address for a local runtime"
        ) from None


def _start_ray(workers: int, address: str | None) -> bool:
    """Connects to Ray; True when this call started the runtime (and so must stop it)."""
    import ray

    if ray.is_initialized():
        return False
    if address is not None:
        try:
            ray.init(address=address, logging_level="ERROR", log_to_driver=False)
        except ConnectionError as exc:
            raise UsageError(f"--address {address}: {exc}") from None
        return True
    ray.init(
        num_cpus=workers,
        include_dashboard=False,
        _node_ip_address="127.0.0.1",
        logging_level="ERROR",
        log_to_driver=False,
    )
    return True


@functools.cache
def _worker_class():
    import ray

    @ray.remote(num_cpus=1, max_restarts=-1, max_task_retries=-1)
    class DatasetWorker:
        """One renderer and the loaded city; renders batches of views into `out`."""

        def __init__(self, map_path, city, config: DatasetConfig, out: str, threads: int):
            os.environ["LP_NUM_THREADS"] = str(threads)  # llvmpipe reads it when the context is made
            from ._sample import SampleRenderer
            from ._source import load_source

            # loaded here, not sent: a restarted actor needs nothing the driver may have let go
            self.renderer = SampleRenderer(load_source(map_path, city), config)
            self.out = Path(out)

        def pid(self) -> int:
            return os.getpid()

        def write(self, views) -> list[dict]:
            return [self.renderer.write(view, self.out) for view in views]

        def frames(self, jobs) -> list:
            """(index, camera, settings) -> (index, HxWx3 uint8): frames of a video, each drawn afresh."""
            return [(index, self.renderer.frame(camera, settings)) for index, camera, settings in jobs]

    return DatasetWorker


def _remove_temporaries(out: Path):
    """Files an actor killed mid-write left behind (the atomic writer's hidden temporaries)."""
    for path in (out / "samples").glob(".*"):
        path.unlink(missing_ok=True)


def generate(
    out: Path,
    samples: int,
    config: DatasetConfig,
    map_path: Path | None = None,
    city: str | None = None,
    workers: int = 1,
    address: str | None = None,
    seed: int = 0,
    resume: bool = False,
    progress: bool = True,
    on_workers=None,
) -> list[dict]:
    """Renders samples 0..samples-1 into `out`; returns the manifest's rows. `on_workers(pids)` is
    called once the actors run (to watch or stop them)."""
    from ._source import load_source

    out = Path(out)
    if samples < 1 or workers < 1:
        raise UsageError(f"--samples and --workers must be at least 1 (got {samples} and {workers})")
    check_output(out)
    if address is not None:
        check_address(address)
    record = {"source": str(map_path) if map_path is not None else f"city:{city}", "seed": seed, **config.settings()}
    if resume and (out / "dataset.json").exists():
        check_record(out, record, resume=True)
    source = load_source(map_path, city)
    if not len(source.streets.segments):
        raise UsageError(f"{record['source']} has no streets to stand on; use --city default or a map with roads")
    check_record(out, record, resume)
    (out / "samples").mkdir(parents=True, exist_ok=True)
    done = {
        row["index"]: row
        for row in read_manifest(out)
        if all((out / row[name]).exists() for name in ("rgb", "depth", "normal", "class", "instance", "meta"))
    }
    views = [sample_view(i, seed, config, source.streets, source.has_date) for i in range(samples) if i not in done]
    batches = [views[k : k + config.batch] for k in range(0, len(views), config.batch)]
    try:
        if batches:
            _render(out, batches, samples, done, config, map_path, city, workers, address, progress, on_workers)
    finally:  # also after an error or Ctrl-C: what is complete stays listed, no temporary file stays
        write_manifest(out, list(done.values()))
        _remove_temporaries(out)
    return read_manifest(out)


def render_frames(
    jobs,
    size: tuple[int, int],
    map_path: Path | None = None,
    city: str | None = None,
    workers: int = 1,
    address: str | None = None,
    batch: int = 4,
):
    """Yields the RGB frames of `jobs` (camera, RenderSettings) in order, rendered by `workers` actors
    (`cityshade video --workers`); each frame draws every shadow cascade, so any actor gives the same one."""
    import ray
    from ray.util import ActorPool

    from ._config import parse_config

    if address is not None:
        check_address(address)
    config = parse_config({"image": {"width": size[0], "height": size[1]}})
    numbered = [(i, camera, settings) for i, (camera, settings) in enumerate(jobs)]
    batches = [numbered[k : k + batch] for k in range(0, len(numbered), batch)]
    started = _start_ray(workers, address)
    try:
        threads = max(1, (os.cpu_count() or 1) // workers) if address is None else 1
        actors = [_worker_class().remote(map_path, city, config, "", threads) for _ in range(workers)]
        waiting, next_index = {}, 0
        for frames in ActorPool(actors).map_unordered(lambda actor, part: actor.frames.remote(part), batches):
            waiting.update(frames)
            while next_index in waiting:
                yield waiting.pop(next_index)
                next_index += 1
    except ray.exceptions.RayError as exc:
        lines = [line for line in str(exc).splitlines() if line.strip()]
        raise CityshadeError(f"a video worker failed: {lines[-1] if lines else type(exc).__name__}") from None
    finally:
        if started:
            ray.shutdown()


def _render(
    out: Path,
    batches,
    samples: int,
    done: dict,
    config: DatasetConfig,
    map_path,
    city,
    workers: int,
    address,
    progress: bool,
    on_workers,
):
    """Deals `batches` to the actors; adds each returned manifest row to `done` as it arrives."""
    import ray
    from ray.util import ActorPool
    from rich.progress import Progress

    started = _start_ray(workers, address)
    try:
        threads = max(1, (os.cpu_count() or 1) // workers) if address is None else 1
        actors = [_worker_class().remote(map_path, city, config, str(out.resolve()), threads) for _ in range(workers)]
        if on_workers is not None:
            on_workers(ray.get([a.pid.remote() for a in actors]))
        last = time.monotonic()
        with Progress(disable=not progress, transient=True) as bar:
            task = bar.add_task(f"dataset {out.name}", total=samples, completed=len(done))
            for rows in ActorPool(actors).map_unordered(lambda actor, batch: actor.write.remote(batch), batches):
                done.update({row["index"]: row for row in rows})
                bar.advance(task, len(rows))
                if time.monotonic() - last > MANIFEST_EVERY:
                    write_manifest(out, list(done.values()))
                    last = time.monotonic()
    except ray.exceptions.RayError as exc:  # an actor that cannot start or render: say why, in one line
        lines = [line for line in str(exc).splitlines() if line.strip()]
        raise CityshadeError(
            f"a dataset worker failed: {lines[-1] if lines else type(exc).__name__}; "
            f"{len(done)} complete samples are kept, --resume continues"
        ) from None
    finally:
        if started:
            ray.shutdown()
