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
import struct
import zlib
from pathlib import Path

import numpy as np

from .._files import write_bytes
from ..errors import CityshadeError
from ._compress import MAP_NAMES, CompressedFacade
from ._factor import Factors
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
    try:
        data = Path(path).read_bytes()
    except FileNotFoundError:
        raise CityshadeError(f"{path}: no such file") from None
    except OSError as exc:
        raise CityshadeError(f"{path}: cannot read ({exc.strerror})") from None
    return from_bytes(data, str(path))


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
    try:
        header = json.loads(data[_PREFIX.size:_PREFIX.size + header_len].decode("utf-8"))
        payload = data[_PREFIX.size + header_len:-4]
        arrays = {}
        for sec in header["sections"]:
            dtype = np.dtype(sec["dtype"])
            count = int(np.prod(sec["shape"], dtype=np.int64))
            if sec["offset"] + count * dtype.itemsize > len(payload):
                raise ValueError(f"section {sec['name']} runs past the end")
            arrays[sec["name"]] = np.frombuffer(payload, dtype, count, sec["offset"]).reshape(sec["shape"])
        factors = {}
        for name in MAP_NAMES:
            terms = header["terms"][name]
            x, s, y = arrays[f"{name}.x"], arrays[f"{name}.s"], arrays[f"{name}.y"]
            if header["method"] == "bmf":
                x, y = unpack_bits(x, terms), unpack_bits(y, terms)
            factors[name] = Factors(header["method"], np.array(x), np.array(s, np.float32), np.array(y))
        return CompressedFacade(header["method"], float(header["texel"]), float(header["depth_unit"]), factors,
                                np.array(arrays["boxes"], np.uint16), dict(header["digests"]))
    except (KeyError, ValueError, TypeError, UnicodeDecodeError) as exc:
        raise CityshadeError(f"{source}: malformed compressed facade header ({exc})") from None
