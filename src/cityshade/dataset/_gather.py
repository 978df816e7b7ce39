"""The dataset-wide files gathered from the samples' camera JSON after a run: nerfstudio's
`transforms.json`, the COLMAP text model in `colmap/` and, with output.panoptic, COCO's
`panoptic.json`; each rewritten whole (atomically) from every sample in the manifest."""

from __future__ import annotations

import json
from pathlib import Path

from ..errors import UsageError
from ._arrays import KITTI_SCALE
from ._config import DatasetConfig
from ._manifest import folder_file, read_manifest, read_sample_file, sample_error
from ._panoptic import panoptic_document
from ._poses import colmap_model, transforms_document
from ._sample import write_atomic

CAMERA_KEYS = ("index", "width", "height", "K", "world_to_camera", "files")


def sample_metas(folder: Path) -> list[dict]:
    """Every listed sample's camera JSON, in index order; one line for one that cannot be read."""
    metas = []
    for row in read_manifest(folder):
        try:
            meta = json.loads(read_sample_file(folder, row, "meta"))
            if not isinstance(meta, dict) or any(key not in meta for key in CAMERA_KEYS):
                raise ValueError
        except (ValueError, RecursionError):
            raise sample_error(folder, row, "meta", "not a sample's camera JSON") from None
        metas.append(meta)
    return metas


def write_gathered(folder: Path, config: DatasetConfig) -> list[Path]:
    """Writes transforms.json, colmap/ and (with output.panoptic) panoptic.json; returns their paths."""
    folder = Path(folder)
    metas = sample_metas(folder)
    written = []

    def put(name: str, text: str):
        write_atomic(folder_file(folder, name), text.encode())
        written.append(folder / name)

    scale = 1.0 / KITTI_SCALE if config.kitti_depth else None
    put("transforms.json", json.dumps(transforms_document(metas, scale), indent=1))
    folder_file(folder, "colmap").mkdir(exist_ok=True)
    for name, text in colmap_model(metas).items():
        put(f"colmap/{name}", text)
    if config.panoptic:
        missing = [m["index"] for m in metas if "panoptic_segments" not in m]
        if missing:
            raise UsageError(
                f"{folder}: sample {missing[0]} was written without output.panoptic; "
                "render the dataset into a new --out with --panoptic"
            )
        records = [{**m, "segments_info": m["panoptic_segments"]} for m in metas]
        put("panoptic.json", json.dumps(panoptic_document(records)))
    return written
