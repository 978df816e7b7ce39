"""The frame as a whole: its passes, their GL state, and GL objects that do not pile up."""

from __future__ import annotations

import moderngl
import numpy as np
import pytest

from cityshade.errors import ShaderError, UsageError
from cityshade.frame import HDR, Pass, Target, declared_targets, run_passes
from cityshade.gl import MAX_SAMPLERS, bind_textures, programs, sampler_units, set_uniforms
from cityshade.render import Renderer, RenderSettings, frame_passes
from cityshade.scene import make_city

# Every Context method that creates a GL object.
CREATORS = (
    "buffer",
    "texture",
    "texture_array",
    "texture_cube",
    "depth_texture",
    "framebuffer",
    "renderbuffer",
    "depth_renderbuffer",
    "vertex_array",
    "program",
    "compute_shader",
    "sampler",
    "query",
)


class ObjectCounter:
    """Wraps a context's creating methods and counts the objects made through them that are not
    released yet."""

    def __init__(self, ctx: moderngl.Context):
        self.ctx = ctx
        self.made = []
        for name in CREATORS:
            setattr(ctx, name, self._wrap(getattr(ctx, name)))

    def detach(self):
        for name in CREATORS:
            delattr(self.ctx, name)  # the class's methods again

    def _wrap(self, create):
        def wrapped(*args, **kwargs):
            obj = create(*args, **kwargs)
            self.made.append(obj)
            return obj

        return wrapped

    def live(self) -> dict[str, int]:
        counts: dict[str, int] = {}
        for obj in self.made:
            if not isinstance(obj.mglo, moderngl.InvalidObject):
                counts[type(obj).__name__] = counts.get(type(obj).__name__, 0) + 1
        return counts


@pytest.fixture(scope="module")
def counted_renderer(gl_context):
    counter = ObjectCounter(gl_context)
    renderer = Renderer((48, 32), RenderSettings(samples=2), ctx=gl_context)
    renderer.set_city(make_city("interior", None))
    yield renderer, counter
    renderer.release()
    counter.detach()


def test_live_gl_objects_stay_flat_over_200_frames(counted_renderer):
    renderer, counter = counted_renderer
    camera = renderer.city.city.camera("front")
    for _ in range(3):  # the first frames compile programs and make targets and vertex arrays
        renderer.render(camera)
    before = counter.live()
    for _ in range(200):
        renderer.draw(camera)
    after = counter.live()
    assert sum(before.values()) > 0, "the counter sees the objects the renderer made"
    assert after == before, f"live GL objects grew over 200 frames: {before} -> {after}"


def test_passes_set_the_state_they_rely_on(counted_renderer):
    """A frame drawn after some other code left odd GL state looks the same as one drawn after a frame."""
    renderer, _ = counted_renderer
    camera = renderer.city.city.camera("corner")
    clean = renderer.render(camera)
    ctx = renderer.ctx
    ctx.enable(moderngl.BLEND | moderngl.CULL_FACE)
    ctx.blend_func = moderngl.ONE, moderngl.ONE
    ctx.depth_func = ">"
    ctx.disable(moderngl.DEPTH_TEST)
    ctx.color_mask = (False, True, False, True)
    ctx.depth_mask = False
    after_mess = renderer.render(camera)
    assert (after_mess != clean).any(axis=-1).sum() == 0


@pytest.mark.parametrize(
    "changes",
    [
        {},
        {"depth_prepass": False},
        {"polygonised_interiors": True},
        {"grammar_deferred": False, "shadows": False, "trees": False},
        {"ssao": True, "samples": 0},
        {"grammar_cache": True},
    ],
)
def test_every_pass_reads_targets_written_before_it(changes):
    passes = frame_passes(RenderSettings().with_(**changes))
    declared_targets(passes)  # refuses a read of a target no earlier pass writes
    assert passes[-1].name == "tone map" and passes[-1].writes.name == "display"
    assert len({p.name for p in passes}) == len(passes), "pass names are unique"


def _nothing(f):
    pass


def test_a_pass_reading_a_target_no_earlier_pass_writes_is_refused():
    glow = Target("glow", (("f1", 4),))
    with pytest.raises(UsageError, match="pass 'bloom' reads target 'glow', which no earlier pass writes"):
        declared_targets([Pass("bloom", _nothing, (glow,), HDR), Pass("glow", _nothing, (), glow)])
    with pytest.raises(UsageError, match="pass 'bloom' reads target 'glow', which no earlier pass writes as declared"):
        declared_targets([Pass("glow", _nothing, (), glow), Pass("bloom", _nothing, (Target("glow"),), HDR)])
    with pytest.raises(UsageError, match="pass 'again' declares target 'glow' unlike an earlier pass"):
        declared_targets([Pass("glow", _nothing, (), glow), Pass("again", _nothing, (), Target("glow"))])
    assert declared_targets([Pass("glow", _nothing, (), glow), Pass("bloom", _nothing, (glow,), HDR)]) == [glow, HDR]


def test_a_new_pass_with_its_own_target_runs_through_the_frame(counted_renderer):
    """A pass and its target declared here, and nowhere else: the frame makes the target, binds and
    clears it for the pass, and a later pass reads it."""
    renderer, _ = counted_renderer
    glow = Target("test glow", (("f1", 4),), divisor=2)
    seen = []
    passes = [
        Pass("glow", _nothing, (), glow, clear=(1.0, 0.0, 0.0, 1.0)),
        Pass("read glow", lambda f: seen.append(f.targets[glow.name].read()), (glow,), "nothing"),
    ]
    run_passes(renderer._inputs(renderer.city.city.camera("front")), [*frame_passes(renderer.settings), *passes])
    assert seen[0].shape == (16, 24, 4) and (seen[0] == (255, 0, 0, 255)).all()


def test_profile_times_every_pass(counted_renderer):
    renderer, _ = counted_renderer
    renderer.draw(renderer.city.city.camera("front"), profile=True)
    assert list(renderer.last_pass_seconds) == [p.name for p in frame_passes(renderer.settings)]
    assert all(seconds > 0 for seconds in renderer.last_pass_seconds.values())


def test_a_misspelt_uniform_is_an_error_in_strict_mode(gl_context):
    program = programs(gl_context).get("frame/tonemap.glsl")
    set_uniforms(program, u_hdr=0, u_god_rays=0.5)  # u_god_rays: compiled away without GOD_RAYS
    with pytest.raises(ShaderError, match="u_exposure"):
        set_uniforms(program, u_exposure=1.0)  # in the frame block, not a uniform of its own
    with pytest.raises(ShaderError, match="u_hrd"):
        set_uniforms(program, u_hrd=0)
    with pytest.raises(ShaderError, match="tonemap.glsl declares no uniform 'u_view_proj'"):
        set_uniforms(program, u_view_proj=np.identity(4))  # another program's uniform is an error too


def test_the_shading_block_takes_exactly_its_fields(gl_context):
    from cityshade.gl import SHADING_BLOCK

    values = {name: 0 for name, _, _ in SHADING_BLOCK.fields}
    with pytest.raises(ValueError, match="u_ligths"):
        SHADING_BLOCK.pack({**values, "u_ligths": 0.5})
    assert "u_lit_share" not in programs(gl_context).get("city/ground.glsl"), "a block member, not a uniform"


def test_block_arrays_take_a_vec4_slot_per_element():
    from cityshade.gl import MAX_USES, SHADING_BLOCK

    def zero(kind: str):  # a scalar, or one zero element per slot of an array field
        if not kind.endswith("]"):
            return 0
        base, count = kind[:-1].split("[")
        return np.zeros((int(count), 4) if base == "vec4" else int(count))

    values = {name: zero(kind) for name, kind, _ in SHADING_BLOCK.fields}
    shares = np.arange(1, MAX_USES + 1, dtype=np.float32) / 10
    data = SHADING_BLOCK.pack({**values, "u_lit_share": shares})
    offset = SHADING_BLOCK.offsets()[0]["u_lit_share"]
    assert offset % 16 == 0
    stored = np.frombuffer(data, np.float32, count=4 * MAX_USES, offset=offset).reshape(MAX_USES, 4)
    assert np.array_equal(stored[:, 0], shares) and not stored[:, 1:].any()
    assert "float u_lit_share[8];" in SHADING_BLOCK.glsl()
    with pytest.raises(ValueError, match="u_lit_share: 8 values expected, got 3"):
        SHADING_BLOCK.pack({**values, "u_lit_share": shares[:3]})


def test_one_registry_chooses_each_building_facade():
    from cityshade.render import FACADE_KINDS, choose_facade
    from cityshade.scene import box, cylinder

    assert [k.precedence for k in FACADE_KINDS] == sorted(k.precedence for k in FACADE_KINDS)
    assert len({k.name for k in FACADE_KINDS}) == len(FACADE_KINDS), "each kind registered once"
    assert choose_facade(box((0, 0), 10, 10, 9, style=2)).name == "relief bay"  # the relief bay on boxes
    assert choose_facade(cylinder((0, 0), 6, 9, style=2)).name == "window bay"  # not on curved walls
    assert choose_facade(box((0, 0), 10, 10, 9, style=7)).name == "grammar fig12"  # its windows recessed
    assert choose_facade(box((0, 0), 10, 10, 9, style=4)).name == "grammar brick"
    assert choose_facade(box((0, 0), 10, 10, 9, style=0)).name == "window bay"


@pytest.mark.parametrize(
    "city, changes",
    [
        ("default", {}),
        ("grid", {"polygonised_interiors": True, "shadows": False}),  # the baseline: box buildings
        ("default", {"grammar_deferred": False, "single_atlas": True}),
    ],
)
def test_every_program_of_the_frame_has_at_most_16_samplers(gl_context, city, changes):
    """Texture units are numbered per program; OpenGL 4.3 guarantees 16 per stage."""
    renderer = Renderer((48, 32), RenderSettings(samples=2).with_(**changes), ctx=gl_context)
    renderer.set_city(make_city(city, None))
    camera = next(iter(renderer.city.city.viewpoints.values()))
    renderer.render(camera)
    renderer.render_ids(camera)
    renderer.release()
    counts = {}
    for path, program in programs(gl_context).built():
        if isinstance(program, moderngl.Program):
            units = sampler_units(program)
            used = [
                unit
                for name, first in units.items()
                for unit in range(first, first + max(program[name].array_length, 1))
            ]
            assert sorted(used) == list(range(len(used))), f"{path}: units {units} are not 0..n-1"
            counts[path] = max(counts.get(path, 0), len(used))
    assert counts.get("city/building.glsl", 0) > 10, counts  # the program that sampled the most
    too_many = {path: n for path, n in counts.items() if n > MAX_SAMPLERS}
    assert not too_many, f"programs with more than {MAX_SAMPLERS} samplers: {too_many}"


def test_binding_a_sampler_the_program_lacks_is_an_error_in_strict_mode(gl_context):
    program = programs(gl_context).get("frame/tonemap.glsl")
    texture = gl_context.texture((1, 1), 4)
    try:
        bind_textures(program, {"u_hdr": texture})
        with pytest.raises(ShaderError, match="u_env"):
            bind_textures(program, {"u_env": texture})  # a sampler of other programs, not of this one
    finally:
        texture.release()


def test_the_polygonised_baseline_renders_with_shadows(gl_context):
    """Its exterior and glass variants read fewer cascades, so the compiled shadow arrays are shorter
    than CASCADES; binding the shadows must fit each program (it once raised 'invalid uniform size')."""
    import numpy as np

    city = make_city("grid")
    renderer = Renderer((64, 48), RenderSettings(samples=0, polygonised_interiors=True, shadows=True), ctx=gl_context)
    renderer.set_city(city)
    image = renderer.render(city.camera("orbit")).astype(float)
    renderer.release()
    assert np.isfinite(image).all() and image.std() > 5
