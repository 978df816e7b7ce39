"""What the tests use of cityshade.dataset's internals: its numpy twins and the parts they check one by one."""

from ._classes import GROUND_CLASSES
from ._manifest import COLUMNS, FILES, check_record, complete_rows

__all__ = ["COLUMNS", "FILES", "GROUND_CLASSES", "check_record", "complete_rows"]
