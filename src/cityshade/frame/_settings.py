"""Everything a frame can be asked to do differently; every flag changes what is drawn."""

from __future__ import annotations

from collections.abc import Callable
from dataclasses import dataclass, field, replace

from .._values import SAMPLES, check_lights, parse_time
from ..errors import UsageError

CULLING = ("gpu", "frustum", "off")


@dataclass(frozen=True)
class CommandFlag:
    """The command-line flag of a settings field, kept in the field's metadata under "flag"; the
    commands that draw a frame offer it from there (cityshade.commands.settings_flags). A bool field's
    flag named --no-X turns the field off; any other bool flag comes with its --no- form."""

    name: str
    help: str
    parse: Callable | None = None  # the flag's text to the field's value
    choices: tuple = ()  # the values the flag takes, checked as the command line is read
    typed_default: str | None = None  # the default as typed, where the field's own is not text (--time)


def flag(name: str, help: str, **details) -> dict:
    """A field's metadata: its command-line flag."""
    return {"flag": CommandFlag(name, help, **details)}


@dataclass(frozen=True)
class RenderSettings:
    # off: the reflective-only windows baseline (paper §3.2)
    interior_mapping: bool = field(default=True, metadata=flag("--no-interiors", "reflective windows only"))
    polygonised_interiors: bool = False  # baseline of paper §3.1: real floors, ceilings, walls instead
    depth_prepass: bool = True  # paper §3.1 "z-cull"
    single_atlas: bool = False  # paper §3.2: one atlas texture instead of four
    furniture: bool = True  # paper §2.4 furniture planes
    curtains: bool = True
    room_variation: bool = True  # paper §4.3 displaced walls
    lod: bool = True  # interiors fade to lit-window colours far away
    lod_range: tuple[float, float] = (220.0, 320.0)
    # relief-bay buildings and grammar windows traced (off: flat; docs/relief.md)
    relief: bool = field(
        default=True,
        metadata=flag("--no-relief", "flat facades: no relief bay, window-bay and grammar windows not recessed"),
    )
    # metres: grammar windows are traced nearer than this, flat beyond; None: where a pixel spans the
    # pane's depth behind the wall (relief.switch_distance), so the recess's parallax is under a pixel
    relief_range: float | None = None
    # far facades: relief untraced, then a style's mean colour (city/lod.glsl)
    building_lod: bool = field(
        default=False,
        metadata=flag(
            "--building-lod",
            "far facades drop relief, grammar and rooms for their own mean colour (dithered bands); "
            "a grammar building's colour is evaluated once a view draws it far away (docs/frame.md)",
        ),
    )
    # pixels a room spans where each cross-fade band starts and ends: relief traced straight into the
    # wall over the first band, the style's mean colour over the second (render/_building_lod.py)
    building_lod_pixels: tuple[float, float, float, float] = (16.0, 12.0, 8.0, 6.0)
    # grammar buildings whose cheap colour a drawn frame evaluates at most (nearest first; about 1 ms
    # each here); until then a building stays at the finer level. A still evaluates all its view needs
    building_lod_budget: int = 32
    room_texture_size: int = 256
    room_variants: int = 8
    # MSAA of the HDR target
    samples: int = field(
        default=4,
        metadata=flag(
            "--samples",
            "MSAA samples (0: off; llvmpipe shades every sample, so 0 is about 4x faster there)",
            choices=SAMPLES,
        ),
    )
    trees: bool = True  # street rows and park groves (SpeedTree ch. 4)
    shadows: bool = True  # cascaded shadow maps (SpeedTree §4.3.2)
    shadow_resolution: int = 1024  # texels per side of each cascade's map (the viewer lowers it with its scale)
    shadow_refresh: int = 1  # cascades redrawn this many times less often than the chapter's rates
    god_rays: bool = True  # radial blur of bright pixels around the sun (SpeedTree §4.5)
    # probability c; None: from the time of day
    lights: float | None = field(
        default=None,
        metadata=flag(
            "--lights",
            "share of lit rooms, 0..1, for every building (default: by each building's use and --time)",
            parse=check_lights,
        ),
    )
    # hours (19:10, dusk); "HH:MM" is taken too (_values.parse_time)
    time_of_day: float = field(
        default=19.17,
        metadata=flag("--time", "time of day HH:MM (sun, sky, lit rooms)", parse=parse_time, typed_default="19:10"),
    )
    sun: tuple[float, float] | None = None  # (elevation, azimuth) degrees over a map; None: from time_of_day
    moon: tuple[float, float, float] | None = None  # (elevation, azimuth, lit fraction): moonlight at night
    animation_time: float = 0.0  # seconds, drives furniture sprites
    grammar_deferred: bool = True  # facade grammars in a deferred pass (Krecklau §4); measured faster
    # the deferred pass shades from a page cache of evaluated facades (docs/scale.md)
    grammar_cache: bool = field(
        default=False,
        metadata=flag(
            "--grammar-cache",
            "shade grammar facades from a page cache of facades evaluated once per texel, evaluating "
            "per pixel only where a page is not resident yet (docs/scale.md)",
        ),
    )
    grammar_cache_pages: int = 4096  # page slots of the cache's atlas (32 x 32 texels of 32 bytes: 128 MiB)
    # a missing page is evaluated into the cache only where it covers at least this many pixels of the
    # frame; the pixels of the others are evaluated per pixel (docs/scale.md, "The grammar cache")
    grammar_cache_min_pixels: int = 256
    culling: str = "gpu"  # buildings: "gpu" (frustum and hierarchical depth, render/_visibility.py),
    # "frustum" (96 m chunks on the CPU), "off" (all drawn)
    ssao: bool = False  # screen-space ambient occlusion of the lit frame (Krecklau §4's pipeline)
    grammar_files: tuple[str, ...] = ()  # grammar files compiled into the facade texture after the library
    # styles, each named by its file stem
    grammar_start: str | None = None  # every grammar facade starts at this grammar (a library style or a
    # grammar_files stem); None: each building's own style

    def __post_init__(self):
        object.__setattr__(self, "lights", check_lights(self.lights))  # frozen: the checked number
        object.__setattr__(self, "time_of_day", parse_time(self.time_of_day))  # "HH:MM" or hours
        if not 16 <= self.shadow_resolution <= 8192:
            raise UsageError(f"shadow_resolution {self.shadow_resolution!r}: give texels per side, 16 to 8192")
        if self.shadow_refresh < 1:
            raise UsageError(f"shadow_refresh {self.shadow_refresh!r}: give 1 (the chapter's rates) or more")
        if self.culling not in CULLING:
            raise UsageError(f"unknown culling {self.culling!r}; allowed: {', '.join(CULLING)}")
        if self.grammar_cache_pages < 1:
            raise UsageError(f"grammar_cache_pages must be at least 1, not {self.grammar_cache_pages}")
        if self.grammar_cache_min_pixels < 0:
            raise UsageError(f"grammar_cache_min_pixels must be 0 or more, not {self.grammar_cache_min_pixels}")
        if self.building_lod_budget < 0:
            raise UsageError(f"building_lod_budget must be 0 or more, not {self.building_lod_budget}")

    def with_(self, **changes) -> "RenderSettings":
        return replace(self, **changes)
