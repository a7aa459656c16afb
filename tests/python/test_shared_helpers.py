"""One copy each of the helpers that several modules use: relMSE (pellucid.image.rel_mse, used by
Image.compare and pellucid.bench), the sRGB encoding (pellucid.image.srgb_encode, used by
Image.to_srgb8 and the bench crops) and the critical z of the Sidak-corrected z-test
(pellucid.bench.critical_z, used by bench.z_test, bench/envmap_check.py and tests/python/zcheck.py)."""
from __future__ import annotations

import math

import numpy as np
import pytest

import pellucid
from pellucid import bench, image
from pellucid._bench_figures import tonemap


def test_critical_z_has_the_sidak_tail_probability() -> None:
    for n in (1, 3, 3072, 10**6, 10**9):
        for alpha in (0.01, 0.05):
            z = bench.critical_z(n, alpha)
            # P(|Z| > z) = erfc(z / sqrt 2) must be 1 - (1 - alpha)^(1/n).
            want = -math.expm1(math.log1p(-alpha) / n)
            assert math.erfc(z / math.sqrt(2.0)) == pytest.approx(want, rel=1e-9), (n, alpha)
    assert bench.critical_z(1, 0.05) == pytest.approx(1.959963984540054, abs=1e-12)


def test_one_relmse_for_compare_and_bench() -> None:
    rng = np.random.default_rng(5)
    ref = pellucid.Image(rng.random((6, 5, 3), dtype=np.float32))
    img = pellucid.Image(ref + rng.normal(0, 0.05, ref.shape).astype(np.float32))
    a, b = np.asarray(img, np.float64), np.asarray(ref, np.float64)
    want = float(np.mean((a - b) ** 2 / (b * b + 1e-2)))
    assert image.rel_mse(img, ref) == pytest.approx(want, rel=1e-12)
    assert img.compare(ref).relmse == image.rel_mse(img, ref)
    assert bench.rel_mse(img, ref) == image.rel_mse(img, ref)
    assert bench.RELMSE_EPS == image.RELMSE_EPSILON


def test_one_srgb_encoding_for_display_and_crops() -> None:
    x = np.linspace(0.0, 1.0, 1001)
    enc = image.srgb_encode(x)
    assert enc[0] == 0.0 and enc[-1] == pytest.approx(1.0, abs=1e-12)
    assert image.srgb_encode(np.array([0.002]))[0] == pytest.approx(12.92 * 0.002)
    assert np.array_equal(tonemap(x.reshape(1, -1, 1)).ravel(), enc)
    lin = pellucid.Image(np.stack([x, x, x], axis=-1).reshape(1, -1, 3).astype(np.float32))
    assert np.array_equal(lin.to_srgb8()[0, :, 0], np.round(image.srgb_encode(x.astype(np.float32)) * 255))
