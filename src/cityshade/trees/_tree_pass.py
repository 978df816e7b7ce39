"""The tree pass: trunks (relief-mapped), silhouette fins, leaf cards and fronds, instanced per
species and LOD, and far trees as impostor cards; and the same trees as shadow casters for the
cascades (§4.2-4.6).

Each tree's LOD alphas come from its distance (`trees.lod_alphas`); a tree in the cross-fade
band is drawn in both LODs with offset alphas that alpha to coverage turns into sample masks.
The mesh gives way to the impostor (trees/_impostor_bake.py) the same way, over a band of the image
rows the tree's height spans.
"""

from __future__ import annotations

from dataclasses import dataclass, replace

import moderngl
import numpy as np
from moderngl import InvalidObject

from ..errors import UsageError
from ..frame import BOX_DTYPE, COMMAND_WORDS, HDR, IDS, Frame, GLState, Pass, frustum_planes, run_cull
from ..gl import VertexArrays, bind_textures, binding, create_buffer, grow_buffer, set_uniforms, upload_texture
from ._cascades import light_basis
from ._generator import (
    BRANCH_ATTRIBUTES,
    BRANCH_LAYOUT,
    CARD_ATTRIBUTES,
    CARD_LAYOUT,
    FROND_ATTRIBUTES,
    FROND_LAYOUT,
    generate_tree,
)
from ._impostor_atlas import ImpostorAtlas
from ._impostor_bake import GPUImpostor, atlas_key, bake_atlas, bounding_sphere, cached_atlas
from ._lod import lod_alphas, vanish_alphas
from ._placement import SPECIES_ORDER
from ._species import SPECIES
from ._textures import bark_textures, leaf_textures
from ._tree_cells import TreeCells

GL_SAMPLE_ALPHA_TO_COVERAGE = 0x809E
# A tree whose height spans fewer image rows than this starts to become its impostor (measured:
# docs/trees.md, scripts/impostor-switch.py).
IMPOSTOR_ROWS = 70.0
BAKED_LOD = 1  # the mesh LOD the impostor shows: the one it takes over from (scripts/impostor-switch.py)
_ATLASES: dict[str, dict[str, np.ndarray]] = {}  # atlas key -> arrays, baked or read once per process
INSTANCE_LAYOUT = "4f 4f/i"
INSTANCE_ATTRIBUTES = ("in_place", "in_params")
PARTS = {  # part -> (program, layout, attributes, extra defines)
    "trunks": ("trees/trunk.glsl", BRANCH_LAYOUT, BRANCH_ATTRIBUTES, {}),
    "fins": ("trees/fins.glsl", BRANCH_LAYOUT, BRANCH_ATTRIBUTES, {}),
    "leaves": ("trees/leaves.glsl", CARD_LAYOUT, CARD_ATTRIBUTES, {}),
    "fronds": ("trees/leaves.glsl", FROND_LAYOUT, FROND_ATTRIBUTES, {"FRONDS": True}),
}
MESHES = ("trunks", "leaves", "fronds")  # each bucket's meshes, in the order of trees/cull.glsl's commands
INSTANCE_FLOATS = 8
INSTANCE_BYTES = INSTANCE_FLOATS * 4
COMMAND_BYTES = len(MESHES) * COMMAND_WORDS * 4  # an instance's draw commands
BARK, LEAF = ("u_bark_color", "u_bark_normal"), ("u_leaf_color", "u_leaf_detail")
BRANCHES = ("trunks", "fins")  # the parts drawn from branch geometry, with bark
PART_SAMPLERS = {"trunks": BARK, "fins": BARK, "leaves": LEAF, "fronds": LEAF}  # the textures each part samples


@dataclass(frozen=True)
class TreeSettings:
    """Each technique of the chapter, switchable, and its tuning."""

    relief: bool = True  # §4.2 relief-mapped bark
    fins: bool = True  # §4.2.1 silhouette fins
    alpha_to_coverage: bool = True  # §4.6 (off: alpha test)
    self_shadow: bool = True  # §4.3.1 per-leaf depth offsets in the shadow look-up
    two_sided: bool = True  # §4.4.1
    shadows: bool = True  # receive the cascaded shadows
    wind: tuple[float, float, float] = (0.35, 0.0, 0.15)  # metres of sway at weight 1
    lod_band: tuple[float, float] = (45.0, 75.0)  # metres: near LOD -> far LOD cross-fade
    vanish_rows: tuple[float, float] = (3.0, 1.5)  # image rows a tree's height spans: fade out between
    fin_fade: tuple[float, float] = (14.0, 28.0)  # metres: fin width -> 0 (fig. 4-8)
    fin_reach: float = 0.2  # metres: clamp of the fin's height trace (§4.2.2)
    specular_fade: tuple[float, float] = (15.0, 60.0)
    leaf_depth: float = 3.0  # self-shadow shift toward the eye at depth offset 1, in card half-sizes
    normal_bias: float = 1.5  # mip bias of the leaf normal fetch (§4.4.2)
    card_shift: float = 1.0  # shadow cards move this many half-sizes toward the light (fig. 4-10)
    impostors: bool = True  # far trees as impostor cards (needs the image's rows: prepare's focal_rows)
    impostor_rows: tuple[float, float] = (IMPOSTOR_ROWS, IMPOSTOR_ROWS * 0.7)  # height in rows: mesh -> impostor

    def __post_init__(self):
        mesh, impostor = self.impostor_rows
        if not mesh > impostor > 0:
            raise UsageError(
                f"impostor_rows {self.impostor_rows!r}: give the rows where the mesh starts to fade, then "
                "the fewer rows where the tree is wholly its impostor, both above 0"
            )

    def with_(self, **changes) -> "TreeSettings":
        return replace(self, **changes)


class _Part:
    """One part (trunks, leaves, fronds) of one species at one LOD, on the GPU."""

    def __init__(self, ctx, vertices: np.ndarray, indices: np.ndarray):
        self.count = len(indices)
        self.vbo = create_buffer(ctx, vertices.astype("f4")) if self.count else None
        self.ibo = create_buffer(ctx, indices.astype("u4")) if self.count else None

    def release(self):
        for buf in (self.vbo, self.ibo):
            if buf is not None:
                buf.release()


class TreePass:
    """All trees of a scene: one model per species, instanced by the records in `trees`."""

    def __init__(
        self, ctx: moderngl.Context, programs, trees: np.ndarray, settings: TreeSettings | None = None, seed: int = 0
    ):
        self.ctx = ctx
        self.programs = programs
        self.settings = settings or TreeSettings()
        self.trees = trees
        self.models = {}
        self.parts = {}  # (species index, lod, part) -> _Part
        for index in sorted(set(int(s) for s in trees["species"])):
            model = generate_tree(SPECIES[SPECIES_ORDER[index]], seed + index)
            self.models[index] = model
            for lod, mesh in enumerate(model.lods):
                self.parts[index, lod, "trunks"] = _Part(ctx, mesh.branches, mesh.branch_indices)
                self.parts[index, lod, "leaves"] = _Part(ctx, mesh.cards, mesh.card_indices)
                self.parts[index, lod, "fronds"] = _Part(ctx, mesh.fronds, mesh.frond_indices)
        bark, leaves = bark_textures(), leaf_textures()
        self._texture_arrays = {
            "u_bark_color": bark.color_height,
            "u_bark_normal": bark.normal,
            "u_leaf_color": leaves.color,
            "u_leaf_detail": leaves.detail,
        }
        self.textures = {
            "u_bark_color": upload_texture(ctx, bark.color_height, "srgb"),
            "u_bark_normal": upload_texture(ctx, bark.normal, "stored", dtype="f1"),
            "u_leaf_color": upload_texture(ctx, leaves.color, "srgb", repeat=False),
            "u_leaf_detail": upload_texture(ctx, leaves.detail, "stored", dtype="f1", repeat=False),
        }
        # (species, lod) -> (instance buffer, trees drawn); the buffers grow to the most trees a frame
        # draws (from the street, a few hundred of a city's hundreds of thousands), not to every tree
        self.instances = {
            (index, lod): (create_buffer(ctx, reserve=INSTANCE_BYTES), 0) for index in self.models for lod in (0, 1)
        }
        # (species, lod) -> draw commands of trees/cull.glsl, one per instance and mesh, grown likewise
        self.commands = {key: create_buffer(ctx, reserve=COMMAND_BYTES) for key in self.instances}
        self.culled = False  # whether the commands of the instances written last are current
        self.impostors: dict[int, GPUImpostor] = {}  # species -> atlas and cards, made when first needed
        self.fin_counts = {index: 0 for index in self.models}  # near-LOD trees that get fins
        # contiguous copies of what every frame reads of every tree (the records' fields are strided)
        self._positions = np.ascontiguousarray(trees["position"], np.float32)
        self._heights = np.ascontiguousarray(self._model_heights()[trees["species"]] * trees["scale"], np.float32)
        self._cells = TreeCells(self._positions, self._heights)
        self._vaos = VertexArrays(ctx)

    # -- per frame -------------------------------------------------------------------------------
    def prepare(self, eye, view_projection: np.ndarray | None = None, focal_rows: float | None = None):
        """Splits the trees into the two LODs by distance and writes their instance buffers, nearest
        first: the fins are drawn only for the leading trees that are close enough to have any
        (§4.2.3 removes them from distant trees), and near-to-far order helps the depth test.
        With `view_projection`, only the trees whose bounds meet its frustum (the camera's, or a
        shadow cascade's, which reaches toward the sun for the casters outside the view). With
        `focal_rows` (the image's rows over 2 tan(fov_y / 2)), trees fade out as their height
        shrinks below TreeSettings.vanish_rows."""
        s = self.settings
        near = self._cells.candidates(eye, view_projection, self.sway(), focal_rows, s.vanish_rows[1])
        distance = np.linalg.norm(self._positions[near] - np.asarray(eye, float), axis=1)
        alphas = (*lod_alphas(distance, *s.lod_band), np.zeros(len(near)))  # near LOD, far LOD, impostor
        if focal_rows is not None:
            rows = self._heights[near] * focal_rows / np.maximum(distance, 1e-6)
            if s.impostors:  # the band is linear in distance: in metres per row
                mesh, impostor = lod_alphas(1.0 / rows, *(1.0 / np.array(s.impostor_rows)), overlap=0.0)
                alphas = (alphas[0] * mesh, alphas[1] * mesh, impostor)
            alphas = tuple(alpha * vanish_alphas(rows, *s.vanish_rows) for alpha in alphas)
        shown = (alphas[0] > 0.0) | (alphas[1] > 0.0) | (alphas[2] > 0.0)
        if view_projection is not None:
            shown &= self._visible(view_projection, near)
        order = np.flatnonzero(shown)  # positions in `near`, sorted after the cuts
        order = order[np.argsort(distance[order], kind="stable")]
        species = self.trees["species"][near[order]]
        for index, model in self.models.items():
            for lod in (0, 1, 2):
                chosen = order[(species == index) & (alphas[lod][order] > 0.0)]
                if lod == 2:
                    if len(chosen) or index in self.impostors:
                        cards = self.impostor(index)
                        cards.count = len(chosen)
                        grow_buffer(cards.instances, len(chosen), INSTANCE_BYTES)
                        cards.instances.write(self._instance_data(near[chosen], alphas[2][chosen]))
                    continue
                if lod == 0:
                    self.fin_counts[index] = int(np.sum(distance[chosen] < s.fin_fade[1] + model.height))
                buffer = self.instances[index, lod][0]
                grow_buffer(buffer, len(chosen), INSTANCE_BYTES)
                buffer.write(self._instance_data(near[chosen], alphas[lod][chosen]))
                self.instances[index, lod] = (buffer, len(chosen))
        self.culled = False

    def _instance_data(self, trees: np.ndarray, alphas: np.ndarray) -> bytes:
        """The instance rows (INSTANCE_LAYOUT) of `trees` (indices) at the given fade alphas."""
        t = self.trees[trees]
        data = np.zeros((len(t), INSTANCE_FLOATS), np.float32)
        data[:, 0:3] = t["position"]
        data[:, 3] = t["yaw"]
        data[:, 4] = t["scale"]
        data[:, 5] = alphas
        data[:, 6] = t["phase"]
        return data.tobytes()

    def impostor(self, species: int) -> GPUImpostor:
        """The species' impostor: its atlas baked from the BAKED_LOD mesh (or read from the cache)
        the first time it is asked for. Baking binds its own framebuffer and draws with depth
        function "<" (the shadow pass's; the tree pass sets its own): the framebuffer bound before
        and the polygon offset are put back."""
        if species in self.impostors:
            return self.impostors[species]
        model = self.models[species]
        mesh = model.lods[BAKED_LOD]
        centre, radius = bounding_sphere(mesh)
        textures = [self._texture_arrays[name] for name in sorted(self._texture_arrays)]
        key = atlas_key(mesh, textures)
        if key not in _ATLASES:
            _ATLASES[key] = cached_atlas(model.species.name, key, lambda: self._bake(species, centre, radius))
        atlas = ImpostorAtlas(_ATLASES[key]["color"], _ATLASES[key]["surface"], centre, radius)
        self.impostors[species] = GPUImpostor(self.ctx, atlas, INSTANCE_BYTES)
        return self.impostors[species]

    def _bake(self, species: int, centre: np.ndarray, radius: float) -> dict[str, np.ndarray]:
        ctx = self.ctx
        saved = ctx.fbo, ctx.polygon_offset
        ctx.polygon_offset = (0.0, 0.0)
        one = create_buffer(ctx, np.array([0, 0, 0, 0, 1, 1, 0, 0], np.float32))  # at the origin, unturned
        vaos = VertexArrays(ctx)
        drawn = {}
        for part in MESHES:
            gpu = self.parts[species, BAKED_LOD, part]
            if gpu.count == 0:
                continue
            _, layout, attributes, _ = PARTS[part]
            program = self._program(part, BAKE=True, NO_SHADOWS=True)
            vao = vaos.get(
                part,
                program,
                [(gpu.vbo, layout, *attributes), (one, INSTANCE_LAYOUT, *INSTANCE_ATTRIBUTES)],
                index_buffer=gpu.ibo,
            )
            drawn[part] = (lambda vao=vao, n=gpu.count: vao.render(moderngl.TRIANGLES, vertices=n), program)

        def bind(program, part):
            bind_textures(program, {name: self.textures[name] for name in PART_SAMPLERS[part]})

        arrays = bake_atlas(ctx, drawn, bind, self.models[species].species, centre, radius)
        vaos.release()
        one.release()
        if saved[0] is not None and not isinstance(saved[0].mglo, InvalidObject):  # none bound, or released since
            saved[0].use()
        ctx.polygon_offset = saved[1]
        return arrays

    def sway(self) -> float:
        """How far the wind can move a tree beyond its model's reach, every way."""
        return float(np.abs(self.settings.wind).sum())

    def cull(self, view_projection: np.ndarray, pyramid: moderngl.Texture | None = None):
        """Culls the prepared instances on the GPU (trees/cull.glsl) against the frustum of
        `view_projection` and, with `pyramid` (render/_visibility.py), the hierarchical depth; the
        draws until the next `prepare` take only the instances kept."""
        for (species, lod), (buffer, count) in self.instances.items():
            if count == 0:
                continue
            counts = tuple(self.parts[species, lod, mesh].count for mesh in MESHES)
            buffer.bind_to_storage_buffer(binding("Instances"))
            grow_buffer(self.commands[species, lod], count, COMMAND_BYTES)
            run_cull(
                self.ctx,
                "trees/cull.glsl",
                count,
                self.commands[species, lod],
                view_projection,
                pyramid,
                u_instance_count=count,
                u_tree_height=self.models[species].height,
                u_sway=self.sway(),
                u_index_counts=counts,
            )
        self.culled = True

    def instance_boxes(self, species: int, lod: int) -> np.ndarray:
        """The boxes trees/cull.glsl tests for one bucket's prepared instances (BOX_DTYPE), in float32 as there."""
        buffer, count = self.instances[species, lod]
        data = np.frombuffer(buffer.read(), np.float32).reshape(-1, INSTANCE_FLOATS)[:count]
        reach = np.float32(self.models[species].height) * data[:, 4] + np.float32(self.sway())
        boxes = np.zeros(count, BOX_DTYPE)
        boxes["lo"][:, :3] = data[:, :3] - reach[:, None]
        boxes["hi"][:, :3] = data[:, :3] + reach[:, None]
        return boxes

    def kept(self, species: int, lod: int) -> np.ndarray:
        """Which of a bucket's prepared instances the last `cull` kept (read back: for tests)."""
        count = self.instances[species, lod][1]
        commands = np.frombuffer(self.commands[species, lod].read(), np.uint32).reshape(-1, COMMAND_WORDS)
        return commands[:count, 1] > 0

    def _visible(self, view_projection: np.ndarray, trees: np.ndarray | None = None) -> np.ndarray:
        """Of `trees` (indices; None: all), those whose box (the model's height, scaled, every way from the root, plus the wind's
        sway) is not wholly outside the frustum: a cube's farthest corner along a plane's normal
        lies its reach times the normal's L1 length beyond its centre (a few vector operations for a
        city's trees, where a corner per plane and tree took a tenth of a second)."""
        planes = frustum_planes(view_projection)
        every = slice(None) if trees is None else trees
        reach = self._heights[every] + self.sway()
        x, y, z = self._positions[every].T.astype(np.float64)
        shown = np.ones(len(x), bool)
        for a, b, c, d in planes:  # plane by plane: a matrix product is slower on a busy machine (BLAS threads)
            shown &= a * x + b * y + c * z + d + reach * (abs(a) + abs(b) + abs(c)) >= 0
        return shown

    def _model_heights(self) -> np.ndarray:
        """Model height by species index."""
        heights = np.zeros(max(self.models, default=0) + 1)
        heights[list(self.models)] = [model.height for model in self.models.values()]
        return heights

    def _vao(self, program, species: int, lod: int, part: str):
        _, layout, attributes, _ = PARTS[part]
        gpu = self.parts[species, lod, "trunks" if part == "fins" else part]
        instances = self.instances[species, lod][0]
        return self._vaos.get(
            (program.glo, species, lod, part),
            program,
            [(gpu.vbo, layout, *attributes), (instances, INSTANCE_LAYOUT, *INSTANCE_ATTRIBUTES)],
            index_buffer=gpu.ibo,
        )

    def _draw_part(self, program, part: str, mode=moderngl.TRIANGLES) -> int:
        bind_textures(program, {name: self.textures[name] for name in PART_SAMPLERS[part]})
        calls = 0
        for (species, lod), (_, prepared) in self.instances.items():
            count = prepared
            if part == "fins":
                count = self.fin_counts[species] if lod == 0 else 0
            gpu = self.parts[species, lod, "trunks" if part == "fins" else part]
            if count == 0 or gpu.count == 0:
                continue
            if part in BRANCHES:
                bark = self.models[species].species
                set_uniforms(
                    program,
                    u_bark_layer=float(bark.bark_layer),
                    u_relief_depth=bark.relief_depth,
                    u_bark_tile=bark.bark_tile,
                )
            vao = self._vao(program, species, lod, part)
            if self.culled:  # one command per instance, in instance order (trees/cull.glsl)
                first = MESHES.index("trunks" if part == "fins" else part) * prepared
                vao.render_indirect(self.commands[species, lod], mode, count=count, first=first)
            else:
                vao.render(mode, vertices=gpu.count, instances=count)
            calls += 1
        return calls

    def _program(self, part: str, **defines):
        path, _, _, extra = PARTS[part]
        return self.programs.get(path, {**extra, **{k: v for k, v in defines.items() if v}})

    def _common(self) -> dict:
        return dict(u_wind=np.array(self.settings.wind, float))

    def draw(
        self,
        uniforms: dict,
        view: np.ndarray,
        shadows=None,
        parts=("trunks", "fins", "leaves", "fronds", "impostors"),
        ids: bool = False,
        env: moderngl.TextureCube | None = None,
    ) -> int:
        """Main pass into the bound (multisampled HDR) target. `uniforms` holds u_view_proj; the
        camera, sun, sky and time come from the frame block (cityshade.gl.FRAME_BLOCK), which the
        caller writes. `view` is the camera's view matrix (its rows give the axes the leaf cards
        span). With `ids`, the id AOV into the bound uint target instead: FACE_TRUNK on trunks and
        fins, FACE_FOLIAGE on leaves and fronds, alpha-tested (a face code cannot be a coverage
        mix). `env` is the sky's radiance, for the leaves' sky light. Returns the number of draw calls.
        Into a target without multisampling, where alpha to coverage does nothing (every fragment
        is written whatever its alpha, so a level fading out would vanish at once), the LOD fades
        dither with the fizzle instead."""
        s, ctx = self.settings, self.ctx
        multisampled = ctx.fbo is not None and ctx.fbo.samples > 0
        alpha_to_coverage = s.alpha_to_coverage and multisampled and not ids
        base = dict(
            ALPHA_TO_COVERAGE=alpha_to_coverage, NO_SHADOWS=not (s.shadows and shadows is not None), ID_PASS=ids
        )
        cards = {
            "u_card_right": view[0, :3],
            "u_card_up": view[1, :3],
            "u_card_shift": np.zeros(3),
            "u_specular_fade": np.array(s.specular_fade),
            "u_leaf_depth": s.leaf_depth,
            "u_normal_bias": s.normal_bias,
        }
        values = {
            "trunks": {},
            "fins": {"u_fin_fade": np.array(s.fin_fade), "u_fin_reach": s.fin_reach},
            "leaves": cards,
            "fronds": cards,
        }  # each part's own uniforms, beside the shared ones
        programs = {
            "trunks": self._program("trunks", RELIEF=s.relief, **base),
            "fins": self._program("fins", **base),
            "leaves": self._program("leaves", LEAF_SELF_SHADOW=s.self_shadow, TWO_SIDED=s.two_sided, **base),
            "fronds": self._program("fronds", TWO_SIDED=s.two_sided, **base),
        }
        ctx.enable(moderngl.DEPTH_TEST)
        ctx.depth_func = "<="
        if alpha_to_coverage:
            ctx.enable_direct(GL_SAMPLE_ALPHA_TO_COVERAGE)
        calls = 0
        for part in (p for p in parts if p in PARTS):  # the meshes; impostors below
            if part == "fins" and not s.fins:
                continue
            program = programs[part]
            set_uniforms(program, **uniforms, **self._common(), **values[part])
            if env is not None:
                bind_textures(program, {"u_env": env})
            if shadows is not None:
                shadows.bind(program)
            if part == "trunks":
                ctx.enable(moderngl.CULL_FACE)
            calls += self._draw_part(program, part)
            ctx.disable(moderngl.CULL_FACE)
        if "impostors" in parts:
            program = self.programs.get("trees/impostor.glsl", {**base, "TWO_SIDED": s.two_sided})
            set_uniforms(program, **uniforms, u_specular_fade=np.array(s.specular_fade))
            if shadows is not None:
                shadows.bind(program)
            calls += self._draw_impostors(program)
        ctx.disable_direct(GL_SAMPLE_ALPHA_TO_COVERAGE)
        return calls

    def _draw_impostors(self, program) -> int:
        """The prepared impostor cards, one instanced strip of four vertices per species."""
        calls = 0
        for species, impostor in self.impostors.items():
            if impostor.count == 0:
                continue
            set_uniforms(program, **impostor.uniforms())
            bind_textures(program, {"u_impostor_color": impostor.color, "u_impostor_surface": impostor.surface})
            vao = self._vaos.get(
                (program.glo, species, "impostors"),
                program,
                [(impostor.instances, INSTANCE_LAYOUT, *INSTANCE_ATTRIBUTES)],
            )
            vao.render(moderngl.TRIANGLE_STRIP, vertices=4, instances=impostor.count)
            calls += 1
        return calls

    def draw_shadow(self, view_proj: np.ndarray, sun_dir, casters) -> int:
        """The trees' casters of one cascade; leaf cards face the light and move toward it.
        Impostor cards, whole trees, cast wherever leaves do (every cascade), facing the light."""
        right, up = light_basis(sun_dir)
        cards = {
            "u_card_right": right,
            "u_card_up": up,
            "u_card_shift": np.asarray(sun_dir, float) * self.settings.card_shift,
        }
        calls = 0
        for part in ("trunks", "fronds", "leaves"):
            if part not in casters:
                continue
            program = self._program(part, SHADOW_PASS=True)
            set_uniforms(program, **self._common(), u_view_proj=view_proj, **({} if part in BRANCHES else cards))
            calls += self._draw_part(program, part)
        if "leaves" in casters:
            program = self.programs.get("trees/impostor.glsl", {"SHADOW_PASS": True})
            set_uniforms(program, u_view_proj=view_proj, u_light_dir=np.asarray(sun_dir, float))
            calls += self._draw_impostors(program)
        return calls

    def release(self):
        self._vaos.release()
        for impostor in self.impostors.values():
            impostor.release()
        for part in self.parts.values():
            part.release()
        for buffer, _ in self.instances.values():
            buffer.release()
        for buffer in self.commands.values():
            buffer.release()
        for tex in self.textures.values():
            tex.release()


def draw_trees(f: Frame, ids: bool = False) -> int:
    """The frame's tree pass (after the ground, before the sky), or with `ids` the id AOV's."""
    trees, view = f.technique(TreePass), f.view
    if trees is None:
        return 0
    # only the trees in view: a multi-draw's commands cost a software rasteriser even when culled
    trees.prepare(view.camera.eye, view.view_projection, view.focal_rows)
    if view.settings.culling == "gpu" and not ids:  # behind the buildings' hierarchical depth, when this frame built it
        trees.cull(view.view_projection, f.depth_pyramid)
    return trees.draw(
        {"u_view_proj": view.view_projection},
        view.camera.view(),
        None if ids else f.shadows,
        ids=ids,
        env=f.env,
    )


def draw_tree_ids(f: Frame) -> int:
    return draw_trees(f, ids=True)


def tree_pass(shadows: tuple[str, ...]) -> Pass:
    """Trunks, fins, leaf cards, fronds with alpha to coverage (TreePass.draw sets cull per part),
    receiving the shadow maps if `shadows` names them."""
    return Pass("trees", draw_trees, ("trees", "tree textures", "environment", *shadows), HDR, GLState(depth_func="<="))


# trunks and fins FACE_TRUNK, leaf cards and fronds FACE_FOLIAGE, alpha-tested
TREE_ID_PASS = Pass("tree ids", draw_tree_ids, ("trees", "tree textures"), IDS, GLState(depth_func="<="))
