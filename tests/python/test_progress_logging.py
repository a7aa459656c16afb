"""render(progress=True) drives a tqdm bar from the C++ counters; C++ log messages reach `logging`."""
from __future__ import annotations

import copy
import io
import logging
import sys

import numpy as np
import pytest

import pellucid


def test_progress_counters_count_every_sample(tiny_scene_path) -> None:
    scene = pellucid.load_file(tiny_scene_path)
    monitor = pellucid._core.RenderProgress()
    assert (monitor.samples, monitor.fraction) == (0, 0.0)
    image, _, stats = pellucid._core.render_full(scene, spp=5, seed=1, monitor=monitor)
    assert monitor.samples == 32 * 24 * 5 == stats["samples"]
    assert monitor.fraction == 1.0
    # Monitoring does not change the image.
    plain, _, _ = pellucid._core.render_full(scene, spp=5, seed=1)
    assert np.array_equal(image, plain)


def test_progress_true_draws_a_tqdm_bar_that_reaches_the_end(tiny_scene_dict, monkeypatch) -> None:
    tqdm_mod = pytest.importorskip("tqdm")
    bars = []

    class Recorder(tqdm_mod.tqdm):
        def __init__(self, *a, **k):
            k["file"] = io.StringIO()
            super().__init__(*a, **k)
            bars.append(self)

    monkeypatch.setattr(pellucid, "_tqdm", lambda: Recorder)
    d = copy.deepcopy(tiny_scene_dict)
    d["film"] = {"width": 64, "height": 64}
    scene = pellucid.load_dict(d)
    img = pellucid.render(scene, spp=16, seed=1, progress=True)
    assert len(bars) == 1
    bar = bars[0]
    assert bar.n == 100 and bar.total == 100
    assert f"{64 * 64 * 16:,} samples" in bar.postfix
    text = bar.fp.getvalue()
    assert "rendering" in text and "100%" in text
    assert np.array_equal(img, pellucid.render(scene, spp=16, seed=1))


def test_progress_without_tqdm_falls_back_quietly(tiny_scene_path, monkeypatch, capfd) -> None:
    monkeypatch.setitem(sys.modules, "tqdm.auto", None)  # makes `from tqdm.auto import tqdm` fail
    assert pellucid._tqdm() is None
    img = pellucid.render(pellucid.load_file(tiny_scene_path), spp=1, progress=True)
    assert img.shape == (24, 32, 3)
    assert "\r" not in capfd.readouterr().err  # the C++ text bar only draws on a terminal


def test_cpp_warnings_reach_python_logging(tiny_scene_dict, caplog) -> None:
    d = copy.deepcopy(tiny_scene_dict)
    d["shapes"][0]["emitter"] = {"type": "area", "radiance": 0}
    d["materials"]["m"] = {"type": "rough_conductor", "alpha": 3.0}  # clamped to 1 with a warning
    with caplog.at_level(logging.WARNING, logger="pellucid"):
        pellucid.load_dict(d)
    msgs = [(r.name, r.levelno, r.getMessage()) for r in caplog.records]
    assert ("pellucid", logging.WARNING, "<dict>: shapes[0].emitter: emitter has zero radiance; skipped") in msgs
    assert ("pellucid", logging.WARNING, "<dict>: materials.m.alpha: value 3 clamped to 1") in msgs


def test_logging_from_a_worker_thread_and_level_filtering(tiny_scene_dict, caplog) -> None:
    import threading

    d = copy.deepcopy(tiny_scene_dict)
    d["shapes"][0]["emitter"] = {"type": "area", "radiance": 0}
    with caplog.at_level(logging.ERROR, logger="pellucid"):
        pellucid.load_dict(d)
    assert not caplog.records  # below the logger's level: filtered by logging, not printed
    with caplog.at_level(logging.WARNING, logger="pellucid"):
        t = threading.Thread(target=pellucid.load_dict, args=(d,))
        t.start()
        t.join()
    assert any("zero radiance" in r.getMessage() for r in caplog.records)
