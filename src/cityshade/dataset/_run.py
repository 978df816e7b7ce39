"""Generating a dataset on Ray: a local runtime started here (or a cluster joined with `address`),
one actor per worker owning a headless renderer and the loaded city, views dealt in batches.

Exactly once: a sample is complete when its files exist and its manifest row is written; only the
driver writes the manifest, from the rows the actors return. An actor that dies is restarted by Ray
and its batch retried (the same views give the same bytes); temporary files a killed actor leaves
are removed at the end. The same actors render the frames of `cityshade video --workers`.

Nothing is written before every check has passed and Ray runs: the counts against their caps
(_limits.py), the folder, the address, the record and manifest of a folder to resume, the source,
and the cluster's CPUs. SIGTERM, SIGHUP and SIGINT end a run as Ctrl-C does: Ray's own handlers,
installed by ray.init, are replaced by the ones before it, and the manifest then lists every sample
the actors finished (its camera JSON, written last, is on disk) before the command exits.
"""

from __future__ import annotations

import contextlib
import functools
import json
import os
import signal
import socket
import stat
import sys
import threading
import time
from pathlib import Path

from .._files import read_input_bytes, signals_deferred
from ..errors import CityshadeError, UsageError
from ._config import DatasetConfig
from ._gather import write_gathered
from ._limits import MAX_SAMPLE_FILE_BYTES, MAX_SAMPLES, MAX_SEED, WORKERS_PER_CORE, local_cores, max_local_workers
from ._manifest import FILES, check_record, complete_rows, folder_file, read_manifest, write_manifest, write_record
from ._progress import progress as show_progress
from ._sample import manifest_row, sample_files
from ._views import SEQUENCES, sample_view, sequence_view

MANIFEST_EVERY = 2.0  # seconds between manifest rewrites while samples arrive
PROBE_SECONDS = 5.0  # for an address to answer
ACTOR_EXIT_SECONDS = 10.0  # for this machine's actors to exit once killed, before finished samples are listed
# An HTTP/2 client's preface and an empty SETTINGS frame: a gRPC server (Ray's GCS, the Ray Client
# server) answers with a SETTINGS frame (type 4) of its own, anything else does not.
HTTP2_HELLO = b"PRI * HTTP/2.0\r\n\r\nSM\r\n\r\n" + bytes([0, 0, 0, 4, 0, 0, 0, 0, 0])
EXIT_SIGNALS = (signal.SIGTERM, signal.SIGHUP, signal.SIGINT)
# Set to see Ray's own log (its Python logger's level; Ray reads it too): otherwise ray.init runs
# with logging_level ERROR, log_to_driver False and its C++ lines on stderr going to /dev/null.
RAY_LOG_VARIABLE = "RAY_LOGGER_LEVEL"


def check_counts(samples: int, workers: int, seed: int = 0):
    """--samples, --workers (against this machine) and --seed within their caps, or one line."""
    if not 1 <= samples <= MAX_SAMPLES:
        raise UsageError(
            f"--samples {samples}: give 1 to {MAX_SAMPLES}; the driver holds every view and manifest row in memory, "
            "so a larger dataset belongs in several --out folders (one seed each)"
        )
    if workers < 1:
        raise UsageError(f"--workers {workers}: give at least 1")
    if not 0 <= seed <= MAX_SEED:
        raise UsageError(f"--seed {seed}: give 0 to {MAX_SEED}")


def check_local_workers(workers: int):
    if workers > max_local_workers():
        raise UsageError(
            f"--workers {workers}: give at most {max_local_workers()} here ({WORKERS_PER_CORE} per core, "
            f"{local_cores()} cores): more actors only add memory, each holds the city and a renderer"
        )


def check_cluster_workers(workers: int, address: str | None):
    """Once connected: one CPU per actor, or the actors beyond the cluster's CPUs never start."""
    import ray

    cpus = int(ray.cluster_resources().get("CPU", 0))
    if workers > cpus:
        where = f"the Ray cluster at {address}" if address is not None else "the Ray runtime"
        raise UsageError(f"--workers {workers}: {where} has {cpus} CPUs, one per actor; give at most {max(cpus, 1)}")


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
    """A host:port where no gRPC server (Ray's GCS or Ray Client server) answers within 5 s is one
    line, not a long hang in ray.init with Ray's log on the terminal."""
    if address == "auto":
        return
    host, _, port = address.removeprefix("ray://").rpartition(":")
    reply = b""
    try:
        if not host.strip("[]"):
            raise ValueError(address)
        with socket.create_connection((host.strip("[]"), int(port)), timeout=PROBE_SECONDS) as connection:
            connection.sendall(HTTP2_HELLO)
            while len(reply) < 9 and (part := connection.recv(9 - len(reply))):
                reply += part
    except (OSError, ValueError, OverflowError, UnicodeError):
        pass
    if len(reply) < 9 or reply[3] != 4:
        raise UsageError(
            f"--address {address}: no Ray cluster answers there; start one with `ray start --head` "
            "or leave out --address for a local runtime"
        )


def _last_line(exc: BaseException) -> str:
    lines = [line.strip() for line in str(exc).splitlines() if line.strip()]
    line = lines[-1] if lines else type(exc).__name__
    return line if len(line) <= 200 else line[:197] + "..."


@contextlib.contextmanager
def _ray_log_hidden(hide: bool):
    """Ray's C++ lines, which it writes straight to file descriptor 2, go to /dev/null meanwhile."""
    try:
        saved = os.dup(2) if hide else None
    except OSError:
        saved = None
    if saved is None:
        yield
        return
    sys.stderr.flush()
    try:
        with open(os.devnull, "wb") as null:
            os.dup2(null.fileno(), 2)
        yield
    finally:
        os.dup2(saved, 2)
        os.close(saved)


@contextlib.contextmanager
def _environment(**values):
    """Environment variables set for the block (those the user set are kept), then restored."""
    old = {name: os.environ.get(name) for name in values}
    for name, value in values.items():
        os.environ.setdefault(name, value)
    try:
        yield
    finally:
        for name, value in old.items():
            if value is None:
                os.environ.pop(name, None)
            else:
                os.environ[name] = value


def _start_ray(workers: int, address: str | None) -> bool:
    """Connects to Ray; True when this call started the runtime (and so must stop it). The signal
    handlers from before ray.init are put back after it: Ray's replace them (a SIGTERM handler
    that exits with status 15 and, in its C++ core, one that prints a crash report), and a run
    must end like Ctrl-C, with its `finally` blocks run."""
    import ray

    if ray.is_initialized():
        return False
    asked = RAY_LOG_VARIABLE in os.environ
    options = {} if asked else {"logging_level": "ERROR", "log_to_driver": False}
    environment = {}
    if address is not None:
        options["address"] = address
        # one attempt (about 40 s when nothing answers), not Ray's twenty
        environment["RAY_gcs_server_port_wait_time_s"] = "1"
    else:
        options.update(num_cpus=workers, include_dashboard=False, _node_ip_address="127.0.0.1")
    main = threading.current_thread() is threading.main_thread()
    handlers = {sig: signal.getsignal(sig) for sig in EXIT_SIGNALS} if main else {}
    try:
        with _ray_log_hidden(not asked), _environment(**environment):
            ray.init(**options)
    except SystemExit as exc:  # Ray's SIGTERM handler, between its start and the return of ours
        ray.shutdown()
        raise SystemExit(128 + signal.SIGTERM if exc.code == signal.SIGTERM else exc.code) from None
    except Exception as exc:
        ray.shutdown()
        hint = f"set {RAY_LOG_VARIABLE}=info to see Ray's log"
        if address is not None:
            raise UsageError(
                f"--address {address}: Ray could not join the cluster there ({_last_line(exc)}); {hint}"
            ) from None
        raise CityshadeError(f"could not start a local Ray runtime ({_last_line(exc)}); {hint}", exit_code=1) from None
    except BaseException:
        ray.shutdown()
        raise
    finally:
        for sig, handler in handlers.items():
            if handler is not None:
                signal.signal(sig, handler)
    return True


@functools.cache
def _worker_class():
    import ray

    @ray.remote(num_cpus=1, max_restarts=-1, max_task_retries=-1)
    class DatasetWorker:
        """One renderer and the loaded city; renders batches of views into `out`."""

        def __init__(self, map_path, city, config: DatasetConfig, out: str, threads: int, terrain=None):
            os.environ["LP_NUM_THREADS"] = str(threads)  # llvmpipe reads it when the context is made
            from ._sample import SampleRenderer
            from ._source import load_source

            # loaded here, not sent: a restarted actor needs nothing the driver may have let go
            self.renderer = SampleRenderer(load_source(map_path, city, terrain), config)
            self.out = Path(out)

        def pid(self) -> int:
            return os.getpid()

        def process(self) -> tuple[str, int]:
            """(Ray node id, process id): where this actor runs."""
            return ray.get_runtime_context().get_node_id(), os.getpid()

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


def _alive(pid: int) -> bool:
    try:
        with open(f"/proc/{pid}/stat", "rb") as status:
            return status.read().rpartition(b")")[2].split()[0] not in (b"Z", b"X")  # a zombie writes nothing
    except FileNotFoundError:
        return False
    except (OSError, IndexError):
        try:
            os.kill(pid, 0)
        except ProcessLookupError:
            return False
        except OSError:
            pass
        return True


def _stop_actors(actors, processes):
    """Kills the actors and waits (a while) for those on this machine to exit, so that no sample
    is finished after the finished ones are listed."""
    import ray

    here = ray.get_runtime_context().get_node_id()
    ready, _ = ray.wait(processes, num_returns=len(processes), timeout=0)
    pids = []
    for ref in ready:
        try:
            node, pid = ray.get(ref, timeout=0)
        except ray.exceptions.RayError:
            continue
        if node == here:
            pids.append(pid)
    for actor in actors:
        with contextlib.suppress(Exception):
            ray.kill(actor)
    deadline = time.monotonic() + ACTOR_EXIT_SECONDS
    while (pids := [pid for pid in pids if _alive(pid)]) and time.monotonic() < deadline:
        time.sleep(0.05)


def _add_finished(out: Path, views, done: dict, since_ns: int, arrays: str):
    """Adds to `done` the samples of `views` whose rows never came back (a run stopped by a signal
    or an error) but whose files an actor of this run finished: six regular files, the camera
    JSON (written last) written since `since_ns` and describing this view."""
    for view in views:
        if view.index in done:
            continue
        files = sample_files(view.index, arrays)
        try:
            info = {name: os.lstat(out / files[name]) for name in FILES}
            if not all(stat.S_ISREG(i.st_mode) for i in info.values()) or info["meta"].st_mtime_ns < since_ns:
                continue
            meta = json.loads(read_input_bytes(out / files["meta"], MAX_SAMPLE_FILE_BYTES, "sample file"))
            if meta["index"] == view.index and meta["eye"] == list(view.eye):
                done[view.index] = manifest_row(view, meta, arrays)
        except (OSError, CityshadeError, ValueError, KeyError, TypeError, RecursionError):
            continue


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
    path: str | None = None,
    terrain: Path | None = None,
) -> list[dict]:
    """Renders samples 0..samples-1 into `out`; returns the manifest's rows. `on_workers(pids)` is
    called once the actors run (to watch or stop them). With `path` (walk or orbit) the samples are
    consecutive views along it (_views.sequence_view); `terrain`: the DEM under the map. Checks
    everything before it writes anything."""
    from ._source import load_source

    out = Path(out)
    check_counts(samples, workers, seed)
    if address is None:
        check_local_workers(workers)
    check_output(out)
    if address is not None:
        check_address(address)
    if path is not None and path not in SEQUENCES:
        raise UsageError(f"--path {path}: unknown path; allowed: {', '.join(SEQUENCES)}")
    record = {"source": str(map_path) if map_path is not None else f"city:{city}", "seed": seed, **config.settings()}
    if terrain is not None:  # another ground, other pictures
        record["terrain"] = str(terrain)
    if path is not None:  # a sequence's views depend on its length too
        record.update(path=path, frames=samples)
    check_record(out, record, resume)
    source = load_source(map_path, city, terrain)
    if not len(source.streets.segments):
        raise UsageError(f"{record['source']} has no streets to stand on; use --city default or a map with roads")
    done = complete_rows(out)
    samples_folder = folder_file(out, "samples")
    views = [
        sequence_view(i, samples, path, seed, config, source.streets, source.has_date, source.city)
        if path is not None
        else sample_view(i, seed, config, source.streets, source.has_date)
        for i in range(samples)
        if i not in done
    ]
    batches = [views[k : k + config.batch] for k in range(0, len(views), config.batch)]
    started = _start_ray(workers, address) if batches else False
    try:
        if batches:
            check_cluster_workers(workers, address)
        write_record(out, record)
        samples_folder.mkdir(parents=True, exist_ok=True)
        since_ns = time.time_ns() - 1_000_000_000  # file times lag the clock by up to a tick
        try:
            if batches:
                _render(
                    out, batches, samples, done, config, map_path, city, workers, address, progress, on_workers, terrain
                )
        finally:  # also after an error, Ctrl-C or SIGTERM: what is complete is listed, no temporary file stays
            with signals_deferred():
                _add_finished(out, views, done, since_ns, config.arrays)
                write_manifest(out, list(done.values()))
                _remove_temporaries(out)
    finally:
        if started:
            import ray

            ray.shutdown()
    write_gathered(out, config)
    return read_manifest(out)


def render_frames(
    jobs,
    size: tuple[int, int],
    map_path: Path | None = None,
    city: str | None = None,
    workers: int = 1,
    address: str | None = None,
    batch: int = 4,
    terrain: Path | None = None,
):
    """Yields the RGB frames of `jobs` (camera, RenderSettings) in order, rendered by `workers` actors
    (`cityshade video --workers`); each frame draws every shadow cascade, so any actor gives the same one."""
    import ray
    from ray.util import ActorPool

    from ._config import parse_config

    if address is None:
        check_local_workers(workers)
    else:
        check_address(address)
    config = parse_config({"image": {"width": size[0], "height": size[1]}})
    numbered = [(i, camera, settings) for i, (camera, settings) in enumerate(jobs)]
    batches = [numbered[k : k + batch] for k in range(0, len(numbered), batch)]
    started = _start_ray(workers, address)
    try:
        check_cluster_workers(workers, address)
        threads = max(1, local_cores() // workers) if address is None else 1
        actors = [_worker_class().remote(map_path, city, config, "", threads, terrain) for _ in range(workers)]
        waiting, next_index = {}, 0
        for frames in ActorPool(actors).map_unordered(lambda actor, part: actor.frames.remote(part), batches):
            waiting.update(frames)
            while next_index in waiting:
                yield waiting.pop(next_index)
                next_index += 1
    except ray.exceptions.RayError as exc:
        raise CityshadeError(f"a video worker failed: {_last_line(exc)}") from None
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
    terrain=None,
):
    """Deals `batches` to the actors (Ray runs); adds each returned manifest row to `done` as it arrives."""
    import ray
    from ray.util import ActorPool

    threads = max(1, local_cores() // workers) if address is None else 1
    actors = [
        _worker_class().remote(map_path, city, config, str(out.resolve()), threads, terrain) for _ in range(workers)
    ]
    processes = [actor.process.remote() for actor in actors]
    try:
        if on_workers is not None:
            on_workers([pid for _, pid in ray.get(processes)])
        last = time.monotonic()
        with show_progress(f"dataset {out.name}", samples, len(done), progress) as advance:
            for rows in ActorPool(actors).map_unordered(lambda actor, batch: actor.write.remote(batch), batches):
                done.update({row["index"]: row for row in rows})
                advance(len(rows))
                if time.monotonic() - last > MANIFEST_EVERY:
                    write_manifest(out, list(done.values()))
                    last = time.monotonic()
    except ray.exceptions.RayError as exc:  # an actor that cannot start or render: say why, in one line
        raise CityshadeError(
            f"a dataset worker failed: {_last_line(exc)}; {len(done)} complete samples are kept, --resume continues"
        ) from None
    finally:
        _stop_actors(actors, processes)
