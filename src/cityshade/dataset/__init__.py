"""Labelled renders of cities for training and testing: views sampled along streets and from the
air, each written as RGB, depth, normals, semantic classes, instance ids and camera JSON, listed in
a Parquet manifest, rendered by Ray actors (docs/datasets.md)."""

from ._classes import CLASS_COLOURS, CLASSES, IGNORE, class_image, instance_image
from ._config import DEFAULTS, DatasetConfig, load_config, parse_config
from ._manifest import read_manifest
from ._preview import write_preview
from ._run import _start_ray as start_ray
from ._run import check_address, generate, render_frames
from ._sample import SampleRenderer, extrinsics, intrinsics, linear_depth, normals_from_depth, sample_files
from ._shards import write_shards
from ._source import Source, load_source
from ._views import KINDS, Streets, View, sample_view

__all__ = [
    "CLASS_COLOURS",
    "CLASSES",
    "IGNORE",
    "class_image",
    "instance_image",
    "DEFAULTS",
    "DatasetConfig",
    "load_config",
    "parse_config",
    "SampleRenderer",
    "extrinsics",
    "intrinsics",
    "linear_depth",
    "normals_from_depth",
    "sample_files",
    "read_manifest",
    "write_preview",
    "write_shards",
    "generate",
    "start_ray",
    "check_address",
    "render_frames",
    "Source",
    "load_source",
    "KINDS",
    "Streets",
    "View",
    "sample_view",
]
