"""`cityshade serve`: a 3D Tiles tileset and its CesiumJS page on 127.0.0.1."""

from __future__ import annotations

from pathlib import Path


def register(subparsers):
    parser = subparsers.add_parser("serve", help="serve a 3D Tiles tileset with its CesiumJS page on 127.0.0.1")
    parser.add_argument("folder", type=Path, help="the tileset's folder (cityshade export --format 3dtiles)")
    parser.add_argument("--port", type=int, default=8000, help="port on 127.0.0.1 (0: any free one; default 8000)")
    parser.add_argument(
        "--cesium",
        type=Path,
        default=None,
        help="CesiumJS's Build/Cesium folder (default: ./node_modules/cesium/Build/Cesium, from `npm install cesium`)",
    )
    parser.set_defaults(run=run)


def run(args) -> int:
    from ..export import tileset_server

    server = tileset_server(args.folder, args.cesium, args.port)
    host, port = server.server_address[:2]
    print(f"serving {args.folder} at http://{host}:{port}/ (Ctrl-C stops)", flush=True)
    try:
        server.serve_forever()
    except KeyboardInterrupt:  # Ctrl-C or SIGTERM: the usual end
        pass
    finally:
        server.server_close()
    return 0
