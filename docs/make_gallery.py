"""Render every scenes/*.json into docs/gallery/<name>.png and write docs/gallery.md.

    .venv/bin/python docs/make_gallery.py [--spp 128] [--max-width 240]

Low sample counts on purpose (a gallery, not a reference): each PNG stays under 100 KB. The same
seed gives the same images. tests/python/test_gallery.py checks that every scene has its picture.
"""
from __future__ import annotations

import argparse
import json
import pathlib
import sys
import time

import pellucid

ROOT = pathlib.Path(__file__).resolve().parents[1]
OUT = ROOT / "docs" / "gallery"
MAX_BYTES = 100 * 1024


def _size(scene: dict, max_width: int) -> tuple:
    film = scene.get("film", {})
    w, h = film.get("width", 256), film.get("height", 256)
    scale = min(1.0, max_width / w)
    return max(1, round(w * scale)), max(1, round(h * scale))


def render_one(path: pathlib.Path, spp: int, max_width: int) -> dict:
    d = json.loads(path.read_text())
    w, h = _size(d, max_width)
    d.setdefault("film", {}).update(width=w, height=h)
    t0 = time.perf_counter()
    image, _, stats = pellucid.render_with_stats(pellucid.load_dict(d, base_dir=path.parent), spp=spp, seed=0)
    seconds = time.perf_counter() - t0
    png = OUT / f"{path.stem}.png"
    image.save(png)
    if png.stat().st_size > MAX_BYTES:
        raise SystemExit(f"{png}: {png.stat().st_size} bytes > {MAX_BYTES}; lower --max-width")
    return {"name": path.stem, "scene": path.relative_to(ROOT).as_posix(),
            "png": png.relative_to(ROOT / "docs").as_posix(), "width": w, "height": h, "spp": stats["spp"],
            "seconds": seconds}


def write_markdown(entries: list, spp: int, max_width: int) -> None:
    lines = [
        "# Gallery",
        "",
        "Every scene in `scenes/`, rendered by [make_gallery.py](make_gallery.py) "
        f"(`.venv/bin/python docs/make_gallery.py`) at {spp} samples per pixel, seed 0, resized to at "
        f"most {max_width} pixels wide, saved as clamped sRGB PNG (no tone mapping). Low sample counts "
        "keep the files small; the noise is expected. Times are wall-clock on the machine that made "
        "them (a shared 2-core machine).",
        "",
    ]
    for e in entries:
        lines += [
            f"## `{e['name']}`",
            "",
            f"[`{e['scene']}`](../{e['scene']}): {e['width']}×{e['height']}, {e['spp']} spp, "
            f"{e['seconds']:.1f} s.",
            "",
            f"![{e['name']}]({e['png']})",
            "",
        ]
    (ROOT / "docs" / "gallery.md").write_text("\n".join(lines))


def main(argv: list) -> int:
    ap = argparse.ArgumentParser(description="render the scene gallery")
    ap.add_argument("--spp", type=int, default=128)
    ap.add_argument("--max-width", type=int, default=240)
    args = ap.parse_args(argv)
    OUT.mkdir(parents=True, exist_ok=True)
    entries = []
    for path in sorted((ROOT / "scenes").glob("*.json")):
        e = render_one(path, args.spp, args.max_width)
        print(f"{e['png']}: {e['width']}x{e['height']}, {e['seconds']:.1f} s", file=sys.stderr)
        entries.append(e)
    write_markdown(entries, args.spp, args.max_width)
    return 0


if __name__ == "__main__":
    sys.exit(main(sys.argv[1:]))
