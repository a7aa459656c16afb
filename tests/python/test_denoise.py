"""pellucid.denoise (Intel Open Image Denoise through the optional pyoidn package): the error when
pyoidn is missing, argument checks, and that it lowers the error of a noisy render against a
reference (skipped when pyoidn is not installed: pip install "pellucid[denoise]")."""
from __future__ import annotations

import importlib.util
import json
import sys

import numpy as np
import pytest

import pellucid

from conftest import ROOT

HAVE_PYOIDN = importlib.util.find_spec("pyoidn") is not None


def _cornell(size: int) -> pellucid.Scene:
    """The Cornell box at size × size with filter sampling and a one-pixel box: pixel noise is
    independent between pixels, as the denoiser expects (a splatting film correlates neighbours,
    and Open Image Denoise then leaves most of the noise in place)."""
    d = json.loads((ROOT / "scenes" / "cornell_box.json").read_text())
    d["film"] = {"width": size, "height": size, "filter": {"type": "box", "radius": 0.5}}
    return pellucid.load_dict(d, ROOT / "scenes")


def test_missing_pyoidn_is_a_clear_import_error(monkeypatch) -> None:
    monkeypatch.setitem(sys.modules, "pyoidn", None)  # makes `import pyoidn` raise ImportError
    with pytest.raises(ImportError, match=r"needs the pyoidn package .*pip install \"pellucid\[denoise\]\""):
        pellucid.denoise(np.zeros((4, 4, 3), np.float32))


def test_bad_arguments_are_errors() -> None:
    img = np.ones((4, 5, 3), np.float32)
    with pytest.raises(pellucid.Error, match=r"beauty: expected an \(H, W, 3\) image, got shape \(4, 5\)"):
        pellucid.denoise(img[:, :, 0])
    with pytest.raises(pellucid.Error, match=r"albedo: shape \(5, 4, 3\) differs from the beauty's \(4, 5, 3\)"):
        pellucid.denoise(img, np.ones((5, 4, 3)))
    with pytest.raises(pellucid.Error, match="a normal guide needs the albedo guide"):
        pellucid.denoise(img, None, img)
    bad = img.copy()
    bad[0, 0, 0] = np.nan
    with pytest.raises(pellucid.Error, match="beauty: the image contains NaN"):
        pellucid.denoise(bad)
    with pytest.raises(pellucid.Error, match="beauty: negative values"):
        pellucid.denoise(-img)
    with pytest.raises(pellucid.Error, match="unknown quality 'best'"):
        pellucid.denoise(img, quality="best")


@pytest.mark.skipif(not HAVE_PYOIDN, reason="pyoidn is not installed (pip install \"pellucid[denoise]\")")
def test_denoising_lowers_the_error_of_a_noisy_render() -> None:
    """4 spp against 1024 spp (fixed seeds): the denoised image's relMSE is below a third of the
    noisy one's, with and without guides; the guides come from the same render's AOVs."""
    scene = _cornell(64)
    ref = pellucid.render(scene, spp=1024, seed=101)
    noisy = pellucid.render(scene, spp=4, seed=7, aovs=["albedo", "normal"])
    e_noisy = noisy.image.compare(ref).relmse
    plain = pellucid.denoise(noisy.image)
    guided = pellucid.denoise(noisy)  # albedo and normal taken from the RenderLayers
    assert isinstance(guided, pellucid.Image) and guided.shape == noisy.image.shape
    assert np.array_equal(guided, pellucid.denoise(noisy.image, noisy["albedo"], noisy["normal"]))
    e_plain, e_guided = plain.compare(ref).relmse, guided.compare(ref).relmse
    assert e_plain < e_noisy / 3, (e_noisy, e_plain)
    assert e_guided < e_noisy / 3, (e_noisy, e_guided)
