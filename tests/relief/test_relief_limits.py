"""A .cfdm file cannot make cityshade allocate more than its declared, limited, consistent sizes;
inputs that are not regular files are refused."""

from __future__ import annotations

import json
import struct
import tracemalloc
import zlib

import pytest

from cityshade.commands import main
from cityshade.errors import CityshadeError
from cityshade.relief import compress, from_bytes, generate_facade, to_bytes

PREFIX = struct.Struct("<8sII")


@pytest.fixture(scope="module")
def file_bytes():
    return to_bytes(compress(generate_facade(60, 80, texel=0.1), "bmf"))


def forge(data: bytes, change) -> bytes:
    """The file with its header changed by `change(header)` and a correct checksum."""
    magic, version, length = PREFIX.unpack_from(data)
    header = json.loads(data[PREFIX.size : PREFIX.size + length])
    change(header)
    text = json.dumps(header).encode()
    body = PREFIX.pack(magic, version, len(text)) + text + data[PREFIX.size + length : -4]
    return body + struct.pack("<I", zlib.crc32(body))


def _section(header, name):
    return next(s for s in header["sections"] if s["name"] == name)


FORGERIES = {
    "huge shape": (lambda h: h.update(shape=[400000, 400000]), "a facade may have at most"),
    "shape disagrees with sections": (lambda h: h.update(shape=[81, 60]), "make it"),
    "terms disagree with sections": (lambda h: h["terms"].update(depth=h["terms"]["depth"] + 40), "make it"),
    "negative terms": (lambda h: h["terms"].update(depth=-1), "terms"),
    "too many terms": (lambda h: h["terms"].update(depth=10**9), "terms"),
    "section too large": (lambda h: _section(h, "depth.x").update(shape=[10**6, 10**6]), "make it"),
    "offset past the end": (lambda h: _section(h, "boxes").update(offset=10**12), "runs past the end"),
    "nan texel": (lambda h: h.update(texel=float("nan")), "texel must be a positive number"),
    "unknown method": (lambda h: h.update(method="zip"), "unknown method"),
    "missing section": (lambda h: h["sections"].pop(), "missing"),
    "shape not a list": (lambda h: h.update(shape=5), "malformed"),
}


@pytest.mark.parametrize("name", FORGERIES)
def test_forged_headers_with_valid_checksums_are_refused_before_allocating(file_bytes, name):
    change, message = FORGERIES[name]
    forged = forge(file_bytes, change)
    tracemalloc.start()  # numpy reports its arrays to tracemalloc: a forged size would show here
    try:
        with pytest.raises(CityshadeError, match=message) as info:
            from_bytes(forged, "forged.cfdm")
        peak = tracemalloc.get_traced_memory()[1]
    finally:
        tracemalloc.stop()
    assert peak < 8 * len(file_bytes) + 2**20, f"{peak} bytes allocated to refuse a {len(forged)}-byte file"
    assert info.value.exit_code == 2 and "\n" not in str(info.value)


def test_header_length_beyond_the_file(file_bytes):
    body = PREFIX.pack(file_bytes[:8], 1, 10**9) + file_bytes[PREFIX.size : -4]
    with pytest.raises(CityshadeError, match="longer than the file"):
        from_bytes(body + struct.pack("<I", zlib.crc32(body)), "long.cfdm")


def test_the_unforged_file_still_reads(file_bytes):
    assert from_bytes(forge(file_bytes, lambda h: None)).shape == (80, 60)


@pytest.mark.parametrize(
    "args",
    [
        ["compress", "--stats", "/dev/zero"],
        ["compress", "--verify", "/dev/zero"],
        ["grammar", "check", "/dev/zero"],
        ["compress", "/dev/zero", "--out", "x.cfdm"],
    ],
)
def test_endless_inputs_are_refused(args, capsys, tmp_path, monkeypatch):
    monkeypatch.chdir(tmp_path)
    code = main(args)
    err = capsys.readouterr().err.strip().splitlines()
    assert code in (1, 2) and len(err) == 1 and "/dev/zero" in err[0] and "character device" in err[0], err
    assert code == (1 if args[0] == "grammar" else 2)
    assert not list(tmp_path.iterdir())


def test_files_over_the_cap_are_not_read(tmp_path, monkeypatch, file_bytes, capsys):
    import cityshade.relief._format as fmt

    monkeypatch.setattr(fmt, "MAX_FILE_BYTES", 1000)
    path = tmp_path / "big.cfdm"
    path.write_bytes(file_bytes + b"\0" * 1000)
    assert main(["compress", "--stats", str(path)]) == 2
    assert "more than the 1000 bytes" in capsys.readouterr().err
