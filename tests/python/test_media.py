"""Media from Python: the phase-function surface pellucid.phase, media in scene dicts and their
errors, and rendering a media scene from Python.
The statistical and analytic checks live in tests/cpp/medium/."""
from __future__ import annotations

import numpy as np
import pytest

import pellucid


def test_phase_known_answer_and_vectorised_calls() -> None:
    wo = np.array([[0.0, 0.0, 1.0]] * 2, np.float32)
    wi = np.array([[1.0, 0.0, 0.0], [0.0, 2.0, 0.0]], np.float32)  # normalised first
    for g in (0.7, -0.7):
        v = 4 * np.pi * pellucid.phase("hg", g=g).eval(wo, wi)
        assert v.shape == (2,) and np.allclose(v, 0.51 / 1.49 ** 1.5, rtol=1e-5)
    iso = pellucid.phase("isotropic")
    assert np.allclose(iso.pdf(wo, wi), 1 / (4 * np.pi))
    rng = np.random.default_rng(1)
    n = 20000
    p = pellucid.phase("hg", g=0.5)
    s = p.sample(np.tile([0.0, 0.6, 0.8], (n, 1)), rng.random((n, 2)))
    assert s.wi.shape == (n, 3) and np.allclose(np.linalg.norm(s.wi, axis=1), 1, atol=1e-5)
    assert np.allclose(s.weight, 1) and not s.delta.any()
    assert np.allclose(p.pdf(np.tile([0.0, 0.6, 0.8], (n, 1)), s.wi), s.pdf, rtol=1e-3)
    mean_cos = -(s.wi @ np.array([0.0, 0.6, 0.8]))
    assert abs(mean_cos.mean() - 0.5) < 4.5 * mean_cos.std() / np.sqrt(n)  # fixed seed; |z| < 4.5


@pytest.mark.parametrize("g", [1.0, -1.0, 0.999, -0.999, 0.0, 1e-7, -1e-7])
def test_phase_is_stable_at_the_edges_of_g(g: float) -> None:
    p = pellucid.phase("hg", g=g)
    wo = np.tile([0.3, -0.4, 0.866], (5, 1)).astype(np.float32)
    u = np.array([[0, 0], [1 - 2 ** -24, 0.5], [0.5, 0.5], [1e-9, 0.1], [0.25, 0.9]], np.float32)
    s = p.sample(wo, u)
    assert np.isfinite(s.wi).all() and np.isfinite(s.pdf).all() and (s.pdf > 0).all()
    assert np.isfinite(p.eval(wo, s.wi)).all() and np.isfinite(p.eval(wo, -wo)).all()
    assert s.delta.all() == (abs(g) == 1.0)


def test_phase_errors_name_the_key() -> None:
    with pytest.raises(pellucid.Error, match=r"g: value 1.5 is out of range \[-1, 1\]"):
        pellucid.phase("hg", g=1.5)
    with pytest.raises(pellucid.Error, match="unknown phase function type 'rayleigh'"):
        pellucid.phase("rayleigh")
    with pytest.raises(pellucid.Error, match=r"u: expected an array of shape \(N, 2\)"):
        pellucid.phase("hg", g=0.1).sample(np.zeros((2, 3)), np.zeros((2, 3)))


def _fog_scene(**medium) -> dict:
    fog = dict({"type": "homogeneous", "sigma_t": 0.5, "albedo": 0.9, "phase": {"type": "hg", "g": 0.7}}, **medium)
    return {"film": {"width": 4, "height": 4}, "media": {"fog": fog},
            "camera": {"type": "perspective", "medium": "fog"},
            "shapes": [{"type": "sphere", "material": {"type": "null"}, "interior": "fog"}]}


def test_media_load_and_render() -> None:
    d = _fog_scene()
    d["lights"] = [{"type": "constant", "radiance": 1.0}]
    img = np.asarray(pellucid.render(pellucid.load_dict(d), spp=4))
    assert np.isfinite(img).all() and (img >= 0).all() and img.mean() > 0


@pytest.mark.parametrize("medium,message", [
    ({"sigma_t": -0.5}, "media.fog.sigma_t: value [-0.500000, -0.500000, -0.500000] must be finite and >= 0"),
    ({"phase": {"type": "hg", "g": 2}}, "media.fog.phase.g: value 2 is out of range [-1, 1]"),
    ({"sigma_a": 0.1}, "media.fog.sigma_t: give either sigma_a and sigma_s, or sigma_t and albedo, not both"),
])
def test_bad_media_errors(medium: dict, message: str) -> None:
    with pytest.raises(pellucid.Error) as e:
        pellucid.load_dict(_fog_scene(**medium))
    assert message in str(e.value)


def test_unknown_medium_name_suggests_the_nearest() -> None:
    d = _fog_scene()
    d["shapes"][0]["interior"] = "fgo"
    with pytest.raises(pellucid.Error, match=r"shapes\[0\].interior: no medium 'fgo' \(did you mean 'fog'\? known: fog\)"):
        pellucid.load_dict(d)
