"""`cityshade bench NAME [--quick] [--json PATH]`: each benchmark module exposes `run(args) -> BenchResult`."""

from __future__ import annotations

import importlib
from pathlib import Path

from .._files import output_folder, output_target
from ..bench import write
from ..errors import UsageError

# benchmark name -> module with run(quick: bool) -> BenchResult
BENCHMARKS = {
    "interior": "cityshade.bench.interior",
    "relief": "cityshade.bench.relief",
    "facades": "cityshade.bench.facades",
    "trees": "cityshade.bench.trees",
    "guesses": "cityshade.bench.guesses",
    "osm": "cityshade.bench.osm",
    "export": "cityshade.bench.export",
    "dataset": "cityshade.bench.dataset",
    "scale": "cityshade.bench.scale",
    "lod": "cityshade.bench.lod",
    "cityjson": "cityshade.bench.cityjson",
}


def register(subparsers):
    parser = subparsers.add_parser("bench", help="reproduce a paper's experiment and compare with its figures")
    parser.add_argument("name", choices=sorted(BENCHMARKS), help="which experiment")
    parser.add_argument("--quick", action="store_true", help="smaller scenes and fewer frames (under a minute)")
    parser.add_argument("--json", type=Path, default=None, metavar="PATH", help="also write the JSON here")
    parser.add_argument("--out-dir", type=Path, default=Path("bench-results"), help="folder for JSON, Markdown, plots")
    parser.add_argument(
        "--map", type=Path, default=None, metavar="FILE", help="guesses: the map whose tagged buildings to measure"
    )
    parser.set_defaults(run=_run)


def _run(args):
    if args.map is not None and args.name != "guesses":
        raise UsageError(f"--map {args.map}: only `bench guesses` measures a map of your choice")
    output_folder(args.out_dir)  # refused before minutes of measuring, not after
    if args.json is not None:
        output_target(args.json)
    module = importlib.import_module(BENCHMARKS[args.name])
    extra = {"map_path": args.map} if args.map is not None else {}
    result = module.run(quick=args.quick, out_dir=args.out_dir, **extra)
    write(result, args.out_dir, args.json)
    return 0
