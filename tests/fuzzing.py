"""What every fuzzer shares: the small budget `make test` runs, the large one `make fuzz` runs for
CITYSHADE_FUZZ_SECONDS, and the property every map reader keeps (a map, or one line naming the file)."""

from __future__ import annotations

import os
import time
from pathlib import Path

from hypothesis import HealthCheck, settings

from cityshade.errors import CityshadeError
from cityshade.maps import load_map

FUZZ_SECONDS = float(os.environ.get("CITYSHADE_FUZZ_SECONDS", "60"))
SMALL = settings(max_examples=25, deadline=None, suppress_health_check=[HealthCheck.too_slow])
LARGE = settings(max_examples=500, deadline=None, suppress_health_check=[HealthCheck.too_slow])


def for_a_while(test):
    """Runs a hypothesis test (a fresh random batch each call) until FUZZ_SECONDS have passed."""
    end = time.monotonic() + FUZZ_SECONDS
    while time.monotonic() < end:
        test()


def loads_or_one_line(path: Path) -> None:
    """`load_map` returns a map or raises one line (exit code 2) that names the file."""
    try:
        load_map(path)
    except CityshadeError as exc:
        message = str(exc)
        assert exc.exit_code == 2 and "\n" not in message and str(path) in message, message
