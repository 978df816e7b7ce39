"""`cityshade grammar check FILE...` and `cityshade grammar render FILE ...`."""

from __future__ import annotations

import sys
from pathlib import Path

from ..grammar import FACADE_INDICES, GrammarError


def register(subparsers):
    parser = subparsers.add_parser("grammar", help="check or render facade grammar files")
    commands = parser.add_subparsers(dest="grammar_command", required=True, metavar="ACTION")
    check = commands.add_parser("check", help="check grammar files; errors as FILE:LINE:COL: error: ...")
    check.add_argument("files", nargs="+", type=Path, metavar="FILE")
    check.set_defaults(run=_check)
    from .arguments import check_count, check_seed, parse_metres, parse_size

    render = commands.add_parser("render", help="render one facade (GPU, or the numpy evaluator with --cpu)")
    render.add_argument("file", type=Path, metavar="FILE")
    render.add_argument("--rule", default=None, help="start rule (default: the file's first rule)")
    render.add_argument(
        "--facade", type=parse_metres, default=(20.0, 16.0), metavar="WxH", help="facade size in metres"
    )
    render.add_argument("--seed", type=check_seed, default=0, help="the facade's random seed, 0 to 2^31-1")
    for option, default, meaning in (
        ("--levels", None, "building.levels for conditions (default: the facade height / 3.2 m, rounded)"),
        ("--level", 0, "facade.level for conditions: the storey the facade starts at (0: the ground)"),
        ("--style", 0, "building.style for conditions"),
    ):
        render.add_argument(
            option, type=lambda v, o=option: check_count(v, o), default=default, metavar="N", help=meaning
        )
    from ..scene import USES

    render.add_argument(
        "--use",
        choices=list(USES),
        default="mixed",
        help="building.use for conditions (building.height is the facade's height)",
    )
    render.add_argument(
        "--face",
        type=int,
        choices=range(FACADE_INDICES),
        default=0,
        metavar="K",
        help=f"which facade of the building, 0 to {FACADE_INDICES - 1} (in the city: its face's "
        "first room column): each has its own random stream",
    )
    render.add_argument("--size", type=parse_size, default=(640, 512), metavar="WxH", help="image size in pixels")
    render.add_argument("--cpu", action="store_true", help="use the numpy reference evaluator")
    render.add_argument("--out", type=Path, default=Path("out/facade.png"), metavar="PNG")
    render.add_argument("--labels", type=Path, default=None, metavar="PNG", help="also write the label image")
    render.set_defaults(run=_render)

    imports = commands.add_parser("import", help="translate a CityEngine CGA rule file (its facade subset)")
    imports.add_argument("file", type=Path, metavar="FILE.cga")
    imports.add_argument(
        "--out", type=Path, default=None, metavar="FILE.grammar", help="write the grammar here (default: print it)"
    )
    imports.set_defaults(run=_import)


def _check(args) -> int:
    from ..grammar import compile_grammars, load

    failed = False
    for path in args.files:
        try:
            grammar = load(path)
            compiled = compile_grammars({str(path): grammar})
        except GrammarError as exc:
            print(str(exc), file=sys.stderr)
            failed = True
            continue
        print(
            f"{path}: ok, {len(grammar.rules)} rules, {compiled.used} texels ({compiled.nbytes} bytes), "
            f"start rule {grammar.start}"
        )
    return 1 if failed else 0


def _import(args) -> int:
    """Translates, lists what was not translated (FILE:LINE: what: instead) and checks the result."""
    from .._files import atomic_output, read_input_bytes
    from ..grammar import CgaError, loads, translate
    from .arguments import check_writable

    if args.out is not None:
        check_writable(args.out)
    data = read_input_bytes(args.file, 1 << 20, "CGA file")
    try:
        text = data.decode("utf-8-sig")
    except UnicodeDecodeError:
        raise CgaError(f"{args.file}: error: the file is not UTF-8 text; save the rules as UTF-8") from None
    if "\0" in text:
        raise CgaError(f"{args.file}: error: this is a binary file, not CGA rules")
    translation = translate(text, str(args.file))
    name = args.out.name if args.out is not None else args.file.with_suffix(".grammar").name
    header = f"# Translated from {args.file.name} by cityshade grammar import.\n"
    grammar_text = header + translation.text
    for note in translation.notes:
        print(note.format(str(args.file)), file=sys.stderr)
    try:
        loads(grammar_text, name)  # a translation that does not check is reported, and not written
    except GrammarError as exc:
        raise CgaError(
            f"{args.file}: error: the translation does not check (recursive rules, or arguments "
            f"that do not match a rule's parameters, cannot be translated); nothing was written:\n"
            f"{exc}"
        ) from None
    print(
        f"{args.file}: {len(translation.notes)} construct{'s' * (len(translation.notes) != 1)} not translated "
        "as written (listed above)",
        file=sys.stderr,
    )
    if args.out is None:
        sys.stdout.write(grammar_text)
        return 0
    with atomic_output(args.out) as tmp:
        tmp.write_text(grammar_text, encoding="utf-8")
    print(f"wrote {args.out}", file=sys.stderr)
    return 0


def _render(args) -> int:
    import numpy as np

    from .._budget import check_image_memory
    from ..assets import LABEL_COLOURS, tile_array
    from ..grammar import CPU_BYTES_PER_PIXEL, compile_grammars, evaluate_facade, facade_seed_vector, load, seed_vector
    from ..scene import USES
    from .arguments import check_writable, save_png

    for path in (args.out, args.labels):
        if path is not None:
            check_writable(path)
    try:
        grammar = load(args.file)
        grammar.rule(args.rule)
        compiled = compile_grammars({"g": grammar})
    except GrammarError as exc:
        print(str(exc), file=sys.stderr)
        return exc.exit_code
    start = compiled.address("g", args.rule)
    levels = args.levels if args.levels is not None else max(1, round(args.facade[1] / 3.2))
    building = (levels, args.style, USES[args.use], args.facade[1])
    tiles = tile_array(128)
    if args.cpu:
        check_image_memory(args.size, CPU_BYTES_PER_PIXEL, "grammar render --cpu")
        result = evaluate_facade(
            compiled,
            start,
            args.facade,
            args.size,
            facade_seed_vector(args.seed, args.face),
            tiles,
            building,
            seed_vector(args.seed),
            args.level,
        )
        colour, labels = result.color, result.label
    else:
        from ..gl import create_context
        from ..grammar import FacadeRenderer, GrammarTextures

        ctx = create_context()
        renderer = FacadeRenderer(ctx, GrammarTextures(ctx, compiled, tiles))
        colour, ids = renderer.render(
            start, args.facade, args.size, seed_vector(args.seed), building, args.face, args.level
        )
        colour, labels = colour[..., :3], ids[..., 1]
    save_png((np.clip(colour, 0, 1) * 255 + 0.5).astype(np.uint8), args.out)
    if args.labels is not None:
        save_png(np.asarray(LABEL_COLOURS, np.uint8)[labels.astype(np.int64)], args.labels)
    print(f"wrote {args.out}" + (f" and {args.labels}" if args.labels else ""))
    return 0
