"""`cityshade bench dataset`: samples per second of `cityshade dataset` on 1 and 2 Ray workers, and
what the outputs beyond RGB cost.

- samples_per_second_{1,2}_workers: the Helsinki extract (or the built-in district without it),
  SAMPLES views through a local Ray runtime with 1 and then 2 actors; timed from the moment every
  actor has loaded the city and made its renderer (Ray's start and the loads are reported apart)
  to the last manifest row. Each worker's llvmpipe gets cpu_count / workers threads.
- workers_2_over_1_throughput: the second over the first (target >= 1.5).
- all_outputs_over_rgb_time: in one process, the median time of a sample's full work (frame, id
  AOV, depth, normals, classes, instances, the files written) over the frame alone (target <= 1.5).
"""

from __future__ import annotations

import os
import statistics
import tempfile
import time
from pathlib import Path

from ..dataset import SampleRenderer, generate, load_source, parse_config, sample_view
from ._harness import BenchResult

HELSINKI = Path(__file__).resolve().parents[3] / "data" / "Helsinki.osm.pbf"
SEED = 3


def _throughput(out: Path, samples: int, config, workers: int, map_path, city) -> tuple[float, float]:
    """(seconds until every actor is ready, samples per second after that)."""
    marks = {}
    start = time.perf_counter()
    generate(
        out,
        samples,
        config,
        map_path,
        city,
        workers=workers,
        seed=SEED,
        progress=False,
        on_workers=lambda pids: marks.setdefault("ready", time.perf_counter()),
    )
    end = time.perf_counter()
    return marks["ready"] - start, samples / (end - marks["ready"])


def _output_cost(source, config, views: int) -> tuple[float, float]:
    """Median seconds of the frame alone and of the full sample, over the same views (after a warm-up)."""
    sampler = SampleRenderer(source, config)
    rgb, full = [], []
    try:
        with tempfile.TemporaryDirectory() as folder:
            chosen = [sample_view(i, SEED, config, source.streets, source.has_date) for i in range(views + 1)]
            sampler.write(chosen[0], Path(folder))  # compiles the programs
            for view in chosen[1:]:
                start = time.perf_counter()
                sampler.render(view, outputs=False)
                rgb.append(time.perf_counter() - start)
                start = time.perf_counter()
                sampler.write(view, Path(folder))
                full.append(time.perf_counter() - start)
    finally:
        sampler.release()
    return statistics.median(rgb), statistics.median(full)


def run(quick: bool = False, out_dir: Path | None = None) -> BenchResult:
    map_path, city = (HELSINKI, None) if HELSINKI.exists() else (None, "default")
    size = (160, 120) if quick else (320, 240)
    samples = 16 if quick else 64
    config = parse_config({"image": {"width": size[0], "height": size[1]}, "run": {"batch": 2}})
    result = BenchResult("dataset", f"llvmpipe, {os.cpu_count()} CPUs, local Ray")
    rows, rates = [], {}
    with tempfile.TemporaryDirectory() as folder:
        for workers in (1, 2):
            ready, rate = _throughput(Path(folder) / f"w{workers}", samples, config, workers, map_path, city)
            rates[workers] = rate
            rows.append([workers, samples, round(ready, 2), round(rate, 3)])
    result.add_table(
        f"{map_path.name if map_path else 'district'}: {samples} samples of {size[0]}x{size[1]}",
        ["workers", "samples", "start-up s", "samples/s"],
        rows,
    )
    rgb, full = _output_cost(load_source(map_path, city), config, 3 if quick else 8)
    result.add_table(
        "one sample's work (median)",
        ["work", "ms"],
        [["frame (RGB) only", round(rgb * 1000, 1)], ["all outputs, files written", round(full * 1000, 1)]],
    )
    result.ratios = {"workers_2_over_1_throughput": rates[2] / rates[1], "all_outputs_over_rgb_time": full / rgb}
    result.targets = {"workers_2_over_1_throughput": ">= 1.5", "all_outputs_over_rgb_time": "<= 1.5"}
    result.notes.append(
        f"{os.cpu_count()} CPUs shared with whatever else runs; llvmpipe threads per worker = cpu_count / workers"
    )
    return result
