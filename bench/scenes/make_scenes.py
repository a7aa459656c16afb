"""Generate scenes/veach_mis.json, scenes/env_spheres.json and the env map scenes/textures/sky.exr.
SPDX-License-Identifier: Apache-2.0

    .venv/bin/python bench/scenes/make_scenes.py

The outputs are committed; this script records how they were made (and remakes them byte for byte,
the env map included, as it is a closed-form function with no randomness).
"""
from __future__ import annotations

import json
import math
import pathlib
import sys

import numpy as np

ROOT = pathlib.Path(__file__).resolve().parents[2]


def _normalize(v):
    v = np.asarray(v, dtype=np.float64)
    return v / np.linalg.norm(v)


def veach_mis() -> dict:
    """Veach's MIS test scene (E. Veach, PhD thesis, Stanford 1997, fig. 9.2): four glossy plates of
    increasing roughness under four spherical lights whose radii span a factor 27 and whose radiances
    scale as 1/r^2, so every light has the same power. BSDF sampling wins on the smooth plates and the
    big lights, light sampling on the rough plates and the small lights; MIS should win everywhere."""
    cam = np.array([0.0, 2.0, 15.0])
    light_row = np.array([0.0, 0.5, 0.0])
    # Plates from the farthest (smoothest) to the nearest (roughest); GGX alpha.
    plates = [((0.0, -2.3, 2.4), 0.01), ((0.0, -2.85, 4.0), 0.04),
              ((0.0, -3.3, 5.6), 0.1), ((0.0, -3.65, 7.2), 0.25)]
    shapes = []
    for k, (c, alpha) in enumerate(plates):
        c = np.array(c)
        # Tilt each plate so that the mirror direction of the camera ray at its centre hits the row of
        # lights: its normal is the half vector of the directions to the camera and to the lights.
        n = _normalize(_normalize(cam - c) + _normalize(light_row - c))
        # rectangle normal +z; rotate about x by theta: (0, 0, 1) -> (0, -sin theta, cos theta)
        theta = math.degrees(math.atan2(-n[1], n[2]))
        shapes.append({"type": "rectangle", "material": f"plate{k}",
                       "to_world": [{"scale": [4.0, 0.75, 1.0]},
                                    {"rotate": {"axis": [1, 0, 0], "angle": round(theta, 4)}},
                                    {"translate": [round(float(x), 4) for x in c]}]})
    radii = [0.0333, 0.1, 0.3, 0.9]
    xs = [-3.75, -1.25, 1.25, 3.75]
    tints = [[1.0, 0.85, 0.7], [0.8, 1.0, 0.8], [0.75, 0.85, 1.0], [1.0, 0.8, 0.9]]
    for x, r, tint in zip(xs, radii, tints):
        L = 1.0 / (r * r)
        shapes.append({"type": "sphere", "center": [x, float(light_row[1]), 0.0], "radius": r, "material": "black",
                       "emitter": {"type": "area", "radiance": [round(L * t, 4) for t in tint]}})
    shapes.append({"type": "rectangle", "material": "floor",
                   "to_world": [{"scale": 30}, {"rotate": {"axis": [1, 0, 0], "angle": -90}}, {"translate": [0, -4.2, 0]}]})
    shapes.append({"type": "rectangle", "material": "floor",
                   "to_world": [{"scale": 30}, {"translate": [0, 0, -3.0]}]})
    materials = {f"plate{k}": {"type": "rough_conductor", "material": "Al", "alpha": a}
                 for k, (_, a) in enumerate(plates)}
    materials["floor"] = {"type": "lambertian", "reflectance": 0.15}
    materials["black"] = {"type": "lambertian", "reflectance": 0.0}
    return {
        "camera": {"type": "perspective", "fov": 36, "fov_axis": "x",
                   "to_world": [{"look_at": {"origin": cam.tolist(), "target": [0, -2.0, 3.0], "up": [0, 1, 0]}}]},
        "film": {"width": 320, "height": 240, "filter": {"type": "gaussian", "stddev": 0.5}},
        "sampler": {"sample_count": 64, "seed": 0},
        "integrator": {"type": "path", "strategy": "mis", "max_depth": 8, "rr_depth": 5},
        "materials": materials,
        "shapes": shapes,
    }


def sky_envmap(width: int = 256, height: int = 128) -> np.ndarray:
    """A closed-form sky in Mitsuba's lat-long convention (row 0 = +y; u = 0 looks along -z and grows
    towards +x): blue zenith, bright horizon, dim brown ground, and a small sun of radius 2.5 degrees
    and radiance 400 (30 % of the map's sin(theta)-weighted radiance) that makes BSDF-only sampling noisy."""
    v, u = np.meshgrid((np.arange(height) + 0.5) / height, (np.arange(width) + 0.5) / width, indexing="ij")
    theta, phi = np.pi * v, 2.0 * np.pi * u
    d = np.stack([np.sin(theta) * np.sin(phi), np.cos(theta), -np.sin(theta) * np.cos(phi)], axis=-1)
    y = d[..., 1:2]
    zenith, horizon, ground = np.array([0.12, 0.3, 0.8]), np.array([0.9, 0.9, 0.85]), np.array([0.18, 0.14, 0.1])
    t = np.clip(y, 0.0, 1.0) ** 0.5
    img = np.where(y >= 0.0, horizon * (1 - t) + zenith * t, ground + (horizon - ground) * np.exp(12.0 * y))
    sun = _normalize([0.6, 0.55, 0.45])  # elevation ~33 degrees, to the right and in front of the camera
    cosg = np.clip(d @ sun, -1.0, 1.0)
    gamma = np.degrees(np.arccos(cosg))[..., None]
    img = img + np.array([1.0, 0.9, 0.75]) * (400.0 * (gamma < 2.5) + 3.0 * np.exp(-gamma / 6.0))
    return img.astype(np.float32)


def env_spheres() -> dict:
    return {
        "camera": {"type": "perspective", "fov": 40, "fov_axis": "x",
                   "to_world": [{"look_at": {"origin": [0, 1.5, 5.2], "target": [0, 0.45, 0], "up": [0, 1, 0]}}]},
        "film": {"width": 320, "height": 200, "filter": {"type": "gaussian", "stddev": 0.5}},
        "sampler": {"sample_count": 64, "seed": 0},
        "integrator": {"type": "path", "strategy": "mis", "max_depth": 8, "rr_depth": 5},
        "materials": {
            "ground": {"type": "lambertian", "reflectance": 0.45},
            "clay": {"type": "lambertian", "reflectance": [0.7, 0.25, 0.15]},
            "gold": {"type": "rough_conductor", "material": "Au", "alpha": 0.12},
            "copper": {"type": "conductor", "material": "Cu"},
            "glass": {"type": "dielectric", "int_ior": "bk7"},
        },
        "shapes": [
            {"type": "rectangle", "material": "ground",
             "to_world": [{"scale": 20}, {"rotate": {"axis": [1, 0, 0], "angle": -90}}]},
            {"type": "sphere", "center": [-1.65, 0.5, 0], "radius": 0.5, "material": "clay"},
            {"type": "sphere", "center": [-0.55, 0.5, 0], "radius": 0.5, "material": "gold"},
            {"type": "sphere", "center": [0.55, 0.5, 0], "radius": 0.5, "material": "copper"},
            {"type": "sphere", "center": [1.65, 0.5, 0], "radius": 0.5, "material": "glass"},
        ],
        "lights": [{"type": "envmap", "filename": "textures/sky.exr", "scale": 1.0}],
    }


def _dump(d: dict) -> str:
    """Pretty JSON with one shape / material per line."""
    lines = ["{"]
    keys = list(d)
    for i, k in enumerate(keys):
        comma = "," if i + 1 < len(keys) else ""
        v = d[k]
        if isinstance(v, list) and v and isinstance(v[0], dict):
            lines.append(f'  "{k}": [')
            lines += [f"    {json.dumps(x)}" + ("," if j + 1 < len(v) else "") for j, x in enumerate(v)]
            lines.append(f"  ]{comma}")
        elif k == "materials":
            lines.append(f'  "{k}": {{')
            items = list(v.items())
            lines += [f"    {json.dumps(n)}: {json.dumps(m)}" + ("," if j + 1 < len(items) else "")
                      for j, (n, m) in enumerate(items)]
            lines.append(f"  }}{comma}")
        else:
            lines.append(f'  "{k}": {json.dumps(v)}{comma}')
    lines.append("}")
    return "\n".join(lines) + "\n"


def main() -> int:
    scenes = ROOT / "scenes"
    (scenes / "veach_mis.json").write_text(_dump(veach_mis()))
    (scenes / "env_spheres.json").write_text(_dump(env_spheres()))
    (scenes / "textures").mkdir(exist_ok=True)
    import pellucid

    pellucid.write_image(scenes / "textures" / "sky.exr", sky_envmap())
    print("wrote", scenes / "veach_mis.json", scenes / "env_spheres.json", scenes / "textures" / "sky.exr")
    return 0


if __name__ == "__main__":
    sys.exit(main())
