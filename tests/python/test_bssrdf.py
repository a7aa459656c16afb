"""pellucid.bssrdf: the Python surface of the diffusion profiles and the searchlight random walk
(a smoke test of the binding; the statistics live in tests/cpp/bssrdf)."""
from __future__ import annotations

import math

import numpy as np
import pytest

import pellucid
from pellucid import bssrdf


@pytest.mark.parametrize("model", bssrdf.MODELS)
def test_profile_members_agree(model: str) -> None:
    p = bssrdf.profile(model, sigma_a=0.02, sigma_s=2.0, g=0.3, eta=1.33)
    assert p.model == model
    assert p.mean_free_path == pytest.approx(1 / (0.02 + 2.0 * 0.7), rel=1e-6)
    # ∫ 2πr R(r) dr by the trapezoid rule in ln r equals the closed-form total.
    t = np.linspace(math.log(1e-6 * p.mean_free_path), math.log(1e6 * p.mean_free_path), 20001)
    r = np.exp(t)
    y = 2 * np.pi * r * r * p.eval(r).astype(np.float64)
    assert float(np.sum(0.5 * (y[1:] + y[:-1]) * np.diff(t))) == pytest.approx(p.total, rel=1e-4)
    u = np.random.default_rng(1).random(10000).astype(np.float32)
    s = p.sample(u)
    assert s.shape == u.shape and s.dtype == np.float32
    assert (s >= 0).all() and (s <= p.r_max).all() and (p.pdf(s) > 0).all()
    assert p.eval(np.zeros((2, 3))).shape == (2, 3)
    assert "total=" in repr(p)


def test_from_diffuse_round_trip_and_errors() -> None:
    sa, ss = bssrdf.from_diffuse("better_dipole", albedo=0.7, mfp=0.25, g=0.5, eta=1.4)
    p = bssrdf.profile("better_dipole", sa, ss, 0.5, 1.4)
    assert p.total == pytest.approx(0.7, abs=1e-5)
    assert p.mean_free_path == pytest.approx(0.25, rel=1e-5)
    assert bssrdf.total("better_dipole", [p.reduced_albedo], 1.4)[0] == pytest.approx(0.7, abs=1e-5)
    with pytest.raises(pellucid.Error, match="albedo 1.0"):
        bssrdf.from_diffuse("dipole", 1.0, 1.0)
    with pytest.raises(pellucid.Error, match="unknown diffusion model 'tripole'"):
        bssrdf.profile("tripole", 1, 1)


def test_fresnel_moments() -> None:
    assert bssrdf.fresnel_moment(1, 1.0) == 0.0
    assert 2 * bssrdf.fresnel_moment(1, 1.3, internal=True) == pytest.approx(0.4445, abs=1e-3)
    # 1 − 2C1(ext) = η²(1 − 2C1(int)) and c = 1 − 2C1(ext).
    assert bssrdf.exit_lobe_norm(1.3) == pytest.approx(1.69 * (1 - 2 * bssrdf.fresnel_moment(1, 1.3)), rel=1e-6)


def test_searchlight_dict_and_determinism() -> None:
    kw = dict(sigma_a=0.1, sigma_s=0.9, g=0.2, eta=1.33, photons=20000, seed=3, r_edges=[0.0, 1.0, 2.0, 4.0])
    a = bssrdf.searchlight(**kw, threads=1)
    b = bssrdf.searchlight(**kw, threads=2)
    assert a["reflectance"] == b["reflectance"] and (a["counts"] == b["counts"]).all()
    assert a["exitance"].shape == (3,) and a["transmittance"] == 0.0
    assert a["reflectance"] + a["absorbed"] + a["lost"] == pytest.approx(1.0, abs=1e-12)
    area = np.pi * np.diff(np.square(kw["r_edges"]))
    assert np.allclose(a["exitance"], a["counts"] / (kw["photons"] * area))
    slab = bssrdf.searchlight(0.0, 1.0, eta=1.5, thickness=2.0, photons=5000)
    assert slab["reflectance"] + slab["transmittance"] == pytest.approx(1.0, abs=1e-12)
    with pytest.raises(pellucid.Error, match="thickness"):
        bssrdf.searchlight(0.1, 1.0, thickness=-1.0)
