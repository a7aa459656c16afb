"""AOV renders: albedo, shading normal and depth of the first hit (see integrator/aov.h).

Usage::

    from pellucid.aov import render_aov
    normals = render_aov("scenes/cornell_box.json", "normal", spp=4)   # float32 (H, W, 3)
"""
from __future__ import annotations

import os
from typing import Any, Dict, Optional, Union

import numpy as np

from . import _core
from ._core import Error, Scene

__all__ = ["AOVS", "render_aov"]

#: The AOV names ``render_aov`` accepts.
AOVS = ("albedo", "normal", "depth")

SceneLike = Union[Scene, str, "os.PathLike[str]", Dict[str, Any]]


def _as_scene(scene_or_path: SceneLike) -> Scene:
    if isinstance(scene_or_path, Scene):
        return scene_or_path
    if isinstance(scene_or_path, dict):
        return _core.load_dict(scene_or_path, ".")
    if isinstance(scene_or_path, (str, os.PathLike)):
        return _core.load_file(os.fspath(scene_or_path))
    raise Error(f"scene: expected a Scene, a scene file path or a dict, got {type(scene_or_path).__name__}")


def render_aov(
    scene_or_path: SceneLike,
    name: str,
    spp: Optional[int] = None,
    seed: Optional[int] = None,
    threads: int = 0,
) -> np.ndarray:
    """Render one AOV of the scene's first hits instead of its integrator; returns a float32
    (H, W, 3) array.

    ``name`` is ``"albedo"`` (mean BSDF sample weight, i.e. directional albedo, 0 on a miss),
    ``"normal"`` (world-space shading normal, components in [-1, 1], 0 on a miss) or ``"depth"``
    (distance along the camera ray, 0 on a miss). ``scene_or_path`` is a built ``Scene``, a scene
    file path (.json or Mitsuba .xml) or a dict in the JSON format. ``spp`` and ``seed`` default to
    the scene's sampler. Raises ``pellucid.Error`` for an unknown AOV or bad arguments.
    """
    if name not in AOVS:
        raise Error(f"aov: unknown aov {name!r} (known: albedo, depth, normal)")
    if spp is not None and (not isinstance(spp, int) or isinstance(spp, bool) or spp < 1):
        raise Error(f"spp: value {spp!r} must be an integer >= 1")
    if seed is not None and (not isinstance(seed, int) or isinstance(seed, bool) or seed < 0):
        raise Error(f"seed: value {seed!r} must be an integer >= 0")
    scene = _as_scene(scene_or_path)
    image, _ = _core.render_aov(
        scene, name, spp=-1 if spp is None else spp, seed=-1 if seed is None else seed, threads=threads
    )
    return image
