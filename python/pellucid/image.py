"""``pellucid.Image``: a float32 (H, W, C) numpy array of linear radiance with a few conveniences.

``Image`` subclasses :class:`numpy.ndarray`, so every function that takes arrays takes an ``Image``
unchanged (and slicing or arithmetic gives ``Image`` again). The extras::

    img = pellucid.render(scene)
    img                      # Image(256x256, 3 channels, float32, mean 0.1832, min 0, max 17.36)
    img.save("out.png")      # .exr/.hdr linear; .png/.jpg clamped and sRGB-encoded
    img.to_srgb8()           # uint8 (H, W, 3) for display
    img.compare(reference)   # Comparison(rmse=..., relmse=...)

In Jupyter an ``Image`` shows itself inline (``_repr_png_``).
"""
from __future__ import annotations

import os
import tempfile
from typing import Any, NamedTuple, Union

import numpy as np

from . import _core

#: ε in relMSE = mean((a − b)² / (b² + ε)): keeps dark reference pixels from dominating.
RELMSE_EPSILON = 1e-2


class Comparison(NamedTuple):
    """Errors of an image against a reference, averaged over every pixel and channel."""

    rmse: float    #: sqrt(mean((a − b)²))
    relmse: float  #: mean((a − b)² / (b² + 1e-2)), b = the reference

    def __repr__(self) -> str:
        return f"Comparison(rmse={self.rmse:.6g}, relmse={self.relmse:.6g})"


def srgb_encode(linear: np.ndarray) -> np.ndarray:
    """sRGB OETF (IEC 61966-2-1) of values already clamped to [0, 1]."""
    return np.where(linear <= 0.0031308, 12.92 * linear, 1.055 * np.power(linear, 1.0 / 2.4) - 0.055)


def rel_mse(image: Any, reference: Any, eps: float = RELMSE_EPSILON) -> float:
    """relMSE = mean((a − b)² / (b² + eps)) over every pixel and channel, in float64; b = the
    reference (a scalar reference broadcasts). No shape or finiteness checks: see Image.compare."""
    a = np.asarray(image, dtype=np.float64)
    b = np.asarray(reference, dtype=np.float64)
    return float(np.mean((a - b) ** 2 / (b * b + eps)))


class Image(np.ndarray):
    """A float32 (H, W, 3) array of linear radiance (also (H, W) or (H, W, 1|4)).

    Build one from any array with ``pellucid.Image(array)`` (no copy when it is already float32
    and C-contiguous); ``pellucid.render`` and ``pellucid.read_image`` return one.
    """

    def __new__(cls, array: Any) -> "Image":
        return np.ascontiguousarray(array, dtype=np.float32).view(cls)

    def __array_wrap__(self, obj: np.ndarray, context: Any = None, return_scalar: bool = False) -> Any:
        # Reductions to a single number give a Python-friendly numpy scalar, not a 0-d Image.
        if obj.ndim == 0:
            return obj[()]
        return super().__array_wrap__(obj, context)

    # ---- pixels -------------------------------------------------------------------------------
    @property
    def width(self) -> int:
        return int(self.shape[1]) if self.ndim >= 2 else 0

    @property
    def height(self) -> int:
        return int(self.shape[0]) if self.ndim >= 2 else 0

    def _rgb(self) -> np.ndarray:
        a = np.asarray(self, dtype=np.float32)
        if a.ndim == 2:
            a = a[:, :, None]
        if a.ndim != 3 or a.shape[2] not in (1, 3, 4):
            raise _core.Error(f"image: expected shape (H, W), (H, W, 1), (H, W, 3) or (H, W, 4), got {a.shape}")
        if a.shape[2] == 1:
            a = np.repeat(a, 3, axis=2)
        return a[:, :, :3]

    def to_srgb8(self) -> np.ndarray:
        """uint8 (H, W, 3): each channel clamped to [0, 1], sRGB-encoded, rounded to nearest. NaN
        becomes 0. Grey images are replicated to three channels; alpha is dropped."""
        a = np.nan_to_num(self._rgb(), nan=0.0, posinf=1.0, neginf=0.0)
        return np.round(srgb_encode(np.clip(a, 0.0, 1.0)) * 255.0).astype(np.uint8)

    def save(self, path: Union[str, "os.PathLike[str]"]) -> None:
        """Write the image: .exr/.hdr keep linear HDR values, .png/.jpg are clamped and sRGB-encoded
        (the same as ``pellucid.write_image``). Raises pellucid.Error naming the path."""
        _core.write_image(os.fspath(path), np.ascontiguousarray(self, dtype=np.float32))

    def _repr_png_(self) -> bytes:
        """PNG bytes for Jupyter's inline display: the pixels of ``to_srgb8`` (clamped, sRGB, no
        tone mapping), encoded by OpenImageIO's PNG writer (``pellucid.write_image``)."""
        with tempfile.TemporaryDirectory(prefix="pellucid-") as d:
            path = os.path.join(d, "image.png")
            _core.write_image(path, np.ascontiguousarray(self._rgb()))
            with open(path, "rb") as f:
                return f.read()

    # ---- comparison ---------------------------------------------------------------------------
    def compare(self, reference: Any) -> Comparison:
        """Errors of this image against ``reference`` (same shape):

        - ``rmse`` = sqrt(mean((a − b)²)),
        - ``relmse`` = mean((a − b)² / (b² + ε)) with ε = 1e-2 (``RELMSE_EPSILON``),

        where a = this image, b = the reference, and the mean runs over every pixel and channel
        (accumulated in float64). Raises pellucid.Error if the shapes differ or a value is not
        finite.
        """
        a = np.asarray(self, dtype=np.float64)
        b = np.asarray(reference, dtype=np.float64)
        if a.shape != b.shape:
            raise _core.Error(f"compare: shapes differ: {a.shape} vs reference {b.shape}")
        if a.size == 0:
            raise _core.Error("compare: empty images")
        if not (np.isfinite(a).all() and np.isfinite(b).all()):
            raise _core.Error("compare: the images contain NaN or infinite values")
        return Comparison(float(np.sqrt(((a - b) ** 2).mean())), rel_mse(a, b))

    # ---- printing -----------------------------------------------------------------------------
    def __str__(self) -> str:
        """The same summary as repr for images (``np.array2string(img)`` prints the values)."""
        return self.__repr__() if self.ndim in (2, 3) and self.size else np.asarray(self).__str__()

    def __repr__(self) -> str:
        if self.ndim not in (2, 3) or self.size == 0:
            return np.asarray(self).__repr__().replace("array", "Image", 1)
        a = np.asarray(self)
        channels = a.shape[2] if a.ndim == 3 else 1
        finite = np.isfinite(a)
        if finite.any():
            v = a[finite].astype(np.float64)
            stats = f"mean {v.mean():.4g}, min {v.min():.4g}, max {v.max():.4g}"
        else:
            stats = "no finite values"
        bad = a.size - int(finite.sum())
        return (f"Image({a.shape[1]}x{a.shape[0]}, {channels} channel{'s' if channels != 1 else ''}, {a.dtype}, "
                f"{stats}" + (f", {bad} non-finite" if bad else "") + ")")
