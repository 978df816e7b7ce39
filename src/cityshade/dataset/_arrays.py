"""A sample's arrays as files: compressed NumPy (`.npz`, one array named `array`) or OpenEXR (ZIP
compression; 32-bit FLOAT channels, 16-bit HALF for float16 arrays), and depth as KITTI's 16-bit
PNG (metres x 256, 0 = no value).

Files are read back only after their headers say they hold a 2-D or 3-D array of a dataset's size
and kind (a dataset folder may come from anyone): an `.npz`'s member is checked in its zip directory
and its `.npy` header before it is inflated, an EXR's data window before its pixels are read.
"""

from __future__ import annotations

import io
import zipfile

import numpy as np
from PIL import Image

from ._limits import MAX_IMAGE_SIDE, MAX_SAMPLE_FILE_BYTES

FORMATS = ("npz", "exr")  # the config's output.arrays
NPZ_MEMBER = "array"
EXR_CHANNELS = {1: ("Z",), 3: ("X", "Y", "Z")}  # one value (depth, distance) or a vector (normals)
KITTI_SCALE = 256.0  # KITTI depth PNGs: uint16 = metres x 256, 0 where there is no depth
KITTI_MAX = 65535 / KITTI_SCALE  # 255.996 m: farther depth is written as 0 (no value)


class ArrayFileError(ValueError):
    """Raised with a short reason when a file is not an array a dataset holds."""


# zlib's fastest level: measured on Helsinki samples at 320x240, 53 ms a sample for its four arrays
# and 412 kB, against level 6 (np.savez_compressed's) 94 ms and 387 kB
NPZ_LEVEL = 1


def encode_npz(array: np.ndarray) -> bytes:
    """An `.npz` as np.savez_compressed writes it (one member `array.npy`), at zlib level NPZ_LEVEL."""
    member = io.BytesIO()
    np.save(member, array)
    buffer = io.BytesIO()
    with zipfile.ZipFile(buffer, "w", zipfile.ZIP_DEFLATED, compresslevel=NPZ_LEVEL) as archive:
        archive.writestr(
            zipfile.ZipInfo(f"{NPZ_MEMBER}.npy", date_time=(1980, 1, 1, 0, 0, 0)),
            member.getvalue(),
            compress_type=zipfile.ZIP_DEFLATED,
            compresslevel=NPZ_LEVEL,
        )
    return buffer.getvalue()


def encode_exr(array: np.ndarray) -> bytes:
    """HxW or HxWx3 float32 (FLOAT channels) or float16 (HALF) as a scanline EXR, ZIP-compressed."""
    import OpenEXR

    planes = array[..., None] if array.ndim == 2 else array
    dtype = np.float16 if array.dtype == np.float16 else np.float32
    channels = {
        name: np.ascontiguousarray(planes[..., k], dtype) for k, name in enumerate(EXR_CHANNELS[planes.shape[-1]])
    }
    header = {"compression": OpenEXR.ZIP_COMPRESSION, "type": OpenEXR.scanlineimage}
    buffer = io.BytesIO()
    OpenEXR.File(header, channels).write(buffer)
    return buffer.getvalue()


def encode(array: np.ndarray, fmt: str) -> bytes:
    return encode_exr(array) if fmt == "exr" else encode_npz(array)


def kitti_depth(z: np.ndarray) -> np.ndarray:
    """HxW uint16 KITTI depth: round(z x 256), 0 on the sky and beyond KITTI_MAX."""
    valid = np.isfinite(z) & (z > 0) & (z <= KITTI_MAX)
    return np.where(valid, np.round(np.where(valid, z, 0.0) * KITTI_SCALE), 0).astype(np.uint16)


def encode_png16(image: np.ndarray) -> bytes:
    buffer = io.BytesIO()
    Image.fromarray(image.astype(np.uint16)).save(buffer, format="PNG")
    return buffer.getvalue()


def _checked_shape(shape, dtype: np.dtype, kinds: str):
    fits = (
        dtype.kind in kinds
        and len(shape) in (2, 3)
        and 0 < min(shape)
        and max(shape[:2]) <= MAX_IMAGE_SIDE
        and (len(shape) == 2 or shape[2] <= 4)
    )
    if not fits:
        raise ArrayFileError(f"a {dtype} array of shape {tuple(shape)}, not a dataset's image")


def decode_npy(data: bytes, kinds: str) -> np.ndarray:
    """A `.npy` file's array of a dtype kind in `kinds`, its header checked before it is allocated."""
    buffer = io.BytesIO(data)
    fmt = np.lib.format
    try:
        version = fmt.read_magic(buffer)
        header = {(1, 0): fmt.read_array_header_1_0, (2, 0): fmt.read_array_header_2_0}.get(version)
        if header is None:
            raise ArrayFileError("not a readable .npy array")
        shape, _, dtype = header(buffer)
        _checked_shape(shape, dtype, kinds)
        if int(np.prod(shape)) * dtype.itemsize > len(data) - buffer.tell():
            raise ArrayFileError("a truncated .npy array")
        return np.load(io.BytesIO(data), allow_pickle=False)
    except ArrayFileError:
        raise
    except (OSError, ValueError, SyntaxError, EOFError, TypeError):
        raise ArrayFileError("not a readable .npy array") from None


def decode_npz(data: bytes, kinds: str) -> np.ndarray:
    """The array of a dataset's `.npz` (one member, `array.npy`), its sizes checked before inflating."""
    try:
        with zipfile.ZipFile(io.BytesIO(data)) as archive:
            members = archive.infolist()
            if len(members) != 1 or members[0].filename != f"{NPZ_MEMBER}.npy":
                raise ArrayFileError(f"not a dataset's .npz (one array named {NPZ_MEMBER!r})")
            if members[0].file_size > MAX_SAMPLE_FILE_BYTES:
                raise ArrayFileError(f"{members[0].file_size} bytes unpacked, more than a dataset's image")
            return decode_npy(archive.read(members[0]), kinds)
    except ArrayFileError:
        raise
    except (zipfile.BadZipFile, OSError, ValueError, EOFError, NotImplementedError):
        raise ArrayFileError("not a readable .npz archive") from None


def decode_exr(data: bytes) -> np.ndarray:
    """A dataset EXR's float32 array (HxW for one channel, HxWx3 for X, Y, Z)."""
    import OpenEXR

    try:
        with OpenEXR.File(io.BytesIO(data), header_only=True) as probe:
            (x0, y0), (x1, y1) = probe.header()["dataWindow"]
        _checked_shape((y1 - y0 + 1, x1 - x0 + 1), np.dtype(np.float32), "f")
        with OpenEXR.File(io.BytesIO(data)) as image:
            channels = image.channels()
            names = next((n for n in EXR_CHANNELS.values() if set(n) == set(channels)), None)
            if names is None:
                raise ArrayFileError(f"EXR channels {', '.join(sorted(channels))}, not a dataset's")
            planes = [np.asarray(channels[name].pixels) for name in names]
            if any(plane.dtype.kind != "f" for plane in planes):
                raise ArrayFileError("EXR channels not of floats, not a dataset's")
    except ArrayFileError:
        raise
    except Exception as exc:  # OpenEXR raises plain exceptions on damaged files
        raise ArrayFileError(f"not a readable EXR image ({type(exc).__name__})") from None
    return planes[0] if len(planes) == 1 else np.stack(planes, axis=-1)


def decode(data: bytes, name: str, kinds: str = "f") -> np.ndarray:
    """An array file by its name's extension: .npz, .exr or .npy (datasets written before .npz)."""
    if name.endswith(".exr"):
        return decode_exr(data)
    if name.endswith(".npz"):
        return decode_npz(data, kinds)
    return decode_npy(data, kinds)
