"""One benchmark harness: one timer, side-by-side ratios, one output format.

`time_interleaved` times every method of a comparison in one loop, taking turns frame by frame,
so a change in the load of a shared machine falls on all of them alike; each point keeps every
timed frame, and tables show the median and the interquartile range. Every benchmark returns a
BenchResult that records how it timed (`timing`) and what each method ran with (`methods`);
`write` prints its tables beside the paper's figures and writes JSON, Markdown and (optionally) a
PNG plot to the output folder.
"""

from __future__ import annotations

import json
import os
import platform
import time
from collections.abc import Callable
from dataclasses import dataclass, field
from pathlib import Path

import numpy as np
from rich.console import Console
from rich.table import Table

from .._files import output_folder, write_text

MIN_TIMED_FRAMES = 9  # per point, after warm-up: enough for a median and quartiles


@dataclass(frozen=True)
class Timing:
    """Seconds per frame of one method at one point: every timed frame."""

    samples: tuple[float, ...]

    @property
    def median(self) -> float:
        return float(np.median(self.samples))

    @property
    def iqr(self) -> float:
        q1, q3 = np.percentile(self.samples, [25, 75])
        return float(q3 - q1)

    def ms(self) -> list[float]:
        """[median, interquartile range] in milliseconds, for a table row."""
        return [round(self.median * 1e3, 2), round(self.iqr * 1e3, 2)]


def time_interleaved(ctx, draws: dict[str, Callable[[int], None]], frames: int, warmup: int = 1) -> dict[str, Timing]:
    """Calls every draw(frame_index) `warmup` times, then `frames` timed times, the draws taking
    turns frame by frame; each frame ends with ctx.finish() (GPU timer queries mean little on a
    software rasteriser)."""
    for i in range(warmup):
        for draw in draws.values():
            draw(i)
    ctx.finish()
    samples: dict[str, list[float]] = {name: [] for name in draws}
    for k in range(frames):
        for name, draw in draws.items():
            start = time.perf_counter()
            draw(warmup + k)
            ctx.finish()
            samples[name].append(time.perf_counter() - start)
    return {name: Timing(tuple(values)) for name, values in samples.items()}


def timing_record(frames: int, warmup: int = 1) -> dict:
    """The `timing` entry of a result timed with time_interleaved."""
    return {
        "samples_per_point": frames,
        "interleaved": True,
        "warmup_frames": warmup,
        "statistic": "median; spread: interquartile range (q3 - q1)",
    }


def method_record(
    *, cull_back_faces: bool, depth_prepass: bool, frustum_culling: bool, msaa: int, size: tuple[int, int], **more
) -> dict:
    """What one compared method ran with, for the result's `methods`."""
    return {
        "cull_back_faces": cull_back_faces,
        "depth_prepass": depth_prepass,
        "frustum_culling": frustum_culling,
        "msaa": int(msaa),
        "size": [int(size[0]), int(size[1])],
        **more,
    }


@dataclass
class BenchResult:
    name: str
    device: str
    timing: dict = field(default_factory=dict)  # timing_record(...)
    methods: dict[str, dict] = field(default_factory=dict)  # method name -> method_record(...)
    tables: list[dict] = field(default_factory=list)  # {"title", "columns", "rows"}
    ratios: dict[str, float] = field(default_factory=dict)
    targets: dict[str, str] = field(default_factory=dict)  # ratio name -> target text, e.g. "<= 1.02"
    notes: list[str] = field(default_factory=list)
    plots: list[str] = field(default_factory=list)

    def add_table(self, title: str, columns: list[str], rows: list[list]):
        self.tables.append({"title": title, "columns": columns, "rows": rows})

    def to_json(self) -> dict:
        return {
            "benchmark": self.name,
            "device": self.device,
            "machine": {"platform": platform.platform(), "cpus": os.cpu_count()},
            "timing": self.timing,
            "methods": self.methods,
            "tables": self.tables,
            "ratios": self.ratios,
            "targets": self.targets,
            "notes": self.notes,
            "plots": self.plots,
        }

    def to_markdown(self) -> str:
        out = (
            [
                f"# bench {self.name}",
                "",
                f"Device: {self.device}",
                "",
                f"Timing: {json.dumps(self.timing)}",
                "",
                "## Methods",
                "",
            ]
            + [f"- {name}: {json.dumps(record)}" for name, record in self.methods.items()]
            + [""]
        )
        for table in self.tables:
            out += [
                f"## {table['title']}",
                "",
                "| " + " | ".join(table["columns"]) + " |",
                "|" + "---|" * len(table["columns"]),
            ]
            out += ["| " + " | ".join(_fmt(v) for v in row) + " |" for row in table["rows"]]
            out.append("")
        out += ["## Ratios", "", "| ratio | value | target |", "|---|---|---|"]
        out += [f"| {k} | {_fmt(v)} | {self.targets.get(k, '')} |" for k, v in self.ratios.items()]
        out += [""] + [f"- {n}" for n in self.notes]
        return "\n".join(out) + "\n"


def _fmt(value) -> str:
    if isinstance(value, float):
        return f"{value:.4g}"
    return str(value)


def write(result: BenchResult, out_dir: Path, json_path: Path | None = None, console: Console | None = None):
    """Prints the result and writes bench-results/NAME.{json,md} (and the JSON at json_path if given)."""
    console = console or Console()
    for table in result.tables:
        view = Table(title=table["title"])
        for column in table["columns"]:
            view.add_column(column)
        for row in table["rows"]:
            view.add_row(*(_fmt(v) for v in row))
        console.print(view)
    ratios = Table(title=f"{result.name}: ratios (device: {result.device})")
    for column in ("ratio", "value", "target"):
        ratios.add_column(column)
    for key, value in result.ratios.items():
        ratios.add_row(key, _fmt(value), result.targets.get(key, ""))
    console.print(ratios)
    for note in result.notes:
        console.print(f"- {note}")
    console.print(f"timing: {json.dumps(result.timing)}")
    for name, record in result.methods.items():
        console.print(f"method {name}: {json.dumps(record)}")
    output_folder(out_dir).mkdir(parents=True, exist_ok=True)
    payload = json.dumps(result.to_json(), indent=2)
    write_text(out_dir / f"{result.name}.json", payload)
    write_text(out_dir / f"{result.name}.md", result.to_markdown())
    if json_path is not None:
        write_text(json_path, payload)
    console.print(
        f"wrote {out_dir / (result.name + '.json')}, {out_dir / (result.name + '.md')}"
        + "".join(f", {p}" for p in result.plots)
    )
