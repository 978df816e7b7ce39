"""A tileset's CesiumJS page in headless Chromium: `cityshade serve` on a free port of 127.0.0.1,
scripts/viewer-screenshot.mjs (puppeteer-core driving Debian's chromium with SwiftShader WebGL) takes
a screenshot coloured as exported and one coloured by height and selects a building, then this
checks what came back:

- the city in the middle: in the middle half of each picture, at least --city of the pixels differ
  from the plain globe's colour (the page's GLOBE);
- building colours: in the height picture at least --warm of the middle pixels are the style's
  reds and oranges (red over blue by 40 or more), in the exported colours far fewer;
- the info box shows the selected building's map id and tags, and no request left 127.0.0.1.

    python scripts/check-viewer.py out/export/helsinki-tiles out/export/viewer [--cesium DIR]

Prints the counts as JSON; exits 1 when a check fails."""

from __future__ import annotations

import argparse
import json
import re
import subprocess
import sys
from pathlib import Path

import numpy as np
from PIL import Image

GLOBE = np.array([0x7D, 0x84, 0x71])  # viewer.js GLOBE
NEAR_GLOBE = 24  # summed |difference| up to this is the globe


def middle(path: Path) -> np.ndarray:
    rgb = np.asarray(Image.open(path).convert("RGB")).astype(int)
    h, w = rgb.shape[:2]
    return rgb[h // 4 : 3 * h // 4, w // 4 : 3 * w // 4].reshape(-1, 3)


def shares(path: Path) -> dict:
    pixels = middle(path)
    city = np.abs(pixels - GLOBE).sum(axis=1) > NEAR_GLOBE
    warm = pixels[:, 0] - pixels[:, 2] >= 40
    return {"city": round(float(city.mean()), 4), "warm": round(float(warm.mean()), 4)}


def serve(tileset: Path, cesium: Path | None) -> tuple[subprocess.Popen, str]:
    command = [sys.executable, "-m", "cityshade", "serve", str(tileset), "--port", "0"]
    if cesium is not None:
        command += ["--cesium", str(cesium)]
    server = subprocess.Popen(command, stdout=subprocess.PIPE, text=True)
    line = server.stdout.readline()
    found = re.search(r"http://127\.0\.0\.1:\d+/", line)
    if found is None:
        server.kill()
        sys.exit(f"cityshade serve did not start: {line.strip() or 'no output'}")
    return server, found.group(0)


def main() -> int:
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("tileset", type=Path)
    parser.add_argument("out", type=Path, help="folder for the two screenshots")
    parser.add_argument("--cesium", type=Path, default=None)
    parser.add_argument("--city", type=float, default=0.3, help="least share of city pixels in the middle")
    parser.add_argument("--warm", type=float, default=0.1, help="least share of height-style pixels in the middle")
    args = parser.parse_args()
    args.out.mkdir(parents=True, exist_ok=True)
    facades, height = args.out / "facades.png", args.out / "height.png"
    server, url = serve(args.tileset, args.cesium)
    try:
        page = subprocess.run(
            ["node", "scripts/viewer-screenshot.mjs", url, str(facades), str(height)], capture_output=True, text=True
        )
    finally:
        server.terminate()
        server.wait()
    sys.stderr.write(page.stderr)
    result = json.loads(page.stdout) if page.stdout.strip() else {"failure": "no output"}
    report = {"url": url, "failure": result.get("failure"), "off_origin": result.get("offOrigin")}
    failures = [] if page.returncode == 0 else [f"the page: {result.get('failure')}"]
    if not failures:
        report.update(facades=shares(facades), height=shares(height))
        selected = result.get("selected") or {}
        report["selected"] = selected.get("source_id")
        info = result.get("infoBox") or ""
        tags = json.loads(selected.get("tags") or "{}")
        for name, share in (("facades", report["facades"]), ("height", report["height"])):
            if share["city"] < args.city:
                failures.append(f"{name}: {share['city']:.1%} of the middle is city, under {args.city:.0%}")
        if report["height"]["warm"] < args.warm:
            failures.append(f"height: {report['height']['warm']:.1%} of the middle in the style's colours")
        if report["height"]["warm"] <= 2 * report["facades"]["warm"]:
            failures.append("the height style barely changes the colours")
        if not re.fullmatch(r"(way|relation)/\d+", selected.get("source_id", "")):
            failures.append(f"selected building has no map id: {selected}")
        if selected.get("source_id", "?") not in info or any(f"{k}\t{v}" not in info for k, v in tags.items()):
            failures.append("the info box lacks the building's id or tags")
        if result.get("offOrigin"):
            failures.append(f"requests left 127.0.0.1: {result['offOrigin'][:3]}")
    report["failures"] = failures
    print(json.dumps(report))
    return 1 if failures else 0


if __name__ == "__main__":
    sys.exit(main())
