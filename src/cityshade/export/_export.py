"""`export_city`: a city to a GLB, a .gltf or a 3D Tiles tileset, written whole or not at all."""

from __future__ import annotations

import numbers
import time
from pathlib import Path

from .._files import atomic_output, check_replaceable_folder, output_target
from ..errors import UsageError
from ._bake import ATLAS_LIMIT, MAX_TEXELS
from ._content import BuildingWriter, Stats, add_ground, add_trees, finest_city_texel, simplified
from ._gltf import DEFAULT_ENCODING, GEOMETRY, TEXTURES, TREES, Document, Encoding, glb_bytes, gltf_text
from ._source import ExportCity

FORMATS = ("glb", "gltf", "3dtiles")
TILESET_KIND = "3dtiles"  # a tileset folder's marker kind (_files.OUTPUT_MARKER)
# The texel of each level is texel * 2**level, up to lod + the tileset's 8 levels: these keep it a
# finite, plain size (a texel of 100 m already leaves most walls one texel wide).
MAX_TEXEL = 100.0
MAX_LOD = 16
FINEST_TEXEL = 0.05  # metres: the default texel where the atlas allows it (a brick course is ~0.075 m)
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
    export: ExportCity,
    texel: float,
    lod: int,
    masses=None,
    metadata=None,
    ground: bool = True,
    trees: bool = True,
    place=None,
    encoding: Encoding = DEFAULT_ENCODING,
) -> tuple[object, Stats]:
    """(GLTF2, stats) of the city, or of some of its masses; lod >= 1 simplifies roofs, and each
    level doubles the texel size. With `place` (a 3D Tiles tile: _place.Placement) the content is
    in the tileset's frame and the buildings merged into one primitive per material."""
    masses = export.city.masses if masses is None else masses
    metadata = export.metadata if metadata is None else metadata
    if lod >= 1:
        masses = [simplified(m) for m in masses]
    stats = Stats()
    doc = Document(frame_extras(export), place, encoding)
    BuildingWriter(doc, masses, metadata, texel * 2**lod, stats, merged=place is not None).write()
    if ground:
        add_ground(doc, export.city, stats)
    if trees:
        add_trees(doc, city_trees(export.city), stats)
    gltf = doc.finish()
    stats.draw_calls = sum(len(mesh.primitives) for mesh in gltf.meshes)
    return gltf, stats


def default_texel(export: ExportCity, lod: int = 0) -> float:
    """The finest texel, no finer than FINEST_TEXEL, at which the city's facades fit the atlas
    limits (check_size) at this level of detail; a tileset's coarser levels then fit too (each a
    subset of the buildings at twice the texel)."""
    masses = export.city.masses if lod == 0 else [simplified(m) for m in export.city.masses]
    return finest_city_texel(masses, FINEST_TEXEL * 2**lod) / 2**lod


def default_texel_note(texel: float) -> str:
    """The line the command prints when it chose the texel."""
    return (
        f"--texel {texel:g}: the finest texel (no finer than {FINEST_TEXEL:g} m) at which the facade "
        f"atlas fits its limits ({MAX_TEXELS:,} texels, sides of {ATLAS_LIMIT})"
    )


def check_output(
    out: Path,
    fmt: str,
    texel: float | None = None,
    lod: int = 0,
    encoding: Encoding = DEFAULT_ENCODING,
    viewer: bool = False,
):
    """Fails with one line before any work if the options are out of range or `out` cannot be
    written (a tileset replaces only an earlier tileset, _files.check_replaceable_folder); texel
    None: chosen later (default_texel)."""
    if fmt not in FORMATS:
        raise UsageError(f"--format {fmt!r}: unknown; use one of {', '.join(FORMATS)}")
    if viewer and fmt != "3dtiles":
        raise UsageError(f"--viewer writes a CesiumJS page beside a tileset; add --format 3dtiles (not {fmt})")
    if encoding.textures not in TEXTURES:
        raise UsageError(f"--textures {encoding.textures!r}: unknown; use one of {', '.join(TEXTURES)}")
    if encoding.geometry not in GEOMETRY:
        raise UsageError(f"--geometry {encoding.geometry!r}: unknown; use one of {', '.join(GEOMETRY)}")
    if encoding.trees not in TREES:
        raise UsageError(f"--trees {encoding.trees!r}: unknown; use one of {', '.join(TREES)}")
    if texel is None:
        pass
    elif isinstance(texel, bool) or not isinstance(texel, numbers.Real) or not 0 < texel <= MAX_TEXEL:
        raise UsageError(f"--texel {texel}: give metres per texel, more than 0 and at most {MAX_TEXEL:g}")
    if isinstance(lod, bool) or not isinstance(lod, numbers.Integral) or not 0 <= lod <= MAX_LOD:
        raise UsageError(f"--lod {lod}: give a level from 0 (full detail) to {MAX_LOD}")
    if fmt == "3dtiles":
        check_replaceable_folder(out, TILESET_KIND)
    elif out.is_dir():
        raise UsageError(f"--out {str(out)!r} is a directory; give a file name such as city.{fmt}")
    else:
        output_target(out)


def export_city(
    export: ExportCity,
    out: Path,
    fmt: str = "glb",
    texel: float | None = None,
    lod: int = 0,
    encoding: Encoding = DEFAULT_ENCODING,
    viewer: bool = False,
) -> dict:
    """Writes the export; returns what it wrote (counts, sizes, seconds). texel None: default_texel.
    viewer: a tileset gets its CesiumJS page beside it (index.html, _serve.write_page)."""
    check_output(out, fmt, texel, lod, encoding, viewer)
    began = time.perf_counter()
    if texel is None:
        texel = default_texel(export, lod)
    try:
        summary = _write(export, out, fmt, texel, lod, encoding, viewer)
    except OSError as exc:  # the temporary file or directory beside `out` (nothing is left behind)
        raise UsageError(f"cannot write {str(out)!r}: {exc.strerror or exc}; choose another --out") from None
    summary.update(
        format=fmt,
        out=str(out),
        seconds=round(time.perf_counter() - began, 3),
        bytes=size_of(out),
        texel=texel,
        lod=lod,
        textures=encoding.textures,
        geometry=encoding.geometry,
        trees=encoding.trees,
    )
    return summary


def _write(export: ExportCity, out: Path, fmt: str, texel: float, lod: int, encoding: Encoding, viewer: bool) -> dict:
    if fmt == "3dtiles":
        from ._tiles import write_tileset

        return write_tileset(export, out, texel, lod, encoding, viewer)
    gltf, stats = city_document(export, texel, lod, encoding=encoding)
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
        "draw_calls": stats.draw_calls,
    }


def size_of(path: Path) -> int:
    if path.is_dir():
        return sum(p.stat().st_size for p in path.rglob("*") if p.is_file())
    return path.stat().st_size
