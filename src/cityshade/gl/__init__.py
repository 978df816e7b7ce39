"""The GL toolkit, the only code that creates OpenGL objects: the context, programs (one cache per
context), vertex arrays, texture uploads with an explicit colour space, full-screen passes, render
targets and timing."""

from ._bindings import binding
from ._blocks import FRAME_BLOCK, MAX_USES, SHADING_BLOCK, UniformBlock
from ._buffers import DrawBuffers, create_buffer, grow_buffer
from ._colour import linear_to_srgb, srgb_to_linear
from ._context import create_context, describe_context
from ._fullscreen import draw_fullscreen
from ._generated import declare_constants
from ._programs import ProgramCache, shader_source
from ._pyramid import R32F, pyramid_levels, pyramid_texture
from ._resources import draw_buffers, programs
from ._samplers import MAX_SAMPLERS, bind_textures, sampler_units
from ._targets import RenderTarget
from ._textures import upload_cubemap, upload_texture
from ._uniforms import set_uniforms
from ._vertex_arrays import VertexArrays

__all__ = [
    "FRAME_BLOCK",
    "DrawBuffers",
    "create_buffer",
    "grow_buffer",
    "MAX_SAMPLERS",
    "SHADING_BLOCK",
    "MAX_USES",
    "bind_textures",
    "binding",
    "sampler_units",
    "UniformBlock",
    "declare_constants",
    "create_context",
    "describe_context",
    "draw_buffers",
    "draw_fullscreen",
    "linear_to_srgb",
    "programs",
    "pyramid_levels",
    "pyramid_texture",
    "R32F",
    "ProgramCache",
    "shader_source",
    "srgb_to_linear",
    "RenderTarget",
    "upload_cubemap",
    "upload_texture",
    "set_uniforms",
    "VertexArrays",
]
