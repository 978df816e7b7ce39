"""`cityshade compress`: factorise a facade's detail maps into a .cfdm file, inspect or verify one."""

from __future__ import annotations

import math
import time
from pathlib import Path

import numpy as np
from rich.console import Console
from rich.progress import Progress

from .._files import output_target
from ..errors import CityshadeError, Finding, UsageError
from ..relief import (
    DEPTH_UNIT,
    MAP_NAMES,
    MAX_TERMS,
    METHODS,
    PAPER_FACADES,
    PAPER_TEXEL,
    DetailMaps,
    check_facade_texels,
    compress,
    detail_matrices,
    digest,
    generate_facade,
    grammar_maps,
    load_png_maps,
    read_compressed,
    write_compressed,
)
from .arguments import check_seed, parse_metres


def register(subparsers):
    parser = subparsers.add_parser(
        "compress",
        help="compress a facade's relief maps (SVD or binary factorisation) into a .cfdm file",
        description="Compress facade detail maps (depth D, material M, free-box acceleration A) losslessly, "
        "or inspect (--stats) or check (--verify) a compressed file.",
    )
    source = parser.add_argument_group("source (one of)")
    source.add_argument(
        "grammar",
        nargs="?",
        type=Path,
        metavar="GRAMMAR_FILE",
        help="a facade grammar, rasterised with a depth and material per terminal label",
    )
    source.add_argument(
        "--layout",
        choices=sorted(PAPER_FACADES),
        help="one of the four test facades of the paper, from the built-in layout generator",
    )
    source.add_argument(
        "--height",
        type=Path,
        metavar="PNG",
        help="16- or 8-bit greyscale PNG of depth steps behind the outermost surface",
    )
    source.add_argument("--material", type=Path, metavar="PNG", help="8- or 16-bit greyscale PNG of material indices")
    parser.add_argument("--rule", help="with GRAMMAR_FILE: the start rule (default: the file's first)")
    parser.add_argument("--seed", type=check_seed, help="with GRAMMAR_FILE: the facade's random seed (default 1)")
    parser.add_argument(
        "--facade",
        metavar="WxH",
        help="facade size in metres (GRAMMAR_FILE: default 12x16; --layout: default the paper's)",
    )
    parser.add_argument("--texel", type=float, metavar="METRES", help=f"texel size (default {PAPER_TEXEL})")
    parser.add_argument(
        "--depth-unit",
        type=float,
        metavar="METRES",
        help=f"with --height: metres per depth step of the height image (default {DEPTH_UNIT})",
    )
    parser.add_argument("--method", choices=METHODS, help="factorisation (default bmf)")
    parser.add_argument("--max-terms", type=int, help=f"refuse maps needing more terms than this (default {MAX_TERMS})")
    parser.add_argument("--out", type=Path, metavar="FILE", help="the .cfdm file to write")
    parser.add_argument("--stats", type=Path, metavar="FILE", help="print sizes, terms and bytes of a .cfdm file")
    parser.add_argument(
        "--verify",
        type=Path,
        metavar="FILE",
        help="decompress on the CPU and compare with the maps it was made from "
        "(or with --height/--material); exit 1 on any mismatch or damage",
    )
    parser.set_defaults(run=_run)


# Options that only some uses of the command read; given anywhere else they would do nothing.
SOURCE_OPTIONS = (
    ("GRAMMAR_FILE", "grammar"),
    ("--layout", "layout"),
    ("--height", "height"),
    ("--material", "material"),
)
MAKING_OPTIONS = (
    ("--rule", "rule"),
    ("--seed", "seed"),
    ("--facade", "facade"),
    ("--texel", "texel"),
    ("--depth-unit", "depth_unit"),
    ("--method", "method"),
    ("--max-terms", "max_terms"),
)
DEFAULTS = {"seed": 1, "texel": PAPER_TEXEL, "depth_unit": DEPTH_UNIT, "method": "bmf", "max_terms": MAX_TERMS}


def _check_arguments(args):
    """Refuses values out of range and options given where they would do nothing, then fills in
    the defaults."""
    for option, value in (("--texel", args.texel), ("--depth-unit", args.depth_unit)):
        if value is not None and not (math.isfinite(value) and value > 0):
            raise UsageError(f"invalid {option} {value:g}; it must be a positive number of metres")
    if args.max_terms is not None and not 1 <= args.max_terms <= MAX_TERMS:
        raise UsageError(f"invalid --max-terms {args.max_terms}; it must be from 1 to {MAX_TERMS}")

    def given(options):
        return [name for name, field in options if getattr(args, field) is not None]

    uses = given((("--out", "out"), ("--stats", "stats"), ("--verify", "verify")))
    if len(uses) > 1:
        raise UsageError(f"{' and '.join(uses)} cannot be combined; give one of --out, --stats or --verify")
    if args.stats is not None and given(SOURCE_OPTIONS + MAKING_OPTIONS):
        raise UsageError(f"--stats reads only its file; drop {', '.join(given(SOURCE_OPTIONS + MAKING_OPTIONS))}")
    if args.verify is not None and given((("--method", "method"), ("--max-terms", "max_terms"))):
        raise UsageError("--verify decompresses the file as it was made; drop --method and --max-terms")
    if args.grammar is None and given((("--rule", "rule"), ("--seed", "seed"))):
        raise UsageError(f"{' and '.join(given((('--rule', 'rule'), ('--seed', 'seed'))))} go with GRAMMAR_FILE")
    images = args.height is not None or args.material is not None
    if images and args.facade is not None:
        raise UsageError("--facade sizes a GRAMMAR_FILE or --layout facade; the images give their own size")
    if args.depth_unit is not None and not images:
        raise UsageError("--depth-unit goes with --height and --material (the depth steps of the height image)")
    for field, value in DEFAULTS.items():
        if getattr(args, field) is None:
            setattr(args, field, value)


def _run(args) -> int:
    _check_arguments(args)
    if args.stats:
        return _stats(args.stats)
    if args.verify:
        return _verify(args)
    if args.out is None:
        raise UsageError("compress needs --out FILE (or --stats FILE / --verify FILE)")
    output_target(args.out)  # refused before the factorisation, not after
    maps = _source_maps(args, required=True)
    console = Console(stderr=True)
    started = time.perf_counter()
    with Progress(console=console, transient=True) as progress:
        task = progress.add_task(f"{args.method.upper()} {maps.shape[1]}x{maps.shape[0]}", total=1 + len(MAP_NAMES))
        facade = compress(
            maps, args.method, args.max_terms, on_map=lambda _: progress.advance(task), source=_source_name(args)
        )
    write_compressed(args.out, facade)
    sizes = facade.nbytes()
    print(
        f"wrote {args.out}: {sum(sizes.values()) / 1024:.1f} KB ({args.method}, terms "
        + ", ".join(f"{n} {facade.factors[n].terms}" for n in MAP_NAMES)
        + f") in {time.perf_counter() - started:.2f} s"
    )
    return 0


def _source_maps(args, required: bool) -> DetailMaps | None:
    images = args.height is not None or args.material is not None
    if sum((args.grammar is not None, args.layout is not None, images)) > 1:
        raise UsageError("give one source: GRAMMAR_FILE, --layout NAME, or --height and --material")
    if args.grammar is not None:
        return _grammar(args)
    if images:
        if args.height is None or args.material is None:
            raise UsageError("--height and --material go together")
        return load_png_maps(args.height, args.material, args.texel, args.depth_unit)
    if args.layout:
        cols, rows, layout = PAPER_FACADES[args.layout]
        if args.facade:
            width, height = parse_metres(args.facade, limit=1000.0)
            cols, rows = max(1, round(width / args.texel)), max(1, round(height / args.texel))
        check_facade_texels(cols, rows, f"--facade {args.facade or args.layout}", args.texel)
        return generate_facade(cols, rows, layout, args.texel)
    if required:
        raise UsageError("give a source: GRAMMAR_FILE, --layout NAME, or --height PNG --material PNG")
    return None


def _grammar(args) -> DetailMaps:
    facade = parse_metres(args.facade or "12x16", limit=1000.0)
    cols, rows = max(1, round(facade[0] / args.texel)), max(1, round(facade[1] / args.texel))
    check_facade_texels(cols, rows, f"--facade {args.facade or '12x16'}", args.texel)
    with Progress(console=Console(stderr=True), transient=True) as progress:
        task = progress.add_task(f"rasterising {args.grammar.name}", total=rows)
        return grammar_maps(
            args.grammar, args.rule, facade, args.texel, args.seed, on_rows=lambda n: progress.advance(task, n)
        )


def _source_name(args) -> str:
    if args.grammar is not None:
        return str(args.grammar)
    return f"layout {args.layout}" if args.layout else f"{args.height} + {args.material}"


def _stats(path: Path) -> int:
    facade = read_compressed(path)
    rows, cols = facade.shape
    raw = facade.raw_nbytes()
    sizes = facade.nbytes()
    print(
        f"{path}: {cols}x{rows} texels of {facade.texel} m, depth unit {facade.depth_unit} m, "
        f"method {facade.method}, {len(facade.boxes)} free boxes, file {path.stat().st_size} bytes"
    )
    print(f"{'map':<10}{'terms':>7}{'bytes':>12}{'raw bytes':>12}{'ratio':>8}")
    for name in MAP_NAMES:
        print(
            f"{name:<10}{facade.factors[name].terms:>7}{sizes[name]:>12}{raw[name]:>12}{raw[name] / sizes[name]:>8.1f}"
        )
    total, total_raw = sum(sizes.values()), sum(raw.values())
    print(f"{'total':<10}{'':>7}{total:>12}{total_raw:>12}{total_raw / total:>8.1f}")
    return 0


def _verify(args) -> int:
    facade = read_compressed(args.verify)
    decoded = facade.decompress()
    maps = _source_maps(args, required=False)
    if maps is not None:
        if maps.shape != facade.shape:
            raise CityshadeError(
                f"{args.verify} is {facade.shape[1]}x{facade.shape[0]} texels but the images are "
                f"{maps.shape[1]}x{maps.shape[0]}"
            )
        expected, _ = detail_matrices(maps)
        bad = [n for n in MAP_NAMES if not np.array_equal(decoded[n], expected[n])]
        against = "the given images"
    else:
        bad = [n for n in MAP_NAMES if digest(decoded[n]) != facade.digests[n]]
        against = "the maps it was made from"
    if bad:
        raise Finding(f"{args.verify}: decompressed {', '.join(bad)} differ from {against}")
    print(f"{args.verify}: ok, D, M and A decompress exactly to {against}")
    return 0
