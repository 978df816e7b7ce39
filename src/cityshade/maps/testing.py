"""What the tests use of cityshade.maps's internals: its numpy twins and the parts they check one by one."""

from . import _osm as osm_reader
from ._form import FEATURES as FORM_FEATURES
from ._form import urban_form
from ._load import MAX_CITYJSON_BYTES
from ._masses import STYLE_BY_USE, building_mass, heights, use_code
from ._osm import check_xml
from ._prior import training_rows
from ._roofs import DORMER_EAVES, DORMER_KINDS, DORMER_SHARE, PARAPET, has_dormers
from ._tags import building_attributes, colour, direction, length, use_of

__all__ = [
    "FORM_FEATURES",
    "training_rows",
    "urban_form",
    "MAX_CITYJSON_BYTES",
    "PARAPET",
    "DORMER_EAVES",
    "DORMER_KINDS",
    "DORMER_SHARE",
    "has_dormers",
    "STYLE_BY_USE",
    "building_attributes",
    "building_mass",
    "heights",
    "check_xml",
    "osm_reader",
    "colour",
    "direction",
    "length",
    "use_code",
    "use_of",
]
