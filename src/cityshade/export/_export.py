"""`export_city`: a city to a GLB, a .gltf or a 3D Tiles tileset, written whole or not at all."""

from __future__ import annotations

import os
import shutil
import tempfile
import time
from pathlib import Path

from .._files import atomic_output
from ..errors import UsageError
from ._content import BuildingWriter, Stats, add_ground, add_trees, simplified
from ._gltf import Document, glb_bytes, gltf_text
from ._source import ExportCity

FORMATS = ("glb", "gltf", "3dtiles")
ATTRIBUTION = "© OpenStreetMap contributors, ODbL 1.0"


def frame_extras(export: ExportCity) -> dict:
    """The scene frame and, for maps, where it stands on Earth (asset and scene `extras`)."""
    extras = {"units": "metres", "frame": "x east, y up, z south (north is -z)"}
    if export.origin is not None:
        extras.update(
            origin={"longitude": export.origin[0], "latitude": export.origin[1], "height": 0.0},
            crs=export.crs,
            attribution=ATTRIBUTION,
            note="scene (x, z) = map metres (east, -north) from the origin in the crs",
        )
    return extras


def city_trees(city):
    from ..trees import city_trees as layout_trees

    return layout_trees(city) if city.trees is None else city.trees


def city_document(
    export: ExportCity, texel: float, lod: int, masses=None, metadata=None, ground: bool = True, trees: bool = True
) -> tuple[object, Stats]:
    """(GLTF2, stats) of the city, or of some of its masses; lod >= 1 simplifies roofs, and each
    level doubles the texel size."""
    masses = export.city.masses if masses is None else masses
    metadata = export.metadata if metadata is None else metadata
    if lod >= 1:
        masses = [simplified(m) for m in masses]
    stats = Stats()
    doc = Document(frame_extras(export))
    BuildingWriter(doc, masses, metadata, texel * 2**lod, stats).write()
    if ground:
        add_ground(doc, export.city, stats)
    if trees:
        add_trees(doc, city_trees(export.city), stats)
    return doc.finish(), stats


def check_output(out: Path, fmt: str):
    """Fails with one line before any work if `out` cannot be written."""
    if fmt not in FORMATS:
        raise UsageError(f"--format {fmt!r}: unknown; use one of {', '.join(FORMATS)}")
    if fmt != "3dtiles" and out.is_dir():
        raise UsageError(f"--out {str(out)!r} is a directory; give a file name such as city.{fmt}")
    if fmt == "3dtiles" and out.exists() and not out.is_dir():
        raise UsageError(f"--out {str(out)!r} is a file; a tileset is written to a directory")
    if fmt == "3dtiles" and out.is_dir() and any(out.iterdir()) and not (out / "tileset.json").is_file():
        # the directory is replaced as a whole: only ever an earlier tileset
        raise UsageError(f"--out {str(out)!r} holds files but no tileset.json; give a new directory for the tileset")
    folder = out.absolute().parent
    probe = folder
    while not probe.exists():
        probe = probe.parent
    if not probe.is_dir() or not os.access(probe, os.W_OK | os.X_OK):
        raise UsageError(f"cannot write {str(out)!r}: {str(probe)!r} is not a writable directory; choose another --out")


def write_directory(out: Path, fill) -> None:
    """Fills a temporary directory beside `out` with `fill(path)`, then puts it in out's place."""
    out.absolute().parent.mkdir(parents=True, exist_ok=True)
    tmp = Path(tempfile.mkdtemp(prefix=f".{out.name}.", dir=out.absolute().parent))
    try:
        fill(tmp)
        umask = os.umask(0)
        os.umask(umask)
        os.chmod(tmp, 0o777 & ~umask)
        if out.exists():
            old = out.with_name(f".{out.name}.old")
            os.replace(out, old)
            os.replace(tmp, out)
            shutil.rmtree(old)
        else:
            os.replace(tmp, out)
    finally:
        if tmp.exists():
            shutil.rmtree(tmp)


def export_city(export: ExportCity, out: Path, fmt: str = "glb", texel: float = 0.05, lod: int = 0) -> dict:
    """Writes the export; returns what it wrote (counts, sizes, seconds)."""
    check_output(out, fmt)
    if not texel > 0:
        raise UsageError(f"--texel {texel}: must be a positive number of metres per texel")
    if lod < 0:
        raise UsageError(f"--lod {lod}: must be 0 (full detail) or more")
    began = time.perf_counter()
    try:
        summary = _write(export, out, fmt, texel, lod)
    except OSError as exc:  # the temporary file or directory beside `out` (nothing is left behind)
        raise UsageError(f"cannot write {str(out)!r}: {exc.strerror or exc}; choose another --out") from None
    summary.update(
        format=fmt,
        out=str(out),
        seconds=round(time.perf_counter() - began, 3),
        bytes=size_of(out),
        texel=texel,
        lod=lod,
    )
    return summary


def _write(export: ExportCity, out: Path, fmt: str, texel: float, lod: int) -> dict:
    if fmt == "3dtiles":
        from ._tiles import write_tileset

        return write_tileset(export, out, texel, lod)
    gltf, stats = city_document(export, texel, lod)
    with atomic_output(out) as tmp:
        if fmt == "glb":
            tmp.write_bytes(glb_bytes(gltf))
        else:
            tmp.write_text(gltf_text(gltf), encoding="utf-8")
    return summary_of(stats)


def summary_of(stats: Stats) -> dict:
    return {
        "buildings": stats.buildings,
        "triangles": stats.triangles,
        "tree_instances": stats.tree_instances,
        "facade_m2": round(stats.facade_area, 1),
        "atlas_pages": [list(s) for s in stats.atlas_sizes],
        "atlas_texels": stats.atlas_texels,
    }


def size_of(path: Path) -> int:
    if path.is_dir():
        return sum(p.stat().st_size for p in path.rglob("*") if p.is_file())
    return path.stat().st_size
