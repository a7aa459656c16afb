"""pellucid.Image: an ndarray subclass with save, to_srgb8, _repr_png_, compare and a readable repr."""
from __future__ import annotations

import numpy as np
import pytest

import pellucid
from pellucid.image import RELMSE_EPSILON


def test_render_and_read_return_images_that_stay_arrays(tiny_scene_path, tmp_path) -> None:
    scene = pellucid.load_file(tiny_scene_path)
    img = pellucid.render(scene, spp=2, seed=1)
    assert type(img) is pellucid.Image and isinstance(img, np.ndarray)
    assert img.shape == (24, 32, 3) and img.dtype == np.float32
    assert not img.flags.owndata  # still a view of the renderer's buffer
    image, variance, stats = pellucid.render_with_stats(scene, spp=2, seed=1)
    assert type(image) is pellucid.Image and type(variance) is pellucid.Image
    assert np.array_equal(image, img)
    # numpy functions and arithmetic work unchanged; full reductions give plain scalars.
    assert isinstance(img.mean(), np.floating) and np.isclose(img.mean(), np.asarray(img).mean())
    assert type(img * 2) is pellucid.Image and np.array_equal(np.asarray(img * 2), np.asarray(img) * 2)
    assert np.clip(img, 0, 1).shape == img.shape
    assert (img.width, img.height) == (32, 24)
    img.save(tmp_path / "a.exr")
    back = pellucid.read_image(tmp_path / "a.exr")
    assert type(back) is pellucid.Image and np.array_equal(back, img)


def test_to_srgb8_clamps_and_encodes() -> None:
    lin = np.array([[[0.0, 0.0031308, 0.5], [1.0, 2.0, -1.0], [np.nan, 0.18, 1e-4]]], dtype=np.float32)
    out = pellucid.Image(lin).to_srgb8()
    assert out.dtype == np.uint8 and out.shape == (1, 3, 3)
    # sRGB OETF (IEC 61966-2-1): 12.92·x below 0.0031308, else 1.055·x^(1/2.4) − 0.055.
    expect = [[[0, round(255 * 12.92 * 0.0031308), round(255 * (1.055 * 0.5 ** (1 / 2.4) - 0.055))],
               [255, 255, 0],
               [0, round(255 * (1.055 * 0.18 ** (1 / 2.4) - 0.055)), round(255 * 12.92 * 1e-4)]]]
    assert out.tolist() == expect
    grey = pellucid.Image(np.full((2, 2), 0.5, np.float32)).to_srgb8()
    assert grey.shape == (2, 2, 3) and (grey == 188).all()


def test_repr_png_round_trips_the_srgb8_pixels(tmp_path) -> None:
    """The PNG holds exactly the to_srgb8 pixels (read back through OpenImageIO, which decodes sRGB
    to linear; re-encoding gives the same 8-bit values)."""
    rng = np.random.default_rng(3)
    lin = rng.random((5, 7, 3), dtype=np.float32) * 1.2
    lin[0, 0] = [np.nan, np.inf, -1.0]
    img = pellucid.Image(lin)
    data = img._repr_png_()
    assert data[:8] == b"\x89PNG\r\n\x1a\n"
    (tmp_path / "a.png").write_bytes(data)
    back = pellucid.read_image(tmp_path / "a.png")
    assert back.shape == (5, 7, 3)
    assert np.array_equal(back.to_srgb8(), img.to_srgb8())
    # Grey and RGBA images show as RGB: grey replicated, alpha dropped.
    grey = pellucid.Image(np.full((2, 3), 0.5, np.float32))
    (tmp_path / "g.png").write_bytes(grey._repr_png_())
    assert (pellucid.read_image(tmp_path / "g.png").to_srgb8() == 188).all()


def test_compare_rmse_and_relmse() -> None:
    ref = pellucid.Image(np.full((4, 4, 3), 0.5, np.float32))
    a = ref.copy()
    a[0, 0, 0] = 1.5  # one channel of one pixel off by 1
    c = a.compare(ref)
    n = 4 * 4 * 3
    assert c.rmse == pytest.approx(np.sqrt(1.0 / n), rel=1e-12)
    assert c.relmse == pytest.approx(1.0 / (0.25 + RELMSE_EPSILON) / n, rel=1e-12)
    assert RELMSE_EPSILON == 1e-2
    assert ref.compare(ref) == (0.0, 0.0)
    assert a.compare(np.asarray(ref)) == c  # plain arrays work as the reference
    assert "rmse=" in repr(c) and "relmse=" in repr(c)
    with pytest.raises(pellucid.Error, match="shapes differ"):
        a.compare(np.zeros((4, 5, 3)))


def test_repr_is_readable() -> None:
    img = pellucid.Image(np.array([[[0.0, 1.0, 2.0], [3.0, 4.0, 5.0]]], dtype=np.float32))
    r = repr(img)
    assert r == "Image(2x1, 3 channels, float32, mean 2.5, min 0, max 5)", r
    assert str(img) == r  # print(img) shows the summary, not 100k numbers
    bad = img.copy()
    bad[0, 0, 0] = np.nan
    assert "1 non-finite" in repr(bad)
    assert repr(img[0, 0]).startswith("Image([")  # not an image any more: the array repr
