"""pellucid: a physically based renderer for material appearance.

Quick start::

    import pellucid
    from pellucid import materials, scenes
    scene = pellucid.load_dict(scenes.cornell_box())       # or load_file("scenes/cornell_box.json")
    image = pellucid.render(scene, spp=64, progress=True)  # pellucid.Image: float32 (H, W, 3) radiance
    image.save("out/cornell_box.png")                      # .exr keeps HDR; .png is sRGB
    image.compare(reference)                               # Comparison(rmse=..., relmse=...)
    result = pellucid.render(scene, spp=16, aovs=["albedo", "normal"])  # beauty + AOVs (RenderLayers)
    clean = pellucid.denoise(result.image, result["albedo"], result["normal"])  # needs pyoidn

C++ log messages go to the ``logging`` logger ``"pellucid"`` (warnings show by default).

Ctrl-C (or any Python signal handler that raises) stops a render within about a second: the
exception is raised with the complete passes kept as ``e.partial`` (a :class:`RenderOutput`, also
returned by :func:`last_interrupted`), whose ``state`` continues the render with
``render(..., resume=state)`` (docs/rendering.md).
"""
from __future__ import annotations

import logging as _logging
import math as _math
import os as _os
import threading as _threading
from typing import Any, Dict, NamedTuple, Optional, Tuple, Union

import numpy as _np

from . import _core
from . import materials, scenes
from . import bssrdf
from ._core import Error, FilmState, Scene, cancel
from .aov import AOVS, RenderLayers, read_layers, render_aov, write_layers
from .denoise import denoise
from .bsdf import bsdf
from .phase import phase
from .image import Comparison, Image
from .parameters import SceneParameters, parameters

__version__: str = _core.__version__
__all__ = [
    "AOVS",
    "Comparison",
    "Error",
    "FilmState",
    "Image",
    "RenderLayers",
    "RenderOutput",
    "SAMPLERS",
    "Scene",
    "SceneParameters",
    "bsdf",
    "bssrdf",
    "cancel",
    "denoise",
    "last_interrupted",
    "load_dict",
    "load_file",
    "load_film_state",
    "materials",
    "parameters",
    "phase",
    "read_image",
    "read_image_attributes",
    "read_layers",
    "render",
    "render_aov",
    "render_with_stats",
    "scenes",
    "write_image",
    "write_layers",
    "__version__",
]

#: Sampler types accepted by ``render(..., sampler=...)`` and the JSON ``sampler.type``.
SAMPLERS: Tuple[str, ...] = ("independent", "sobol")

_log = _logging.getLogger("pellucid")


def _sink(level: int, message: str) -> None:
    _log.log(level, message)


_core.set_log_sink(_sink)


def _param_str(value: Any) -> str:
    """A Python value as the text of a Mitsuba XML parameter (booleans as true/false)."""
    if isinstance(value, bool):
        return "true" if value else "false"
    if isinstance(value, (list, tuple)):
        return ", ".join(_param_str(v) for v in value)
    return str(value)


def load_file(path: Union[str, "_os.PathLike[str]"], lenient: bool = False, **params: Any) -> Scene:
    """Load and build a scene file: JSON (docs/scene-format.md) or Mitsuba 3 XML
    (docs/mitsuba-import.md). Raises pellucid.Error naming the file, and the line for XML.

    ``lenient=True`` turns unsupported Mitsuba XML elements (plugins, parameters, media) into
    warnings on the ``"pellucid"`` logger, naming the element and line, and skips them; malformed
    XML, unknown ids, missing files and bad values stay errors. JSON scenes ignore it.

    Keyword ``params`` set Mitsuba XML ``$name`` parameters, overriding the file's ``<default>``
    values as Mitsuba 3's ``load_file(path, spp=256)`` does: ``load_file("scene.xml", spp=16,
    res=128)``. Values are passed as text (``True``/``False`` as ``true``/``false``, sequences
    comma-separated). JSON scenes have no parameters, so params are an error there.
    """
    return _core.load_file(_os.fspath(path), bool(lenient), {str(k): _param_str(v) for k, v in params.items()})


def load_dict(d: Dict[str, Any], base_dir: Union[str, "_os.PathLike[str]"] = ".") -> Scene:
    """Build a scene from a dict with the JSON format's structure. Raises pellucid.Error with the
    key path of the problem (for example ``shapes[3].material: no material 'gold'``)."""
    if not isinstance(d, dict):
        raise Error(f"<dict>: expected a dict, got {type(d).__name__}")
    return _core.load_dict(d, _os.fspath(base_dir))


def write_image(path: Union[str, "_os.PathLike[str]"], array: _np.ndarray,
                attributes: Optional[Dict[str, Any]] = None) -> None:
    """Write an (H, W) or (H, W, C) float array: .exr keeps linear HDR values and any number of
    channels (R, G, B, A, then OpenImageIO's default names); .png/.jpg are clamped and sRGB-encoded
    (alpha stays linear), PNG with 1 to 4 channels. Missing folders are created. ``attributes`` (name -> int, float or
    str) go into the file's header where the format has one (EXR attributes). Raises
    pellucid.Error naming the path."""
    if attributes:
        _core.write_image_with_attributes(_os.fspath(path), array, dict(attributes))
    else:
        _core.write_image(_os.fspath(path), array)


def read_image(path: Union[str, "_os.PathLike[str]"]) -> Image:
    """Read every channel of an image file as a linear float32 (H, W, C) :class:`Image`, in the
    file's channel order: an RGBA file gives C = 4 (alpha kept), a grey one C = 1, a multi-layer
    EXR all its channels (:func:`read_layers` splits them into named images). 8-bit files are
    decoded from sRGB, except alpha."""
    return _core.read_image(_os.fspath(path)).view(Image)


def read_image_attributes(path: Union[str, "_os.PathLike[str]"]) -> Dict[str, Any]:
    """The header attributes of an image file, e.g. the ``pellucid:spp`` and
    ``pellucid:invalid_samples`` that every rendered image carries (docs/rendering.md)."""
    return _core.read_image_attributes(_os.fspath(path))


def load_film_state(path: Union[str, "_os.PathLike[str]"]) -> FilmState:
    """Read a film state file (``FilmState.save`` or ``pellucid-render --state``) to continue the
    render with ``render(..., resume=state)``."""
    return _core.load_film_state(_os.fspath(path))


class RenderOutput(NamedTuple):
    """What a render produced: the image, the variance of each pixel's mean (None when the render
    kept none), the stats dict and the :class:`FilmState` to continue from (None unless kept)."""

    image: Image
    variance: Optional[Image]
    stats: Dict[str, Any]
    state: Optional[FilmState]


_last_interrupted: Optional[RenderOutput] = None


def last_interrupted() -> Optional[RenderOutput]:
    """The complete passes of the most recent render that a signal stopped (Ctrl-C in a terminal
    or Jupyter's interrupt), or None. The same object is the ``partial`` attribute of the
    ``KeyboardInterrupt`` the render raised."""
    return _last_interrupted


def _render_attributes(stats: Dict[str, Any]) -> Dict[str, Any]:
    """The header attributes that both command lines write with a rendered image (the same names
    and values as pellucid-render's): samples per pixel, dropped samples, interruption, time, seed,
    sampler and version."""
    attrs: Dict[str, Any] = {
        "pellucid:spp": int(stats["spp"]),
        "pellucid:invalid_samples": int(stats["invalid_samples"]),
        "pellucid:interrupted": 1 if stats["cancelled"] else 0,
        "pellucid:seconds": float(stats["seconds"]),
        "pellucid:version": __version__,
    }
    if "seed" in stats:
        attrs["pellucid:seed"] = str(stats["seed"])
        attrs["pellucid:sampler"] = str(stats["sampler"])
    return attrs


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


def _render_full(kwargs: Dict[str, Any], progress: bool) -> Tuple[Any, Any, Dict[str, Any]]:
    """_core.render_full with a progress bar if asked; a signal that stops it raises its exception
    with ``partial`` set to a RenderOutput, which last_interrupted() also returns."""
    global _last_interrupted
    tqdm = _tqdm() if progress else None
    try:
        if tqdm is not None:
            return _render_with_bar(tqdm, kwargs)
        return _core.render_full(progress=bool(progress), **kwargs)
    except BaseException as e:
        partial = getattr(e, "partial", None)
        if isinstance(partial, tuple) and len(partial) == 3:
            image, variance, stats = partial
            _last_interrupted = RenderOutput(image.view(Image), None if variance is None else variance.view(Image),
                                             stats, stats.get("state"))
            e.partial = _last_interrupted
        raise


def _render_kwargs(scene: Scene, spp: Optional[int], seed: Optional[int], threads: int, time_budget: Optional[float],
                   target_rel_error: Optional[float], sampler: Optional[str], resume: Any,
                   variance: bool = True) -> Dict[str, Any]:
    _check_int("spp", spp, 1, _INT32_MAX)
    _check_int("seed", seed, 0, _INT64_MAX)
    _check_int("threads", threads, 0, _INT32_MAX)
    _check_seconds("time_budget", time_budget)
    _check_seconds("target_rel_error", target_rel_error)
    if sampler is not None and sampler not in SAMPLERS:
        raise Error(f"sampler: unknown sampler {sampler!r} (known: {', '.join(SAMPLERS)})")
    if resume is not None and not isinstance(resume, (FilmState, str, _os.PathLike)):
        raise Error(f"resume: expected a FilmState or the path of a film state file, got {type(resume).__name__}")
    if not isinstance(variance, bool):
        raise Error(f"variance: expected True or False, got {variance!r}")
    return dict(
        variance=variance,
        scene=scene,
        spp=-1 if spp is None else spp,
        seed=-1 if seed is None else seed,
        threads=threads,
        time_budget=time_budget or 0.0,
        target_rel_error=target_rel_error or 0.0,
        sampler=sampler or "",
        resume=resume,
    )


def render_with_stats(
    scene: Scene,
    spp: Optional[int] = None,
    seed: Optional[int] = None,
    threads: int = 0,
    time_budget: Optional[float] = None,
    target_rel_error: Optional[float] = None,
    progress: bool = False,
    sampler: Optional[str] = None,
    resume: Union[FilmState, str, "_os.PathLike[str]", None] = None,
    keep_state: bool = False,
    variance: bool = True,
):
    """Render and return ``(image, variance, stats)``.

    ``image`` is the per-pixel mean radiance, ``variance`` the variance of that mean (both
    :class:`Image`, float32 (H, W, 3), viewing C++ memory; ``variance=False`` returns None instead
    and, with a splatting film, renders faster: the film then keeps only the sums of the mean, and
    the image is the same), ``stats`` a dict with the spp reached
    (every pixel has that many samples), wall seconds, camera samples, ``invalid_samples`` (the
    NaN/Inf/negative samples kept out of the film; a non-zero count is also logged as a warning on
    the ``"pellucid"`` logger), ``cancelled``, and the ``seed`` and ``sampler`` used. With
    ``keep_state=True``, ``stats["state"]`` is the :class:`FilmState` to continue from.

    ``progress=True`` shows a tqdm bar (a widget in Jupyter) when tqdm is installed, else the
    renderer's own text bar on a terminal's stderr.

    ``sampler`` (``"independent"`` or ``"sobol"``) overrides the scene's ``sampler.type``. With
    ``"sobol"`` the samples of a pixel are stratified, so ``variance`` (computed as if they were
    independent) overestimates the error of the mean.

    ``resume`` (a :class:`FilmState` or the path of a state file) continues that render up to
    ``spp``, with its seed; the result is bit-identical to an uninterrupted render. A state rendered
    without variance (``variance=False``, or ``pellucid-render`` without the variance AOV) resumes
    only with ``variance=False``.

    Ctrl-C stops the render within about a second and raises ``KeyboardInterrupt`` whose
    ``partial`` attribute (also :func:`last_interrupted`) is a :class:`RenderOutput` of the
    complete passes, with their state.
    """
    kwargs = _render_kwargs(scene, spp, seed, threads, time_budget, target_rel_error, sampler, resume, variance)
    kwargs["keep_state"] = bool(keep_state)
    image, var, stats = _render_full(kwargs, progress)
    if stats["invalid_samples"]:
        # The warning both command lines print.
        _log.warning("%d NaN/Inf/negative samples were discarded", stats["invalid_samples"])
    return image.view(Image), None if var is None else var.view(Image), stats


def render(
    scene: Scene,
    spp: Optional[int] = None,
    seed: Optional[int] = None,
    threads: int = 0,
    time_budget: Optional[float] = None,
    target_rel_error: Optional[float] = None,
    progress: bool = False,
    sampler: Optional[str] = None,
    resume: Union[FilmState, str, "_os.PathLike[str]", None] = None,
    aovs: Union[str, "list[str]", "tuple[str, ...]", None] = None,
) -> Union[Image, RenderLayers]:
    """Render ``scene`` and return the image: an :class:`Image` (a numpy.ndarray subclass), float32
    (H, W, 3) linear radiance that views the renderer's memory (no copy). The GIL is released
    while rendering.

    ``spp`` and ``seed`` default to the scene's sampler; ``threads=0`` uses every core. The same
    scene and seed give the same image at any thread count. ``progress=True`` shows a tqdm bar.
    ``sampler`` (``"independent"`` or ``"sobol"``) overrides the scene's ``sampler.type``.
    ``resume`` continues a :class:`FilmState` (or state file) up to ``spp``. Samples dropped as
    NaN, infinite or negative are logged as a warning with their count (``render_with_stats``
    returns it).

    Without ``aovs`` the film keeps no per-pixel variance (``render_with_stats`` returns it), unless
    ``target_rel_error`` needs it: a splatting film then keeps only the sums of the mean.

    ``aovs`` (names from :data:`AOVS`, as a list or a comma-separated string) also renders those
    AOVs and returns a :class:`RenderLayers` instead of the image: ``.image`` is the beauty,
    ``.aovs["albedo"]`` (or ``["albedo"]``) each AOV as an :class:`Image`, ``.save(path)`` writes
    one multi-layer EXR. The AOV pass runs after the beauty, along its camera rays (pellucid.aov).

    Ctrl-C (Jupyter's interrupt too) stops the render within about a second and raises
    ``KeyboardInterrupt``; the complete passes are kept: ``e.partial`` or
    :func:`last_interrupted` (a :class:`RenderOutput` with image, variance, stats and state;
    without AOVs).
    """
    if aovs is not None:
        from .aov import layers_from_render, parse_aovs
        kwargs = _render_kwargs(scene, spp, seed, threads, time_budget, target_rel_error, sampler, resume)
        kwargs["aovs"] = parse_aovs(aovs)
        image, variance, stats = _render_full(kwargs, progress)
        return layers_from_render(image, variance, stats)
    image, _, _ = render_with_stats(scene, spp, seed, threads, time_budget, target_rel_error, progress, sampler,
                                    resume, variance=False)
    return image
