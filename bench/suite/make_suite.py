"""Generate the benchmark suite: bench/suite/*.json and bench/suite/suite.json (the manifest).
SPDX-License-Identifier: Apache-2.0

    .venv/bin/python bench/suite/make_suite.py           # rewrite the scenes (committed)
    .venv/bin/python bench/suite/make_suite.py --assets  # also write the generated meshes now

The scenes are committed; this script records how they were made and remakes them byte for byte
(tests/python/test_bench_suite.py checks that). Large assets are never committed: the 1 M-triangle
mesh is a closed-form surface written at run time by `ensure_assets` into bench/cache/suite/
(git-ignored), which `python -m pellucid bench --suite` calls before it loads a scene.

Every scene is about 256 x 256 pixels, 64 spp, with an explicit `max_depth`, and uses the options that
give Mitsuba 3's definition of each model where pellucid offers both (splatting film, separable
shadowing, the rough plastic coat's own transmittance, Mitsuba's bump model, bilinear image
lookups, point-sampled checkerboards), so the Mitsuba twin that bench/peers/mitsuba_runner.py
writes renders the same image and the two can be z-tested. The manifest marks the one scene whose
models Mitsuba 3 lacks (`peer: "substitute"`). The runner's converter has no media, so the scenes with
media also get a Mitsuba XML twin written here (`mitsuba_twin`, manifest key `twin`, Mitsuba's volpath),
which bench/suite/mitsuba_twin.py renders at the suite's spp and film size.
"""
from __future__ import annotations

import argparse
import json
import pathlib
import sys
from typing import Dict, List

import numpy as np

HERE = pathlib.Path(__file__).resolve().parent
ROOT = HERE.parents[1]
CACHE = ROOT / "bench" / "cache" / "suite"
TEX = "../../scenes/textures/"  # the committed textures, relative to bench/suite/
SKY = TEX + "sky.exr"

# ----------------------------------------------------------------------------------- assets
KNOT_SEGMENTS, KNOT_SIDES = 4096, 128  # 2 * 4096 * 128 = 1,048,576 triangles


def torus_knot(segments: int = KNOT_SEGMENTS, sides: int = KNOT_SIDES, p: int = 2, q: int = 3,
               tube: float = 0.22):
    """A (p, q) torus knot swept by a circle of radius `tube`: positions, unit vertex normals (the
    exact normals of the swept tube) and triangle indices, 2 * segments * sides triangles."""
    t = np.arange(segments, dtype=np.float64) * (2 * np.pi / segments)
    r = 2.0 + np.cos(q * t)
    c = np.stack([r * np.cos(p * t), r * np.sin(p * t), -np.sin(q * t)], axis=1)
    dc = np.stack([-p * r * np.sin(p * t) - q * np.sin(q * t) * np.cos(p * t),
                   p * r * np.cos(p * t) - q * np.sin(q * t) * np.sin(p * t),
                   -q * np.cos(q * t)], axis=1)
    tangent = dc / np.linalg.norm(dc, axis=1, keepdims=True)
    # A frame that turns with the curve without twisting much: project a fixed axis off the tangent.
    ref = np.array([0.0, 0.0, 1.0])
    n1 = ref - tangent * (tangent @ ref)[:, None]
    n1 /= np.linalg.norm(n1, axis=1, keepdims=True)
    n2 = np.cross(tangent, n1)
    v = np.arange(sides, dtype=np.float64) * (2 * np.pi / sides)
    normal = (np.cos(v)[None, :, None] * n1[:, None, :] + np.sin(v)[None, :, None] * n2[:, None, :])
    pos = c[:, None, :] + tube * normal
    i = np.arange(segments)[:, None]
    j = np.arange(sides)[None, :]
    a = i * sides + j
    b = ((i + 1) % segments) * sides + j
    c2 = ((i + 1) % segments) * sides + (j + 1) % sides
    d = i * sides + (j + 1) % sides
    tri = np.stack([np.stack([a, b, c2], -1), np.stack([a, c2, d], -1)], axis=2).reshape(-1, 3)
    return pos.reshape(-1, 3), normal.reshape(-1, 3), tri


def write_ply(path: pathlib.Path, pos: np.ndarray, nrm: np.ndarray, tri: np.ndarray) -> None:
    """Binary little-endian PLY with float positions and normals and uchar/int face lists."""
    header = (f"ply\nformat binary_little_endian 1.0\nelement vertex {len(pos)}\n"
              "property float x\nproperty float y\nproperty float z\n"
              "property float nx\nproperty float ny\nproperty float nz\n"
              f"element face {len(tri)}\nproperty list uchar int vertex_indices\nend_header\n")
    vert = np.concatenate([pos, nrm], axis=1).astype("<f4")
    face = np.zeros(len(tri), dtype=[("n", "u1"), ("i", "<i4", (3,))])
    face["n"], face["i"] = 3, tri
    tmp = path.with_suffix(".tmp")
    with open(tmp, "wb") as f:
        f.write(header.encode("ascii"))
        f.write(vert.tobytes())
        f.write(face.tobytes())
    tmp.replace(path)


ASSETS = {"torus_knot_1m.ply": lambda path: write_ply(path, *torus_knot())}


def ensure_assets(names: List[str], log=print) -> None:
    """Write each named generated asset into bench/cache/suite/ unless it is there already."""
    CACHE.mkdir(parents=True, exist_ok=True)
    for name in names:
        if name not in ASSETS:
            raise KeyError(f"bench/suite: unknown generated asset {name!r} (known: {', '.join(ASSETS)})")
        path = CACHE / name
        if not path.exists():
            log(f"generating {path.name} ...")
            ASSETS[name](path)


# ----------------------------------------------------------------------------------- helpers
def look_at(origin, target, up=(0, 1, 0)):
    return [{"look_at": {"origin": list(origin), "target": list(target), "up": list(up)}}]


def base(origin, target, fov=40.0, width=256, height=256, max_depth=8, spp=64) -> dict:
    return {"camera": {"type": "perspective", "fov": fov, "fov_axis": "x", "to_world": look_at(origin, target)},
            "film": {"width": width, "height": height, "filter": {"type": "gaussian", "stddev": 0.5, "shift": True},
                     "reconstruction": "splatting"},
            "sampler": {"type": "independent", "sample_count": spp, "seed": 0},
            "integrator": {"type": "path", "max_depth": max_depth, "rr_depth": 5}}


def floor(material: str, y: float = 0.0, size: float = 20.0) -> dict:
    return {"type": "rectangle", "material": material,
            "to_world": [{"scale": size}, {"rotate": {"axis": [1, 0, 0], "angle": -90}}, {"translate": [0, y, 0]}]}


def sphere(center, radius, material) -> dict:
    return {"type": "sphere", "center": list(center), "radius": radius, "material": material}


def rough(d: dict) -> dict:
    """Mitsuba's Smith shadowing (G1 * G1) on a microfacet material."""
    return {**d, "shadowing": "separable"}


def rplastic(kd, alpha, distribution="ggx", **kw) -> dict:
    """Rough plastic as Mitsuba's roughplastic computes it."""
    return rough({"type": "rough_plastic", "diffuse_reflectance": kd, "alpha": alpha, "distribution": distribution,
                  "coat_transmittance": "rough", **kw})


def image(name: str, scale: float, **kw) -> dict:
    return {"type": "image", "filename": TEX + name, "filter": "bilinear", "to_uv": [{"scale": [scale, scale, 1]}],
            **kw}


def bump(d: dict, texture, scale: float) -> dict:
    """Mitsuba's bumpmap on a material."""
    return {**d, "bump_map": texture, "bump_scale": scale, "bump_model": "mitsuba", "terminator_model": "estevez",
            "invalid_normals": "mirror"}


CORNELL_WALLS = {"white": {"type": "lambertian", "reflectance": [0.885809, 0.698859, 0.666422]},
                 "green": {"type": "lambertian", "reflectance": [0.105421, 0.37798, 0.076425]},
                 "red": {"type": "lambertian", "reflectance": [0.570068, 0.0430135, 0.0443706]}}


def cornell_shapes() -> List[dict]:
    return [{"type": "rectangle", "material": "white", "emitter": {"type": "area", "radiance": [18.387, 13.9873, 6.75357]},
             "to_world": [{"scale": [0.23, 0.19, 0.19]}, {"rotate": {"axis": [1, 0, 0], "angle": 90}},
                          {"translate": [0, 0.99, 0.01]}]},
            {"type": "rectangle", "material": "white",
             "to_world": [{"rotate": {"axis": [1, 0, 0], "angle": -90}}, {"translate": [0, -1, 0]}]},
            {"type": "rectangle", "material": "white",
             "to_world": [{"rotate": {"axis": [1, 0, 0], "angle": 90}}, {"translate": [0, 1, 0]}]},
            {"type": "rectangle", "material": "white", "to_world": [{"translate": [0, 0, -1]}]},
            {"type": "rectangle", "material": "green",
             "to_world": [{"rotate": {"axis": [0, 1, 0], "angle": -90}}, {"translate": [1, 0, 0]}]},
            {"type": "rectangle", "material": "red",
             "to_world": [{"rotate": {"axis": [0, 1, 0], "angle": 90}}, {"translate": [-1, 0, 0]}]}]


def cornell_base() -> dict:
    d = base((0, 0, 3.9), (0, 0, 0), fov=39.3077)
    d["camera"]["fov_axis"] = "smaller"
    return d


# ----------------------------------------------------------------------------------- scenes
def cornell_lambert() -> dict:
    """The Cornell box: Lambertian walls and boxes, one rectangular area light."""
    d = cornell_base()
    d["materials"] = dict(CORNELL_WALLS)
    d["shapes"] = cornell_shapes() + [
        {"type": "cube", "material": "white",
         "to_world": [{"scale": 0.3}, {"rotate": {"axis": [0, 1, 0], "angle": -17}}, {"translate": [0.335, -0.7, 0.38]}]},
        {"type": "cube", "material": "white",
         "to_world": [{"scale": [0.3, 0.61, 0.3]}, {"rotate": {"axis": [0, 1, 0], "angle": 18.25}},
                      {"translate": [-0.33, -0.4, -0.28]}]}]
    return d


def cornell_spheres() -> dict:
    """The Cornell box with a rough plastic, a smooth gold and a glass sphere."""
    d = cornell_base()
    d["materials"] = {**CORNELL_WALLS,
                      "plastic": rplastic([0.1, 0.25, 0.6], 0.1),
                      "gold": {"type": "conductor", "material": "Au"},
                      "glass": {"type": "dielectric", "int_ior": "bk7"}}
    d["shapes"] = cornell_shapes() + [sphere((-0.55, -0.7, -0.25), 0.3, "plastic"),
                                      sphere((0.0, -0.7, 0.35), 0.3, "gold"),
                                      sphere((0.55, -0.7, -0.2), 0.3, "glass")]
    return d


def textured_bump() -> dict:
    """Image-textured, bump-mapped floor, panel and sphere under the sky environment map."""
    d = base((0, 1.6, 5.0), (0, 0.6, 0), fov=45)
    height = image("tiles_height.exr", 3)
    d["textures"] = {"tiles": image("tiles.png", 3), "tiles_height": height}
    d["materials"] = {
        "floor": bump({"type": "lambertian", "reflectance": image("tiles.png", 8)}, image("tiles_height.exr", 8), 0.02),
        "panel": bump({"type": "lambertian", "reflectance": {"type": "checkerboard", "color0": 0.7, "color1": 0.15,
                                                              "filtered": False, "to_uv": [{"scale": [6, 6, 1]}]}},
                      "tiles_height", 0.01),
        "ball": bump(rplastic("tiles", 0.15), "tiles_height", 0.01)}
    d["shapes"] = [floor("floor", size=6),
                   {"type": "rectangle", "material": "panel",
                    "to_world": [{"scale": [1.6, 1.2, 1]}, {"rotate": {"axis": [0, 1, 0], "angle": 20}},
                                 {"translate": [-1.0, 1.2, -1.2]}]},
                   sphere((0.9, 0.7, 0.3), 0.7, "ball")]
    d["lights"] = [{"type": "envmap", "filename": SKY, "scale": 1.0}]
    return d


def env_diffuse() -> dict:
    """A Lambertian sphere in a constant environment (nothing else in the scene)."""
    d = base((0, 0, 4), (0, 0, 0), fov=35)
    d["materials"] = {"clay": {"type": "lambertian", "reflectance": [0.8, 0.5, 0.3]}}
    d["shapes"] = [sphere((0, 0, 0), 1.0, "clay")]
    d["lights"] = [{"type": "constant", "radiance": 1.0}]
    return d


def env_rough_metal() -> dict:
    """An isotropic Beckmann rough copper sphere in a constant environment."""
    d = base((0, 0, 4), (0, 0, 0), fov=35)
    d["materials"] = {"copper": rough({"type": "rough_conductor", "material": "Cu", "alpha": 0.2,
                                       "distribution": "beckmann"})}
    d["shapes"] = [sphere((0, 0, 0), 1.0, "copper")]
    d["lights"] = [{"type": "constant", "radiance": 1.0}]
    return d


def aniso_metal() -> dict:
    """An anisotropic GGX aluminium sphere on a grey floor: a small spherical area light and the sky."""
    d = base((0, 1.2, 4.2), (0, 0.8, 0), fov=38)
    d["materials"] = {"brushed": rough({"type": "rough_conductor", "material": "Al", "alpha_u": 0.05, "alpha_v": 0.35}),
                      "ground": {"type": "lambertian", "reflectance": 0.4},
                      "black": {"type": "lambertian", "reflectance": 0.0}}
    d["shapes"] = [floor("ground"),
                   {"type": "sphere", "center": [0, 0.8, 0], "radius": 0.8, "material": "brushed",
                    "to_world": [{"rotate": {"axis": [1, 0, 0], "angle": -60}}]},
                   {"type": "sphere", "center": [1.6, 2.6, 1.4], "radius": 0.08, "material": "black",
                    "emitter": {"type": "area", "radiance": 400.0}}]
    d["lights"] = [{"type": "envmap", "filename": SKY, "scale": 0.5}]
    return d


def _from_scenes(name: str, width: int, height: int) -> dict:
    """One of scenes/*.json with the suite's film and Mitsuba's shadowing on its rough materials."""
    d = json.loads((ROOT / "scenes" / f"{name}.json").read_text())
    d["film"] = {**d["film"], "width": width, "height": height, "filter": {"type": "gaussian", "stddev": 0.5, "shift": True},
                 "reconstruction": "splatting"}
    d["sampler"] = {"type": "independent", "sample_count": 64, "seed": 0}
    d["integrator"] = {"type": "path", "max_depth": 8, "rr_depth": 5}
    d["materials"] = {k: (rough(m) if m["type"].startswith("rough_") else m) for k, m in d["materials"].items()}
    for light in d.get("lights", []):
        if "filename" in light:
            light["filename"] = "../../scenes/" + light["filename"]
    return d


def veach_mis() -> dict:
    """Veach's MIS scene (scenes/veach_mis.json): four GGX aluminium plates, four spherical lights."""
    return _from_scenes("veach_mis", 320, 240)


def env_spheres() -> dict:
    """scenes/env_spheres.json: diffuse, rough gold, smooth copper and glass spheres under the sky."""
    return _from_scenes("env_spheres", 320, 200)


def glass() -> dict:
    """Rough GGX and Beckmann glass spheres and a thin-glass pane on a checkerboard, under a spot light
    and a dim constant environment."""
    d = base((0, 1.5, 4.8), (0, 0.5, 0), fov=40)
    d["materials"] = {
        "checker": {"type": "lambertian", "reflectance": {"type": "checkerboard", "color0": 0.8, "color1": 0.2,
                                                          "filtered": False, "to_uv": [{"scale": [20, 20, 1]}]}},
        "frosted": rough({"type": "rough_dielectric", "int_ior": "bk7", "alpha": 0.15}),
        "etched": rough({"type": "rough_dielectric", "int_ior": 1.33, "alpha": 0.3, "distribution": "beckmann"}),
        "pane": {"type": "thin_dielectric", "int_ior": "bk7", "specular_transmittance": [0.9, 0.95, 1.0]}}
    d["shapes"] = [floor("checker", size=10),
                   sphere((-0.9, 0.55, 0.2), 0.55, "frosted"), sphere((0.5, 0.55, 0.6), 0.55, "etched"),
                   {"type": "rectangle", "material": "pane",
                    "to_world": [{"scale": [0.8, 0.7, 1]}, {"rotate": {"axis": [0, 1, 0], "angle": -25}},
                                 {"translate": [0.9, 0.7, -0.9]}]}]
    d["lights"] = [{"type": "spot", "intensity": 60.0, "cutoff_angle": 35, "beam_width": 25,
                    "to_world": look_at((1.5, 4.5, 2.5), (0, 0, 0))},
                   {"type": "constant", "radiance": 0.15}]
    return d


def plastics() -> dict:
    """Smooth plastic, rough GGX and Beckmann plastic spheres and a plastic cube under a point light
    and a dim constant environment."""
    d = base((0, 1.6, 5.0), (0, 0.5, 0), fov=42)
    d["materials"] = {
        "ground": {"type": "lambertian", "reflectance": 0.5},
        "smooth": {"type": "plastic", "diffuse_reflectance": [0.7, 0.1, 0.1], "variant": "coupled"},
        "ggx": rplastic([0.1, 0.6, 0.2], 0.08, variant="linear"),
        "beckmann": rplastic([0.15, 0.25, 0.7], 0.25, distribution="beckmann"),
        "box": rplastic([0.8, 0.7, 0.2], 0.3, int_ior=1.6)}
    d["shapes"] = [floor("ground"), sphere((-1.3, 0.5, 0), 0.5, "smooth"), sphere((0, 0.5, 0.3), 0.5, "ggx"),
                   sphere((1.3, 0.5, 0), 0.5, "beckmann"),
                   {"type": "cube", "material": "box",
                    "to_world": [{"scale": 0.35}, {"rotate": {"axis": [0, 1, 0], "angle": 30}},
                                 {"translate": [0.8, 0.35, 1.5]}]}]
    d["lights"] = [{"type": "point", "position": [2.0, 3.5, 2.5], "intensity": 25.0},
                   {"type": "constant", "radiance": 0.1}]
    return d


def principled() -> dict:
    """Principled 2015: plastic-like, metallic, clear-coated, sheen, glass (specular transmission) and a
    thin leaf, under a directional light and a constant environment."""
    d = base((0, 1.8, 5.2), (0, 0.5, 0), fov=45)
    p = {"type": "principled", "variant": "2015"}
    d["materials"] = {
        "ground": {"type": "lambertian", "reflectance": 0.45},
        "dielectric": {**p, "base_color": [0.7, 0.2, 0.1], "roughness": 0.4},
        "metal": {**p, "base_color": [0.9, 0.7, 0.4], "metallic": 1.0, "roughness": 0.3, "anisotropic": 0.5},
        "coated": {**p, "base_color": [0.1, 0.2, 0.6], "roughness": 0.6, "clearcoat": 1.0, "clearcoat_gloss": 0.8},
        "velvet": {**p, "base_color": [0.5, 0.1, 0.4], "roughness": 0.8, "sheen": 1.0, "flatness": 0.5},
        "glassy": {**p, "base_color": [0.9, 0.95, 1.0], "roughness": 0.1, "specular_transmission": 1.0, "eta": 1.5},
        "leaf": {**p, "thin": True, "base_color": [0.3, 0.6, 0.1], "roughness": 0.6, "diffuse_transmission": 1.0}}
    d["shapes"] = [floor("ground"),
                   sphere((-1.6, 0.45, 0), 0.45, "dielectric"), sphere((-0.55, 0.45, 0), 0.45, "metal"),
                   sphere((0.55, 0.45, 0), 0.45, "coated"), sphere((1.6, 0.45, 0), 0.45, "velvet"),
                   sphere((-0.5, 0.45, 1.2), 0.45, "glassy"),
                   {"type": "rectangle", "material": "leaf",
                    "to_world": [{"scale": [0.5, 0.4, 1]}, {"rotate": {"axis": [1, 0, 0], "angle": -60}},
                                 {"translate": [0.7, 0.45, 1.2]}]}]
    d["lights"] = [{"type": "directional", "direction": [-0.4, -1.0, -0.5], "irradiance": 3.0},
                   {"type": "constant", "radiance": 0.3}]
    return d


def no_twin() -> dict:
    """The models Mitsuba 3 has no plugin for: Oren-Nayar (EON and classic) and principled 2012, under
    a point light and a constant environment. The Mitsuba twin substitutes diffuse and principled."""
    d = base((0, 1.6, 5.0), (0, 0.5, 0), fov=42)
    d["materials"] = {
        "ground": {"type": "lambertian", "reflectance": 0.5},
        "eon": {"type": "oren_nayar", "reflectance": [0.8, 0.6, 0.4], "roughness": 0.8},
        "classic": {"type": "oren_nayar", "variant": "classic", "reflectance": [0.4, 0.6, 0.8], "sigma": 30},
        "disney": {"type": "principled", "base_color": [0.8, 0.2, 0.2], "roughness": 0.4, "sheen": 0.5},
        "disney_metal": {"type": "principled", "base_color": [0.9, 0.8, 0.5], "metallic": 1.0, "roughness": 0.3,
                         "clearcoat": 0.5}}
    d["shapes"] = [floor("ground"), sphere((-1.65, 0.5, 0), 0.5, "eon"), sphere((-0.55, 0.5, 0), 0.5, "classic"),
                   sphere((0.55, 0.5, 0), 0.5, "disney"), sphere((1.65, 0.5, 0), 0.5, "disney_metal")]
    d["lights"] = [{"type": "point", "position": [1.0, 4.0, 3.0], "intensity": 30.0},
                   {"type": "constant", "radiance": 0.2}]
    return d


def big_mesh() -> dict:
    """A 1,048,576-triangle torus knot (generated into bench/cache/suite/) of rough GGX gold over a floor,
    under a directional light and a constant environment."""
    d = base((0, 2.0, 7.5), (0, 0.9, 0), fov=45)
    d["materials"] = {"gold": rough({"type": "rough_conductor", "material": "Au", "alpha": 0.2}),
                      "ground": {"type": "lambertian", "reflectance": 0.35}}
    d["shapes"] = [floor("ground"),
                   {"type": "ply", "filename": "../cache/suite/torus_knot_1m.ply", "material": "gold",
                    "to_world": [{"scale": 0.6}, {"rotate": {"axis": [1, 0, 0], "angle": -70}},
                                 {"translate": [0, 1.0, 0]}]}]
    d["lights"] = [{"type": "directional", "direction": [-0.3, -1.0, -0.4], "irradiance": 2.5},
                   {"type": "constant", "radiance": 0.25}]
    return d


METALS = ["Au", "Ag", "Cu", "Al", "Cr", "Fe", "Ti", "Ni"]


def many_materials_list() -> Dict[str, dict]:
    """36 materials: every model that Mitsuba 3 has, with a spread of parameters (no randomness)."""
    m: Dict[str, dict] = {}
    hues = [[0.8, 0.2, 0.2], [0.2, 0.7, 0.2], [0.2, 0.3, 0.8], [0.8, 0.7, 0.2], [0.6, 0.2, 0.7], [0.9, 0.9, 0.9]]
    for i, c in enumerate(hues):
        m[f"diffuse_{i}"] = {"type": "lambertian", "reflectance": c}
    for i, metal in enumerate(METALS):
        d = {"type": "rough_conductor", "material": metal, "alpha": [0.05, 0.1, 0.2, 0.35][i % 4],
             "distribution": "ggx" if i % 2 == 0 else "beckmann"}
        if i in (5, 7):
            d.pop("alpha")
            d["alpha_u"], d["alpha_v"] = 0.05, 0.3
        m[f"metal_{metal}"] = rough(d)
    m["mirror_Au"] = {"type": "conductor", "material": "Au"}
    m["mirror_Ag"] = {"type": "conductor", "material": "Ag"}
    for i, c in enumerate(hues[:4]):
        m[f"plastic_{i}"] = {"type": "plastic", "diffuse_reflectance": c, "variant": "linear" if i % 2 else "coupled"}
    for i, c in enumerate(hues):
        m[f"rough_plastic_{i}"] = rplastic(c, [0.05, 0.15, 0.3][i % 3], distribution="ggx" if i < 3 else "beckmann")
    m["glass"] = {"type": "dielectric", "int_ior": "bk7"}
    m["water"] = {"type": "dielectric", "int_ior": "water"}
    m["frosted"] = rough({"type": "rough_dielectric", "int_ior": "bk7", "alpha": 0.2})
    m["thin"] = {"type": "thin_dielectric", "int_ior": "bk7"}
    m["diamond"] = {"type": "dielectric", "int_ior": "diamond"}
    p = {"type": "principled", "variant": "2015"}
    m["principled_0"] = {**p, "base_color": hues[0], "roughness": 0.3}
    m["principled_1"] = {**p, "base_color": hues[3], "metallic": 1.0, "roughness": 0.4}
    m["principled_2"] = {**p, "base_color": hues[2], "clearcoat": 1.0, "roughness": 0.5}
    m["principled_3"] = {**p, "base_color": hues[4], "sheen": 1.0, "roughness": 0.7}
    m["principled_4"] = {**p, "base_color": hues[5], "specular_transmission": 1.0, "roughness": 0.2}
    return m


def many_materials() -> dict:
    """A 6 x 6 grid of spheres, each of its own material (36), on a floor under a rectangular area
    light and the sky."""
    d = base((0, 5.5, 7.5), (0, 0, 0.3), fov=50)
    mats = many_materials_list()
    assert len(mats) == 36, len(mats)
    d["materials"] = {"ground": {"type": "lambertian", "reflectance": 0.3},
                      "black": {"type": "lambertian", "reflectance": 0.0}, **mats}
    shapes = [floor("ground")]
    for k, name in enumerate(mats):
        x, z = k % 6, k // 6
        shapes.append(sphere((1.1 * (x - 2.5), 0.45, 1.1 * (z - 2.5)), 0.45, name))
    shapes.append({"type": "rectangle", "material": "black", "emitter": {"type": "area", "radiance": 6.0},
                   "to_world": [{"scale": [1.5, 1.0, 1]}, {"rotate": {"axis": [1, 0, 0], "angle": 90}},
                                {"translate": [-1.0, 4.0, 0.5]}]})
    d["shapes"] = shapes
    d["lights"] = [{"type": "envmap", "filename": SKY, "scale": 0.3}]
    return d


def media_fog_box() -> dict:
    """The Cornell box filled with forward-scattering fog, closed in front by a null boundary."""
    d = cornell_base()
    d["integrator"]["max_depth"] = 16
    d["media"] = {"fog": {"type": "homogeneous", "sigma_t": 0.6, "albedo": 0.9, "phase": {"type": "hg", "g": 0.7}}}
    d["materials"] = {**CORNELL_WALLS, "boundary": {"type": "null"}}
    d["shapes"] = [{**s, "exterior": "fog"} for s in cornell_lambert()["shapes"]] + [
        {"type": "rectangle", "material": "boundary", "interior": "fog", "to_world": [{"translate": [0, 0, 1]}]}]
    return d


def media_glass_sphere() -> dict:
    """A smooth glass sphere filled with a chromatic scattering medium on a floor, lit by a rectangle
    light and a constant environment (next-event estimation from inside cannot reach the lights)."""
    d = base((0, 1.2, 4.5), (0, 0.6, 0), fov=40, max_depth=16)
    d["media"] = {"murky": {"type": "homogeneous", "sigma_t": [2.5, 3, 4], "albedo": [0.95, 0.75, 0.45],
                            "phase": {"type": "hg", "g": 0.3}}}
    d["materials"] = {"ground": {"type": "lambertian", "reflectance": 0.6},
                      "glass": {"type": "dielectric", "int_ior": 1.5},
                      "black": {"type": "lambertian", "reflectance": 0.0}}
    d["shapes"] = [floor("ground", size=6), {**sphere((0, 0.75, 0), 0.75, "glass"), "interior": "murky"},
                   {"type": "rectangle", "material": "black", "emitter": {"type": "area", "radiance": 9.0},
                    "to_world": [{"scale": 0.45}] + look_at((-2.2, 2.6, 2.4), (0, 0, 0))}]
    d["lights"] = [{"type": "constant", "radiance": 0.3}]
    return d


def subsurface() -> dict:
    """Two translucent spheres (the `subsurface` material's random walk: the same light transport as
    Mitsuba's volpath through a dielectric over a homogeneous interior) on a floor, lit by a rectangle
    light and a dim constant environment. One interior has the same mean free path, 0.05, in every
    channel (albedo 0.9/0.8/0.7, g 0.3), the other a mean free path that differs per channel. Depth is
    unlimited, as the walk's events count as bounces in volpath."""
    d = base((0, 1.1, 3.2), (0, 0.45, 0), fov=40, max_depth=-1)
    d["integrator"]["rr_depth"] = 16
    d["materials"] = {"ground": {"type": "lambertian", "reflectance": 0.5},
                      "wax": {"type": "subsurface", "model": "random_walk", "sigma_a": [2, 4, 6],
                              "sigma_s": [18, 16, 14], "g": 0.3, "int_ior": 1.4, "ext_ior": 1.0},
                      "jade": {"type": "subsurface", "model": "random_walk", "sigma_a": [3, 0.5, 2.5],
                               "sigma_s": [12, 14, 9], "g": 0.0, "int_ior": 1.5, "ext_ior": 1.0},
                      "black": {"type": "lambertian", "reflectance": 0.0}}
    d["shapes"] = [floor("ground", size=4), sphere((-0.3, 0.5, 0), 0.5, "wax"), sphere((0.62, 0.3, 0.45), 0.3, "jade"),
                   {"type": "rectangle", "material": "black", "emitter": {"type": "area", "radiance": 10.0},
                    "to_world": [{"scale": 0.5}] + look_at((-1.6, 2.4, 1.2), (0, 0.4, 0))}]
    d["lights"] = [{"type": "constant", "radiance": 0.3}]
    return d


# ----------------------------------------------------------------------------------- Mitsuba XML twins
def _xml_vec(v) -> str:
    v = [v] * 3 if isinstance(v, (int, float)) else list(v)
    return ", ".join(f"{x:g}" for x in v)


def _xml_transform(ops: List[dict], ind: str) -> List[str]:
    out = [f'{ind}<transform name="to_world">']
    for op in ops:
        (k, v), = op.items()
        if k == "scale":
            out.append(f'{ind}    <scale value="{_xml_vec(v)}"/>')
        elif k == "rotate":
            ax = v["axis"]
            out.append(f'{ind}    <rotate x="{ax[0]:g}" y="{ax[1]:g}" z="{ax[2]:g}" angle="{v["angle"]:g}"/>')
        elif k == "translate":
            out.append(f'{ind}    <translate x="{v[0]:g}" y="{v[1]:g}" z="{v[2]:g}"/>')
        elif k == "look_at":
            out.append(f'{ind}    <lookat origin="{_xml_vec(v["origin"])}" target="{_xml_vec(v["target"])}" '
                       f'up="{_xml_vec(v["up"])}"/>')
        else:
            raise ValueError(f"XML twin: transform {k!r} not supported")
    return out + [f"{ind}</transform>"]


def _xml_spectrum(name: str, v, ind: str) -> str:
    return f'{ind}<rgb name="{name}" value="{_xml_vec(v)}"/>'


def _xml_bsdf(m: dict, ind: str) -> List[str]:
    if m["type"] == "lambertian":
        return [f'{ind}<bsdf type="diffuse">', _xml_spectrum("reflectance", m["reflectance"], ind + "    "),
                f"{ind}</bsdf>"]
    if m["type"] == "dielectric":
        return [f'{ind}<bsdf type="dielectric">', f'{ind}    <float name="int_ior" value="{m["int_ior"]:g}"/>',
                f"{ind}</bsdf>"]
    if m["type"] == "null":
        return [f'{ind}<bsdf type="null"/>']
    if m["type"] == "subsurface":  # the boundary; the interior is the medium of _subsurface_media
        return [f'{ind}<bsdf type="dielectric">', f'{ind}    <float name="int_ior" value="{m["int_ior"]:g}"/>',
                f'{ind}    <float name="ext_ior" value="{m.get("ext_ior", 1.0):g}"/>', f"{ind}</bsdf>"]
    raise ValueError(f"XML twin: material {m['type']!r} not supported")


def _subsurface_media(d: dict) -> Dict[str, dict]:
    """The interior of each `subsurface` material as a Mitsuba homogeneous medium: sigma_t = sigma_a +
    sigma_s, albedo sigma_s/sigma_t, per channel. Only the smooth random walk given by its coefficients
    has this twin; anything else (albedo/mfp, scale, a rough boundary, another model) is an error rather
    than a twin that renders something else."""
    out = {}
    supported = {"type", "model", "sigma_a", "sigma_s", "g", "int_ior", "ext_ior"}
    for name, m in d["materials"].items():
        if m["type"] != "subsurface":
            continue
        extra = sorted(set(m) - supported)
        if extra or m.get("model") != "random_walk" or "sigma_a" not in m or "sigma_s" not in m:
            raise ValueError(f"XML twin: subsurface material {name!r} needs model random_walk, sigma_a and "
                             f"sigma_s, and nothing of {extra or 'else'}")
        sa, ss = m["sigma_a"], m["sigma_s"]
        st = [a + b for a, b in zip(sa, ss)]
        out[f"{name}_interior"] = {"sigma_t": st, "albedo": [b / t for b, t in zip(ss, st)],
                                   "phase": {"g": m.get("g", 0.0)}}
    return out


def mitsuba_twin(d: dict, comment: str) -> str:
    """Mitsuba 3 XML of a suite scene that uses only what the media and subsurface scenes use (Mitsuba's
    volpath; spp, width and height are XML parameters, so the suite can change them)."""
    cam, film, integ = d["camera"], d["film"], d["integrator"]
    L = ['<?xml version="1.0" encoding="utf-8"?>', "<!-- Generated by bench/suite/make_suite.py; do not edit. -->",
         f"<!-- {comment} -->", '<scene version="3.0.0">',
         f'    <default name="spp" value="{d["sampler"]["sample_count"]}"/>',
         f'    <default name="width" value="{film["width"]}"/>', f'    <default name="height" value="{film["height"]}"/>',
         '    <integrator type="volpath">', f'        <integer name="max_depth" value="{integ["max_depth"]}"/>',
         f'        <integer name="rr_depth" value="{integ["rr_depth"]}"/>', "    </integrator>",
         '    <sensor type="perspective">', f'        <float name="fov" value="{cam["fov"]:g}"/>',
         f'        <string name="fov_axis" value="{cam["fov_axis"]}"/>',
         *_xml_transform(cam["to_world"], "        "),
         '        <sampler type="independent"><integer name="sample_count" value="$spp"/></sampler>',
         '        <film type="hdrfilm">', '            <integer name="width" value="$width"/>',
         '            <integer name="height" value="$height"/>', '            <rfilter type="gaussian"/>',
         "        </film>", "    </sensor>"]
    for name, m in {**d.get("media", {}), **_subsurface_media(d)}.items():
        st = m["sigma_t"]  # Mitsuba reads an RGB sigma_t as a reflectance (in [0, 1]): scale it there
        top = st if isinstance(st, (int, float)) else max(st)
        L += [f'    <medium type="homogeneous" id="{name}">',
              (f'        <float name="sigma_t" value="{st:g}"/>' if isinstance(st, (int, float)) else
               _xml_spectrum("sigma_t", [x / top for x in st], "        ")
               + f'\n        <float name="scale" value="{top:g}"/>'),
              _xml_spectrum("albedo", m["albedo"], "        "),
              f'        <phase type="hg"><float name="g" value="{m["phase"]["g"]:g}"/></phase>', "    </medium>"]
    for light in d.get("lights", []):
        if light["type"] != "constant":
            raise ValueError(f"XML twin: light {light['type']!r} not supported")
        L += ['    <emitter type="constant">', _xml_spectrum("radiance", light["radiance"], "        "), "    </emitter>"]
    for s in d["shapes"]:
        L.append(f'    <shape type="{s["type"]}">')
        if s["type"] == "sphere":
            c = s["center"]
            L += [f'        <point name="center" x="{c[0]:g}" y="{c[1]:g}" z="{c[2]:g}"/>',
                  f'        <float name="radius" value="{s["radius"]:g}"/>']
        else:
            L += _xml_transform(s["to_world"], "        ")
        L += _xml_bsdf(d["materials"][s["material"]], "        ")
        if d["materials"][s["material"]]["type"] == "subsurface":
            L.append(f'        <ref name="interior" id="{s["material"]}_interior"/>')
        for side in ("interior", "exterior"):
            if side in s:
                L.append(f'        <ref name="{side}" id="{s[side]}"/>')
        if "emitter" in s:
            L += ['        <emitter type="area">', _xml_spectrum("radiance", s["emitter"]["radiance"], "            "),
                  "        </emitter>"]
        L.append("    </shape>")
    return "\n".join(L + ["</scene>", ""])


# name -> (builder, peer relation, what the suite scene is there for)
SCENES = {
    "cornell_lambert": (cornell_lambert, "same", "Lambertian meshes, mesh area light"),
    "cornell_spheres": (cornell_spheres, "same", "rough plastic (GGX), smooth conductor, smooth dielectric"),
    "textured_bump": (textured_bump, "same", "image and checkerboard textures, bump maps, environment map"),
    "env_diffuse": (env_diffuse, "same", "Lambertian sphere, constant environment"),
    "env_rough_metal": (env_rough_metal, "same", "Beckmann rough conductor sphere, constant environment"),
    "aniso_metal": (aniso_metal, "same", "anisotropic GGX conductor, small sphere light, environment map"),
    "veach_mis": (veach_mis, "same", "GGX conductor plates, sphere area lights"),
    "env_spheres": (env_spheres, "same", "diffuse, rough and smooth conductors, glass, environment map"),
    "glass": (glass, "same", "rough dielectric (GGX, Beckmann), thin dielectric, spot light"),
    "plastics": (plastics, "same", "smooth plastic, rough plastic (GGX, Beckmann), point light"),
    "principled": (principled, "same", "principled 2015 (incl. thin), directional light"),
    "no_twin": (no_twin, "substitute", "Oren-Nayar (EON, classic), principled 2012: Mitsuba substitutes diffuse "
                "and principled"),
    "big_mesh": (big_mesh, "same", "1,048,576-triangle mesh (generated), directional light"),
    "many_materials": (many_materials, "same", "38 materials on 36 spheres, rectangle area light, environment map"),
    "media_fog_box": (media_fog_box, "same", "homogeneous fog (HG g = 0.7) in a Cornell box, null boundary; "
                      "Mitsuba twin: media_fog_box.xml (volpath)"),
    "media_glass_sphere": (media_glass_sphere, "same", "chromatic scattering medium in a smooth glass sphere, "
                           "area light, constant environment; Mitsuba twin: media_glass_sphere.xml (volpath)"),
    "subsurface": (subsurface, "same", "subsurface scattering (random walk) in two spheres, one chromatic; area light, "
                   "constant environment; Mitsuba twin: subsurface.xml (volpath, dielectric over a homogeneous medium)"),
}
# Scenes with media or subsurface scattering: Mitsuba renders the XML twin (volpath) that mitsuba_twin()
# writes, since the JSON converter of bench/peers/mitsuba_runner.py has neither.
TWINS = {"media_fog_box": "fog box", "media_glass_sphere": "glass sphere filled with a medium",
         "subsurface": "two subsurface spheres: a dielectric boundary over a homogeneous interior medium"}
SCENE_ASSETS = {"big_mesh": ["torus_knot_1m.ply"]}


def manifest() -> dict:
    return {"scenes": [{"name": n, "file": f"{n}.json", "peer": peer, "covers": what,
                        "assets": SCENE_ASSETS.get(n, []), **({"twin": f"{n}.xml"} if n in TWINS else {})}
                       for n, (_, peer, what) in SCENES.items()]}


def dumps(d: dict) -> str:
    return json.dumps(d, indent=1) + "\n"


def outputs() -> Dict[str, str]:
    """File name -> text of every file this script writes into bench/suite/."""
    out = {f"{n}.json": dumps(build()) for n, (build, _, _) in SCENES.items()}
    for n, comment in TWINS.items():
        out[f"{n}.xml"] = mitsuba_twin(SCENES[n][0](), comment)
    out["suite.json"] = dumps(manifest())
    return out


def main(argv=None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("--assets", action="store_true", help="also write the generated assets into bench/cache/suite/")
    a = ap.parse_args(argv)
    for name, text in outputs().items():
        (HERE / name).write_text(text)
        print("wrote", HERE / name)
    if a.assets:
        ensure_assets([x for v in SCENE_ASSETS.values() for x in v])
    return 0


if __name__ == "__main__":
    sys.exit(main())
