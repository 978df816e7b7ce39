"""The numpy twin of shaders/grammar/eval.glsl: the same per-pixel grammar evaluation, vectorised.

It reads the compiled texture (so it also checks the compiler) and follows the shader step for
step in float32: every pixel walks the grammar from its start rule, updating its scope, texture
coordinates, random-seed stack and layer stack, until a terminal makes it opaque (§3.1, §4).
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from ..assets import LABELS, TileArray
from . import _limits as limits
from ._compiler import CompiledGrammars
from ._expressions import BINARY, CASE, NEG, NOT, PUSH, VARIABLE, apply
from ._random import noise_at

F = np.float32
BIG = F(1e30)
OPAQUE = F(0.999)
BACKGROUND = F(0.5)
DEFAULT_SPECULAR = (0.08, 0.25)
WALL_LABEL = LABELS.index("wall")
REPEAT_SLACK = F(1e-4)  # ceil(S_w / v) must not jump when S_w / v is an integer up to rounding


def repeat_count(size, v, ceil_mode):
    """Repeat's tile count: the nearest whole number (half up), or the paper's ceil; at least 1."""
    ratio = size / v
    return np.maximum(np.where(ceil_mode, np.ceil(ratio - REPEAT_SLACK), np.floor(ratio + F(0.5))), F(1))


# The evaluator's work arrays take hundreds of bytes per pixel (7.7 GB for 4096x4096 at once);
# it runs on tiles of this many pixels.
# What stays per pixel is the Evaluation, the view rays and the 8-bit images.
CHUNK_PIXELS = 1 << 16
CPU_BYTES_PER_PIXEL = 150  # measured: 242 MB peak at 1024x1024, 584 MB before tiling


@dataclass
class Evaluation:
    """Per-pixel results; terminal is the winning Mat's texel address (-1: none)."""

    color: np.ndarray  # (..., 3)
    alpha: np.ndarray
    normal: np.ndarray  # (..., 3) tangent space
    specular: np.ndarray  # (..., 2) intensity, shininess / 128
    terminal: np.ndarray
    tile: np.ndarray  # tile index of the terminal (-1: constant or none)
    label: np.ndarray  # index into LABELS
    glass: np.ndarray  # bool: the terminal's texel is glass (a window to see a room through)
    scope: np.ndarray  # (..., 4) the terminal's scope: lower left in facade uv (translations undone), size
    hole: np.ndarray  # address of the last SkipMask that cut a hole here (-1: none), eval.glsl GrammarResult.hole
    hole_scope: np.ndarray  # (..., 4) that SkipMask's scope, as scope


class _Pixels:
    """The evaluation state of n pixels (one row each)."""

    def __init__(
        self,
        n: int,
        start: int,
        facade,
        seed,
        uv,
        directions,
        building=(0, 0, 0, 0),
        building_seed=None,
        level=0,
        through=-1,
    ):
        s = np.broadcast_to(np.asarray(seed, F), (n, 2))
        self.s = s
        self.addr = np.broadcast_to(np.asarray(start, np.int32), (n,)).copy()
        self.lb = np.broadcast_to(s, (n, 2)).astype(F)
        self.size = np.broadcast_to(np.asarray(facade, F), (n, 2)).astype(F)
        self.t = uv.astype(F) + s
        self.uv = uv.astype(F)
        self.facade = np.broadcast_to(np.asarray(facade, F), (n, 2)).astype(F)
        self.building = np.broadcast_to(np.asarray(building, F), (n, 4)).astype(F)  # levels, style, use, height
        self.level = np.broadcast_to(np.asarray(level, F), (n,)).astype(F)[:, None]  # facade.level
        self.split = np.broadcast_to(np.array([0, 1], F), (n, 2)).copy()  # split.index, split.total
        self.params = np.zeros((n, limits.MAX_PARAMS), F)  # the parameters of the rule being evaluated
        self.d = directions.astype(F)
        self.stack = np.zeros((n, limits.MAX_STACK, 2), F)
        self.stack[:, 0] = s if building_seed is None else np.asarray(building_seed, F)  # Rand l >= 1, no entry
        self.sp = np.ones(n, np.int32)
        L = limits.MAX_LAYER_DEPTH
        self.depth = np.zeros(n, np.int32)
        self.f_addr = np.zeros((n, L), np.int32)
        self.f_index = np.zeros((n, L), np.int32)
        self.f_lb = np.zeros((n, L, 2), F)
        self.f_size = np.zeros((n, L, 2), F)
        self.f_t = np.zeros((n, L, 2), F)
        self.f_split = np.zeros((n, L, 2), F)
        self.f_params = np.zeros((n, L, limits.MAX_PARAMS), F)
        self.f_d = np.zeros((n, L, 3), F)
        self.f_sp = np.zeros((n, L), np.int32)
        self.C = np.zeros((n, 3), F)
        self.A = np.zeros(n, F)
        self.tint = np.ones((n, 3), F)  # Tint's factor for colour Mats
        self.f_tint = np.ones((n, L, 3), F)
        self.N = np.zeros((n, 3), F)
        self.AN = np.zeros(n, F)
        self.S = np.zeros((n, 2), F)
        self.AS = np.zeros(n, F)
        self.best_w = np.zeros(n, F)
        self.best_addr = np.full(n, -1, np.int32)
        self.best_tile = np.full(n, -1, np.int32)
        self.best_texel = np.zeros((n, 2), np.int32)
        self.best_scope = np.concatenate([np.zeros((n, 2), F), self.size], axis=1)
        self.active = np.ones(n, bool)
        # seen through the hole of this SkipMask (eval.glsl grammar_through), -1 once it is passed
        self.through = np.broadcast_to(np.asarray(through, np.int32), (n,)).copy()
        self.hole = np.full(n, -1, np.int32)
        self.hole_scope = np.zeros((n, 4), F)


class _Evaluator:
    def __init__(self, compiled: CompiledGrammars, tiles: TileArray):
        # Split and Rand read all MAX_PARTS part slots (and a Split its rand highs) and mask those
        # past n, as the shader's loop does; zero texels after the last rule keep those reads inside.
        padding = 2 + limits.MAX_PARTS // 2 + limits.MAX_PARTS // 4
        self.tex = np.concatenate([compiled.flat(), np.zeros((padding, 4), F)])
        self.tiles = tiles

    def channel(self, addr, index):
        index = np.asarray(index)
        return self.tex[addr + index // 4, index % 4]

    # ------------------------------------------------------------------ texture sampling

    def sample(self, code, usage, params, lb, size, t):
        """rgba of Mat's sampling: constant (code 0), fitted (> 0) or tiled (< 0); nearest texel."""
        n = len(code)
        rgba = params.copy()
        texel = np.zeros((n, 2), np.int32)
        tile = np.abs(code) - 1
        textured = code != 0
        if np.any(textured):
            r = self.tiles.size
            fit = code > 0
            rect0, rect1 = params[:, 0:2], params[:, 2:4]
            uv_fit = rect0 + (t - lb) / size * (rect1 - rect0)
            uv_rep = t * rect1 + rect0
            uv = np.where(fit[:, None], uv_fit, uv_rep)
            ix = np.floor(uv * F(r)).astype(np.int32)
            ix = np.where(fit[:, None], np.clip(ix, 0, r - 1), ix & (r - 1))
            texel = ix
            layer = 3 * np.maximum(tile, 0) + usage - 1
            fetched = self.tiles.layers[layer, ix[:, 1], ix[:, 0]].astype(F) / F(255)
            rgba = np.where(textured[:, None], fetched, rgba)
        return rgba, texel, np.where(textured, tile, -1)

    def mat_params(self, addr, extra):
        """Mat's m2..m5: the next texel, or the unit rectangle when the rule is one texel."""
        unit = np.broadcast_to(np.array([0, 0, 1, 1], F), (len(addr), 4))
        return np.where(extra[:, None], self.tex[addr + 1], unit)

    # ------------------------------------------------------------------ the evaluation

    def run(self, p: _Pixels):
        for _ in range(limits.MAX_STEPS):
            live = np.nonzero(p.active)[0]
            if live.size == 0:
                break
            ops = self.tex[p.addr[live], 0].astype(np.int32)
            for _ in range(limits.MAX_STEPS):  # Binds and Cases lead straight on to the next rule (eval.glsl)
                if not np.any((ops == 14) | (ops == 15)):
                    break
                for op in (14, 15):
                    getattr(self, _HANDLERS[op])(p, live[ops == op], op)
                ops = self.tex[p.addr[live], 0].astype(np.int32)
            for op in np.unique(ops):
                idx = live[ops == op]
                getattr(self, _HANDLERS[op])(p, idx, op)

    def op_repeat(self, p, idx, op):
        a = op - 1
        head = self.tex[p.addr[idx]]
        random = head[:, 3] >= 2
        v = np.where(random, self.drawn(p, idx, head[:, 1], self.tex[p.addr[idx] + 1, 0], 0), head[:, 1])
        size, lb, t = p.size[idx, a], p.lb[idx, a], p.t[idx, a]
        count = repeat_count(size, v, np.mod(head[:, 3], F(2)) == 1)
        w = size / count
        i = np.clip(np.floor((t - lb) / w), F(0), count - F(1))
        p.lb[idx, a] = lb + i * w
        p.size[idx, a] = w
        p.split[idx] = np.stack([i, count], axis=1)
        p.addr[idx] = head[:, 2].astype(np.int32)

    def drawn(self, p, idx, low, high, part):
        """A size from rand(low, high) for each pixel's scope, part `part` of its rule (eval.glsl grammar_drawn)."""
        r = noise_at(p.lb[idx], p.addr[idx] + limits.PART_STREAMS * (part + 1))
        return low + (high - low) * r

    def part_sizes(self, p, idx, first, highs, random, i):
        """Part i's sign-carrying stored size and its drawn (or fixed) size."""
        part = self.tex[first + i // 2]
        sv, ref = part[:, 2 * (i % 2)], part[:, 2 * (i % 2) + 1]
        high = self.channel(highs, np.full(len(idx), i))
        size = np.where(random & (ref >= 0), self.drawn(p, idx, np.abs(sv), high, i), np.abs(sv))
        return sv, ref, size

    def op_split(self, p, idx, op):
        a = op - 3
        addr = p.addr[idx]
        head = self.tex[addr]
        tiled = head[:, 1] < 0
        n = np.abs(head[:, 1]).astype(np.int32)
        random = n >= limits.RANDOM_PARTS
        n = n - np.where(random, limits.RANDOM_PARTS, 0)
        first = addr + np.where(tiled, 2, 1)
        highs = first + (n + 1) // 2
        size = p.size[idx, a]
        absolute, relative = np.where(random, F(0), head[:, 3]), np.where(random, F(0), head[:, 2])
        for i in range(limits.MAX_PARTS):
            sv, ref, drawn = self.part_sizes(p, idx, first, highs, random, i)
            used = random & (i < n)
            absolute = absolute + np.where(used & (sv < 0), drawn, F(0))
            relative = relative + np.where(used & (sv > 0) & (ref >= 0), drawn, F(0))
        tile = np.where(tiled, self.tex[addr + 1, 0], F(0))
        with np.errstate(divide="ignore", invalid="ignore"):
            count = np.where(tiled, np.maximum(np.floor((size - absolute - relative) / tile + F(0.5)), F(1)), F(0))
        floating = relative + count * tile
        scale = np.where(floating > 0, np.maximum(size - absolute, F(0)) / np.where(floating > 0, floating, F(1)), F(0))
        pos = p.lb[idx, a].copy()
        t = p.t[idx, a]
        chosen_pos, chosen_w = pos.copy(), np.zeros_like(pos)
        chosen_index = np.zeros_like(pos)
        after_tile = np.zeros(len(idx), bool)
        target = np.zeros(len(idx), np.int32)
        searching = np.ones(len(idx), bool)
        over = np.zeros(len(idx), bool)  # an Overhang part reaches t: the last one is drawn over the others
        for i in range(limits.MAX_PARTS):
            sv, ref, drawn = self.part_sizes(p, idx, first, highs, random, i)
            w = np.where(sv < 0, drawn, drawn * scale)
            is_tile = ref < 0
            span = np.where(is_tile, w * count, w)
            index = F(i) + np.where(after_tile, count - F(1), F(0))
            child = self.tex[np.clip(ref, F(0), F(len(self.tex) - 1)).astype(np.int32)]  # slots past n: any texel
            before, after = child[:, 1], child[:, 2]
            overhang = (i < n) & ~is_tile & (child[:, 0] == 17) & (t >= pos - before) & (t < pos + span + after)
            hit = searching & ~over & ~overhang & (i < n) & ((t < pos + span) | (i == n - 1))
            with np.errstate(divide="ignore", invalid="ignore"):
                k = np.where(is_tile, np.clip(np.floor((t - pos) / w), F(0), count - F(1)), F(0))
            chosen_pos = np.where(overhang, pos - before, np.where(hit, pos + k * w, chosen_pos))
            chosen_w = np.where(overhang, span + before + after, np.where(hit, np.where(is_tile, w, span), chosen_w))
            chosen_index = np.where(overhang, index, np.where(hit, index + k, chosen_index))
            after_tile |= is_tile
            target = np.where(
                overhang,
                child[:, 3].astype(np.int32),
                np.where(hit, np.where(is_tile, -ref - F(1), ref).astype(np.int32), target),
            )
            searching &= ~hit
            over |= overhang
            pos = pos + span
        p.lb[idx, a] = chosen_pos
        p.size[idx, a] = chosen_w
        p.split[idx] = np.stack([chosen_index, n.astype(F) + np.maximum(count - F(1), F(0))], axis=1)
        p.addr[idx] = target

    def program(self, p, idx, first, n):
        """Runs postfix tokens per pixel (eval.glsl grammar_program): the rule of the first test
        taken (-1 if none) and the value stack."""
        rows = np.arange(len(idx))
        variables = np.concatenate(
            [p.split[idx], p.size[idx], p.facade[idx], p.building[idx], p.level[idx], p.params[idx]], axis=1
        )
        stack = np.zeros((len(idx), limits.MAX_EXPR_STACK), F)
        sp = np.zeros(len(idx), np.int32)
        target = np.full(len(idx), -1, np.int32)
        deciding = np.ones(len(idx), bool)
        for i in range(limits.MAX_CASE_TOKENS):
            live = deciding & (i < n)
            if not live.any():
                break
            pair = self.tex[np.where(live, first + i // 2, first)]
            code = np.where(live, pair[:, 2 * (i % 2)].astype(np.int32), -1)
            value = pair[:, 2 * (i % 2) + 1]
            push = (code == PUSH) | (code == VARIABLE)
            index = np.clip(value.astype(np.int32), 0, variables.shape[1] - 1)
            pushed = np.where(code == PUSH, value, variables[rows, index])
            slot = np.minimum(sp, limits.MAX_EXPR_STACK - 1)
            stack[rows[push], slot[push]] = pushed[push]
            sp = np.where(push, np.minimum(sp + 1, limits.MAX_EXPR_STACK), sp)
            test = code == CASE
            sp = np.where(test, np.maximum(sp - 1, 0), sp)
            taken = test & (stack[rows, np.minimum(sp, limits.MAX_EXPR_STACK - 1)] != 0)
            target = np.where(taken, value.astype(np.int32), target)
            deciding &= ~taken
            top = np.maximum(sp - 1, 0)
            x = stack[rows, top]
            for code_value, name in ((NOT, "not"), (NEG, "neg")):
                unary = code == code_value
                stack[rows[unary], top[unary]] = apply(name, x[unary])
            binary = (code >= min(BINARY.values())) & (code <= max(BINARY.values()))
            sp = np.where(binary, np.maximum(sp - 1, 1), sp)
            top = sp - 1
            a = stack[rows, top]
            for name, code_value in BINARY.items():
                mask = binary & (code == code_value)
                if mask.any():
                    stack[rows[mask], top[mask]] = apply(name, a[mask], x[mask])
        return target, stack

    def op_case(self, p, idx, op):
        head = self.tex[p.addr[idx]]
        taken, _ = self.program(p, idx, p.addr[idx] + 1, head[:, 1].astype(np.int32))
        p.addr[idx] = np.where(taken >= 0, taken, head[:, 2].astype(np.int32))

    def op_tint(self, p, idx, op):
        p.tint[idx] *= self.tex[p.addr[idx] + 1, :3]
        p.addr[idx] = self.tex[p.addr[idx], 1].astype(np.int32)

    def op_overhang(self, p, idx, op):
        """An Overhang not reached through its Split (a start rule): its rule, in the scope as it is."""
        p.addr[idx] = self.tex[p.addr[idx], 3].astype(np.int32)

    def op_bind(self, p, idx, op):
        head = self.tex[p.addr[idx]]
        _, values = self.program(p, idx, p.addr[idx] + 1, head[:, 1].astype(np.int32))
        count = head[:, 3].astype(np.int32)
        for k in range(limits.MAX_PARAMS):  # the rule's parameters; the others are 0
            p.params[idx, k] = np.where(k < count, values[:, k], F(0))
        p.addr[idx] = head[:, 2].astype(np.int32)

    def random(self, p, idx, level):
        slot = np.maximum(p.sp[idx] - level, 0)
        corner = np.where((level == 0)[:, None], p.lb[idx], p.stack[idx, slot])
        return noise_at(corner, p.addr[idx])

    def op_rand(self, p, idx, op):
        addr = p.addr[idx]
        head = self.tex[addr]
        n = head[:, 1].astype(np.int32)
        r = self.random(p, idx, head[:, 2].astype(np.int32))
        target = np.zeros(len(idx), np.int32)
        searching = np.ones(len(idx), bool)
        for i in range(limits.MAX_PARTS):
            part = self.tex[addr + 1 + i // 2]
            hit = searching & (i < n) & ((r < part[:, 2 * (i % 2)]) | (i == n - 1))
            target = np.where(hit, part[:, 2 * (i % 2) + 1].astype(np.int32), target)
            searching &= ~hit
        p.addr[idx] = target

    def op_rand_uni(self, p, idx, op):
        addr = p.addr[idx]
        head = self.tex[addr]
        n = head[:, 1].astype(np.int32)
        r = self.random(p, idx, head[:, 2].astype(np.int32))
        k = np.minimum(np.floor(r * n.astype(F)).astype(np.int32), n - 1)
        p.addr[idx] = self.channel(addr, 3 + k).astype(np.int32)

    def op_rand_stack(self, p, idx, op):
        slot = np.minimum(p.sp[idx], limits.MAX_STACK - 1)
        p.stack[idx, slot] = p.lb[idx]
        p.sp[idx] = slot + 1
        p.addr[idx] = self.tex[p.addr[idx], 1].astype(np.int32)

    def op_layer(self, p, idx, op):
        addr = p.addr[idx]
        n = self.tex[addr, 1].astype(np.int32)
        top = np.minimum(p.depth[idx], p.f_addr.shape[1] - 1)
        p.f_addr[idx, top] = addr
        p.f_index[idx, top] = n
        p.f_lb[idx, top] = p.lb[idx]
        p.f_size[idx, top] = p.size[idx]
        p.f_split[idx, top] = p.split[idx]
        p.f_params[idx, top] = p.params[idx]
        p.f_t[idx, top] = p.t[idx]
        p.f_d[idx, top] = p.d[idx]
        p.f_sp[idx, top] = p.sp[idx]
        p.f_tint[idx, top] = p.tint[idx]
        p.depth[idx] = top + 1
        self.end_layer(p, idx, np.zeros(len(idx), np.int32))

    def end_layer(self, p, idx, skip):
        """The current layer is done (skipping `skip` more): enter the next one below, or finish."""
        rows, k = idx, skip
        for _ in range(p.f_addr.shape[1] + 1):
            if rows.size == 0:
                break
            top = p.depth[rows] - 1
            finished = top < 0
            p.active[rows[finished]] = False
            rows, top, k = rows[~finished], top[~finished], k[~finished]
            index = p.f_index[rows, top] - 1 - k
            p.f_index[rows, top] = index
            enter = index >= 0
            er, et, ei = rows[enter], top[enter], index[enter]
            offset = (ei + 1).astype(F)[:, None] * p.s[er]  # layer i is translated by i * s
            p.lb[er] = p.f_lb[er, et] + offset
            p.t[er] = p.f_t[er, et] + offset
            p.size[er] = p.f_size[er, et]
            p.split[er] = p.f_split[er, et]
            p.params[er] = p.f_params[er, et]
            p.d[er] = p.f_d[er, et]
            p.sp[er] = p.f_sp[er, et]
            p.tint[er] = p.f_tint[er, et]
            p.addr[er] = self.channel(p.f_addr[er, et], 2 + ei).astype(np.int32)
            rows = rows[~enter]  # this Layer is exhausted: continue below it in the enclosing one
            p.depth[rows] -= 1
            k = np.zeros(len(rows), np.int32)

    def op_skip(self, p, idx, op):
        self.end_layer(p, idx, self.tex[p.addr[idx], 1].astype(np.int32))

    def op_skip_mask(self, p, idx, op):
        """Skips head[2] layers where the mask's texel is 0, head[3] where it is 1; the bit that skips
        more cuts a hole (recorded), and it is cut wherever the pixel is seen through this SkipMask."""
        head = self.tex[p.addr[idx]]
        code = head[:, 1].astype(np.int32)
        unit = np.broadcast_to(np.array([0, 0, 1, 1], F), (len(idx), 4))
        rgba, _, _ = self.sample(code, 1, unit.copy(), p.lb[idx], p.size[idx], p.t[idx])
        one = rgba[:, 3] > F(0.5)
        through = p.addr[idx] == p.through[idx]
        one = np.where(through, head[:, 3] > head[:, 2], one)
        p.through[idx[through]] = -1
        cut = np.where(one, head[:, 3] > head[:, 2], head[:, 2] > head[:, 3])
        rows = idx[cut]
        p.hole[rows] = p.addr[rows]
        p.hole_scope[rows] = self.current_scope(p, rows)
        self.end_layer(p, idx, np.where(one, head[:, 3], head[:, 2]).astype(np.int32))

    @staticmethod
    def current_scope(p, rows):
        """The scope of pixels `rows` in facade uv: the corner is the same for all its pixels, and so
        are the whole seed vectors it was translated by (layers, the start), which undo it exactly."""
        with np.errstate(divide="ignore", invalid="ignore"):  # no seed: nothing to undo
            s = p.s[rows]
            shift = np.where(s != 0, np.round((p.t[rows] - p.uv[rows]) / s) * s, F(0))
        return np.concatenate([p.lb[rows] - shift, p.size[rows]], axis=1)

    def op_intrusion(self, p, idx, op):
        addr = p.addr[idx]
        depth = self.tex[addr, 1]
        lb, size, d = p.lb[idx], p.size[idx], p.d[idx]
        local = p.t[idx] - lb
        dx, dy, dz = d[:, 0], d[:, 1], d[:, 2]
        with np.errstate(divide="ignore", invalid="ignore"):
            tx = np.where(dx > 0, (size[:, 0] - local[:, 0]) / dx, np.where(dx < 0, -local[:, 0] / dx, BIG))
            ty = np.where(dy > 0, (size[:, 1] - local[:, 1]) / dy, np.where(dy < 0, -local[:, 1] / dy, BIG))
            tz = np.where(dz > 0, depth / dz, BIG)
        back = (tz <= tx) & (tz <= ty)
        side = ~back & (tx <= ty)
        face = np.where(back, 2, np.where(side, np.where(dx < 0, 1, 3), np.where(dy < 0, 4, 5)))
        h = np.minimum(np.minimum(tx, ty), tz)
        px, py, pz = local[:, 0] + dx * h, local[:, 1] + dy * h, dz * h
        # Each face seen from inside the box: (u, v) on it, its size, and the ray in its frame.
        f = face[:, None]
        new_local = np.select(
            [f == 1, f == 2, f == 3, f == 4],
            [np.stack([pz, py], 1), np.stack([px, py], 1), np.stack([depth - pz, py], 1), np.stack([px, pz], 1)],
            np.stack([px, depth - pz], 1),
        )
        new_size = np.select(
            [(f == 1) | (f == 3), f == 2], [np.stack([depth, size[:, 1]], 1), size], np.stack([size[:, 0], depth], 1)
        )
        new_d = np.select(
            [f == 1, f == 2, f == 3, f == 4],
            [np.stack([dz, dy, -dx], 1), d, np.stack([-dz, dy, dx], 1), np.stack([dx, dz, -dy], 1)],
            np.stack([dx, -dz, dy], 1),
        )
        new_lb = lb + face.astype(F)[:, None] * p.s[idx]
        p.lb[idx] = new_lb
        p.size[idx] = new_size
        p.t[idx] = new_lb + np.clip(new_local, F(0), new_size)
        p.d[idx] = new_d
        p.addr[idx] = self.channel(addr, 1 + face).astype(np.int32)

    def op_mat(self, p, idx, op):
        above = p.through[idx] >= 0  # a layer above the hole seen through: not in the way
        self.end_layer(p, idx[above], np.zeros(int(above.sum()), np.int32))
        idx = idx[~above]
        addr = p.addr[idx]
        head = self.tex[addr]
        usage = head[:, 1].astype(np.int32)
        code = head[:, 2].astype(np.int32)
        if op == 12:
            params = self.mat_params(addr, head[:, 3] > 0)
        else:
            params = self.tex[addr + 1]
        lb, size, t = p.lb[idx], p.size[idx], p.t[idx]
        rgba, texel, tile = self.sample(code, usage, params, lb, size, t)
        if op == 13:
            factor, _, _ = self.sample(head[:, 3].astype(np.int32), 1, self.tex[addr + 2].copy(), lb, size, t)
            rgba[:, 3] *= factor[:, 3]
        a = rgba[:, 3]
        colour, normal, spec = usage == 1, usage == 2, usage == 3
        w = (F(1) - p.A[idx]) * a
        p.C[idx] += np.where(colour[:, None], w[:, None] * rgba[:, :3] * p.tint[idx], F(0))
        p.A[idx] += np.where(colour, w, F(0))
        better = colour & (w > p.best_w[idx])
        rows = idx[better]
        p.best_w[rows] = w[better]
        p.best_addr[rows] = addr[better]
        p.best_tile[rows] = tile[better]
        p.best_texel[rows] = texel[better]
        p.best_scope[rows] = self.current_scope(p, rows)
        wn = (F(1) - p.AN[idx]) * a
        p.N[idx] += np.where(normal[:, None], wn[:, None] * (rgba[:, :3] * F(2) - F(1)), F(0))
        p.AN[idx] += np.where(normal, wn, F(0))
        ws = (F(1) - p.AS[idx]) * a
        p.S[idx] += np.where(spec[:, None], ws[:, None] * rgba[:, :2], F(0))
        p.AS[idx] += np.where(spec, ws, F(0))
        done = p.A[idx] >= OPAQUE
        p.active[idx[done]] = False
        rest = idx[~done]
        self.end_layer(p, rest, np.zeros(len(rest), np.int32))

    def finish(self, p: _Pixels) -> Evaluation:
        remaining = (F(1) - p.A)[:, None]
        normal = p.N + (F(1) - p.AN)[:, None] * np.array([0, 0, 1], F)
        normal /= np.maximum(np.linalg.norm(normal, axis=1, keepdims=True), F(1e-6))
        spec = p.S + (F(1) - p.AS)[:, None] * np.array(DEFAULT_SPECULAR, F)
        tile = p.best_tile
        has_tile = tile >= 0
        glass_plane = 3 * np.maximum(tile, 0) + 2
        glass = has_tile & (self.tiles.layers[glass_plane, p.best_texel[:, 1], p.best_texel[:, 0], 2] > 127)
        head = self.tex[np.maximum(p.best_addr, 0)]
        written = (head[:, 0] == 12) & (head[:, 2] == 0) & (head[:, 3] >= 2)  # Color(r, g, b, label)
        constant = np.where(written, head[:, 3].astype(np.int32) - 1, WALL_LABEL)
        label = np.where(has_tile, self.tiles.labels[np.maximum(tile, 0)], np.where(p.best_addr >= 0, constant, 0))
        return Evaluation(
            p.C + remaining * BACKGROUND,
            p.A,
            normal,
            spec,
            p.best_addr,
            tile,
            label,
            glass,
            p.best_scope,
            p.hole,
            p.hole_scope,
        )


_HANDLERS = {
    1: "op_repeat",
    2: "op_repeat",
    3: "op_split",
    4: "op_split",
    5: "op_rand",
    6: "op_rand_uni",
    7: "op_rand_stack",
    8: "op_layer",
    9: "op_skip",
    10: "op_skip_mask",
    11: "op_intrusion",
    12: "op_mat",
    13: "op_mat",
    14: "op_case",
    15: "op_bind",
    16: "op_tint",
    17: "op_overhang",
}


def evaluate(
    compiled: CompiledGrammars,
    start: int,
    uv: np.ndarray,
    facade,
    seed,
    tiles: TileArray,
    directions: np.ndarray | None = None,
    building=(0, 0, 0, 0),
    building_seed=None,
    level=0,
    through=-1,
) -> Evaluation:
    """Evaluates the grammar from rule address `start` at facade points uv (n, 2) in metres;
    `building` is (building.levels, building.style, building.use, building.height) for conditions;
    `building_seed` the building's seed vector (entry 0 of the seed stack; None: `seed`, the facade's);
    `level` facade.level, the storey the facade starts at; `through` a SkipMask's address: what its
    hole shows there (eval.glsl grammar_through; -1 none). start, facade, seed, building,
    building_seed, level and through may also be given per point ((n,) and (n, k)): several facades
    in one evaluation."""
    n = len(uv)
    if directions is None:
        directions = np.broadcast_to(np.array([0, 0, 1], F), (n, 3))
    pixels = _Pixels(n, start, facade, seed, uv, directions, building, building_seed, level, through)
    evaluator = _Evaluator(compiled, tiles)
    evaluator.run(pixels)
    return evaluator.finish(pixels)


def hole_cut(compiled: CompiledGrammars, tiles: TileArray, address: int, uv: np.ndarray) -> np.ndarray:
    """Whether the SkipMask at `address` cuts its hole (skips more layers, op_skip_mask) at points uv
    (n, 2) of its scope in [0, 1], whatever is layered above it: the hole's own shape. Only a mask
    fitted to its scope has one shape (a tiled mask's hole depends on where it is): ValueError else."""
    evaluator = _Evaluator(compiled, tiles)
    head = evaluator.tex[address]
    if head[0] != 10 or head[1] <= 0:
        raise ValueError(f"rule at {address} is not a SkipMask with a fitted (Fit>) mask")
    n = len(uv)
    unit = np.broadcast_to(np.array([0, 0, 1, 1], F), (n, 4))
    zero, one = np.zeros((n, 2), F), np.ones((n, 2), F)
    rgba, _, _ = evaluator.sample(np.full(n, int(head[1])), 1, unit.copy(), zero, one, uv.astype(F))
    return np.where(rgba[:, 3] > F(0.5), head[3] > head[2], head[2] > head[3])


def facade_view(facade, size) -> tuple[np.ndarray, np.ndarray]:
    """Pixel centres (uv in metres, bottom row first) and view rays of the standalone facade render:
    a camera at distance max(w, h) in front of the facade's centre (as shaders/grammar/facade.glsl)."""
    w, h = (F(x) for x in facade)
    cols, rows = size
    x = (np.arange(cols, dtype=F) + F(0.5)) / F(cols) * w
    y = (np.arange(rows, dtype=F) + F(0.5)) / F(rows) * h
    uv = np.stack(np.meshgrid(x, y), axis=-1).reshape(-1, 2)
    rays = np.concatenate([uv - np.array([w, h], F) * F(0.5), np.full((len(uv), 1), max(w, h), F)], axis=1)
    rays /= np.sqrt(np.sum(rays * rays, axis=1, keepdims=True))
    return uv, rays


FACADE_LIGHT = (-0.4, 0.5, 0.75)  # towards the light, tangent space with z out of the wall


def shade(result: Evaluation, rays: np.ndarray, light=FACADE_LIGHT) -> np.ndarray:
    """Lit colour of the standalone render: Phong in tangent space, as shaders/grammar/facade.glsl.
    Normals have z out of the wall; rays have z into it, so the eye lies along (-x, -y, +z)."""
    to_light = np.asarray(light, F) / np.linalg.norm(light)
    diffuse = np.maximum(np.sum(result.normal * to_light, axis=-1), F(0))
    to_eye = rays * np.array([-1, -1, 1], F)
    half = to_light + to_eye
    half /= np.linalg.norm(half, axis=-1, keepdims=True)
    spec = result.specular[..., 0] * np.maximum(np.sum(result.normal * half, axis=-1), F(0)) ** (
        F(1) + F(128) * result.specular[..., 1]
    )
    return result.color * (F(0.35) + F(0.65) * diffuse)[..., None] + spec[..., None]


def evaluate_facade(
    compiled: CompiledGrammars,
    start: int,
    facade,
    size,
    seed,
    tiles: TileArray,
    building=(0, 0, 0, 0),
    building_seed=None,
    level=0,
) -> Evaluation:
    """The standalone facade render on the CPU, colour lit; arrays are (rows, cols, ...), top row first."""
    uv, rays = facade_view(facade, size)
    parts = []
    for first in range(0, len(uv), CHUNK_PIXELS):  # pixels are independent: tiles bound the work arrays
        part = evaluate(
            compiled,
            start,
            uv[first : first + CHUNK_PIXELS],
            facade,
            seed,
            tiles,
            rays[first : first + CHUNK_PIXELS],
            building,
            building_seed,
            level,
        )
        part.color = shade(part, rays[first : first + CHUNK_PIXELS])
        parts.append(part)
    result = Evaluation(**{name: np.concatenate([vars(p)[name] for p in parts]) for name in vars(parts[0])})
    cols, rows = size
    for name, value in vars(result).items():
        setattr(result, name, value.reshape((rows, cols) + value.shape[1:])[::-1])
    return result
