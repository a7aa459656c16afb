"""Textured material parameters: a BxDF rebuilt at every hit from the material's Params and the
constants it precomputed at load (material/textured.h) renders exactly as the prebuilt one."""
from __future__ import annotations

import copy

import numpy as np
import pellucid

# Rough materials whose BxDF constructor reads a Fresnel average (plastic's R̄, Kulla–Conty of the
# rough dielectric and conductor), each on its own sphere. ALPHA is replaced by a texture below.
ALPHA = 0.25  # exact in float, and the mean of three equal channels of 0.25 is 0.25 again
MATERIALS = {
    "plastic": {"type": "rough_plastic", "alpha": ALPHA, "diffuse_reflectance": [0.2, 0.4, 0.7]},
    "plastic_beckmann": {"type": "rough_plastic", "distribution": "beckmann", "alpha": ALPHA, "variant": "linear"},
    "glass": {"type": "rough_dielectric", "alpha": ALPHA, "multiple_scattering": True},
    "metal": {"type": "rough_conductor", "material": "Cu", "alpha": ALPHA, "multiple_scattering": True},
}


def scene(materials: dict) -> dict:
    names = list(materials)
    return {
        "film": {"width": 64, "height": 32},
        "sampler": {"sample_count": 4, "seed": 7},
        "integrator": {"type": "path", "max_depth": 6},
        "camera": {"type": "perspective", "fov": 40,
                   "to_world": [{"look_at": {"origin": [0, 1.5, 6], "target": [0, 0.4, 0], "up": [0, 1, 0]}}]},
        "materials": materials,
        "shapes": [{"type": "rectangle", "to_world": [{"scale": [20, 20, 1]},
                                                      {"rotate": {"axis": [1, 0, 0], "angle": -90}}]}]
        + [{"type": "sphere", "center": [-2.4 + 1.2 * (i % 5), 0.5, -1.2 * (i // 5)], "radius": 0.5, "material": n}
           for i, n in enumerate(names)],
        "lights": [{"type": "constant", "radiance": 0.4}, {"type": "point", "position": [2, 4, 3], "intensity": 30}],
    }


def with_alpha(texture: dict) -> dict:
    out = copy.deepcopy(MATERIALS)
    for m in out.values():
        m["alpha"] = texture
    return out


def render(d: dict, threads: int) -> np.ndarray:
    return np.asarray(pellucid.render(pellucid.load_dict(d), threads=threads)).copy()


def test_constant_texture_renders_as_the_constant() -> None:
    # A texture that is ALPHA everywhere: every hit rebuilds its BxDF, reusing the material's
    # precomputed Fresnel averages, and must give the prebuilt BxDF's image bit for bit.
    const = {"type": "checkerboard", "color0": ALPHA, "color1": ALPHA}
    textured = render(scene(with_alpha(const)), 1)
    untextured = render(scene(copy.deepcopy(MATERIALS)), 1)
    assert textured.shape == (32, 64, 3) and textured.mean() > 0.0
    assert textured.tobytes() == untextured.tobytes()


def noise(lo: float, hi: float, scale: float) -> dict:
    return {"type": "mix", "texture0": lo, "texture1": hi,
            "amount": {"type": "noise", "variant": "fbm", "scale": scale}}


def test_textured_roughness_and_ior_are_identical_at_one_and_two_threads() -> None:
    # Textured α reuses the precomputed averages; a textured IOR computes them at every hit. Any
    # state kept between hits (a per-thread cache) would make the image depend on the order of the
    # hits, hence on the thread count.
    materials = with_alpha(noise(0.05, 0.5, 4))
    materials["plastic_ior"] = {"type": "rough_plastic", "alpha": noise(0.05, 0.5, 4), "int_ior": noise(1.3, 1.8, 3)}
    materials["glass_ior"] = {"type": "rough_dielectric", "alpha": 0.3, "int_ior": noise(1.3, 1.8, 3),
                              "multiple_scattering": True}
    materials["metal_eta"] = {"type": "rough_conductor", "eta": noise(0.2, 1.5, 3), "k": [3, 2.5, 2],
                              "alpha": noise(0.05, 0.5, 4), "multiple_scattering": True}
    d = scene(materials)
    one, two = render(d, 1), render(d, 2)
    assert one.tobytes() == two.tobytes()
    # The textures are read: with each one replaced by its texture0 the image changes.
    flat = {n: {k: v["texture0"] if isinstance(v, dict) else v for k, v in m.items()} for n, m in materials.items()}
    assert one.tobytes() != render(scene(flat), 1).tobytes()
