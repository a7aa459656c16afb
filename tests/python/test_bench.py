"""The speed-against-accuracy harness (pellucid.bench): metrics, ladder bookkeeping, CSV and figures."""
from __future__ import annotations

import csv
import json
import math
import pathlib

import numpy as np
import pytest

import pellucid
from pellucid import bench

# A Lambertian sphere (albedo 0.5) that fills the whole frame under a uniform environment of radiance 1:
# a convex object never sees itself, so every pixel's exact value is 0.5 (Kajiya's equation with one
# bounce of constant incident radiance: L = albedo * 1).
FURNACE = {
    "camera": {"type": "perspective", "fov": 20,
               "to_world": [{"look_at": {"origin": [0, 0, 3], "target": [0, 0, 0], "up": [0, 1, 0]}}]},
    "film": {"width": 16, "height": 16},
    "sampler": {"sample_count": 4, "seed": 0},
    "integrator": {"type": "path", "max_depth": 4},
    "materials": {"grey": {"type": "lambertian", "reflectance": 0.5}},
    "shapes": [{"type": "sphere", "radius": 1, "material": "grey"}],
    "lights": [{"type": "constant", "radiance": 1}],
}


def test_rel_mse_and_rmse_on_known_arrays() -> None:
    ref = np.ones((2, 3, 3))
    img = ref + 0.1
    assert bench.rmse(img, ref) == pytest.approx(0.1, rel=1e-12)
    assert bench.rel_mse(img, ref) == pytest.approx(0.01 / 1.01, rel=1e-12)
    # Mixed pixels: errors 0 and 2 against references 0 and 1; the 0.01 keeps the dark pixel finite.
    a, r = np.array([[0.0, 3.0]]), np.array([[0.0, 1.0]])
    assert bench.rel_mse(a, r) == pytest.approx(0.5 * (0.0 + 4.0 / 1.01), rel=1e-12)
    assert bench.rmse(a, r) == pytest.approx(math.sqrt(2.0), rel=1e-12)
    # An analytic constant is broadcast.
    assert bench.rel_mse(img, 1.0) == pytest.approx(0.01 / 1.01, rel=1e-12)
    assert bench.rel_mse(ref, ref) == 0.0
    with pytest.raises(ValueError, match="shape"):
        bench.rmse(np.ones((2, 2, 3)), np.ones((2, 3, 3)))


def test_reference_noise_floor() -> None:
    ref = np.full((4, 4, 3), 2.0)
    assert bench.ref_relmse_floor(ref, np.full_like(ref, 0.04)) == pytest.approx(0.04 / 4.01, rel=1e-12)
    assert bench.ref_relmse_floor(ref, None) == 0.0


def test_z_test_passes_equal_means_and_fails_shifted_ones() -> None:
    rng = np.random.default_rng(1)
    a = rng.normal(size=(32, 32, 3))
    var = np.full_like(a, 0.01)
    frac, zc = bench.z_test(a, var, a + 0.05, var)  # |z| = 0.35
    assert frac == 1.0
    assert zc > 4.0  # Sidak over 3072 channels at alpha 0.01: z ~ 4.6
    frac, _ = bench.z_test(a, var, a + 1.0, var)  # |z| = 7.1
    assert frac == 0.0
    _, z1 = bench.z_test(np.zeros(1), np.ones(1), np.zeros(1), np.ones(1))
    assert z1 == pytest.approx(2.5758, abs=1e-3)  # one channel: the plain two-sided 1 % point


def test_parse_methods_and_ladders() -> None:
    assert bench.parse_methods("ours") == ["bsdf", "nee", "mis"]
    assert bench.parse_methods("mis, llvm_ad_rgb,mis") == ["mis", "llvm_ad_rgb"]
    with pytest.raises(ValueError, match="unknown method 'pt'"):
        bench.parse_methods("pt")
    assert bench.parse_floats("10,1,2.5", "--budgets") == [1.0, 2.5, 10.0]
    for bad in ("1,-2", "a", "", "nan"):
        with pytest.raises(ValueError, match="--budgets"):
            bench.parse_floats(bad, "--budgets")


def test_ladder_bookkeeping_and_csv(tmp_path: pathlib.Path) -> None:
    rows = bench.run_ladder(FURNACE, tmp_path, "furnace", ["nee", "mis"], 0.5, None, spp_ladder=[1, 64],
                            threads=2, seed=3, with_flip=False, log=lambda s: None)
    assert [(r.method, r.rung, r.spp) for r in rows] == [("nee", 0, 1), ("nee", 1, 64), ("mis", 0, 1), ("mis", 1, 64)]
    for r in rows:
        assert r.renderer == "pellucid" and r.budget_s is None and r.seconds > 0 and r.samples_per_second > 0
        assert r.image.shape == (16, 16, 3)
        assert abs(float(r.image.mean()) - 0.5) < 0.1  # the analytic answer, within 1-spp noise
    lo, hi = (r.relmse for r in rows if r.method == "nee")
    assert 0 < hi < lo / 8  # 64x the samples: relMSE falls ~64x for an unbiased estimator
    # Under mis the constant environment is BSDF sampling's alone (docs/scene-format.md, "lights"):
    # cosine sampling of the Lambertian sphere, which fills the view, gives every path 0.5.
    for r in rows:
        if r.method == "mis":
            assert r.relmse < 1e-10 and abs(float(r.image.mean()) - 0.5) < 1e-6

    path = tmp_path / "out" / "furnace.csv"
    bench.write_csv(rows, path)
    back = bench.read_csv(path)
    assert list(back[0]) == list(bench.CSV_FIELDS)
    assert len(back) == 4
    assert [int(r["spp"]) for r in back] == [1, 64, 1, 64]
    assert float(back[3]["relmse"]) == pytest.approx(rows[3].relmse, rel=1e-5)
    assert back[0]["budget_s"] == "" and back[0]["flip"] == ""


def test_time_budget_ladder(tmp_path: pathlib.Path) -> None:
    native = bench.run_ladder(FURNACE, tmp_path, "furnace", ["mis"], 0.5, None, budgets=[0.05, 0.2], threads=1,
                              seed=0, with_flip=False, budget_mode="native", log=lambda s: None)
    assert [r.budget_s for r in native] == [0.05, 0.2]
    assert native[1].spp > native[0].spp >= 1
    assert all(r.seconds >= r.budget_s for r in native)  # the loop stops after the pass that crosses the budget
    # The second rung's spp comes from the first rung's measured speed, which a loaded machine can
    # lower several-fold for a render this short: a 12x larger budget keeps "grows with the budget"
    # true under such noise.
    calibrated = bench.run_ladder(FURNACE, tmp_path, "furnace", ["mis"], 0.5, None, budgets=[0.05, 0.6], threads=1,
                                  seed=0, with_flip=False, log=lambda s: None)
    assert calibrated[1].spp > calibrated[0].spp >= 1  # spp from the measured speed, growing with the budget
    with pytest.raises(ValueError, match="budget_mode"):
        bench.run_ladder(FURNACE, tmp_path, "furnace", ["mis"], 0.5, None, budgets=[0.05], budget_mode="fast")


def test_main_writes_csv_chart_crops_and_summary(tmp_path: pathlib.Path) -> None:
    scene = tmp_path / "furnace.json"
    scene.write_text(json.dumps(FURNACE))
    out = tmp_path / "results"
    rc = bench.main([str(scene), "--methods", "nee,mis", "--spp-ladder", "1,4", "--reference-constant", "0.5",
                     "--out-dir", str(out), "--threads", "1", "--no-flip"])
    assert rc == 0
    for f in ("furnace.csv", "furnace_error.png", "furnace_crops.png", "furnace_summary.md"):
        assert (out / f).stat().st_size > 0, f
    with open(out / "furnace.csv", newline="") as f:
        assert [r["method"] for r in csv.DictReader(f)] == ["nee", "nee", "mis", "mis"]
    assert "--reference-constant 0.5" in (out / "furnace_summary.md").read_text()


def test_main_rejects_bad_arguments(tmp_path: pathlib.Path, capsys) -> None:
    scene = tmp_path / "furnace.json"
    scene.write_text(json.dumps(FURNACE))
    assert bench.main([str(scene), "--methods", "nope"]) == 2
    assert "unknown method 'nope'" in capsys.readouterr().err
    assert bench.main([str(tmp_path / "missing.json")]) == 1
    assert "missing.json" in capsys.readouterr().err
    bad = json.loads(json.dumps(FURNACE))
    bad["shapes"][0]["material"] = "gold"
    scene.write_text(json.dumps(bad))
    assert bench.main([str(scene)]) == 1
    assert "gold" in capsys.readouterr().err


def test_reference_cache_key_depends_on_scene_and_settings() -> None:
    k = bench.reference_key(FURNACE, {"spp": 4})
    assert k == bench.reference_key(json.loads(json.dumps(FURNACE)), {"spp": 4})
    assert k != bench.reference_key(FURNACE, {"spp": 8})
    other = json.loads(json.dumps(FURNACE))
    other["materials"]["grey"]["reflectance"] = 0.6
    assert k != bench.reference_key(other, {"spp": 4})


@pytest.mark.skipif(bench.mitsuba_python() is None, reason="Mitsuba 3 peer not set up (bench/peers/setup_mitsuba.sh)")
def test_mitsuba_converter_handles_lights_spheres_and_envmaps(tmp_path: pathlib.Path) -> None:
    # The converter on what the committed scenes use: a rough conductor, a dielectric, spheres, a point light
    # and an envmap (read by Mitsuba itself, so this runs before pellucid has an envmap light).
    env = np.zeros((8, 16, 3), np.float32) + np.array([0.2, 0.3, 0.4], np.float32)
    pellucid.write_image(tmp_path / "env.exr", env)
    scene = json.loads(json.dumps(FURNACE))
    scene["materials"]["metal"] = {"type": "rough_conductor", "material": "Au", "alpha": 0.2}
    scene["materials"]["glass"] = {"type": "dielectric", "int_ior": "bk7"}
    scene["shapes"] = [{"type": "sphere", "center": [-0.25, 0, 0], "radius": 0.2, "material": "metal"},
                       {"type": "sphere", "center": [0.25, 0, 0], "radius": 0.2, "material": "glass"}]
    scene["lights"] = [{"type": "envmap", "filename": "env.exr", "scale": 2.0},
                       {"type": "point", "position": [0, 2, 2], "intensity": 5.0}]
    r = bench.run_mitsuba(bench.mitsuba_python(), scene, tmp_path, "scalar_rgb", 4, 0, 1)
    assert r.image.shape == (16, 16, 3)
    corner = r.image[0, 0]  # the background sees the envmap directly, times its scale
    assert np.allclose(corner, [0.4, 0.6, 0.8], rtol=1e-3)
    gold = r.image[8, 4]  # gold reflects red more than blue, and the point light adds to it
    assert gold[0] > gold[2] > 0.0


def test_reference_is_rendered_once_and_cached(tmp_path: pathlib.Path) -> None:
    logs = []
    # A plastic sphere: under mis the Lambertian furnace is exact, with zero variance, and the
    # reference is always rendered with mis.
    scene = {**FURNACE, "materials": {"grey": {"type": "plastic", "diffuse_reflectance": 0.5}}}
    a, va, pa = bench.cached_reference(scene, tmp_path, "ours", 8, 1, 1, tmp_path / "cache", None, logs.append)
    b, vb, pb = bench.cached_reference(scene, tmp_path, "ours", 8, 1, 1, tmp_path / "cache", None, logs.append)
    assert pa == pb and np.array_equal(a, b) and np.array_equal(va, vb)
    assert "rendering" in logs[0] and "cached" in logs[1]
    assert 0.3 < float(a.mean()) < 0.7 and float(va.max()) > 0.0
    with pytest.raises(RuntimeError, match="Mitsuba is not set up"):
        bench.cached_reference(scene, tmp_path, "mitsuba", 8, 1, 1, tmp_path / "cache", None, logs.append)
