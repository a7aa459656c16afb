"""AOVs (arbitrary output variables): per-pixel images rendered besides the beauty image.

Usage::

    result = pellucid.render(scene, spp=64, aovs=["albedo", "normal", "depth"])
    result.image                 # the beauty: pellucid.Image, float32 (H, W, 3)
    result.aovs["albedo"]        # pellucid.Image (H, W, 3); result["depth"] is (H, W, 1)
    result.save("out/frame.exr") # one multi-layer EXR: R, G, B, albedo.R, ..., depth.Z
    back = pellucid.read_layers("out/frame.exr")   # the same named images

    # One AOV as the whole image (the "aov" integrator), a plain float32 (H, W, 3) array:
    normals = render_aov("scenes/cornell_box.json", "normal", spp=4)

What each AOV holds (docs/rendering.md, "AOVs", and integrator/aov.h):

============  ==================  ==========================================================
name          channels            value
============  ==================  ==========================================================
albedo        albedo.R, .G, .B    denoiser guide: directional albedo at the first vertex whose
                                  sampled BSDF lobe is not delta (delta bounces followed, their
                                  reflectances multiplied in); 0 on a miss
normal        normal.X, .Y, .Z    denoiser guide: world-space shading normal at that vertex
                                  (in [-1, 1], not remapped); 0 on a miss
depth         depth.Z             distance from the camera to the first hit; 0 on a miss
position      position.X, .Y, .Z  world-space position of the first hit; 0 on a miss
uv            uv.U, .V            surface (u, v) of the first hit; 0 on a miss
shape_id      shape_id.X          index of the shape hit by the pixel-centre ray (one ray,
                                  not averaged); -1 on a miss
material_id   material_id.X       index of that hit's material; -1 on a miss
variance      variance.R, .G, .B  variance of the beauty pixel's mean (the film's estimate)
sample_count  sample_count.X      camera samples taken in the pixel
============  ==================  ==========================================================

albedo, normal, depth, position and uv are means over the pixel's camera samples with the scene's
pixel filter, taken along the very camera rays of the beauty render (same seed, sampler and spp).
"""
from __future__ import annotations

import os
from typing import Any, Dict, Iterable, Iterator, List, Mapping, Optional, Tuple, Union

import numpy as np

from . import _core
from ._core import Error, FilmState, Scene
from .image import Image

__all__ = ["AOVS", "RenderLayers", "read_layers", "render_aov", "write_layers"]

#: Every AOV name ``render(..., aovs=[...])`` accepts, in the order of the table above.
AOVS: Tuple[str, ...] = tuple(_core.aov_names())

#: The AOVs ``render_aov`` and the ``aov`` integrator render as the whole image.
SINGLE_AOVS: Tuple[str, ...] = ("albedo", "normal", "depth")

SceneLike = Union[Scene, str, "os.PathLike[str]", Dict[str, Any]]
PathLike = Union[str, "os.PathLike[str]"]


def _as_scene(scene_or_path: SceneLike) -> Scene:
    if isinstance(scene_or_path, Scene):
        return scene_or_path
    if isinstance(scene_or_path, dict):
        return _core.load_dict(scene_or_path, ".")
    if isinstance(scene_or_path, (str, os.PathLike)):
        return _core.load_file(os.fspath(scene_or_path))
    raise Error(f"scene: expected a Scene, a scene file path or a dict, got {type(scene_or_path).__name__}")


def parse_aovs(aovs: Union[str, Iterable[str]]) -> List[str]:
    """The AOV names of ``aovs`` (a list, or one comma-separated string), duplicates dropped and the
    order kept. Raises pellucid.Error for an unknown name or an empty list."""
    names = [n.strip() for n in aovs.split(",")] if isinstance(aovs, str) else list(aovs)
    out: List[str] = []
    for n in names:
        if not isinstance(n, str):
            raise Error(f"aovs: expected AOV names (str), got {n!r}")
        if n not in AOVS:
            raise Error(f"aovs: unknown aov {n!r} (known: {', '.join(AOVS)})")
        if n not in out:
            out.append(n)
    if not out:
        raise Error(f"aovs: no AOV named (known: {', '.join(AOVS)})")
    return out


def _channels(name: str, array: np.ndarray) -> List[str]:
    """The channel names of a layer: the AOV's own, else by channel count."""
    c = array.shape[2] if array.ndim == 3 else 1
    if name in AOVS:
        own = list(_core.aov_channels(name))
        if len(own) == c:
            return own
    if name == "" and c in (3, 4):
        return ["R", "G", "B", "A"][:c]
    return {1: ["Y"], 2: ["Y", "A"], 3: ["R", "G", "B"], 4: ["R", "G", "B", "A"]}.get(c, [f"c{i}" for i in range(c)])


def write_layers(path: PathLike, image: Optional[np.ndarray], aovs: Mapping[str, np.ndarray],
                 attributes: Optional[Dict[str, Any]] = None) -> None:
    """Write ``image`` (the beauty, channels ``R, G, B[, A]``; may be None) and the named ``aovs``
    as one multi-layer OpenEXR file: layer ``name`` has channels ``name.R`` ... (the AOVs of
    :data:`AOVS` get their own names: ``normal.X``, ``depth.Z``, ``uv.U``; other layers R, G, B(, A)
    or Y by channel count). ``attributes`` go into the header. All layers must have the same size.
    Raises pellucid.Error naming the path."""
    layers = []
    if image is not None:
        a = np.ascontiguousarray(image, dtype=np.float32)
        layers.append(("", _channels("", a), a))
    for name, arr in aovs.items():
        if not isinstance(name, str) or not name:
            raise Error(f"{os.fspath(path)}: layer names must be non-empty strings, got {name!r}")
        a = np.ascontiguousarray(arr, dtype=np.float32)
        layers.append((name, _channels(name, a), a))
    _core.write_layers(os.fspath(path), layers, dict(attributes or {}))


class RenderLayers:
    """A render with AOVs: what ``pellucid.render(scene, aovs=[...])`` and :func:`read_layers` return.

    - ``image``: the beauty, an :class:`Image` (H, W, 3);
    - ``aovs``: ``{name: Image}`` in the order asked for, each (H, W, C) with the AOV's channels;
    - ``variance``: the variance of each beauty pixel's mean (None when read from a file);
    - ``stats``: the render's stats dict (``spp``, ``seconds``, ``aov_seconds`` for the AOV pass,
      ``shape_names`` / ``material_names`` when shape_id / material_id were asked for ...); from
      a file, its header attributes;
    - ``state``: the :class:`FilmState` to continue from, or None.

    ``layers["albedo"]`` is ``layers.aovs["albedo"]``; ``save(path)`` writes one multi-layer EXR.
    """

    def __init__(self, image: Image, aovs: Dict[str, Image], variance: Optional[Image] = None,
                 stats: Optional[Dict[str, Any]] = None, state: Optional[FilmState] = None) -> None:
        self.image = image
        self.aovs = aovs
        self.variance = variance
        self.stats = dict(stats or {})
        self.state = state

    def __getitem__(self, name: str) -> Image:
        try:
            return self.aovs[name]
        except KeyError:
            raise KeyError(f"no AOV {name!r} in this render (it has: {', '.join(self.aovs) or 'none'})") from None

    def __contains__(self, name: object) -> bool:
        return name in self.aovs

    def __iter__(self) -> Iterator[str]:
        return iter(self.aovs)

    def save(self, path: PathLike, attributes: Optional[Dict[str, Any]] = None) -> None:
        """Write the beauty and every AOV as one multi-layer EXR (:func:`write_layers`), with the
        render's header attributes (``pellucid:spp`` ...) unless ``attributes`` are given."""
        if attributes is None and "spp" in self.stats:
            from . import _render_attributes
            attributes = _render_attributes(self.stats)
        write_layers(path, self.image, self.aovs, attributes)

    def __repr__(self) -> str:
        h, w = self.image.shape[:2]
        return f"RenderLayers({w}x{h}, aovs=[{', '.join(self.aovs)}])"


def read_layers(path: PathLike) -> RenderLayers:
    """Read a multi-layer image file (as :meth:`RenderLayers.save` and ``--aovs`` write it) back
    into a :class:`RenderLayers`: the unnamed layer (channels ``R, G, B[, A]``) is ``image``, every
    other layer an entry of ``aovs`` with its channels in order (R, G, B, A / X, Y, Z / U, V);
    ``stats`` holds the header attributes. Raises pellucid.Error naming the path."""
    p = os.fspath(path)
    layers = _core.read_layers(p)
    image: Optional[Image] = None
    aovs: Dict[str, Image] = {}
    for name, _channels_read, array in layers:
        if name == "":
            image = array.view(Image)
        else:
            aovs[name] = array.view(Image)
    if image is None:
        raise Error(f"{p}: no unnamed (beauty) layer: its channels are all named 'layer.channel'")
    return RenderLayers(image, aovs, None, _core.read_image_attributes(p), None)


def layers_from_render(image: Any, variance: Any, stats: Dict[str, Any]) -> RenderLayers:
    """The RenderLayers of a render_full result with stats['aovs'] (popped from stats)."""
    aovs = {name: np.asarray(a).view(Image) for name, a in stats.pop("aovs", {}).items()}
    var = None if variance is None else np.asarray(variance).view(Image)
    return RenderLayers(np.asarray(image).view(Image), aovs, var, stats,
                        stats.get("state"))


def render_aov(
    scene_or_path: SceneLike,
    name: str,
    spp: Optional[int] = None,
    seed: Optional[int] = None,
    threads: int = 0,
) -> np.ndarray:
    """Render one AOV instead of the scene's integrator; returns a float32 (H, W, 3) array.

    ``name`` is ``"albedo"`` or ``"normal"`` (the denoiser guides of the table above) or
    ``"depth"`` (distance along the camera ray, replicated to three channels); for the other AOVs,
    or several at once, use ``pellucid.render(scene, aovs=[...])``. ``scene_or_path`` is a built
    ``Scene``, a scene file path (.json or Mitsuba .xml) or a dict in the JSON format. ``spp`` and
    ``seed`` default to the scene's sampler. Raises ``pellucid.Error`` for an unknown AOV or bad
    arguments.
    """
    if name not in SINGLE_AOVS:
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
