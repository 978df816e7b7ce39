"""`cityshade dataset`: labelled renders of a map or a built-in city, on Ray (docs/datasets.md)."""

from __future__ import annotations

from pathlib import Path

from ..errors import UsageError
from .arguments import add_map_option, add_terrain_option


def register(subparsers):
    parser = subparsers.add_parser("dataset", help="labelled renders (RGB, depth, normals, classes, instances) on Ray")
    add_map_option(parser)
    add_terrain_option(parser)
    parser.add_argument("--city", default=None, metavar="NAME", help="a built-in city with streets: default")
    parser.add_argument("--samples", type=int, default=None, metavar="N", help="number of samples")
    parser.add_argument("--out", type=Path, default=None, metavar="DIR", help="dataset folder")
    parser.add_argument("--config", type=Path, default=None, metavar="FILE.toml", help="settings (docs/datasets.md)")
    parser.add_argument("--workers", type=int, default=1, metavar="K", help="Ray actors, one renderer each")
    parser.add_argument(
        "--address", default=None, help="join this Ray cluster (host:port or auto) instead of starting a local runtime"
    )
    parser.add_argument("--seed", type=int, default=0, metavar="S", help="views, dates and times follow from it")
    parser.add_argument("--resume", action="store_true", help="complete a dataset folder made with the same settings")
    parser.add_argument(
        "--shards",
        type=int,
        default=None,
        metavar="SAMPLES",
        help="also write WebDataset tar shards of SAMPLES samples each to DIR/shards/",
    )
    parser.add_argument(
        "--classes",
        choices=("native", "cityscapes"),
        default=None,
        help="cityscapes: also Cityscapes labelIds/trainIds images (config output.classes)",
    )
    parser.add_argument(
        "--panoptic", action="store_true", help="also COCO panoptic PNGs in DIR/panoptic/ and DIR/panoptic.json"
    )
    parser.add_argument("--path", default=None, choices=("walk", "orbit"), help="consecutive views along a path")
    parser.add_argument("--frames", type=int, default=None, metavar="N", help="with --path: the number of views")
    parser.add_argument(
        "--preview",
        type=Path,
        default=None,
        metavar="DIR",
        help="write DIR/preview.png: samples of the dataset in DIR with their labels over them",
    )
    parser.set_defaults(run=run)


def run(args) -> int:
    from dataclasses import replace

    from ..dataset import load_config

    if (args.path is None) != (args.frames is None):
        raise UsageError("give --path walk|orbit with --frames N")
    if args.path is not None:
        if args.samples is not None:
            raise UsageError("give --frames N with --path, not --samples")
        args.samples = args.frames
    generating = args.samples is not None or args.out is not None or args.map is not None or args.city is not None
    if generating:
        if (args.map is None) == (args.city is None):
            raise UsageError("give one of --map FILE or --city NAME")
        if args.samples is None or args.out is None:
            raise UsageError("give --samples N and --out DIR")
        if args.shards is not None and args.shards < 1:
            raise UsageError(f"--shards {args.shards}: give the number of samples per shard, at least 1")
        config = load_config(args.config)
        if args.classes is not None:
            config = replace(config, classes=args.classes)
        if args.panoptic:
            config = replace(config, panoptic=True)
        from ..dataset import generate

        rows = generate(
            args.out,
            args.samples,
            config,
            args.map,
            args.city,
            args.workers,
            args.address,
            args.seed,
            args.resume,
            path=args.path,
            terrain=args.terrain,
        )
        print(f"wrote {args.out}: {len(rows)} samples listed in {args.out / 'manifest.parquet'}")
        if args.shards is not None:
            from ..dataset import write_shards

            print(f"wrote {len(write_shards(args.out, args.shards))} shards to {args.out / 'shards'}")
    elif args.preview is None or args.shards is not None:
        raise UsageError(
            "give --map FILE or --city NAME with --samples N --out DIR [--shards SAMPLES], or --preview DIR"
        )
    if args.preview is not None:
        from ..dataset import write_preview

        print(f"wrote {write_preview(args.preview)}")
    return 0
