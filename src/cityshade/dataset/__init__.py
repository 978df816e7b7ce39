"""Labelled renders of cities for training and testing: views sampled along streets and from the
air, each written as RGB, depth, normals, semantic classes, instance ids and camera JSON, listed in
a Parquet manifest, rendered by Ray actors, with nerfstudio, COLMAP and COCO panoptic files beside
them; read back with Samples (docs/datasets.md)."""

from ._classes import (
    CITYSCAPES_LABEL_IDS,
    CITYSCAPES_TRAIN_IDS,
    CLASS_COLOURS,
    CLASSES,
    IGNORE,
    building_instances,
    cityscapes_images,
    class_image,
    instance_image,
)
from ._config import DEFAULTS, DatasetConfig, load_config, parse_config
from ._gather import write_gathered
from ._manifest import read_manifest
from ._panoptic import BUILDING_CATEGORY, panoptic, panoptic_document
from ._poses import camera_to_world_gl, colmap_model, transforms_document
from ._preview import write_preview
from ._reader import Samples
from ._run import _start_ray as start_ray
from ._run import check_address, generate, render_frames
from ._sample import (
    SampleRenderer,
    extra_files,
    extrinsics,
    intrinsics,
    linear_depth,
    normals_from_depth,
    ray_distance,
    sample_files,
    write_sample,
)
from ._shards import write_shards
from ._source import Source, load_source
from ._views import KINDS, SEQUENCES, Streets, View, sample_view, sequence_view, walk_camera, walk_route

__all__ = [
    "CITYSCAPES_LABEL_IDS",
    "CITYSCAPES_TRAIN_IDS",
    "building_instances",
    "cityscapes_images",
    "write_gathered",
    "BUILDING_CATEGORY",
    "panoptic",
    "panoptic_document",
    "camera_to_world_gl",
    "colmap_model",
    "transforms_document",
    "Samples",
    "extra_files",
    "ray_distance",
    "write_sample",
    "SEQUENCES",
    "sequence_view",
    "walk_route",
    "walk_camera",
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
