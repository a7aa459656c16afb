"""A constant environment under MIS is estimated by BSDF sampling alone (docs/scene-format.md,
"lights"): next-event estimation never picks it. That is unbiased only if every model's BSDF
sampling reaches every direction its BSDF reflects or transmits into, so the image must equal the
render of the same scene under an environment map of the same constant radiance, which NEE does
sample (with MIS against the BSDF samples, as before). One sphere per model, on a Lambertian wall.

Per-pixel z-test with both images' variances, two-sided α = 0.01 Šidák-corrected over the pixel
channels, at most 0.25 % failing (as tests/cpp/integrator/test_analytic_scenes.cpp's strategy
comparison); and the image means, two-sided α = 1e-4 against their standard error. Fixed seeds.
"""
from __future__ import annotations

from statistics import NormalDist

import numpy as np

import pellucid

MODELS = [
    {"type": "lambertian", "reflectance": 0.7},
    {"type": "oren_nayar", "reflectance": 0.7, "roughness": 0.5},
    {"type": "rough_conductor", "material": "Au", "alpha_u": 0.15, "alpha_v": 0.4, "distribution": "ggx"},
    {"type": "rough_conductor", "material": "Cu", "alpha": 0.3, "distribution": "beckmann"},
    {"type": "rough_dielectric", "alpha": 0.3, "int_ior": 1.5},
    {"type": "thin_dielectric", "int_ior": 1.5},
    {"type": "plastic", "diffuse_reflectance": [0.6, 0.3, 0.2]},
    {"type": "rough_plastic", "diffuse_reflectance": [0.2, 0.4, 0.6], "alpha": 0.2, "coat_transmittance": "rough"},
    {"type": "principled", "base_color": [0.8, 0.5, 0.3], "roughness": 0.4, "metallic": 0.3, "clearcoat": 0.5,
     "sheen": 0.5, "anisotropic": 0.5},
    {"type": "principled", "variant": "2015", "base_color": [0.9, 0.9, 0.9], "roughness": 0.3,
     "specular_transmission": 0.8, "eta": 1.5, "flatness": 0.3},
    {"type": "principled", "variant": "2015", "base_color": [0.7, 0.6, 0.5], "roughness": 0.5, "thin": True,
     "diffuse_transmission": 0.5, "specular_transmission": 0.3, "eta": 1.4},
    {"type": "subsurface", "albedo": 0.6, "mfp": 0.05, "int_ior": 1.33, "model": "better_dipole"},
]


def _scene(light: dict, seed: int) -> dict:
    materials = {f"m{k}": m for k, m in enumerate(MODELS)}
    shapes = [{"type": "sphere", "center": [-1.5 + k % 4, 1 - k // 4, 0], "radius": 0.45, "material": f"m{k}"}
              for k in range(len(MODELS))]
    shapes.append({"type": "rectangle", "material": {"type": "lambertian", "reflectance": 0.5},
                   "to_world": [{"scale": 4}, {"translate": [0, 0, -1]}]})
    return {"camera": {"type": "perspective", "fov": 50,
                       "to_world": [{"look_at": {"origin": [0, 0, 4.5], "target": [0, 0, 0], "up": [0, 1, 0]}}]},
            "film": {"width": 64, "height": 48}, "sampler": {"sample_count": 256, "seed": seed},
            "integrator": {"type": "path", "max_depth": 6}, "materials": materials, "shapes": shapes,
            "lights": [light]}


def _render(light: dict, seed: int):
    img, var, _ = pellucid.render_with_stats(pellucid.load_dict(_scene(light, seed)), threads=2, variance=True)
    return np.asarray(img, np.float64), np.asarray(var, np.float64)


def test_constant_environment_by_bsdf_sampling_equals_the_sampled_map(tmp_path) -> None:
    white = tmp_path / "white.exr"
    pellucid.write_image(white, np.ones((8, 16, 3), np.float32))
    a, va = _render({"type": "constant", "radiance": 1}, 1)
    b, vb = _render({"type": "envmap", "filename": str(white)}, 2)
    n = a.size
    z_max = NormalDist().inv_cdf(1 - (1 - 0.99 ** (1 / n)) / 2)
    z = (a - b) / np.sqrt(va + vb + 1e-12)
    fails = int((np.abs(z) > z_max).sum())
    assert fails <= int(0.0025 * n), f"{fails} of {n} pixel channels with |z| > {z_max:.2f}"
    se = np.sqrt(va.sum() + vb.sum()) / n
    z_mean = (a.mean() - b.mean()) / se
    assert abs(z_mean) < NormalDist().inv_cdf(1 - 1e-4 / 2), f"image means {a.mean()} and {b.mean()}: z = {z_mean}"


def test_a_scene_lit_by_constant_environments_takes_no_light_samples_under_mis() -> None:
    # Under mis the constant environment is BSDF sampling's alone, so mis and bsdf are the same
    # estimator: the same image bit for bit. nee still samples it by NEE, a different image.
    def render(strategy: str) -> np.ndarray:
        sc = _scene({"type": "constant", "radiance": 1}, 3)
        sc["integrator"]["strategy"] = strategy
        sc["film"] = {"width": 16, "height": 12}
        sc["sampler"]["sample_count"] = 8
        return pellucid.render(pellucid.load_dict(sc), threads=2)
    mis, bsdf, nee = render("mis"), render("bsdf"), render("nee")
    assert np.array_equal(mis, bsdf)
    assert not np.array_equal(mis, nee)
