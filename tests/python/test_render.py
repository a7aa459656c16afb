"""Rendering through Python: shapes, zero copy, determinism, errors, the GIL."""
from __future__ import annotations

import copy
import threading
import time

import numpy as np
import pytest

import pellucid


def test_import_surface() -> None:
    assert pellucid.__version__
    for name in pellucid.__all__:
        assert hasattr(pellucid, name), name
    assert issubclass(pellucid.Error, Exception)


def test_dict_and_file_give_the_same_image(tiny_scene_path, tiny_scene_dict) -> None:
    a = pellucid.render(pellucid.load_file(tiny_scene_path), seed=3)
    b = pellucid.render(pellucid.load_dict(tiny_scene_dict), seed=3)
    assert a.shape == (24, 32, 3) and a.dtype == np.float32
    assert np.array_equal(a, b)
    assert a.mean() > 0.01


def test_render_is_zero_copy(tiny_scene_path) -> None:
    img = pellucid.render(pellucid.load_file(tiny_scene_path), spp=1)
    assert not img.flags.owndata  # the array views the renderer's buffer
    assert img.base is not None
    assert img.flags.c_contiguous


def test_deterministic_across_thread_counts(tiny_scene_path) -> None:
    scene = pellucid.load_file(tiny_scene_path)
    one = pellucid.render(scene, spp=8, seed=1, threads=1)
    two = pellucid.render(scene, spp=8, seed=1, threads=2)
    assert np.array_equal(one, two)
    other = pellucid.render(scene, spp=8, seed=2, threads=2)
    assert not np.array_equal(one, other)


def test_render_releases_the_gil(tiny_scene_dict) -> None:
    d = copy.deepcopy(tiny_scene_dict)
    d["film"] = {"width": 96, "height": 96}
    scene = pellucid.load_dict(d)
    done = threading.Event()
    t = threading.Thread(target=lambda: (pellucid.render(scene, spp=256, threads=1), done.set()))
    start = time.perf_counter()
    t.start()
    ticks = 0
    while not done.is_set():  # the main thread keeps running Python while the worker renders
        ticks += 1
        time.sleep(0.001)
    t.join()
    elapsed = time.perf_counter() - start
    assert elapsed > 0.05, "render too short to observe the GIL"
    # Had the GIL been held, the main thread would have ticked about once; a free main thread
    # ticks once per ~1 ms sleep. Require at least 15 % of that rate (sleep overshoot, load).
    assert ticks >= 0.15 * elapsed / 0.001


def test_bad_scene_raises_error_with_key_path(tiny_scene_dict) -> None:
    d = copy.deepcopy(tiny_scene_dict)
    d["shapes"][3]["material"] = "gold"
    with pytest.raises(pellucid.Error, match=r"<dict>: shapes\[3\]\.material: no material 'gold'"):
        pellucid.load_dict(d)
    d = copy.deepcopy(tiny_scene_dict)
    d["materials"]["white"]["roughnes"] = 0.1
    with pytest.raises(pellucid.Error, match=r"materials\.white\.roughnes: unknown parameter"):
        pellucid.load_dict(d)
    d = copy.deepcopy(tiny_scene_dict)
    d["materials"]["red"]["reflectance"] = float("nan")
    with pytest.raises(pellucid.Error, match=r"materials\.red\.reflectance: value nan is not finite"):
        pellucid.load_dict(d)


def test_bad_render_arguments(tiny_scene_path) -> None:
    scene = pellucid.load_file(tiny_scene_path)
    with pytest.raises(pellucid.Error, match="spp"):
        pellucid.render(scene, spp=0)
    with pytest.raises(pellucid.Error, match="seed"):
        pellucid.render(scene, seed=-1)


def test_missing_file_and_malformed_json(tmp_path) -> None:
    with pytest.raises(pellucid.Error, match="cannot open scene file"):
        pellucid.load_file(tmp_path / "nope.json")
    bad = tmp_path / "bad.json"
    bad.write_text('{"film": {"width": 3,}}')
    with pytest.raises(pellucid.Error, match=r"bad\.json: malformed JSON: parse error at line 1"):
        pellucid.load_file(bad)


def test_image_round_trip(tmp_path) -> None:
    img = np.random.default_rng(0).random((5, 7, 3), dtype=np.float32) * 4
    pellucid.write_image(tmp_path / "a.exr", img)
    back = pellucid.read_image(str(tmp_path / "a.exr"))
    assert np.array_equal(back, img)
    pellucid.write_image(str(tmp_path / "a.png"), img)
    png = pellucid.read_image(str(tmp_path / "a.png"))
    assert png.shape == (5, 7, 3)
    assert np.allclose(png, np.clip(img, 0, 1), atol=0.01)
    with pytest.raises(pellucid.Error, match="image file not found"):
        pellucid.read_image(str(tmp_path / "missing.exr"))


def test_stats_and_variance(tiny_scene_path) -> None:
    img, var, stats = pellucid.render_with_stats(pellucid.load_file(tiny_scene_path), spp=8)
    assert stats["spp"] == 8 and stats["invalid_samples"] == 0 and not stats["cancelled"]
    assert var.shape == img.shape and (var >= 0).all() and var.max() > 0
    _, _, s2 = pellucid.render_with_stats(pellucid.load_file(tiny_scene_path), time_budget=0.2)
    assert s2["spp"] >= 1


def test_variance_off_gives_the_same_image(tiny_scene_dict) -> None:
    # A splatting film without variance keeps only the sums of the mean: the same image, bit for bit,
    # no variance; render() keeps none; a state without variance resumes only without it.
    d = copy.deepcopy(tiny_scene_dict)
    d["film"].update(filter={"type": "gaussian", "stddev": 0.5}, reconstruction="splatting")
    scene = pellucid.load_dict(d)
    img, var, _ = pellucid.render_with_stats(scene, spp=4, seed=5)
    img_off, var_off, stats = pellucid.render_with_stats(scene, spp=4, seed=5, variance=False, keep_state=True)
    assert var is not None and var.max() > 0 and var_off is None
    assert np.array_equal(img, img_off)
    assert np.array_equal(pellucid.render(scene, spp=4, seed=5), img)
    with pytest.raises(pellucid.Error, match="rendered without variance, and this render asks for variance"):
        pellucid.render_with_stats(scene, spp=8, resume=stats["state"])
    more, none, _ = pellucid.render_with_stats(scene, spp=8, resume=stats["state"], variance=False)
    assert none is None
    assert np.array_equal(more, pellucid.render(scene, spp=8, seed=5))
    with pytest.raises(pellucid.Error, match="variance: expected True or False"):
        pellucid.render_with_stats(scene, spp=1, variance="yes")


def test_scene_repr(tiny_scene_path) -> None:
    s = pellucid.load_file(tiny_scene_path)
    assert "film=32x24" in repr(s) and s.width == 32 and s.height == 24
