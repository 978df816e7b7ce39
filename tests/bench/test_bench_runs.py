"""`cityshade bench NAME --quick` for every benchmark: the JSON records how it timed and what each
compared method ran with. Marked slow (minutes each on two cores: `make test-slow`); speed itself
is never asserted."""

from __future__ import annotations

import json

import numpy as np
import pytest

from cityshade.bench.testing import MIN_TIMED_FRAMES
from cityshade.commands import main
from cityshade.commands.bench import BENCHMARKS

pytestmark = [pytest.mark.slow, pytest.mark.gl]  # renders through the command line
# benchmarks of pipeline stages (reading, guessing, exporting, writing samples), each timed in
# repeated runs and described in their notes, not frame by frame
STAGE_TIMED = {"cityjson", "dataset", "export", "guesses"}
STAGES_AND_FRAMES = {"osm"}  # loads and tiles, and one street frame against the district's, interleaved
METHOD_KEYS = {"cull_back_faces": bool, "depth_prepass": bool, "frustum_culling": bool, "msaa": int, "size": list}


# `bench scale --quick` draws 100,000-building frames (a minute each on two cores): 3 per camera
# path, not MIN_TIMED_FRAMES; its own check is below
@pytest.mark.parametrize("name", sorted(set(BENCHMARKS) - {"scale"}))
def test_quick_run_records_timing_and_methods(tmp_path, name):
    path = tmp_path / f"{name}.json"
    assert main(["bench", name, "--quick", "--out-dir", str(tmp_path / "out"), "--json", str(path)]) == 0
    data = json.loads(path.read_text())
    assert data["ratios"] or data["tables"], "a benchmark reports numbers"
    assert all(np.isfinite(v) for v in data["ratios"].values() if isinstance(v, float))
    assert data["notes"] or data["methods"], "every benchmark says how it measured"
    if name in STAGE_TIMED:
        assert not data["timing"], "stages are timed run by run, not frame by frame"
        return
    assert data["timing"]["interleaved"] is True and data["timing"]["samples_per_point"] >= MIN_TIMED_FRAMES
    if name in STAGES_AND_FRAMES:
        return
    assert len(data["methods"]) >= 2
    for method, record in data["methods"].items():
        for key, kind in METHOD_KEYS.items():
            assert isinstance(record[key], kind), f"{method}: {key}"
        assert len(record["size"]) == 2
    assert any("IQR" in column for table in data["tables"] for column in table["columns"])


def test_quick_scale_run_measures_every_ratio_or_says_why_not(tmp_path):
    path = tmp_path / "scale.json"
    assert main(["bench", "scale", "--quick", "--out-dir", str(tmp_path / "out"), "--json", str(path)]) == 0
    data = json.loads(path.read_text())
    assert data["timing"]["interleaved"] is True and data["timing"]["quick"] is True
    assert data["timing"]["frames_per_path"] == data["timing"]["samples_per_point"] >= 3
    for method, record in data["methods"].items():
        for key, kind in METHOD_KEYS.items():
            assert isinstance(record[key], kind), f"{method}: {key}"
        assert record["size"] == [1024, 768]
    for name in (
        "street_100k_over_1k",
        "aerial_100k_over_1k",
        "grammar_cache_speedup",
        "bytes_per_building",
        "culled_pixels_differing",
        "viewer_fps_llvmpipe",
    ):
        value = data["ratios"][name]
        assert (value is None) == (name in data["missing"]), name
        assert value is None or np.isfinite(value)
    frames = data["tables"][0]
    assert {row[0] for row in frames["rows"]} == {"generator", "osm"} and max(row[1] for row in frames["rows"]) > 90_000
