"""Denoising with Intel Open Image Denoise (OIDN), through the optional ``pyoidn`` package.

Install it with ``pip install "pellucid[denoise]"`` (or ``pip install pyoidn``). Usage::

    result = pellucid.render(scene, spp=16, aovs=["albedo", "normal"])
    clean = pellucid.denoise(result.image, result["albedo"], result["normal"])
    clean = pellucid.denoise(result)   # the same: the guides are taken from the RenderLayers

A denoised image is not an unbiased estimate: the filter trades noise for bias (blur, lost
detail, a shifted mean in places). bench/results/denoise/ measures both against render time.
"""
from __future__ import annotations

from typing import Any, Optional

import numpy as np

from ._core import Error
from .image import Image

__all__ = ["denoise"]

_QUALITIES = ("high", "balanced", "fast")


def _import_pyoidn() -> Any:
    try:
        import pyoidn
    except ImportError as e:
        raise ImportError(
            "pellucid.denoise needs the pyoidn package (Intel Open Image Denoise), which is not "
            f"installed ({e}); install it with: pip install \"pellucid[denoise]\" (or pip install pyoidn)"
        ) from e
    return pyoidn


def _rgb(name: str, array: Any, shape: Optional[tuple] = None) -> np.ndarray:
    a = np.ascontiguousarray(array, dtype=np.float32)
    if a.ndim != 3 or a.shape[2] != 3 or a.shape[0] < 1 or a.shape[1] < 1:
        raise Error(f"denoise: {name}: expected an (H, W, 3) image, got shape {a.shape}")
    if shape is not None and a.shape != shape:
        raise Error(f"denoise: {name}: shape {a.shape} differs from the beauty's {shape}")
    if not np.isfinite(a).all():
        raise Error(f"denoise: {name}: the image contains NaN or infinite values")
    return a


def denoise(beauty: Any, albedo: Any = None, normal: Any = None, *, clean_aux: bool = False,
            quality: str = "high") -> Image:
    """Denoise a rendered image with Intel Open Image Denoise's ray-tracing filter ("RT", HDR mode).

    ``beauty`` is a linear HDR (H, W, 3) image (values >= 0), or a :class:`pellucid.RenderLayers`
    whose ``albedo`` and ``normal`` AOVs are then used as guides unless given. ``albedo`` and
    ``normal`` are optional guide images of the same shape: the AOVs ``albedo`` and ``normal`` of
    ``pellucid.render(scene, aovs=["albedo", "normal"])``, which follow delta bounces as OIDN
    expects. ``normal`` needs ``albedo`` (OIDN takes normals only with albedo).
    ``clean_aux=True`` tells OIDN the guides are noise-free (rendered at many spp), so it does not
    prefilter them. ``quality`` is ``"high"``, ``"balanced"`` or ``"fast"``.

    Returns a new :class:`pellucid.Image`. Raises ImportError naming the package to install when
    pyoidn is missing, and pellucid.Error for images of the wrong shape or with NaN/Inf values.
    """
    from .aov import RenderLayers

    if isinstance(beauty, RenderLayers):
        layers = beauty
        beauty = layers.image
        if albedo is None and "albedo" in layers:
            albedo = layers["albedo"]
        if normal is None and albedo is not None and "normal" in layers:
            normal = layers["normal"]
    color = _rgb("beauty", beauty)
    if (color < 0).any():
        raise Error("denoise: beauty: negative values (a rendered radiance image is >= 0)")
    if normal is not None and albedo is None:
        raise Error("denoise: normal: a normal guide needs the albedo guide too (Open Image Denoise takes "
                    "normals only with albedo)")
    if quality not in _QUALITIES:
        raise Error(f"denoise: quality: unknown quality {quality!r} (known: {', '.join(_QUALITIES)})")
    alb = None if albedo is None else _rgb("albedo", albedo, color.shape)
    nrm = None if normal is None else _rgb("normal", normal, color.shape)
    pyoidn = _import_pyoidn()
    out = pyoidn.denoise(color, alb, nrm, hdr=True, clean_aux=bool(clean_aux), quality=quality)
    return np.asarray(out, dtype=np.float32).view(Image)
