"""The compressed-facade file (.cfdm): versioned, checksummed, written atomically.

Layout (little endian):
    8 bytes   magic b"CFDM\\r\\n\\x1a\\n" (catches text-mode and truncated transfers)
    u32       format version
    u32       header length H
    H bytes   UTF-8 JSON header: facade size, texel, depth unit, method, and per section its
              name, dtype, shape and byte offset into the payload
    payload   the arrays: per map X (float32, or bit-packed uint32 for BMF), S, Y; then the boxes
    u32       CRC-32 of every byte before it
"""

from __future__ import annotations

import json
import math
import struct
import zlib
from pathlib import Path

import numpy as np

from .._files import read_input_bytes, write_bytes
from .._json import check_depth
from ..errors import CityshadeError
from ._compress import MAP_NAMES, CompressedFacade
from ._factor import MAX_TERMS, METHODS, Factors
from ._limits import MAX_FILE_BYTES, MAX_TEXELS, check_facade_texels
from ._pack import pack_bits, unpack_bits

MAGIC = b"CFDM\r\n\x1a\n"
VERSION = 1
_PREFIX = struct.Struct("<8sII")


def _sections(facade: CompressedFacade) -> list[tuple[str, np.ndarray]]:
    out = []
    for name in MAP_NAMES:
        f = facade.factors[name]
        if f.method == "bmf":
            x, y = pack_bits(f.x), pack_bits(f.y)
        else:
            x, y = f.x.astype("<f4"), f.y.astype("<f4")
        out += [(f"{name}.x", x), (f"{name}.s", f.s.astype("<f4")), (f"{name}.y", y)]
    out.append(("boxes", facade.boxes.astype("<u2")))
    return out


def to_bytes(facade: CompressedFacade) -> bytes:
    sections, offset, table = _sections(facade), 0, []
    for name, array in sections:
        table.append({"name": name, "dtype": array.dtype.str, "shape": list(array.shape), "offset": offset})
        offset += array.nbytes
    header = {
        "method": facade.method,
        "shape": list(facade.shape),
        "texel": facade.texel,
        "depth_unit": facade.depth_unit,
        "terms": {name: facade.factors[name].terms for name in MAP_NAMES},
        "digests": facade.digests,
        "sections": table,
    }
    header_bytes = json.dumps(header, sort_keys=True).encode("utf-8")
    body = _PREFIX.pack(MAGIC, VERSION, len(header_bytes)) + header_bytes
    body += b"".join(np.ascontiguousarray(a).tobytes() for _, a in sections)
    return body + struct.pack("<I", zlib.crc32(body))


def write_compressed(path: Path, facade: CompressedFacade):
    """Writes to a temporary file beside path, then renames: never a half-written file."""
    write_bytes(Path(path), to_bytes(facade))


def read_compressed(path: Path) -> CompressedFacade:
    return from_bytes(read_input_bytes(Path(path), MAX_FILE_BYTES, "compressed facade file"), str(path))


def from_bytes(data: bytes, source: str = "<bytes>") -> CompressedFacade:
    if len(data) < _PREFIX.size + 4 or data[:8] != MAGIC:
        if MAGIC.startswith(data[:8]) and len(data) < _PREFIX.size + 4:
            raise CityshadeError(f"{source}: truncated compressed facade ({len(data)} bytes)")
        raise CityshadeError(f"{source}: not a compressed facade file (bad magic bytes)")
    _, version, header_len = _PREFIX.unpack_from(data)
    if version != VERSION:
        raise CityshadeError(
            f"{source}: compressed facade format version {version}; this cityshade reads version {VERSION} "
            "(re-run `cityshade compress` to rebuild it)"
        )
    (stored_crc,) = struct.unpack_from("<I", data, len(data) - 4)
    if zlib.crc32(data[:-4]) != stored_crc:
        raise CityshadeError(f"{source}: damaged or truncated compressed facade (checksum mismatch)")
    if header_len > len(data) - _PREFIX.size - 4:
        raise CityshadeError(f"{source}: malformed compressed facade header (longer than the file)")
    try:
        header_bytes = data[_PREFIX.size : _PREFIX.size + header_len]
        check_depth(header_bytes)  # json.loads recurses per level: a deep header would exhaust the stack
        header = json.loads(header_bytes.decode("utf-8"))
        payload = data[_PREFIX.size + header_len : -4]
        expected = _expected_sections(header, source)
        arrays = {}
        for sec in header["sections"]:
            name = sec["name"]
            if name not in expected or name in arrays:
                raise ValueError(f"unexpected section {name!r}")
            dtype_text, shape = expected[name]
            declared = [int(n) for n in sec["shape"]]
            if name == "boxes" and len(declared) == 2 and 0 <= declared[0] <= MAX_TEXELS and declared[1] == 4:
                shape = declared
            if sec["dtype"] != dtype_text or declared != shape:
                raise ValueError(
                    f"section {name} is {sec['dtype']} {declared}; the facade's size and terms "
                    f"make it {dtype_text} {shape}"
                )
            dtype, offset = np.dtype(dtype_text), int(sec["offset"])
            if offset < 0 or offset + math.prod(shape) * dtype.itemsize > len(payload):
                raise ValueError(f"section {name} runs past the end")
            arrays[name] = np.frombuffer(payload, dtype, math.prod(shape), offset).reshape(shape)
        if set(arrays) != set(expected):
            raise ValueError(f"sections {sorted(set(expected) - set(arrays))} are missing")
        factors = {}
        for name in MAP_NAMES:
            terms = header["terms"][name]
            x, s, y = arrays[f"{name}.x"], arrays[f"{name}.s"], arrays[f"{name}.y"]
            if header["method"] == "bmf":
                x, y = unpack_bits(x, terms), unpack_bits(y, terms)
            factors[name] = Factors(header["method"], np.array(x), np.array(s, np.float32), np.array(y))
        return CompressedFacade(
            header["method"],
            float(header["texel"]),
            float(header["depth_unit"]),
            factors,
            np.array(arrays["boxes"], np.uint16),
            {n: str(header["digests"][n]) for n in MAP_NAMES},
        )
    except (KeyError, ValueError, TypeError, UnicodeDecodeError, OverflowError, AttributeError) as exc:
        raise CityshadeError(f"{source}: malformed compressed facade header ({exc})") from None


def _expected_sections(header: dict, source: str) -> dict[str, tuple[str, list[int]]]:
    """Each section's dtype and shape as the header's size, method and terms imply; the declared
    size is checked against the limits before anything is allocated."""
    method = header["method"]
    if method not in METHODS:
        raise ValueError(f"unknown method {method!r}")
    rows, cols = (int(n) for n in header["shape"])
    check_facade_texels(cols, rows, f"{source}: the facade")
    for key in ("texel", "depth_unit"):
        if not (isinstance(header[key], (int, float)) and math.isfinite(header[key]) and header[key] > 0):
            raise ValueError(f"{key} must be a positive number")
    out = {"boxes": ("<u2", ["n", 4])}
    for name in MAP_NAMES:
        terms = header["terms"][name]
        if not (isinstance(terms, int) and 0 <= terms <= MAX_TERMS):
            raise ValueError(f"{name} has {terms!r} terms; at most {MAX_TERMS}")
        width, dtype = (-(-terms // 32), "<u4") if method == "bmf" else (terms, "<f4")
        out.update(
            {f"{name}.x": (dtype, [rows, width]), f"{name}.s": ("<f4", [terms]), f"{name}.y": (dtype, [cols, width])}
        )
    return out
