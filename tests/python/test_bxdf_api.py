"""Smoke tests of the vectorised BxDF surface ``pellucid.bsdf`` (the χ² and furnace suites are in
tests/cpp/bxdf; here: shapes, dtypes, eval/pdf consistency with sample, errors)."""
from __future__ import annotations

import numpy as np
import pytest

import pellucid
from pellucid.bsdf import FLAGS

MATERIALS = [
    {"type": "lambertian", "reflectance": [0.2, 0.5, 0.8]},
    {"type": "oren_nayar", "variant": "classic", "sigma": 30},
    {"type": "oren_nayar", "variant": "eon", "roughness": 0.7},
    {"type": "conductor", "material": "Au"},
    {"type": "rough_conductor", "material": "Cu", "alpha": 0.3, "multiple_scattering": True},
    {"type": "rough_conductor", "distribution": "beckmann", "alpha_u": 0.1, "alpha_v": 0.4},
    {"type": "dielectric", "int_ior": "water"},
    {"type": "rough_dielectric", "int_ior": 1.5, "roughness": 0.5},
    {"type": "rough_dielectric", "int_ior": 1.5, "alpha": 0.5, "multiple_scattering": True},
    {"type": "rough_dielectric", "distribution": "beckmann", "alpha_u": 0.2, "alpha_v": 0.5},
    {"type": "thin_dielectric"},
    {"type": "plastic", "diffuse_reflectance": 0.3},
    {"type": "rough_plastic", "alpha": 0.2, "variant": "sum"},
    {"type": "rough_plastic", "distribution": "beckmann", "alpha": 0.3},
    {"type": "principled", "base_color": [0.8, 0.3, 0.2], "clearcoat": 1.0, "roughness": 0.4},
]


def _wo(n: int, rng: np.random.Generator) -> np.ndarray:
    cos = rng.uniform(0.05, 1.0, n)
    phi = rng.uniform(0, 2 * np.pi, n)
    s = np.sqrt(1 - cos**2)
    return np.stack([s * np.cos(phi), s * np.sin(phi), cos], axis=1).astype(np.float32)


@pytest.mark.parametrize("desc", MATERIALS, ids=lambda d: d["type"])
def test_shapes_and_consistency(desc: dict) -> None:
    rng = np.random.default_rng(5)
    b = pellucid.bsdf(desc)
    n = 512
    wo = _wo(n, rng)
    s = b.sample(wo, rng.random((n, 3)))
    assert s.wi.shape == (n, 3) and s.wi.dtype == np.float32
    assert s.weight.shape == (n, 3) and s.weight.dtype == np.float32
    assert s.pdf.shape == (n,) and s.pdf.dtype == np.float32
    assert s.lobe.shape == (n,) and s.lobe.dtype == np.uint32
    assert np.all(np.isfinite(s.weight)) and np.all(s.weight >= 0)
    f = b.eval(wo, s.wi)
    p = b.pdf(wo, s.wi)
    assert f.shape == (n, 3) and f.dtype == np.float32 and p.shape == (n,)
    specular = (s.lobe & FLAGS["specular"]) != 0
    ok = (s.pdf > 0) & ~specular
    # Non-delta samples: pdf() reproduces the sample pdf and eval/pdf the weight.
    np.testing.assert_allclose(p[ok], s.pdf[ok], rtol=2e-3, atol=1e-6)
    np.testing.assert_allclose(f[ok] / p[ok, None], s.weight[ok], rtol=2e-3, atol=1e-5)
    # Sampled lobes are a subset of the declared flags.
    assert np.all((s.lobe & ~np.uint32(b.flags)) == 0)
    assert repr(b).startswith("bsdf(" + desc["type"] + "[") and " -> " in repr(b)


def test_lambertian_albedo_equals_reflectance() -> None:
    b = pellucid.bsdf({"type": "lambertian", "reflectance": [0.2, 0.5, 0.8]})
    wo = np.array([[0, 0, 1], [0.8, 0, 0.6], [0.99, 0, 0.141]], dtype=np.float32)
    a = b.albedo(wo, 256)
    assert a.shape == (3, 3) and a.dtype == np.float32
    np.testing.assert_allclose(a, np.tile([0.2, 0.5, 0.8], (3, 1)), rtol=1e-5)


def test_albedo_is_deterministic_and_bounded() -> None:
    b = pellucid.bsdf({"type": "rough_conductor", "material": "none", "alpha": 0.5, "multiple_scattering": True})
    wo = np.array([[0, 0, 1], [0.866, 0, 0.5]], dtype=np.float32)
    a1, a2 = b.albedo(wo, 20000, threads=1), b.albedo(wo, 20000, threads=2)
    np.testing.assert_array_equal(a1, a2)
    np.testing.assert_allclose(a1, 1.0, atol=0.02)  # Kulla–Conty white furnace


def test_flags_and_benchmark() -> None:
    flags = FLAGS
    b = pellucid.bsdf({"type": "dielectric"})
    assert b.flags & flags["specular"] and b.flags & flags["transmission"]
    t = pellucid.bsdf({"type": "lambertian"}).benchmark(2000)
    assert set(t) == {"ns_eval", "ns_pdf", "ns_sample"} and all(v > 0 for v in t.values())


@pytest.mark.parametrize(
    "desc, needle",
    [
        ({"type": "rough_conductor", "alpha": -0.1}, "alpha: value -0.1 must be >= 0"),
        ({"type": "dielectric", "int_ior": 0.0}, "int_ior: value 0 must be > 0"),
        ({"type": "conductor", "material": "mithril"}, "material: unknown metal 'mithril'"),
        ({"type": "rough_conductor", "distribution": "phong"}, "distribution: unknown distribution 'phong'"),
        ({"type": "plastic", "variant": "fancy"}, "variant: unknown variant 'fancy'"),
        ({"type": "lambertian", "albedo": 0.5}, "albedo: unknown parameter"),
        ({"type": "velvet"}, "type: unknown material type 'velvet'"),
    ],
)
def test_bad_dict_raises_with_parameter_name(desc: dict, needle: str) -> None:
    with pytest.raises(pellucid.Error, match=needle):
        pellucid.bsdf(desc)


def test_bad_shapes_raise() -> None:
    b = pellucid.bsdf({"type": "lambertian"})
    with pytest.raises(pellucid.Error, match="wi and|wo and|shape"):
        b.eval(np.zeros((4, 3)), np.zeros((5, 3)))
    with pytest.raises(pellucid.Error, match=r"\(N, 3\)"):
        b.pdf(np.zeros((4, 2)), np.zeros((4, 2)))


def test_rough_dielectric_multiple_scattering_restores_energy() -> None:
    """White rough glass, Importance mode (energy): R+T < 1 single-scattering, = 1 (table error 3e-3
    + Monte Carlo) with Kulla–Conty, from outside and inside (tests/cpp/bxdf/test_kulla_conty_dielectric.cpp)."""
    cos = np.array([1.0, 0.5, 0.2, -1.0, -0.5, -0.2])
    wo = np.stack([np.sqrt(1 - cos**2), np.zeros_like(cos), cos], axis=1).astype(np.float32)
    desc = {"type": "rough_dielectric", "int_ior": 1.5, "ext_ior": 1.0, "alpha": 0.8}
    single = pellucid.bsdf(desc, "importance").albedo(wo, 1 << 16)[:, 0]
    comp = pellucid.bsdf({**desc, "multiple_scattering": True}, "importance").albedo(wo, 1 << 16)[:, 0]
    assert np.all(single < 0.97)
    np.testing.assert_allclose(comp, 1.0, atol=3e-3 + 5 * 0.003)
