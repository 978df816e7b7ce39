"""The generated GLSL includes: text made from Python definitions when programs are built, so a
value or layout is written once (in Python) and never copied into a shader by hand."""

from __future__ import annotations

from ._blocks import FRAME_BLOCK
from ._programs import GENERATED, PRELUDE

GENERATED[FRAME_BLOCK.include] = FRAME_BLOCK.glsl()
PRELUDE.append(FRAME_BLOCK.include)  # shared by all programs: declared in every one
