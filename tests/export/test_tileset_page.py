"""The tileset's CesiumJS page (`export --viewer`) and `cityshade serve`. The page itself is drawn
in headless Chromium by scripts/check-viewer.py in `make validate-export`."""

from __future__ import annotations

import json
import re
import threading
import urllib.error
import urllib.request
from pathlib import Path

import pytest

from cityshade.commands import main
from cityshade.errors import UsageError
from cityshade.export import tileset_server

TAGGED = Path(__file__).parents[1] / "data" / "maps" / "tagged.osm"


@pytest.fixture(scope="module")
def tileset(tmp_path_factory) -> Path:
    out = tmp_path_factory.mktemp("viewer") / "tiles"
    args = ["export", "--map", str(TAGGED), "--out", str(out), "--format", "3dtiles", "--texel", "1", "--viewer"]
    assert main(args) == 0
    return out


def test_viewer_is_written_beside_the_tileset_and_loads_nothing_from_the_internet(tileset):
    marker = json.loads((tileset / ".cityshade-output").read_text())
    assert {"index.html", "viewer.js"} <= set(marker["files"])
    page = (tileset / "index.html").read_text() + (tileset / "viewer.js").read_text()
    assert 'src="cesium/Cesium.js"' in page and "tileset.json" in page
    assert re.findall(r"https?://", page) == []  # no imagery, terrain, token or script from elsewhere
    assert "baseLayer: false" in page and "Cesium3DTileFeature" in page and "${height}" in page


def test_viewer_needs_a_tileset(tmp_path, capsys):
    code = main(["export", "--map", str(TAGGED), "--out", str(tmp_path / "c.glb"), "--viewer"])
    err = capsys.readouterr().err.strip()
    assert code == 2 and len(err.splitlines()) == 1 and "--format 3dtiles" in err
    assert list(tmp_path.iterdir()) == []


def _get(url: str) -> tuple[int, str, bytes]:
    try:
        with urllib.request.urlopen(url, timeout=10) as reply:
            return reply.status, reply.headers["Content-Type"], reply.read()
    except urllib.error.HTTPError as exc:
        return exc.code, "", b""


def test_serve_gives_the_tileset_its_page_and_cesium(tileset, tmp_path):
    cesium = tmp_path / "Build" / "Cesium"
    (cesium / "Widgets").mkdir(parents=True)
    (cesium / "Cesium.js").write_text("var Cesium = {};")
    (cesium / "Widgets" / "widgets.css").write_text("body {}")
    (tmp_path / "secret.txt").write_text("not served")
    server = tileset_server(tileset, cesium, 0)
    thread = threading.Thread(target=server.serve_forever, daemon=True)
    thread.start()
    try:
        host, port = server.server_address[:2]
        assert host == "127.0.0.1"
        base = f"http://127.0.0.1:{port}"
        status, kind, body = _get(f"{base}/")
        assert status == 200 and kind.startswith("text/html") and b"cesium/Cesium.js" in body
        assert _get(f"{base}/cesium/Cesium.js")[2] == b"var Cesium = {};"
        assert _get(f"{base}/cesium/Widgets/widgets.css")[0] == 200
        assert json.loads(_get(f"{base}/tileset.json")[2])["asset"]["version"] == "1.1"
        tile = json.loads((tileset / "tileset.json").read_text())["root"]["content"]["uri"]
        status, kind, body = _get(f"{base}/{tile}")
        assert status == 200 and kind == "model/gltf-binary" and body[:4] == b"glTF"
        assert _get(f"{base}/cesium/../../../secret.txt")[0] == 404
        assert _get(f"{base}/cesium/%2e%2e/%2e%2e/%2e%2e/secret.txt")[0] == 404
    finally:
        server.shutdown()
        server.server_close()


def test_serve_gives_the_page_to_a_tileset_exported_without_it(tileset, tmp_path):
    bare = tmp_path / "bare"
    bare.mkdir()
    (bare / "tileset.json").write_text((tileset / "tileset.json").read_text())
    (tmp_path / "Cesium.js").write_text("")
    server = tileset_server(bare, tmp_path, 0)
    thread = threading.Thread(target=server.serve_forever, daemon=True)
    thread.start()
    try:
        port = server.server_address[1]
        assert b"viewer.js" in _get(f"http://127.0.0.1:{port}/index.html")[2]
        assert b"Cesium3DTileset" in _get(f"http://127.0.0.1:{port}/viewer.js")[2]
    finally:
        server.shutdown()
        server.server_close()


@pytest.mark.parametrize(
    "args, words",
    [
        (["--cesium", "{tmp}/nowhere"], ["Cesium.js", "npm install cesium"]),
        (["--port", "70000"], ["--port 70000", "65535"]),
    ],
)
def test_serve_bad_input_is_one_line(tileset, tmp_path, capsys, args, words):
    (tmp_path / "Cesium.js").write_text("")
    args = [a.replace("{tmp}", str(tmp_path)) for a in args]
    if "--cesium" not in args:
        args += ["--cesium", str(tmp_path)]
    code = main(["serve", str(tileset), *args])
    err = capsys.readouterr().err.strip()
    assert code == 2 and len(err.splitlines()) == 1 and all(w in err for w in words)


def test_serve_needs_a_tileset_folder(tmp_path):
    (tmp_path / "Cesium.js").write_text("")
    with pytest.raises(UsageError, match="no tileset.json"):
        tileset_server(tmp_path, tmp_path, 0)
