"""A dataset of a CityJSON city: its buildings are the CityObjects; without streets read it is refused."""

from __future__ import annotations

from pathlib import Path

from cityshade.commands import main

DEN_HAAG = Path(__file__).parents[1] / "data" / "cityjson" / "den_haag_lod2.city.json"


def test_a_cityjson_city_without_streets_is_one_line_and_writes_nothing(tmp_path, capsys):
    # CityJSON roads are drawn as ground of their class, not read as street centrelines yet: the
    # dataset's cameras have nowhere to stand
    out = tmp_path / "ds"
    code = main(["dataset", "--map", str(DEN_HAAG), "--samples", "1", "--out", str(out)])
    err = capsys.readouterr().err.strip()
    assert code == 2 and "has no streets to stand on" in err and "\n" not in err
    assert not out.exists()
