"""pellucid: a physically based renderer for material appearance.

Quick start::

    import pellucid
    scene = pellucid.load_file("scenes/cornell_box.json")
    image = pellucid.render(scene, spp=64)          # float32 (H, W, 3), linear radiance
    pellucid.write_image("out/cornell_box.exr", image)
"""
from __future__ import annotations

import logging as _logging
import os as _os
from typing import Any, Dict, Optional, Union

import numpy as _np

from . import _core
from ._core import Error, Scene, cancel
from .bsdf import bsdf

__version__: str = _core.__version__
__all__ = [
    "Error",
    "Scene",
    "bsdf",
    "cancel",
    "load_dict",
    "load_file",
    "read_image",
    "render",
    "render_with_stats",
    "write_image",
    "__version__",
]

_log = _logging.getLogger("pellucid")


def _sink(level: int, message: str) -> None:
    _log.log(level, message)


_core.set_log_sink(_sink)


def load_file(path: Union[str, "_os.PathLike[str]"]) -> Scene:
    """Load and build a scene file (JSON, see docs/scene-format.md). Raises pellucid.Error."""
    return _core.load_file(_os.fspath(path))


def load_dict(d: Dict[str, Any], base_dir: Union[str, "_os.PathLike[str]"] = ".") -> Scene:
    """Build a scene from a dict with the JSON format's structure. Raises pellucid.Error with the
    key path of the problem (for example ``shapes[3].material: no material 'gold'``)."""
    if not isinstance(d, dict):
        raise Error(f"<dict>: expected a dict, got {type(d).__name__}")
    return _core.load_dict(d, _os.fspath(base_dir))


def write_image(path: Union[str, "_os.PathLike[str]"], array: _np.ndarray) -> None:
    """Write an (H, W, 3) or (H, W) float array: .exr/.hdr keep linear HDR values, .png/.jpg are
    clamped and sRGB-encoded. Raises pellucid.Error naming the path."""
    _core.write_image(_os.fspath(path), array)


def read_image(path: Union[str, "_os.PathLike[str]"]) -> _np.ndarray:
    """Read an image as a linear float32 (H, W, 3) array (8-bit files are decoded from sRGB)."""
    return _core.read_image(_os.fspath(path))


def render_with_stats(
    scene: Scene,
    spp: Optional[int] = None,
    seed: Optional[int] = None,
    threads: int = 0,
    time_budget: Optional[float] = None,
    target_rel_error: Optional[float] = None,
    progress: bool = False,
):
    """Render and return ``(image, variance, stats)``.

    ``image`` is the per-pixel mean radiance, ``variance`` the variance of that mean (both float32
    (H, W, 3) arrays that view C++ memory), ``stats`` a dict with the spp reached, wall seconds,
    camera samples and the number of NaN/Inf samples kept out of the film.
    """
    if spp is not None and (not isinstance(spp, int) or isinstance(spp, bool) or spp < 1):
        raise Error(f"spp: value {spp!r} must be an integer >= 1")
    if seed is not None and (not isinstance(seed, int) or seed < 0):
        raise Error(f"seed: value {seed!r} must be an integer >= 0")
    return _core.render_full(
        scene,
        spp=-1 if spp is None else spp,
        seed=-1 if seed is None else seed,
        threads=threads,
        time_budget=time_budget or 0.0,
        target_rel_error=target_rel_error or 0.0,
        progress=progress,
    )


def render(
    scene: Scene,
    spp: Optional[int] = None,
    seed: Optional[int] = None,
    threads: int = 0,
    time_budget: Optional[float] = None,
    target_rel_error: Optional[float] = None,
    progress: bool = False,
) -> _np.ndarray:
    """Render ``scene`` and return the image, a float32 (H, W, 3) numpy array of linear radiance
    that views the renderer's memory (no copy). The GIL is released while rendering.

    ``spp`` and ``seed`` default to the scene's sampler; ``threads=0`` uses every core. The same
    scene and seed give the same image at any thread count.
    """
    image, _, _ = render_with_stats(scene, spp, seed, threads, time_budget, target_rel_error, progress)
    return image
