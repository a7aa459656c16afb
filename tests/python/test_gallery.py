"""docs/gallery.md shows every scenes/*.json (regenerate with `docs/make_gallery.py`)."""
from __future__ import annotations

from conftest import ROOT


def test_every_scene_has_a_small_gallery_image() -> None:
    md = (ROOT / "docs" / "gallery.md").read_text()
    scenes = sorted((ROOT / "scenes").glob("*.json"))
    assert scenes
    for path in scenes:
        png = ROOT / "docs" / "gallery" / f"{path.stem}.png"
        assert png.exists(), f"{png} is missing: run .venv/bin/python docs/make_gallery.py"
        assert png.read_bytes()[:8] == b"\x89PNG\r\n\x1a\n"
        assert png.stat().st_size <= 100 * 1024, png
        assert f"](gallery/{path.stem}.png)" in md, f"docs/gallery.md does not show {path.name}"
