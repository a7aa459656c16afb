"""pellucid: a physically based renderer for material appearance.

Quick start::

    import pellucid
    from pellucid import materials, scenes
    scene = pellucid.load_dict(scenes.cornell_box())       # or load_file("scenes/cornell_box.json")
    image = pellucid.render(scene, spp=64, progress=True)  # pellucid.Image: float32 (H, W, 3) radiance
    image.save("out/cornell_box.png")                      # .exr keeps HDR; .png is sRGB
    image.compare(reference)                               # Comparison(rmse=..., relmse=...)

C++ log messages go to the ``logging`` logger ``"pellucid"`` (warnings show by default).
"""
from __future__ import annotations

import logging as _logging
import math as _math
import os as _os
import threading as _threading
from typing import Any, Dict, Optional, Tuple, Union

import numpy as _np

from . import _core
from . import materials, scenes
from ._core import Error, Scene, cancel
from .aov import AOVS, render_aov
from .bsdf import bsdf
from .image import Comparison, Image

__version__: str = _core.__version__
__all__ = [
    "AOVS",
    "Comparison",
    "Error",
    "Image",
    "SAMPLERS",
    "Scene",
    "bsdf",
    "cancel",
    "load_dict",
    "load_file",
    "materials",
    "read_image",
    "render",
    "render_aov",
    "render_with_stats",
    "scenes",
    "write_image",
    "__version__",
]

#: Sampler types accepted by ``render(..., sampler=...)`` and the JSON ``sampler.type``.
SAMPLERS: Tuple[str, ...] = ("independent", "sobol")

_log = _logging.getLogger("pellucid")


def _sink(level: int, message: str) -> None:
    _log.log(level, message)


_core.set_log_sink(_sink)


def load_file(path: Union[str, "_os.PathLike[str]"], lenient: bool = False) -> Scene:
    """Load and build a scene file: JSON (docs/scene-format.md) or Mitsuba 3 XML
    (docs/mitsuba-import.md). Raises pellucid.Error naming the file, and the line for XML.

    ``lenient=True`` turns unsupported Mitsuba XML elements (plugins, parameters, media) into
    warnings on the ``"pellucid"`` logger, naming the element and line, and skips them; malformed
    XML, unknown ids, missing files and bad values stay errors. JSON scenes ignore it.
    """
    return _core.load_file(_os.fspath(path), bool(lenient))


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


def read_image(path: Union[str, "_os.PathLike[str]"]) -> Image:
    """Read an image as a linear float32 (H, W, 3) :class:`Image` (8-bit files are decoded from
    sRGB)."""
    return _core.read_image(_os.fspath(path)).view(Image)


def _tqdm() -> Any:
    """tqdm's auto bar (notebook widget or terminal), or None when tqdm is not installed."""
    try:
        from tqdm.auto import tqdm
    except ImportError:
        return None
    return tqdm


def _render_with_bar(tqdm: Any, kwargs: Dict[str, Any]) -> Tuple[Any, Any, Dict[str, Any]]:
    """Run _core.render_full while a Python thread polls its progress counters into a tqdm bar
    (the render releases the GIL, so the thread runs; no callback from C++ is needed)."""
    monitor = _core.RenderProgress()
    done = _threading.Event()
    bar = tqdm(total=100, desc="rendering", unit="%", bar_format="{l_bar}{bar}| {elapsed}<{remaining}{postfix}")

    def poll() -> None:
        while not done.wait(0.1):
            bar.n = round(100.0 * monitor.fraction, 1)
            bar.set_postfix_str(f"{monitor.samples:,} samples", refresh=True)

    t = _threading.Thread(target=poll, name="pellucid-progress", daemon=True)
    t.start()
    try:
        return _core.render_full(monitor=monitor, **kwargs)
    finally:
        done.set()
        t.join()
        bar.n = round(100.0 * monitor.fraction, 1)
        bar.set_postfix_str(f"{monitor.samples:,} samples", refresh=False)
        bar.close()


_INT32_MAX = 2**31 - 1
_INT64_MAX = 2**63 - 1


def _check_int(name: str, value: Any, lo: int, hi: int) -> None:
    """A render argument that the C++ core stores as a fixed-width integer: the range is checked here,
    so that a value such as 10**12 gets a pellucid.Error instead of a binding TypeError."""
    if value is None:
        return
    if isinstance(value, bool) or not isinstance(value, int):
        raise Error(f"{name}: expected an integer, got {value!r}")
    if not lo <= value <= hi:
        raise Error(f"{name}: value {value} is out of range [{lo}, {hi}]")


def _check_seconds(name: str, value: Any) -> None:
    """time_budget and target_rel_error: None or 0 (off), else a finite number > 0; NaN is an error,
    never silently ignored."""
    if value is None:
        return
    if isinstance(value, bool) or not isinstance(value, (int, float)):
        raise Error(f"{name}: expected a number, got {value!r}")
    if not _math.isfinite(value) or value < 0:
        raise Error(f"{name}: value {value!r} must be a finite number >= 0 (0 or None: no limit)")


def render_with_stats(
    scene: Scene,
    spp: Optional[int] = None,
    seed: Optional[int] = None,
    threads: int = 0,
    time_budget: Optional[float] = None,
    target_rel_error: Optional[float] = None,
    progress: bool = False,
    sampler: Optional[str] = None,
):
    """Render and return ``(image, variance, stats)``.

    ``image`` is the per-pixel mean radiance, ``variance`` the variance of that mean (both
    :class:`Image`, float32 (H, W, 3), viewing C++ memory), ``stats`` a dict with the spp reached,
    wall seconds, camera samples and the number of NaN/Inf samples kept out of the film.

    ``progress=True`` shows a tqdm bar (a widget in Jupyter) when tqdm is installed, else the
    renderer's own text bar on a terminal's stderr.

    ``sampler`` (``"independent"`` or ``"sobol"``) overrides the scene's ``sampler.type``. With
    ``"sobol"`` the samples of a pixel are stratified, so ``variance`` (computed as if they were
    independent) overestimates the error of the mean.
    """
    _check_int("spp", spp, 1, _INT32_MAX)
    _check_int("seed", seed, 0, _INT64_MAX)
    _check_int("threads", threads, 0, _INT32_MAX)
    _check_seconds("time_budget", time_budget)
    _check_seconds("target_rel_error", target_rel_error)
    if sampler is not None and sampler not in SAMPLERS:
        raise Error(f"sampler: unknown sampler {sampler!r} (known: {', '.join(SAMPLERS)})")
    kwargs: Dict[str, Any] = dict(
        scene=scene,
        spp=-1 if spp is None else spp,
        seed=-1 if seed is None else seed,
        threads=threads,
        time_budget=time_budget or 0.0,
        target_rel_error=target_rel_error or 0.0,
        sampler=sampler or "",
    )
    tqdm = _tqdm() if progress else None
    if tqdm is not None:
        image, variance, stats = _render_with_bar(tqdm, kwargs)
    else:
        image, variance, stats = _core.render_full(progress=bool(progress), **kwargs)
    return image.view(Image), variance.view(Image), stats


def render(
    scene: Scene,
    spp: Optional[int] = None,
    seed: Optional[int] = None,
    threads: int = 0,
    time_budget: Optional[float] = None,
    target_rel_error: Optional[float] = None,
    progress: bool = False,
    sampler: Optional[str] = None,
) -> Image:
    """Render ``scene`` and return the image: an :class:`Image` (a numpy.ndarray subclass), float32
    (H, W, 3) linear radiance that views the renderer's memory (no copy). The GIL is released
    while rendering.

    ``spp`` and ``seed`` default to the scene's sampler; ``threads=0`` uses every core. The same
    scene and seed give the same image at any thread count. ``progress=True`` shows a tqdm bar.
    ``sampler`` (``"independent"`` or ``"sobol"``) overrides the scene's ``sampler.type``.
    """
    image, _, _ = render_with_stats(scene, spp, seed, threads, time_budget, target_rel_error, progress, sampler)
    return image
