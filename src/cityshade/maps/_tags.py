"""OpenStreetMap-style tags -> typed building attributes, with one rule per unreadable or absurd value.

Every format's reader hands its properties to `building_attributes` as a dict of strings, so a
GeoJSON `height` and an OpenStreetMap `height` are read by the same rules:

- lengths accept `12`, `12.5`, `12 m`, `12,5`, `40 ft`, `40'`, `12'6"`; anything else (`tall`,
  `nan`, `1e308`) is not used and counted as a fallback "not a number";
- values outside a plausible range are not used and counted "out of range" (no clamping: a
  clamped 10,000 storeys would still be wrong, while dropping it lets the guessing model decide):
  height and min_height 0..1000 m (height > 0), levels and min_level 0..200, roof:levels 0..50,
  roof:height 0..300 m, roof:angle 0..90 degrees;
- `roof:direction` is degrees (taken modulo 360) or a compass point (N, NNE, ..., NW);
- colours are CSS names (`light grey` and `light_grey` read as `lightgrey`) or `#rgb`/`#rrggbb`;
- roof shapes are the values in ROOF_SHAPES plus common synonyms (`pitched` -> gabled, ...).
"""

from __future__ import annotations

import math
import re

from PIL import ImageColor

from ._model import ROOF_SHAPES, MapBuilding, ReadReport

FOOT = 0.3048
INCH = 0.0254

_METRES = re.compile(r"^\s*(-?[0-9]+(?:[.,][0-9]+)?)\s*(m|metres|meters|metre|meter)?\s*$", re.IGNORECASE)
_FEET = re.compile(
    r"^\s*([0-9]+(?:\.[0-9]+)?)\s*(?:ft|feet|')\s*"
    r"(?:([0-9]+(?:\.[0-9]+)?)\s*(?:\"|in|inch|inches))?\s*$",
    re.IGNORECASE,
)
_NUMBER = re.compile(r"^\s*(-?[0-9]+(?:[.,][0-9]+)?)\s*$")

# (smallest, largest) accepted value of each numeric attribute; outside it the value is dropped.
RANGES = {
    "height": (0.0, 1000.0),
    "min_height": (0.0, 1000.0),
    "levels": (0.0, 200.0),
    "min_level": (0.0, 200.0),
    "roof_levels": (0.0, 50.0),
    "roof_height": (0.0, 300.0),
    "roof_angle": (0.0, 90.0),
}
# OpenStreetMap key of each typed attribute.
KEYS = {
    "height": "height",
    "min_height": "min_height",
    "levels": "building:levels",
    "min_level": "building:min_level",
    "roof_levels": "roof:levels",
    "roof_height": "roof:height",
    "roof_angle": "roof:angle",
    "roof_shape": "roof:shape",
    "roof_direction": "roof:direction",
    "roof_orientation": "roof:orientation",
    "building_colour": "building:colour",
    "roof_colour": "roof:colour",
    "building_material": "building:material",
    "roof_material": "roof:material",
}
LENGTHS = ("height", "min_height", "roof_height")
COUNTS = ("levels", "min_level", "roof_levels", "roof_angle")

COMPASS = {name: 22.5 * i for i, name in enumerate("N NNE NE ENE E ESE SE SSE S SSW SW WSW W WNW NW NNW".split())}
ROOF_SYNONYMS = {
    "pitched": "gabled",
    "gable": "gabled",
    "hip": "hipped",
    "half_hipped": "half-hipped",
    "halfhipped": "half-hipped",
    "pyramid": "pyramidal",
    "cone": "cone",
    "conical": "cone",
    "domed": "dome",
    "onion": "onion",
    "round": "round",
    "lean_to": "skillion",
    "shed": "skillion",
    "mono-pitched": "skillion",
    "flat": "flat",
    "saltbox": "saltbox",
    "mansard": "mansard",
    "gambrel": "gambrel",
}


def length(value: str) -> float | None:
    """Metres from `12`, `12.5 m`, `12,5`, `40 ft`, `12'6"`; None when the text is not a length."""
    match = _METRES.match(value)
    if match:
        return float(match.group(1).replace(",", "."))
    match = _FEET.match(value)
    if match:
        return float(match.group(1)) * FOOT + float(match.group(2) or 0.0) * INCH
    return None


def number(value: str) -> float | None:
    match = _NUMBER.match(value)
    return float(match.group(1).replace(",", ".")) if match else None


def yes(tags: dict[str, str], key: str) -> bool:
    return tags.get(key, "no") not in ("no", "false", "0")


def layer(tags: dict[str, str]) -> int:
    """`layer=*` clamped to -5..5 (0 when not a whole number)."""
    try:
        return max(-5, min(5, int(tags.get("layer", "0"))))
    except ValueError:
        return 0


def direction(value: str) -> float | None:
    """Degrees clockwise from north from `45`, `N`, `SSW`; None otherwise."""
    text = value.strip().upper()
    if text in COMPASS:
        return COMPASS[text]
    degrees = number(text)
    return None if degrees is None else degrees % 360.0


def colour(value: str) -> tuple[float, float, float] | None:
    """sRGB 0..1 from a CSS colour name or `#rgb`/`#rrggbb`; None otherwise."""
    text = value.strip().lower().replace("_", "").replace(" ", "")
    try:
        rgb = ImageColor.getrgb(text)
    except ValueError:
        return None
    return tuple(channel / 255.0 for channel in rgb[:3])


def roof_shape(value: str) -> str | None:
    text = value.strip().lower()
    if text in ROOF_SHAPES:
        return text
    return ROOF_SYNONYMS.get(text.replace(" ", "_"))


def use_of(tags: dict[str, str]) -> str | None:
    """What the building is for: a specific `building=*` value, else shop -> retail, office, amenity=*."""
    kind = tags.get("building:part") if tags.get("building") in (None, "yes") else tags.get("building")
    if kind and kind not in ("yes", "part", "no", "roof"):
        return kind
    if "shop" in tags:
        return "retail"
    if "office" in tags:
        return "office"
    return tags.get("amenity")


def _checked(name: str, value: float | None, text: str, report: ReadReport, element: str) -> float | None:
    if value is None or not math.isfinite(value):
        report.fallback(KEYS[name], "not a number", f"{element} {KEYS[name]}={text[:40]}")
        return None
    low, high = RANGES[name]
    if not low <= value <= high or (name == "height" and value == 0.0):
        report.fallback(KEYS[name], f"out of range {low:g}..{high:g}", f"{element} {KEYS[name]}={text[:40]}")
        return None
    return value


def building_attributes(building: MapBuilding, tags: dict[str, str], report: ReadReport) -> None:
    """Fill `building`'s attributes and `tagged` from its tags; unreadable values are counted and left None."""
    element = building.source_id
    for name in LENGTHS + COUNTS:
        text = tags.get(KEYS[name])
        if text is None:
            continue
        value = length(text) if name in LENGTHS else number(text)
        value = _checked(name, value, text, report, element)
        if value is not None:
            setattr(building, name, value)
            building.tagged.add(name)
    parsers = {
        "roof_shape": roof_shape,
        "roof_direction": direction,
        "roof_orientation": lambda v: v.strip().lower() if v.strip().lower() in ("along", "across") else None,
        "building_colour": colour,
        "roof_colour": colour,
        "building_material": lambda v: v.strip().lower() or None,
        "roof_material": lambda v: v.strip().lower() or None,
    }
    for name, parse in parsers.items():
        text = tags.get(KEYS[name])
        if text is None:
            continue
        value = parse(text)
        if value is None:
            report.fallback(KEYS[name], "unknown value", f"{element} {KEYS[name]}={text[:40]}")
            continue
        setattr(building, name, value)
        building.tagged.add(name)
    building.use = use_of(tags)
    building.shop_front = "shop" in tags
    if building.use is not None:
        building.tagged.add("use")
