"""GPU evaluator (shaders/grammar/eval.glsl) against the numpy twin, pixel by pixel, per operator."""

from __future__ import annotations

import numpy as np
import pytest

from cityshade.assets import LABELS, tile_array
from cityshade.grammar import (
    FacadeRenderer,
    GrammarTextures,
    compile_grammars,
    evaluate,
    evaluate_facade,
    library_path,
    load,
    loads,
    seed_vector,
)
from cityshade.grammar.testing import facade_view
from cityshade.scene import USES
from grammar_compare import FACADE, SIZE, compare, ctx  # noqa: F401  (ctx is a fixture)

pytestmark = pytest.mark.gl  # renders or opens a context of its own, not only through gl_context


def colours(*names: str) -> str:
    """Constant-colour terminals, one per name, so every scope has its own id."""
    rng = np.random.default_rng(len(names))
    return "".join(
        f"{n}->Mat(Color, 0, {r:.3f}, {g:.3f}, {b:.3f}, 1)\n"
        for n, (r, g, b) in zip(names, rng.uniform(0.1, 0.9, (len(names), 3)))
    )


CASES = {
    "split": "S->SplitX(Abs, 2.5, A, Rel, 1, Col, Rel, 2, B, Abs, 1.2, C)\n"
    "Col->SplitY(Rel, 1, D, Abs, 3, E, Rel, 0.5, F)\n" + colours(*"ABCDEF"),
    "repeat": "S->RepeatX(1.7, Col)\nCol->RepeatY(2.3, Cell)\nCell->SplitX(Rel, 1, A, Rel, 1, B)\n" + colours("A", "B"),
    "repeat_ceil": "S->RepeatX(1.7, Col, Ceil)\nCol->RepeatY(2.3, Cell, Ceil)\nCell->SplitX(Rel, 1, A, Rel, 1, B)\n"
    + colours("A", "B"),
    "split_tile": "S->SplitX(Rel, 1, A, Tile, 2.2, Bay, Abs, 1.5, C, Rel, 0.5, D)\n"
    "Bay->SplitY(Abs, 2, E, Tile, 1.3, Row, Rel, 1, F)\nRow->SplitX(Rel, 1, G, Rel, 1, H)\n" + colours(*"ACDEFGH"),
    "case": "S->SplitY(Abs, 2, Ground, Tile, 3, Floor, Rel, 1, Roof)\nFloor->RepeatX(2.5, Bay)\n"
    "Bay->Case(split.first || split.last, A, split.index % 2 == 0 && scope.sx > 2.4, B, !(split.index < 3), C, D)\n"
    "Ground->Case(facade.width >= 16, E, F)\nRoof->Case(-scope.sy + 1 > 0, G, split.total / 0.5 == 2 * 3, H, A)\n"
    + colours(*"ABCDEFGH"),
    "rand_sizes": "S->SplitY(Abs, rand(2, 4), Ground, Rel, 1, Upper)\nUpper->RepeatY(rand(2.5, 3.5), Floor)\n"
    "Floor->SplitX(Rel, rand(1, 3), A, Abs, rand(0.5, 2), B, Rel, 1, C, Tile, 2, D)\n"
    + colours(*"ABCD")
    + "Ground->RepeatX(rand(1, 4), Shop, Ceil)\nShop->SplitX(Rel, 1, E, Rel, 1, F)\n"
    + colours("E", "F"),
    "params": "S->RepeatY(3, Floor(split.index, split.total))\nFloor(level, count)->RepeatX(2.5, Bay(level, split.index))\n"
    "Bay(level, column)->Case(level == 0, E, (level + column) % 2 == 0, A, Upper(level))\n"
    "Upper(l)->Layer(B, Top(l, -l))\nTop(l, m)->Case(l + m != 0, D, l >= 3, C, Skip)\nSkip->Skip(0)\n"
    + colours(*"ABCDE"),
    "rand": "S->RepeatX(2, Col)\nCol->RepeatY(2, R)\nR->Rand(0, 0.2, A, 0.5, B, 0.3, C)\n" + colours(*"ABC"),
    "rand_uni": "S->RepeatY(1.5, Row)\nRow->RepeatX(1.5, R)\nR->RandUni(0, A, B, C, D, E)\n" + colours(*"ABCDE"),
    "rand_stack": "S->RepeatY(3, Floor)\nFloor->RandStack(Win)\nWin->RepeatX(2, Pick)\n"
    "Pick->RandUni(1, Fit1, Fit2, Fit3)\n"
    "Fit1->Mat(Color, Fit>window1, 0, 0, 1, 1)\nFit2->Mat(Color, Fit>window2, 0, 0, 1, 1)\n"
    "Fit3->Mat(Color, Fit>window_round, 0, 0, 1, 1)\n",
    "layer": "S->Layer(Wall, Mid, Top)\nWall->Mat(Color, Rep:wall1, 0, 0, 1, 1)\n"
    "Mid->RepeatX(3, Arch)\nArch->Mat(Color, Fit>window3, 0, 0, 1, 1)\n"
    "Top->SplitY(Rel, 1, Inner, Abs, 2, Skip)\nInner->Layer(Skip, Rail)\n"
    "Rail->RepeatX(4, RailTile)\nRailTile->Mat(Color, Fit>balcony_rail1, 0, 0, 1, 0.3)\nSkip->Skip(0)\n",
    "skip": "S->Layer(A, B, C)\nC->SplitX(Rel, 1, Skip1, Rel, 1, Skip0, Rel, 1, Cc)\n"
    "Skip1->Skip(1)\nSkip0->Skip(0)\n" + colours("A", "B", "Cc"),
    "skip_mask": "S->Layer(Room, Wall, Mask)\nMask->RepeatX(2, Cell)\nCell->RepeatY(2, Hole)\n"
    "Hole->SkipMask(Fit>mask_round, 0, 1)\n"
    "Wall->Mat(Color, Rep:wall3, 0, 0, 0.5, 0.5)\nRoom->Mat(Color, Rep:room_wall1, 0, 0, 1, 1)\n",
    "intrusion": "S->RepeatX(4, Bay)\nBay->RepeatY(4, Box)\nBox->Intrusion(3, L, Back, R, Fl, Ce)\n"
    "Back->SplitX(Rel, 1, B1, Rel, 1, Nested)\nNested->Intrusion(0.5, L2, B2, R2, F2, C2)\n"
    + colours("L", "R", "Fl", "Ce", "B1", "L2", "B2", "R2", "F2", "C2"),
    "mat": "S->SplitX(Rel, 1, Const, Rel, 1, FitPart, Rel, 1, Tiled, Rel, 1, Alpha)\n"
    "Const->Mat(Color, 0, 0.2, 0.4, 0.6, 1)\nFitPart->Mat(Color, Fit>door1, 0.1, 0.0, 0.9, 0.8)\n"
    "Tiled->Layer(Back, Lit)\nBack->Mat(Color, Rep:wall1, 0.3, 0.1, 0.7, 1.3)\n"
    "Lit->Layer(Spec, Norm)\nNorm->Mat(Normal, Rep:wall3, 0, 0, 1, 1)\nSpec->Mat(Specular, 0, 0.9, 0.5, 0, 1)\n"
    "Alpha->Layer(Under, Over)\nUnder->Mat(Color, Rep:wall2, 0, 0, 1, 1)\n"
    "Over->MatAlpha(Color, Rep:brick_dark, 0, 0, 1, 1, Fit>mask_arch, 0, 0, 1, 1)\n",
}


@pytest.mark.parametrize("name", sorted(CASES))
def test_operator_gpu_matches_numpy(ctx, name, output_dir):
    compiled = compile_grammars({name: loads(CASES[name], f"{name}.grammar")})
    compare(ctx, compiled, name, output_dir)


def test_labelled_colours_gpu_matches_numpy(ctx, output_dir):
    text = (
        "S->Layer(Wall, Front)\nWall->Color(0.8, 0.7, 0.6)\nFront->RepeatX(3, Bay)\n"
        "Bay->SplitX(Rel, 1, Skip, Abs, 1.2, Col, Rel, 1, Skip)\nCol->SplitY(Abs, 1, Skip, Abs, 1.5, Glass, "
        "Rel, 1, Rail)\nGlass->Color(0.2, 0.3, 0.4, window)\nRail->Color(0.1, 0.1, 0.1, balcony)\nSkip->Skip(0)\n"
    )
    compiled = compile_grammars({"colours": loads(text)})
    cpu, _ = compare(ctx, compiled, "colours", output_dir, nearest=False, allowed=0)
    assert set(np.unique(cpu.label).tolist()) == {LABELS.index(n) for n in ("wall", "window", "balcony")}


def test_building_attributes_gpu_matches_numpy(ctx, output_dir):
    text = (
        "S->RepeatY(3, Floor)\nFloor->Case(split.index >= building.levels - 1, A, "
        "building.style == 4 && split.index % 2 == 1, B, C)\n" + colours(*"ABC")
    )
    compiled = compile_grammars({"attributes": loads(text)})
    for building in ((3, 4, 0, 12), (2, 1, 0, 12)):
        cpu, _ = compare(ctx, compiled, "attributes", output_dir, building=building)
        rows = cpu.terminal[:: -SIZE[1] // 4][:4]  # one row per storey, bottom first
        picked = [int(np.unique(r)[0]) for r in rows]
        names = {compiled.address("attributes", n): n for n in "ABC"}
        want = [("A" if i >= building[0] - 1 else "B" if building[1] == 4 and i % 2 else "C") for i in range(4)]
        assert [names[p] for p in picked] == want


def test_building_use_and_height_gpu_matches_numpy(ctx, output_dir):
    """building.use (named by use.*) and building.height pick storeys alike on the GPU and numpy."""
    text = (
        "S->RepeatY(3, Floor)\nFloor->Case(building.use == use.shop && split.first, A, "
        "building.use == use.office, B, building.height > 20 && split.last, C, D)\n" + colours(*"ABCD")
    )
    compiled = compile_grammars({"uses": loads(text)})
    names = {compiled.address("uses", n): n for n in "ABCD"}
    for use, height, want in (("shop", 12, "ADDD"), ("office", 12, "BBBB"), ("home", 24, "DDDC"), ("shop", 24, "ADDC")):
        building = (4, 0, USES[use], height)
        cpu, _ = compare(
            ctx, compiled, "uses", output_dir, building=building, nearest=False, allowed=0, min_terminals=1
        )
        rows = cpu.terminal[:: -SIZE[1] // 4][:4]  # one row per storey, bottom first
        assert "".join(names[int(np.unique(r)[0])] for r in rows) == want, (use, height)


def test_facade_level_gpu_matches_numpy(ctx, output_dir):
    """facade.level (the storey the face starts at) picks storeys alike on the GPU and numpy: a
    ground floor only on a face at level 0, and a parity counted from the ground, not the face."""
    text = (
        "S->RepeatY(3, Floor)\nFloor->Case(facade.level == 0 && split.first, G, "
        "(facade.level + split.index) % 2 == 0, E, O)\n" + colours(*"GEO")
    )
    compiled = compile_grammars({"level": loads(text)})
    names = {compiled.address("level", n): n for n in "GEO"}
    for level, want in ((0, "GOEO"), (1, "OEOE"), (2, "EOEO"), (7, "OEOE")):
        cpu, _ = compare(ctx, compiled, "level", output_dir, nearest=False, allowed=0, min_terminals=2, level=level)
        rows = cpu.terminal[:: -SIZE[1] // 4][:4]  # one row per storey, bottom first
        assert "".join(names[int(np.unique(r)[0])] for r in rows) == want, level


def test_each_facade_has_its_own_stream_gpu_matches_numpy(ctx, output_dir):
    """The GPU hashes the building's seed with the facade index exactly as the twin does."""
    text = "S->RepeatX(1, Row)\nRow->RepeatY(1, Pick)\nPick->RandUni(0, A, B, C)\n" + colours(*"ABC")
    compiled = compile_grammars({"faces": loads(text)})
    pictures = {}
    for face in (0, 4, 8, 12):
        cpu, _ = compare(ctx, compiled, "faces", output_dir, face=face, nearest=False, allowed=0, min_terminals=3)
        pictures[face] = cpu.terminal.tobytes()
    assert len(set(pictures.values())) == 4  # the four sides of a box choose differently
    text = "S->RepeatX(1, Pick)\nPick->RandUni(1, A, B, C)\n" + colours(*"ABC")  # l = 1: the building's seed
    compiled = compile_grammars({"once": loads(text)})
    pictures = {
        compare(ctx, compiled, "once", output_dir, face=face, nearest=False, allowed=0, min_terminals=1)[
            0
        ].terminal.tobytes()
        for face in (0, 4)
    }
    assert len(pictures) == 1  # a choice made once per building is the same on its sides


def test_fig12_gpu_matches_numpy(ctx, output_dir):
    compiled = compile_grammars({"fig12": load(library_path("fig12.grammar"))})
    cpu, _ = compare(ctx, compiled, "fig12", output_dir, facade=(20.0, 16.0), size=(160, 128))
    labels = set(np.unique(cpu.label).tolist())
    assert labels == {1, 2} and cpu.glass.any()  # wall and window, with glass panes


def test_intrusion_shows_all_five_faces():
    compiled = compile_grammars({"i": loads(CASES["intrusion"])})
    cpu = evaluate_facade(compiled, compiled.address("i"), FACADE, SIZE, seed_vector(1), tile_array(32))
    faces = {compiled.address("i", r) for r in ("L", "R", "Fl", "Ce", "B1", "L2", "B2", "R2", "F2", "C2")}
    assert faces <= set(np.unique(cpu.terminal).tolist())


def test_rand_stack_groups_a_floor():
    """RandUni(1, ...) after RandStack picks one window per floor (fig. 6 random groups)."""
    compiled = compile_grammars({"g": loads(CASES["rand_stack"])})
    rows_per_floor = SIZE[1] // 4
    kinds = set()
    for seed in range(3):
        cpu = evaluate_facade(compiled, compiled.address("g"), FACADE, SIZE, seed_vector(seed), tile_array(32))
        # -1: outside a round window, where no layer lies below
        floors = [
            np.setdiff1d(cpu.terminal[i * rows_per_floor + 2 : (i + 1) * rows_per_floor - 2], [-1]) for i in range(4)
        ]
        assert all(len(f) == 1 for f in floors)
        kinds.add(tuple(int(f[0]) for f in floors))
    assert any(len(set(k)) > 1 for k in kinds)  # but floors differ


def test_tint_multiplies_the_colour_below_it(ctx, output_dir):
    """Tint(r, g, b, Rule): the colour Mats below it are multiplied, on the GPU as in numpy; ids unchanged."""
    plain = "S->SplitX(Rel, 1, Wall, Rel, 1, Tinted)\nTinted->Tint(0.5, 0.8, 1, Wall)\nWall->Mat(Color, Rep:wall1, 0, 0, 1, 1)\n"
    compiled = compile_grammars({"tint": loads(plain)})
    cpu, _ = compare(ctx, compiled, "tint", output_dir, min_terminals=1)
    start = compiled.address("tint")
    uv = np.array([[2.0, 3.0], [10.0, 3.0]], np.float32)  # the same wall texel on both halves
    result = evaluate(compiled, start, uv, (16.0, 12.0), (0.0, 0.0), tile_array(32))
    assert result.terminal[0] == result.terminal[1]
    np.testing.assert_allclose(result.color[1], result.color[0] * np.array([0.5, 0.8, 1.0]), rtol=1e-3)
    textures = GrammarTextures(ctx, compiled, tile_array(32))
    colour, _ = FacadeRenderer(ctx, textures, nearest=True).render(start, FACADE, SIZE, seed_vector(3))
    textures.release()
    lit = evaluate_facade(compiled, start, FACADE, SIZE, seed_vector(3), tile_array(32)).color
    assert np.abs(colour[..., :3] - lit).max() < 0.02  # colours agree within a small tolerance


@pytest.mark.parametrize("nearest", [True, False])
def test_holes_and_what_they_show_gpu_matches_numpy(ctx, nearest):
    """dusk's windows are holes (SkipMask) through which its Intrusion rooms show: per pixel the hole
    (GrammarResult.hole) and what that hole shows from a point further along (grammar_through, as the
    city's recessed holes evaluate it from their bottom), GPU against the numpy twin; filtered
    alphas included (a frame opaque on its exact texel hides the hole in both). What a hole shows is
    the grammar's rooms, never the frame layered over it, and the shift moves it."""
    compiled = compile_grammars({"dusk": load(library_path("dusk.grammar"))})
    tiles = tile_array(32)
    start, facade, size, shift = compiled.address("dusk"), (12.0, 10.0), (240, 200), (0.06, -0.04)
    textures = GrammarTextures(ctx, compiled, tiles)
    _, ids = FacadeRenderer(ctx, textures, nearest=nearest, hole_shift=shift).render(
        start, facade, size, seed_vector(3)
    )
    textures.release()
    uv, rays = facade_view(facade, size)
    flat = evaluate(compiled, start, uv, facade, seed_vector(3), tiles, rays, building_seed=seed_vector(3))
    behind = evaluate(
        compiled, start, uv + np.float32(shift), facade, seed_vector(3), tiles, rays, building_seed=seed_vector(3),
        through=flat.hole,
    )  # fmt: skip
    cols, rows = size

    def image(values):
        return values.reshape(rows, cols)[::-1]

    hole, room, wall = image(flat.hole), LABELS.index("room"), LABELS.index("wall")
    differ = (ids[..., 0].astype(np.int64) - 1 != hole) | (ids[..., 1].astype(np.int64) - 1 != image(behind.terminal))
    differ |= (ids[..., 2] != image(behind.label)) | (ids[..., 3].astype(bool) != image(behind.glass))
    holes = hole >= 0
    moved = holes & (image(behind.terminal) != image(flat.terminal))
    print(
        f"nearest={nearest}: {differ.sum()} of {differ.size} pixels differ (hole, or what it shows); {holes.sum()} hole "
        f"pixels, {moved.sum()} of them show another terminal from {shift} m further along"
    )
    assert holes.sum() > 0.05 * differ.size and moved.any()
    assert differ.sum() <= 0.001 * differ.size
    assert set(np.unique(image(behind.label)[holes])) <= {room, wall}, "a hole shows the rooms below it"
    assert not np.isin(
        image(behind.terminal)[holes], image(flat.terminal)[image(flat.label) == LABELS.index("window")]
    ).any()
