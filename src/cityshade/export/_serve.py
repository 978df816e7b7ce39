"""The CesiumJS page for a tileset: written beside it (`export --viewer`) and served with the
tileset and CesiumJS on 127.0.0.1 (`cityshade serve`), from Python's http.server."""

from __future__ import annotations

import functools
import http.server
import posixpath
import shutil
from importlib import resources
from pathlib import Path
from urllib.parse import unquote, urlsplit

from ..errors import UsageError

PAGE_FILES = ("index.html", "viewer.js")  # the page, in the package's export/viewer/
CESIUM_PREFIX = "/cesium/"  # where the page reads CesiumJS from (its Build/Cesium folder)
CESIUM_NPM = "cesium@1.136.0"  # the version the page is tested with
DEFAULT_CESIUM = Path("node_modules/cesium/Build/Cesium")  # after `npm install cesium` here
CONTENT_TYPES = {
    ".glb": "model/gltf-binary",
    ".json": "application/json",
    ".js": "text/javascript",
    ".wasm": "application/wasm",
}


def page_source(name: str):
    return resources.files("cityshade.export") / "viewer" / name


def write_page(folder: Path):
    """The page's files into a tileset's folder (it reads CesiumJS from cesium/ beside them)."""
    for name in PAGE_FILES:
        with resources.as_file(page_source(name)) as source:
            shutil.copyfile(source, folder / name)


def check_cesium(cesium: Path | None) -> Path:
    """The Build/Cesium folder to serve: `cesium`, else ./node_modules/cesium/Build/Cesium; one line
    saying how to get it when it is missing."""
    folder = DEFAULT_CESIUM if cesium is None else Path(cesium)
    if not (folder / "Cesium.js").is_file():
        where = "--cesium" if cesium is not None else "no --cesium given and"
        raise UsageError(
            f"{where} {str(folder)!r} holds no Cesium.js; run `npm install {CESIUM_NPM}` in this folder "
            "or give --cesium PATH/node_modules/cesium/Build/Cesium"
        )
    return folder


def check_tileset(folder: Path) -> Path:
    if not (Path(folder) / "tileset.json").is_file():
        raise UsageError(
            f"{str(folder)!r} has no tileset.json; give a folder written by `cityshade export --format 3dtiles`"
        )
    return Path(folder)


def _under(root: Path, url_path: str) -> str:
    """The file `url_path` names under `root`; '..' and empty parts are dropped (as http.server does)."""
    parts = [p for p in posixpath.normpath(unquote(url_path)).split("/") if p not in ("", ".", "..")]
    return str(root.joinpath(*parts))


class TilesetHandler(http.server.SimpleHTTPRequestHandler):
    """The tileset's folder, CesiumJS under /cesium/, and the page where the folder has none."""

    extensions_map = {**http.server.SimpleHTTPRequestHandler.extensions_map, **CONTENT_TYPES}

    def __init__(self, *args, tileset: Path, cesium: Path, **kwargs):
        self.tileset, self.cesium = tileset, cesium
        super().__init__(*args, directory=str(tileset), **kwargs)

    def translate_path(self, path: str) -> str:
        url_path = urlsplit(path).path
        if url_path.startswith(CESIUM_PREFIX):
            return _under(self.cesium, url_path[len(CESIUM_PREFIX) :])
        name = "index.html" if url_path == "/" else url_path.lstrip("/")
        if name in PAGE_FILES and not (self.tileset / name).is_file():
            with resources.as_file(page_source(name)) as source:
                return str(source)
        return _under(self.tileset, url_path)

    def log_message(self, format, *args):  # noqa: A002 (http.server's name) - quiet but for errors
        pass

    def log_error(self, format, *args):  # noqa: A002
        super().log_message(format, *args)


def tileset_server(tileset: Path, cesium: Path | None = None, port: int = 8000) -> http.server.ThreadingHTTPServer:
    """A server on 127.0.0.1:port (0: any free port) for the tileset, its page and CesiumJS."""
    if isinstance(port, bool) or not 0 <= port <= 65535:
        raise UsageError(f"--port {port}: give a port from 0 (any free one) to 65535")
    handler = functools.partial(
        TilesetHandler, tileset=check_tileset(tileset).resolve(), cesium=check_cesium(cesium).resolve()
    )
    try:
        return http.server.ThreadingHTTPServer(("127.0.0.1", port), handler)
    except OSError as exc:
        raise UsageError(
            f"--port {port}: cannot listen on 127.0.0.1: {exc.strerror or exc}; choose another port"
        ) from None
