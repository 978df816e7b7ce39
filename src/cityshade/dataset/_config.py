"""The dataset's settings: a TOML file (read with tomllib) over documented defaults.

Every key is checked: an unknown section, key or class, a wrong type, a number that is not finite
or a range the wrong way round is one line naming the file, the key and the value. The file is read
as a capped regular file and its nesting is bounded before tomllib recurses into it (_limits.py).
"""

from __future__ import annotations

import datetime as dt
import importlib.util
import math
import tomllib
from dataclasses import dataclass
from pathlib import Path

from .._files import read_input_bytes
from .._json import value_depth
from ..errors import UsageError
from ._arrays import FORMATS
from ._classes import CLASSES
from ._limits import MAX_CONFIG_BYTES, MAX_IMAGE_SIDE, MAX_NESTING, shown, shown_key, toml_nesting

# section -> key -> default; docs/datasets.md lists them with their meaning
DEFAULTS: dict[str, dict] = {
    "image": {"width": 320, "height": 240, "fov": 66.0},
    "views": {
        "pedestrian": 0.4,
        "vehicle": 0.3,
        "aerial": 0.3,  # shares of the three kinds of view
        "pedestrian_height": 1.7,
        "vehicle_height": [1.2, 2.5],
        "aerial_height": [60.0, 250.0],
        "aerial_pitch": [30.0, 60.0],
        "across": 0.5,  # share of street views looking across the street instead of along it
    },
    "time": {"dates": ["2025-03-01", "2025-10-31"], "hours": [8.0, 18.0]},
    "classes": {"ignore": []},  # classes written as IGNORE (255) in the class image
    # float arrays as "npz" or "exr"; KITTI 16-bit depth PNGs; the class images ("native" or also
    # "cityscapes" labelIds/trainIds); COCO panoptic PNGs and panoptic.json
    "output": {"arrays": "npz", "kitti_depth": False, "classes": "native", "panoptic": False},
    "run": {"batch": 4},
}
CLASS_SETS = ("native", "cityscapes")


@dataclass(frozen=True)
class DatasetConfig:
    """The settings (defaults in DEFAULTS; build one with parse_config or load_config)."""

    width: int
    height: int
    fov: float  # vertical, degrees
    pedestrian: float
    vehicle: float
    aerial: float
    pedestrian_height: float
    vehicle_height: tuple[float, float]
    aerial_height: tuple[float, float]
    aerial_pitch: tuple[float, float]  # degrees below the horizon
    across: float
    dates: tuple[str, str]
    hours: tuple[float, float]
    ignore: tuple[str, ...]
    batch: int
    arrays: str = "npz"
    kitti_depth: bool = False
    classes: str = "native"
    panoptic: bool = False

    def settings(self) -> dict:
        """The settings that decide the images, as 'section.key' -> value (for --resume checks)."""
        flat = {}
        for section, keys in DEFAULTS.items():
            for key in keys if section != "run" else ():  # how the work is dealt changes no image
                value = getattr(self, key)
                flat[f"{section}.{key}"] = list(value) if isinstance(value, tuple) else value
        return flat

    @property
    def day_range(self) -> tuple[dt.date, dt.date]:
        return tuple(dt.date.fromisoformat(d) for d in self.dates)


def _fail(where: str, key: str, value, what: str):
    raise UsageError(f"{where}: {shown_key(key)} = {shown(value)}: {what}")


def _number(where, key, value, low=None, high=None, integer=False):
    if isinstance(value, bool) or not isinstance(value, int if integer else (int, float)):
        _fail(where, key, value, "expected " + ("an integer" if integer else "a number"))
    if isinstance(value, float) and not math.isfinite(value):
        _fail(where, key, value, f"expected a finite number from {low} to {high}")
    if (low is not None and value < low) or (high is not None and value > high):
        _fail(where, key, value, f"expected a value from {low} to {high}")
    return value


def _pair(where, key, value, low=None, high=None):
    if not isinstance(value, list) or len(value) != 2:
        _fail(where, key, value, "expected [low, high]")
    pair = tuple(float(_number(where, key, v, low, high)) for v in value)
    if pair[0] > pair[1]:
        _fail(where, key, value, "low is above high")
    return pair


def _dates(where, key, value):
    if not isinstance(value, list) or len(value) != 2 or not all(isinstance(v, str) for v in value):
        _fail(where, key, value, 'expected ["YYYY-MM-DD", "YYYY-MM-DD"]')
    try:
        first, last = (dt.date.fromisoformat(v) for v in value)
    except ValueError:
        _fail(where, key, value, 'expected ["YYYY-MM-DD", "YYYY-MM-DD"]')
    if first > last:
        _fail(where, key, value, "the first date is after the last")
    return tuple(value)


def _choice(where, key, value, allowed):
    if value not in allowed or not isinstance(value, str):
        _fail(where, key, value, f"expected one of {', '.join(allowed)}")
    return value


def _flag(where, key, value):
    if not isinstance(value, bool):
        _fail(where, key, value, "expected true or false")
    return value


def _classes(where, key, value):
    if not isinstance(value, list) or not all(isinstance(v, str) for v in value):
        _fail(where, key, value, "expected a list of class names")
    for name in value:
        if name not in CLASSES:
            _fail(where, key, name, f"unknown class; classes: {', '.join(CLASSES)}")
    return tuple(value)


def parse_config(data: dict, where: str = "config") -> DatasetConfig:
    """A DatasetConfig from a TOML document's tables; defaults for what is left out."""
    for section, table in data.items():
        if section not in DEFAULTS:
            raise UsageError(f"{where}: [{shown_key(section)}]: unknown section; sections: {', '.join(DEFAULTS)}")
        if not isinstance(table, dict):
            _fail(where, section, table, "expected a table")
        for key in table:
            if key not in DEFAULTS[section]:
                _fail(where, f"{section}.{key}", table[key], f"unknown key; keys: {', '.join(DEFAULTS[section])}")
    get = lambda section, key: data.get(section, {}).get(key, DEFAULTS[section][key])  # noqa: E731
    shares = {
        k: float(_number(where, f"views.{k}", get("views", k), 0.0, 1.0)) for k in ("pedestrian", "vehicle", "aerial")
    }
    if sum(shares.values()) <= 0:
        _fail(where, "views", shares, "at least one kind of view needs a share above 0")
    arrays = _choice(where, "output.arrays", get("output", "arrays"), FORMATS)
    if arrays == "exr" and importlib.util.find_spec("OpenEXR") is None:
        _fail(where, "output.arrays", arrays, "needs OpenEXR: pip install 'cityshade[exr]', or use npz")
    return DatasetConfig(
        width=int(_number(where, "image.width", get("image", "width"), 8, MAX_IMAGE_SIDE, integer=True)),
        height=int(_number(where, "image.height", get("image", "height"), 8, MAX_IMAGE_SIDE, integer=True)),
        fov=float(_number(where, "image.fov", get("image", "fov"), 5.0, 150.0)),
        **shares,
        pedestrian_height=float(
            _number(where, "views.pedestrian_height", get("views", "pedestrian_height"), 0.3, 10.0)
        ),
        vehicle_height=_pair(where, "views.vehicle_height", get("views", "vehicle_height"), 0.3, 10.0),
        aerial_height=_pair(where, "views.aerial_height", get("views", "aerial_height"), 10.0, 5000.0),
        aerial_pitch=_pair(where, "views.aerial_pitch", get("views", "aerial_pitch"), 5.0, 89.0),
        across=float(_number(where, "views.across", get("views", "across"), 0.0, 1.0)),
        dates=_dates(where, "time.dates", get("time", "dates")),
        hours=_pair(where, "time.hours", get("time", "hours"), 0.0, 23.99),
        ignore=_classes(where, "classes.ignore", get("classes", "ignore")),
        batch=int(_number(where, "run.batch", get("run", "batch"), 1, 1024, integer=True)),
        arrays=arrays,
        kitti_depth=_flag(where, "output.kitti_depth", get("output", "kitti_depth")),
        classes=_choice(where, "output.classes", get("output", "classes"), CLASS_SETS),
        panoptic=_flag(where, "output.panoptic", get("output", "panoptic")),
    )


def load_config(path: Path | None) -> DatasetConfig:
    """The config in `path` (TOML), or the defaults without one."""
    if path is None:
        return parse_config({})
    data = read_input_bytes(path, MAX_CONFIG_BYTES, "dataset config")
    try:
        text = data.decode("utf-8")
    except UnicodeDecodeError as exc:
        raise UsageError(f"{path}: not valid TOML: not UTF-8 text (byte {exc.start})") from None
    too_deep = UsageError(
        f"{path}: arrays or tables nested more than {MAX_NESTING} levels deep; a config needs three (docs/datasets.md)"
    )
    if toml_nesting(text) > MAX_NESTING:
        raise too_deep
    try:
        document = tomllib.loads(text)
    except tomllib.TOMLDecodeError as exc:
        raise UsageError(f"{path}: not valid TOML: {exc}") from None
    except RecursionError:  # not reached after the check above; kept so that no input gives a traceback
        raise too_deep from None
    if value_depth(document) > MAX_NESTING:  # dotted keys nest tables without brackets
        raise too_deep
    return parse_config(document, str(path))
