"""One benchmark harness: warm-up, median of many frames, side-by-side ratios, one output format.

Every benchmark returns a BenchResult; `write` prints its table beside the paper's figures and
writes JSON, Markdown and (optionally) a PNG plot to the output folder.
"""

from __future__ import annotations

import json
import os
import platform
from dataclasses import dataclass, field
from pathlib import Path

from rich.console import Console
from rich.table import Table

from .._files import output_folder, write_text


@dataclass
class BenchResult:
    name: str
    device: str
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
            "tables": self.tables,
            "ratios": self.ratios,
            "targets": self.targets,
            "notes": self.notes,
            "plots": self.plots,
        }

    def to_markdown(self) -> str:
        out = [f"# bench {self.name}", "", f"Device: {self.device}", ""]
        for table in self.tables:
            out += [f"## {table['title']}", "", "| " + " | ".join(table["columns"]) + " |",
                    "|" + "---|" * len(table["columns"])]
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
    output_folder(out_dir).mkdir(parents=True, exist_ok=True)
    payload = json.dumps(result.to_json(), indent=2)
    write_text(out_dir / f"{result.name}.json", payload)
    write_text(out_dir / f"{result.name}.md", result.to_markdown())
    if json_path is not None:
        write_text(json_path, payload)
    console.print(f"wrote {out_dir / (result.name + '.json')}, {out_dir / (result.name + '.md')}"
                  + "".join(f", {p}" for p in result.plots))
