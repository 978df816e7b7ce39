"""--terrain on the command line: one line and exit code 2 for a bad DEM, nothing written; a DEM
elsewhere warns and the map renders flat."""

from __future__ import annotations

from pathlib import Path

import numpy as np
import pytest

from cityshade.commands import main
from cityshade.terrain.testing import write_dem

TAGGED = Path(__file__).parents[1] / "data" / "maps" / "tagged.osm"


@pytest.mark.parametrize("command", ["render", "export", "tile"])
def test_a_directory_is_one_line_and_exit_code_2(tmp_path, capsys, command):
    out = tmp_path / ("out.png" if command == "render" else "out.glb" if command == "export" else "tiles")
    argv = {
        "render": ["render", "--map", str(TAGGED), "--out", str(out)],
        "export": ["export", "--map", str(TAGGED), "--out", str(out)],
        "tile": ["tile", str(TAGGED), "--out", str(out)],
    }[command] + ["--terrain", str(tmp_path)]
    assert main(argv) == 2
    err = capsys.readouterr().err.strip()
    assert err.count("\n") == 0 and "is a directory" in err and str(tmp_path) in err, err
    assert not out.exists()


@pytest.mark.gl
def test_a_dem_elsewhere_warns_and_renders_flat(tmp_path, capsys):
    far = write_dem(tmp_path / "far.tif", np.ones((10, 10), np.float32), "EPSG:32635", 100000.0, 100000.0, 10.0)
    out = tmp_path / "flat.png"
    assert main(["render", "--map", str(TAGGED), "--terrain", str(far), "--size", "96x54", "--out", str(out)]) == 0
    assert "warning:" in capsys.readouterr().err and out.is_file()


def test_help_says_camera_heights_are_above_the_ground(capsys):
    with pytest.raises(SystemExit):
        main(["render", "--help"])
    text = " ".join(capsys.readouterr().out.split())
    assert "--terrain FILE" in text and "metres above the ground" in text


def test_info_describes_the_terrain(tmp_path, capsys):
    import json

    from cityshade.maps import load_map
    from cityshade.terrain.testing import dem_over

    data = load_map(TAGGED)
    dem = dem_over(tmp_path / "slope.tif", data.crs, data.origin, data.bounds(), lambda x, y: 100.0 + 0.1 * y)
    assert main(["info", str(TAGGED), "--terrain", str(dem), "--json"]) == 0
    terrain = json.loads(capsys.readouterr().out)["terrain"]
    west, south, east, north = data.bounds()
    assert terrain["lowest_m"] < 100.0 + 0.1 * south and terrain["highest_m"] > 100.0 + 0.1 * north
