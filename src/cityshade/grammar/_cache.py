"""The grammar page cache: each facade's grammar evaluated once per texel into a fixed atlas of pages,
and the deferred pass shading from it (docs/scale.md, "The grammar cache").

A page is a square of PAGE x PAGE texels of one wall face (a building and its face index) at one
mip level: level L has texels of FINEST_TEXEL * 2^L metres, and a page holds CONTENT x CONTENT of
them plus a border of BORDER texels evaluated past its edges (so bilinear filtering reads across a
page border without a seam). The G-buffer pass writes, per pixel, the page its footprint needs
(shaders/grammar/cache.glsl, grammar_cache_page); the `grammar cache update` pass reads them back,
keeps the pages used this frame, evaluates up to `budget` missing ones that cover at least
RenderSettings.grammar_cache_min_pixels pixels (a page costs PAGE x PAGE texel evaluations, each
about as dear as a pixel's: one seen by few pixels is cheaper evaluated per pixel over the frames it
stays in view) into free or least recently used slots of the atlas (shaders/grammar/cache_page.glsl)
and uploads the page table, a hash table from page key to slot. The evaluation pass then reads
resident pages and evaluates the other pixels per pixel as before.
"""

from __future__ import annotations

import weakref

import moderngl
import numpy as np

from ..gl import RenderTarget, VertexArrays, bind_textures, binding, create_buffer, set_uniforms
from ._gpu import shader_defines

PAGE = 32  # texels per page side, border included (64 measured: 1.75x the texels for the same view)
BORDER = 1  # texels evaluated past each edge of the page's content
CONTENT = PAGE - 2 * BORDER
FINEST_TEXEL = 1.0 / 128.0  # metres per texel at level 0; a pixel finer than this is evaluated per pixel
LEVELS = 16  # 4 bits of the key
MAX_PROBES = 32  # bound of the page table's probe loop
PAGE_BUDGET = 256  # pages evaluated per frame at most (262,144 texels)
# The key: x = building index + 1 (21 bits) | filter level - level << 21 (3 bits) | the face's storeys << 24 (8 bits);
# y = face index (10 bits) | level << 10 (4 bits) | page column << 14 (10 bits) | page row << 24 (8 bits).
PAGE_RECORD = 8  # uint32 per page to evaluate: key x, key y, face width bits, height bits, slot, 0, 0, 0


def cache_defines() -> dict[str, object]:
    """The #defines of shaders/grammar/cache.glsl."""
    return dict(
        GRAMMAR_CACHE_PAGE=PAGE,
        GRAMMAR_CACHE_BORDER=BORDER,
        GRAMMAR_CACHE_CONTENT=CONTENT,
        GRAMMAR_CACHE_TEXEL=f"{FINEST_TEXEL!r}",
        GRAMMAR_CACHE_LEVELS=LEVELS,
        GRAMMAR_CACHE_MAX_PROBES=MAX_PROBES,
    )


def page_hash(keys: np.ndarray) -> np.ndarray:
    """The page table's hash of (N, 2) uint32 keys, as grammar_cache_hash in cache.glsl."""
    k = keys.astype(np.uint32)
    h = (k[:, 0] * np.uint32(0x9E3779B1)) ^ (k[:, 1] * np.uint32(0x85EBCA77))
    h ^= h >> np.uint32(16)
    h *= np.uint32(0x7FEB352D)
    h ^= h >> np.uint32(15)
    return h


def page_table(keys: np.ndarray, slots: np.ndarray, size: int) -> tuple[np.ndarray, int]:
    """Open addressing with linear probing: (size, 4) uint32 entries (key x, key y, slot, 0), an
    empty entry's key x 0, and the longest probe sequence a lookup needs."""
    table = np.zeros((size, 4), np.uint32)
    longest = 1
    for key, slot, h in zip(keys, slots, page_hash(keys)):
        for probe in range(size):
            at = (int(h) + probe) & (size - 1)
            if table[at, 0] == 0:
                table[at] = (key[0], key[1], slot, 0)
                longest = max(longest, probe + 1)
                break
    return table, longest


def needed_pages(requests: np.ndarray) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """The distinct pages the G-buffer asks for ((H, W, 4) uint32: key x, key y, face width and
    height bits; key x 0 where none): their (N, 4) records, keys as uint64 and pixel counts.
    Neighbouring pixels mostly ask for the same page, so runs of equal keys along the rows are
    counted first and only the runs are sorted (a thirtieth of the pixels in a street view)."""
    flat = requests.reshape(-1, 4)
    keys = flat[:, 0].astype(np.uint64) | (flat[:, 1].astype(np.uint64) << np.uint64(32))
    starts = np.flatnonzero(np.concatenate([[True], keys[1:] != keys[:-1]]))
    lengths = np.diff(np.append(starts, len(keys)))
    asked = flat[starts, 0] != 0
    starts, lengths = starts[asked], lengths[asked]
    unique, first, inverse = np.unique(keys[starts], return_index=True, return_inverse=True)
    counts = np.bincount(inverse, weights=lengths, minlength=len(unique)).astype(np.int64)
    return flat[starts[first]], unique, counts


class GrammarPageCache:
    """The atlas of `pages` page slots, which page each holds, when each was last used, and the
    page table on the GPU."""

    def __init__(self, ctx: moderngl.Context, pages: int, budget: int = PAGE_BUDGET):
        self.ctx = ctx
        self.pages = pages
        self.budget = budget
        self.per_row = int(np.ceil(np.sqrt(pages)))
        rows = -(-pages // self.per_row)
        self.atlas_size = (self.per_row * PAGE, rows * PAGE)
        # colour (sRGB) + specular intensity; tangent normal + shininess; glass | view-dependent | label, window centre
        self.atlas = RenderTarget(ctx, self.atlas_size, (("f2", 4), ("f2", 4), ("u4", 4)))
        for texture in self.atlas.colors[:2]:
            texture.filter = (moderngl.LINEAR, moderngl.LINEAR)
        self.table_size = 1 << int(np.ceil(np.log2(2 * pages)))
        self.table = create_buffer(ctx, reserve=self.table_size * 16)
        self.records = create_buffer(ctx, reserve=budget * PAGE_RECORD * 4)
        self.vertex_arrays = VertexArrays(ctx)
        self.probes = 1
        self.frame = 0
        self.stats: dict[str, int] = {}
        self._source = None
        self.flush()

    def flush(self):
        """Forgets every page (a new city, other start rules or grammars)."""
        self.slot_keys = np.zeros(self.pages, np.uint64)  # 0: a free slot
        self.slot_used = np.full(self.pages, -1, np.int64)  # the frame that last read the slot
        self.slot_of: dict[int, int] = {}
        self.table.write(np.zeros((self.table_size, 4), np.uint32))
        self.probes = 1
        self.evicted = 0

    def _check_source(self, f):
        """Flushes when the city or what its records start at changed since the last frame."""
        s = f.view.settings
        source = (s.grammar_start, s.grammar_files)
        city = self._source[0]() if self._source else None
        if city is not f.city or self._source[1] != source:
            self.flush()
            self._source = (weakref.ref(f.city), source)

    def update(self, f, grammar, requests: np.ndarray):
        """Keeps the pages frame `f` asks for (`requests`, the G-buffer's page attachment) and
        evaluates up to `budget` missing ones covering at least grammar_cache_min_pixels pixels into
        the atlas, least recently used slots first."""
        self._check_source(f)
        self.frame += 1
        records, keys, counts = needed_pages(requests)
        slots = np.array([self.slot_of.get(int(k), -1) for k in keys], np.int64)
        self.slot_used[slots[slots >= 0]] = self.frame
        missing = np.flatnonzero((slots < 0) & (counts >= f.view.settings.grammar_cache_min_pixels))
        missing = missing[np.argsort(-counts[missing], kind="stable")][: self.budget]  # the most pixels first
        free = np.flatnonzero(self.slot_keys == 0)
        old = np.flatnonzero((self.slot_keys != 0) & (self.slot_used < self.frame))
        candidates = np.concatenate([free, old[np.argsort(self.slot_used[old], kind="stable")]])
        chosen = missing[: len(candidates)]
        targets = candidates[: len(chosen)]
        for index, slot in zip(chosen, targets):
            if self.slot_keys[slot]:
                del self.slot_of[int(self.slot_keys[slot])]
                self.evicted += 1
            self.slot_of[int(keys[index])] = int(slot)
            self.slot_keys[slot] = keys[index]
            self.slot_used[slot] = self.frame
        if len(chosen):
            self._evaluate(f, grammar, records[chosen], targets)
            resident = np.flatnonzero(self.slot_keys != 0)
            pairs = np.stack(
                [self.slot_keys[resident] & np.uint64(0xFFFFFFFF), self.slot_keys[resident] >> np.uint64(32)], 1
            )
            table, self.probes = page_table(pairs.astype(np.uint32), resident, self.table_size)
            self.table.write(table)
        slots[chosen] = targets
        self.stats = dict(
            requested=len(keys),
            evaluated=len(chosen),
            not_resident=int(np.count_nonzero(slots < 0)),  # their pixels are evaluated per pixel
            resident=int(np.count_nonzero(self.slot_keys)),
            evicted=self.evicted,
            pixels=int(counts.sum()),  # pixels that asked for a page
            pixels_resident=int(counts[slots >= 0].sum()),  # of those, pixels whose page is resident
        )

    def _evaluate(self, f, grammar, records: np.ndarray, slots: np.ndarray):
        """One instanced draw: a quad per page into its slot, evaluating the grammar per texel."""
        data = np.zeros((len(records), PAGE_RECORD), np.uint32)
        data[:, :4] = records
        data[:, 4] = slots
        self.records.write(data)
        program = f.programs.get("grammar/cache_page.glsl", {**shader_defines(), **cache_defines()})
        set_uniforms(program, u_cache_atlas_size=tuple(map(float, self.atlas_size)), u_cache_per_row=self.per_row)
        grammar.bind(program)
        f.city.records.bind_to_storage_buffer(binding("Buildings"))
        self.records.bind_to_storage_buffer(binding("GrammarPageRecords"))
        self.atlas.use()
        self.vertex_arrays.get(id(program), program, []).render(moderngl.TRIANGLES, vertices=6, instances=len(records))

    def bind(self, program):
        """The atlas, the page table and its layout for a program that reads the cache."""
        bind_textures(program, dict(zip(("u_cache_color", "u_cache_normal", "u_cache_ids"), self.atlas.colors)))
        self.table.bind_to_storage_buffer(binding("GrammarPageTable"))
        set_uniforms(
            program,
            u_cache_atlas_size=tuple(map(float, self.atlas_size)),
            u_cache_per_row=self.per_row,
            u_cache_table_mask=self.table_size - 1,
            u_cache_probes=self.probes,
        )

    def release(self):
        self.vertex_arrays.release()
        self.atlas.release()
        self.table.release()
        self.records.release()
