"""What the tests use of cityshade.dataset's internals: its numpy twins and the parts they check one by one."""

from ._arrays import KITTI_MAX, decode, encode
from ._classes import GROUND_CLASSES
from ._manifest import COLUMNS, FILES, check_record, complete_rows, write_manifest
from ._poses import CV_TO_GL
from ._progress import ProgressLines
from ._source import building_tables

__all__ = [
    "COLUMNS",
    "CV_TO_GL",
    "FILES",
    "GROUND_CLASSES",
    "KITTI_MAX",
    "ProgressLines",
    "building_tables",
    "check_record",
    "complete_rows",
    "decode",
    "encode",
    "write_manifest",
]
