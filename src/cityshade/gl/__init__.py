"""Everything that talks to OpenGL: context creation, shader programs, render targets."""

from ._context import create_context, describe_context
from ._programs import ProgramCache, shader_source
from ._targets import RenderTarget

__all__ = ["create_context", "describe_context", "ProgramCache", "shader_source", "RenderTarget"]
