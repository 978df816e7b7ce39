"""What the tests use of cityshade.scene's internals: its numpy twins and the parts they check one by one."""

from ._dormers import DORMER_SPACING, DORMER_WIDTH, END_MARGIN
from ._materials import (
    GUESSED_FLAT_ROOFS,
    GUESSED_ROOF_SPREAD,
    ROOF_MATERIALS,
    ROOF_PART_SHEET,
    ROOF_PART_SURFACE,
    ROOF_SLATE,
    guessed_roof,
    linear,
    roof_part_material,
    roof_pattern,
)
from ._meshes import OUTLINE_TOLERANCE, simplified_outline
from ._roof_units import CLEARANCE, HOUSING_ROOF, rooftop_units, unit_count
from ._roofs import PARAPET_THICKNESS

__all__ = [
    "GUESSED_FLAT_ROOFS",
    "GUESSED_ROOF_SPREAD",
    "guessed_roof",
    "CLEARANCE",
    "DORMER_SPACING",
    "DORMER_WIDTH",
    "END_MARGIN",
    "HOUSING_ROOF",
    "OUTLINE_TOLERANCE",
    "PARAPET_THICKNESS",
    "ROOF_MATERIALS",
    "ROOF_PART_SHEET",
    "ROOF_PART_SURFACE",
    "ROOF_SLATE",
    "linear",
    "roof_part_material",
    "roof_pattern",
    "rooftop_units",
    "simplified_outline",
    "unit_count",
]
