"""``pellucid.scenes``: pure-Python helpers that build scene dicts (docs/scene-format.md).

Every helper returns a fresh dict; change it freely, then build it with ``pellucid.load_dict``::

    import pellucid
    from pellucid import materials, scenes
    box = pellucid.load_dict(scenes.cornell_box(film={"width": 128, "height": 128}))
    ball = pellucid.load_dict(scenes.material_ball(materials.rough_conductor("Au", alpha=0.2)))
    white = pellucid.load_dict(scenes.furnace(materials.lambertian(1.0)))   # renders 1 everywhere
"""
from __future__ import annotations

import copy
from typing import Any, Dict, Optional, Union

SceneDict = Dict[str, Any]

__all__ = ["cornell_box", "furnace", "material_ball", "merge"]


def merge(base: SceneDict, overrides: Dict[str, Any]) -> SceneDict:
    """``base`` with ``overrides`` applied (``base`` is not modified): a dict value is merged key
    by key into a dict of ``base`` (so ``film={"width": 64}`` keeps the height), any other value
    replaces the entry, and ``None`` removes it."""
    out = copy.deepcopy(base)
    for key, value in overrides.items():
        if value is None:
            out.pop(key, None)
        elif isinstance(value, dict) and isinstance(out.get(key), dict):
            out[key] = merge(out[key], value)
        else:
            out[key] = copy.deepcopy(value)
    return out


def cornell_box(**overrides: Any) -> SceneDict:
    """The Cornell box of ``scenes/cornell_box.json`` (identical dict; Mitsuba 3's
    ``mi.cornell_box()`` geometry and colours): 256×256, 64 spp, path tracing to depth 8.

    Keyword arguments override top-level entries with :func:`merge`, e.g.
    ``cornell_box(film={"width": 64, "height": 64}, sampler={"sample_count": 16})``.
    """
    white = {"type": "lambertian", "reflectance": [0.885809, 0.698859, 0.666422]}
    scene: SceneDict = {
        "camera": {
            "type": "perspective",
            "fov": 39.3077,
            "fov_axis": "smaller",
            "to_world": [{"look_at": {"origin": [0, 0, 3.9], "target": [0, 0, 0], "up": [0, 1, 0]}}],
        },
        "film": {"width": 256, "height": 256, "filter": {"type": "gaussian", "stddev": 0.5},
                 "reconstruction": "splatting"},
        "sampler": {"sample_count": 64, "seed": 0},
        "integrator": {"type": "path", "max_depth": 8, "rr_depth": 5},
        "materials": {
            "white": white,
            "green": {"type": "lambertian", "reflectance": [0.105421, 0.37798, 0.076425]},
            "red": {"type": "lambertian", "reflectance": [0.570068, 0.0430135, 0.0443706]},
        },
        "shapes": [
            {"type": "rectangle", "material": "white",
             "to_world": [{"scale": [0.23, 0.19, 0.19]}, {"rotate": {"axis": [1, 0, 0], "angle": 90}},
                          {"translate": [0, 0.99, 0.01]}],
             "emitter": {"type": "area", "radiance": [18.387, 13.9873, 6.75357]}},
            {"type": "rectangle", "material": "white",
             "to_world": [{"rotate": {"axis": [1, 0, 0], "angle": -90}}, {"translate": [0, -1, 0]}]},
            {"type": "rectangle", "material": "white",
             "to_world": [{"rotate": {"axis": [1, 0, 0], "angle": 90}}, {"translate": [0, 1, 0]}]},
            {"type": "rectangle", "material": "white", "to_world": [{"translate": [0, 0, -1]}]},
            {"type": "rectangle", "material": "green",
             "to_world": [{"rotate": {"axis": [0, 1, 0], "angle": -90}}, {"translate": [1, 0, 0]}]},
            {"type": "rectangle", "material": "red",
             "to_world": [{"rotate": {"axis": [0, 1, 0], "angle": 90}}, {"translate": [-1, 0, 0]}]},
            {"type": "cube", "material": "white",
             "to_world": [{"scale": 0.3}, {"rotate": {"axis": [0, 1, 0], "angle": -17}},
                          {"translate": [0.335, -0.7, 0.38]}]},
            {"type": "cube", "material": "white",
             "to_world": [{"scale": [0.3, 0.61, 0.3]}, {"rotate": {"axis": [0, 1, 0], "angle": 18.25}},
                          {"translate": [-0.33, -0.4, -0.28]}]},
        ],
    }
    return merge(scene, overrides)


def _material(material: Union[str, Dict[str, Any], None], default: Dict[str, Any]) -> Dict[str, Any]:
    if material is None:
        return dict(default)
    if isinstance(material, str):
        return {"type": material}
    if not isinstance(material, dict):
        raise TypeError(f"material: expected a dict (see pellucid.materials) or a type name, got "
                        f"{type(material).__name__}")
    return copy.deepcopy(material)


def furnace(material: Union[str, Dict[str, Any], None] = None, *, radiance: float = 1.0, width: int = 64,
            height: int = 64, spp: int = 16, max_depth: int = -1, **overrides: Any) -> SceneDict:
    """White-furnace test scene: a unit sphere with ``material`` (default: white ``lambertian``,
    reflectance 1) lit by a uniform ``constant`` environment of ``radiance``, seen by a camera
    that the sphere fills. An energy-conserving, non-absorbing material renders ``radiance`` at
    every pixel; darker pixels show energy loss, brighter ones energy gain.

    ``max_depth=-1`` (unbounded) is what the test needs; ``overrides`` as in :func:`cornell_box`.
    """
    scene: SceneDict = {
        "camera": {"type": "perspective", "fov": 30,
                   "to_world": [{"look_at": {"origin": [0, 0, 4], "target": [0, 0, 0], "up": [0, 1, 0]}}]},
        "film": {"width": width, "height": height},
        "sampler": {"sample_count": spp, "seed": 0},
        "integrator": {"type": "path", "max_depth": max_depth},
        "shapes": [{"type": "sphere", "radius": 1.0,
                    "material": _material(material, {"type": "lambertian", "reflectance": 1.0})}],
        "lights": [{"type": "constant", "radiance": radiance}],
    }
    return merge(scene, overrides)


def material_ball(material: Union[str, Dict[str, Any], None] = None, *, width: int = 256, height: int = 192,
                  spp: int = 64, environment: Optional[float] = 0.25, **overrides: Any) -> SceneDict:
    """One sphere of ``material`` (a dict from :mod:`pellucid.materials`, or a type name with
    default parameters) on a grey floor in front of a backdrop, lit by a large soft area light
    and a dim ``constant`` environment (``environment=None`` removes it). ``overrides`` as in
    :func:`cornell_box`.
    """
    scene: SceneDict = {
        "camera": {"type": "perspective", "fov": 32,
                   "to_world": [{"look_at": {"origin": [0, 1.6, 5.2], "target": [0, 0.75, 0], "up": [0, 1, 0]}}]},
        "film": {"width": width, "height": height},
        "sampler": {"sample_count": spp, "seed": 0},
        "integrator": {"type": "path", "max_depth": 12},
        "materials": {
            "ball": _material(material, {"type": "lambertian", "reflectance": 0.5}),
            "floor": {"type": "lambertian", "reflectance": 0.4},
            "backdrop": {"type": "lambertian", "reflectance": [0.55, 0.55, 0.6]},
            "light": {"type": "lambertian", "reflectance": 0.0},
        },
        "shapes": [
            {"type": "sphere", "center": [0, 0.8, 0], "radius": 0.8, "material": "ball"},
            {"type": "rectangle", "material": "floor",
             "to_world": [{"scale": 8}, {"rotate": {"axis": [1, 0, 0], "angle": -90}}]},
            {"type": "rectangle", "material": "backdrop", "to_world": [{"scale": 8}, {"translate": [0, 0, -2.5]}]},
            {"type": "rectangle", "material": "light",
             "to_world": [{"scale": 1.2}, {"rotate": {"axis": [1, 0, 0], "angle": 120}},
                          {"translate": [-1.5, 4.0, 3.0]}],
             "emitter": {"type": "area", "radiance": 6.0}},
        ],
    }
    if environment is not None:
        scene["lights"] = [{"type": "constant", "radiance": environment}]
    return merge(scene, overrides)
