"""What the tests use of cityshade.gl's internals: its numpy twins and the parts they check one by one."""

from ._bindings import BINDINGS, binding_defines, binding_macro
from ._programs import GENERATED

__all__ = ["BINDINGS", "GENERATED", "binding_defines", "binding_macro"]
