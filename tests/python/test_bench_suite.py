"""The benchmark suite (bench/suite/) covers what it claims, and its runner works.
SPDX-License-Identifier: Apache-2.0

Coverage is read from the scenes themselves: every BxDF of the variant in cpp/pellucid/bxdf/bxdf.h (as
the material type, distribution and variant that build it), every light type of the registry, area
lights on spheres and meshes, image textures and bump maps, a generated mesh of at least 1 M
triangles, and a scene with dozens of materials. The runner is run in its quick mode, without the
peer, on two tiny scenes.
"""
from __future__ import annotations

import csv
import importlib.util
import json
import os
import pathlib
import re
import subprocess
import sys

import numpy as np
import pytest

import pellucid
from pellucid import bench, bench_suite

ROOT = pathlib.Path(__file__).resolve().parents[2]
SUITE = ROOT / "bench" / "suite"
MESH_SHAPES = {"rectangle", "cube", "disk", "mesh", "obj", "ply"}


def _generator():
    spec = importlib.util.spec_from_file_location("make_suite_under_test", SUITE / "make_suite.py")
    mod = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(mod)
    return mod


MANIFEST = bench_suite.load_manifest(SUITE)
SCENES = {e["name"]: json.loads((SUITE / e["file"]).read_text()) for e in MANIFEST}


def _materials(scene: dict):
    """Every material a scene uses: the named ones and those written inline on shapes (not `null`, the
    boundary of a medium, which builds no BxDF)."""
    out = list(scene.get("materials", {}).values())
    out += [s["material"] for s in scene.get("shapes", []) if isinstance(s.get("material"), dict)]
    return [m for m in out if m["type"] != "null"]


def bxdf_of(m: dict) -> str:
    """The alternative of the BxDF variant (cpp/pellucid/bxdf/bxdf.h) that a material builds."""
    t = m["type"]
    dist = "Beckmann" if m.get("distribution", "ggx") == "beckmann" else "GGX"
    if t == "rough_conductor":
        return "RoughConductorBeckmann" if dist == "Beckmann" else "RoughConductor"
    if t in ("rough_dielectric", "rough_plastic"):
        return {"rough_dielectric": "RoughDielectric", "rough_plastic": "RoughPlastic"}[t] + f"<{dist}>"
    if t == "subsurface":  # its boundary: smooth, or rough where it has a roughness
        rough = any(k in m for k in ("alpha", "alpha_u", "roughness"))
        return f"RoughDielectric<{dist}>" if rough else "SmoothDielectric"
    if t == "principled":
        return "PrincipledBSDF" if m.get("variant", "2012") == "2015" else "Principled"
    return {"lambertian": "Lambertian", "oren_nayar": "OrenNayar", "conductor": "SmoothConductor<ConductorFresnel>",
            "dielectric": "SmoothDielectric", "thin_dielectric": "ThinDielectric", "plastic": "SmoothPlastic"}[t]


# Per registered material type, the BxDFs it can build (a new type fails the test until it is listed
# here and a suite scene uses it).
BXDFS_OF_TYPE = {
    "lambertian": ["Lambertian"], "oren_nayar": ["OrenNayar"], "conductor": ["SmoothConductor<ConductorFresnel>"],
    "rough_conductor": ["RoughConductor", "RoughConductorBeckmann"], "dielectric": ["SmoothDielectric"],
    "rough_dielectric": ["RoughDielectric<GGX>", "RoughDielectric<Beckmann>"], "thin_dielectric": ["ThinDielectric"],
    "plastic": ["SmoothPlastic"], "rough_plastic": ["RoughPlastic<GGX>", "RoughPlastic<Beckmann>"],
    "principled": ["Principled", "PrincipledBSDF"],
    # The boundary of a subsurface material is a dielectric (its interior is a BSSRDF or a medium).
    "subsurface": ["SmoothDielectric", "RoughDielectric<GGX>", "RoughDielectric<Beckmann>"]}


def test_generator_reproduces_the_committed_scenes():
    gen = _generator()
    outputs = gen.outputs()
    for name, text in outputs.items():
        assert (SUITE / name).read_text() == text, f"bench/suite/{name} differs from make_suite.py's output"
    committed = {p.name for p in [*SUITE.glob("*.json"), *SUITE.glob("*.xml")]}
    assert committed == set(outputs), f"files not written by make_suite.py: {committed - set(outputs)}"
    assert len(MANIFEST) >= 12


def test_every_bxdf_of_the_variant_appears():
    registered = pellucid._core.registry_types()["materials"]
    unknown = [t for t in registered if t not in BXDFS_OF_TYPE]
    assert not unknown, f"material types with no BxDF listed in this test: {unknown}"
    expected = {b for t in registered for b in BXDFS_OF_TYPE[t]}
    used = {bxdf_of(m) for s in SCENES.values() for m in _materials(s)}
    assert expected - used == set(), f"BxDFs no suite scene uses: {sorted(expected - used)}"
    aniso = [m for s in SCENES.values() for m in _materials(s)
             if m["type"] == "rough_conductor" and "alpha_u" in m and m["alpha_u"] != m.get("alpha_v", m["alpha_u"])]
    assert aniso, "no anisotropic rough conductor"


def test_the_variant_has_the_bxdfs_this_test_lists():
    """The list above is the variant's: compared with `using BxDF = std::variant<...>` while that line
    exists in this form."""
    text = (ROOT / "cpp" / "pellucid" / "bxdf" / "bxdf.h").read_text()
    m = re.search(r"using\s+BxDF\s*=\s*std::variant<(.*?)>\s*;", text, re.S)
    if m is None:
        pytest.skip("bxdf.h has no plain `using BxDF = std::variant<...>;`")
    names = {re.sub(r"\s+", "", n) for n in re.split(r",(?![^<]*>)", m.group(1))}
    assert names == {b for bs in BXDFS_OF_TYPE.values() for b in bs}


def test_lights_and_emitters():
    lights = {l["type"] for s in SCENES.values() for l in s.get("lights", [])}
    assert set(pellucid._core.registry_types()["lights"]) <= lights  # constant, directional, envmap, point, spot
    area_on = {("sphere" if sh["type"] == "sphere" else "mesh" if sh["type"] in MESH_SHAPES else sh["type"])
               for s in SCENES.values() for sh in s["shapes"] if sh.get("emitter")}
    assert {"sphere", "mesh"} <= area_on


def test_textures_and_bump_maps():
    def textures(x):
        if isinstance(x, dict):
            if x.get("type") in ("image", "checkerboard"):
                yield x["type"]
            for v in x.values():
                yield from textures(v)
        elif isinstance(x, list):
            for v in x:
                yield from textures(v)

    kinds = set(textures(list(SCENES.values())))
    assert {"image", "checkerboard"} <= kinds
    assert any("bump_map" in m for s in SCENES.values() for m in _materials(s))


def test_dozens_of_materials_and_explicit_settings():
    assert max(len(s["materials"]) for s in SCENES.values()) >= 24
    for name, s in SCENES.items():
        assert "max_depth" in s["integrator"], name
        px = s["film"]["width"] * s["film"]["height"]
        assert 128 * 128 <= px <= 384 * 384, f"{name}: {px} pixels"


def test_generated_mesh_has_a_million_triangles(tmp_path):
    gen = _generator()
    pos, nrm, tri = gen.torus_knot()
    assert len(tri) >= 1_000_000 and tri.max() < len(pos)
    assert np.allclose(np.linalg.norm(nrm, axis=1), 1.0, atol=1e-6)
    big = [e for e in MANIFEST if e.get("assets")]
    assert big and all(a in gen.ASSETS for e in big for a in e["assets"])
    for e in big:  # the scene names the generated file, in the git-ignored cache
        files = [sh["filename"] for sh in SCENES[e["name"]]["shapes"] if sh["type"] == "ply"]
        assert files and all(f.startswith("../cache/") and pathlib.PurePath(f).name in e["assets"] for f in files)
    # The writer makes a file pellucid reads (a small knot of the same generator).
    small = tmp_path / "knot.ply"
    gen.write_ply(small, *gen.torus_knot(segments=16, sides=6))
    scene = {"shapes": [{"type": "ply", "filename": str(small)}], "lights": [{"type": "constant"}],
             "film": {"width": 8, "height": 8}, "camera": {"type": "perspective", "to_world": gen.look_at((0, 0, 9), (0, 0, 0))}}
    img = pellucid.render(pellucid.load_dict(scene), spp=1)
    assert np.isfinite(np.asarray(img)).all()


def test_scenes_load_in_pellucid():
    for e in MANIFEST:
        if e.get("assets"):
            continue  # needs the generated mesh; the runner writes it
        pellucid.load_dict(SCENES[e["name"]], SUITE)


def test_mitsuba_twins_convert():
    """Every scene converts without substitutes except those the manifest marks; those convert with."""
    py = bench.mitsuba_python()
    if py is None:
        pytest.skip("Mitsuba 3 is not set up (bench/peers/setup_mitsuba.sh)")
    names = [e["name"] for e in MANIFEST if not e.get("assets") and not e.get("twin")]
    code = f"""
import json, sys
sys.path.insert(0, {str(ROOT / 'bench' / 'peers')!r})
import mitsuba_runner as r
r.mi.set_variant("scalar_rgb")
out = {{}}
for name in {names!r}:
    sj = json.load(open({str(SUITE)!r} + "/" + name + ".json"))
    try:
        r.mi.load_dict(r.to_mitsuba_dict(sj, {str(SUITE)!r}))
        out[name] = "same"
    except NotImplementedError:
        r.mi.load_dict(r.to_mitsuba_dict(sj, {str(SUITE)!r}, substitute=True))
        out[name] = "substitute"
print(json.dumps(out))
"""
    res = subprocess.run([str(py), "-c", code], capture_output=True, text=True, timeout=120)
    assert res.returncode == 0, res.stderr[-3000:]
    got = json.loads(res.stdout.strip().splitlines()[-1])
    assert got == {e["name"]: e["peer"] for e in MANIFEST if not e.get("assets") and not e.get("twin")}


def _has_subsurface(scene: dict) -> bool:
    return any(m["type"] == "subsurface" for m in _materials(scene))


def test_media_and_subsurface_scenes_have_xml_twins_that_mitsuba_renders(tmp_path):
    """Scenes with media or a subsurface material name a Mitsuba XML twin (the JSON converter has
    neither); each renders a few samples with every value finite, and pellucid loads the twin too."""
    twins = [e for e in MANIFEST if e.get("twin")]
    assert {e["name"] for e in twins} >= {"media_fog_box", "media_glass_sphere", "subsurface"}
    assert {e["name"] for e in MANIFEST if SCENES[e["name"]].get("media") or _has_subsurface(SCENES[e["name"]])} \
        == {e["name"] for e in twins}
    for e in twins:
        pellucid.load_file(SUITE / e["twin"], spp=4, width=8, height=8)
    py = bench.mitsuba_python()
    if py is None:
        pytest.skip("Mitsuba 3 is not set up (bench/peers/setup_mitsuba.sh)")
    for e in twins:
        rep = tmp_path / f"{e['name']}.json"
        cmd = [str(py), str(SUITE / "mitsuba_twin.py"), str(SUITE / e["twin"]), "--spp", "4", "--width", "8",
               "--height", "8", "--out", str(tmp_path / f"{e['name']}.exr"), "--json-report", str(rep)]
        res = subprocess.run(cmd, capture_output=True, text=True, timeout=120)
        assert res.returncode == 0, res.stderr[-3000:]
        st = json.loads(rep.read_text())
        assert st["nonfinite"] == 0 and (st["width"], st["height"], st["spp"]) == (8, 8, 4)


def test_subsurface_twin_is_the_materials_interior():
    """The subsurface scene's twin gives each `subsurface` material (the random walk, whose transport
    volpath shares) a dielectric boundary of the same IORs over a homogeneous medium of sigma_t =
    sigma_a + sigma_s and albedo sigma_s/sigma_t, per channel, with the material's g."""
    import xml.etree.ElementTree as ET
    scene = SCENES["subsurface"]
    root = ET.parse(SUITE / "subsurface.xml").getroot()
    media = {m.get("id"): m for m in root.iter("medium")}
    shapes = [s for s in root.iter("shape")]
    subsurface = [(s, scene["materials"][s["material"]]) for s in scene["shapes"]
                  if scene["materials"][s["material"]]["type"] == "subsurface"]
    assert len(subsurface) == 2
    for s, m in subsurface:
        assert m["model"] == "random_walk"
        (x,) = [x for x in shapes if x.get("type") == "sphere" and
                [float(x.find("point").get(k)) for k in "xyz"] == s["center"]]
        bsdf = x.find("bsdf")
        assert bsdf.get("type") == "dielectric"
        assert float(bsdf.find("float[@name='int_ior']").get("value")) == m["int_ior"]
        assert float(bsdf.find("float[@name='ext_ior']").get("value")) == m["ext_ior"]
        med = media[x.find("ref[@name='interior']").get("id")]
        st = np.array([a + b for a, b in zip(m["sigma_a"], m["sigma_s"])])
        rgb = lambda name: np.array([float(v) for v in med.find(f"rgb[@name='{name}']").get("value").split(",")])
        scale = float(med.find("float[@name='scale']").get("value"))
        np.testing.assert_allclose(rgb("sigma_t") * scale, st, rtol=1e-5)
        np.testing.assert_allclose(rgb("albedo"), np.array(m["sigma_s"]) / st, rtol=1e-5)
        assert float(med.find("phase/float[@name='g']").get("value")) == m["g"]
    # A subsurface material the twin cannot translate is an error, not a twin of another scene.
    gen = _generator()
    for change in ({"scale": 2.0}, {"roughness": 0.3}, {"model": "dipole"}):
        bad = json.loads(json.dumps(scene))
        bad["materials"]["wax"].update(change)
        with pytest.raises(ValueError, match="wax"):
            gen.mitsuba_twin(bad, "x")


def test_equal_time_relmse_and_geomean():
    ref = np.ones((2, 2, 3))
    mk = lambda v, s: bench_suite.Run(np.full((2, 2, 3), v), None, 4, s, 16.0 * s, 0.0, None)
    res = bench_suite.Result("x", "same", 2, 2, 4, 2, ours=mk(1.1, 1.0), mitsuba=mk(1.2, 2.0), reference="r",
                             ref_floor=0.0)
    r = bench_suite.row(res, ref)
    assert r["ratio"] == pytest.approx(1.0)  # both 16 samples per second
    assert r["ours_eqtime_relmse"] == pytest.approx(0.01 / 1.01)
    # Mitsuba took twice as long for its relMSE: at pellucid's time it would have twice the error
    assert r["mitsuba_eqtime_relmse"] == pytest.approx(2 * 0.04 / 1.01)
    assert r["relmse_ratio"] == pytest.approx(0.125)
    res.ref_floor = 0.005
    assert bench_suite.row(res, ref)["ours_eqtime_relmse"] == pytest.approx(0.01 / 1.01 - 0.005)
    # repeats: relMSE is the mean over the repeats' images, the time their mean
    res.ref_floor = 0.0
    res.ours_all = [mk(1.1, 1.0), mk(1.3, 3.0)]
    r = bench_suite.row(res, ref)
    assert r["ours_eqtime_relmse"] == pytest.approx((0.01 + 0.09) / 2 / 1.01)
    assert r["mitsuba_eqtime_relmse"] == pytest.approx(0.04 / 1.01 * 2.0 / 2.0)
    assert bench_suite.geomean([2.0, 0.5, 4.0]) == pytest.approx(4.0 ** (1 / 3))
    assert bench_suite.geomean([None]) is None
    assert "busy" in bench_suite.busy_note([1.0, 10.0], cpus=2, threads=2)
    assert "idle" in bench_suite.busy_note([2.5, None], cpus=2, threads=2)
    # NaN/Inf/negative samples of the timed renders: summed over the repeats, named in the summary
    assert r["ours_invalid_samples"] == 0
    res.ours_all[1].invalid_samples = 3
    r = bench_suite.row(res, ref)
    assert r["ours_invalid_samples"] == 3
    assert "3 in x" in bench_suite.invalid_note([r])
    assert bench_suite.invalid_note([bench_suite.row(bench_suite.Result(
        "y", "same", 2, 2, 4, 2, ours=mk(1.0, 1.0), mitsuba=None, reference="r", ref_floor=0.0), ref)]).endswith("none")


def test_error_repeats_and_the_ratio_interval(tmp_path):
    ref = np.ones((2, 2, 3))
    mk = lambda v, s: bench_suite.Run(np.full((2, 2, 3), v), None, 4, s, 16.0 * s, 0.0, None)
    res = bench_suite.Result("x", "same", 2, 2, 4, 2, ours=mk(1.1, 1.0), mitsuba=mk(1.2, 1.0), reference="r",
                             ref_floor=0.0)
    r = bench_suite.row(res, ref)
    assert "relmse_ratio_lo" not in r and r["relmse_images"] == 1  # one image a side: no interval
    assert bench_suite._ratio_with_interval(r) == f"{r['relmse_ratio']:.2f}"
    # The error renders count in relMSE (and in its time scale), never in samples/s.
    res.ours_err = [mk(1.3, 1.0), mk(1.1, 1.0)]
    res.mitsuba_err = [mk(1.2, 3.0), mk(1.2, 1.0)]
    r = bench_suite.row(res, ref)
    assert r["relmse_images"] == 3
    assert r["ratio"] == pytest.approx(1.0)
    assert r["ours_eqtime_relmse"] == pytest.approx((0.01 + 0.09 + 0.01) / 3 / 1.01)
    assert r["mitsuba_eqtime_relmse"] == pytest.approx(0.04 / 1.01 * (5.0 / 3) / 1.0)
    lo, hi = r["relmse_ratio_lo"], r["relmse_ratio_hi"]
    assert lo <= r["relmse_ratio"] <= hi and lo < hi
    # Ours' images are 0.01, 0.09, 0.01 (/1.01): resamples of their mean run from 0.01 to 0.09, so the
    # 90 % interval lies within and is wide; Mitsuba's are all alike.
    scale = 0.04 / 1.01 * 5.0 / 3
    assert lo >= 0.01 / 1.01 / scale - 1e-12 and hi <= 0.09 / 1.01 / scale + 1e-12
    assert hi / lo > 2
    assert bench_suite._ratio_with_interval(r) == f"{r['relmse_ratio']:.2f} ({lo:.2f}-{hi:.2f})"
    # Fixed seed: the same interval every time.
    assert bench_suite.row(res, ref)["relmse_ratio_lo"] == lo
    # All images alike: the interval is the ratio itself.
    iv = bench_suite.relmse_ratio_interval([0.02] * 4, [0.04] * 4, 0.0, 1.0)
    assert iv == pytest.approx((0.5, 0.5))
    assert bench_suite.relmse_ratio_interval([0.02] * 2, [0.04] * 4, 0.0, 1.0) is None
    # The chart draws the interval as an error bar (a row without one beside it).
    bench_suite.plot([r, bench_suite.row(bench_suite.Result("y", "same", 2, 2, 4, 2, ours=mk(1.1, 1.0),
                                                            mitsuba=mk(1.2, 1.0), reference="r", ref_floor=0.0), ref)],
                     tmp_path / "suite.png", "t")
    assert (tmp_path / "suite.png").stat().st_size > 0


def test_undecided_images_count_in_relmse_not_in_time():
    ref = np.ones((2, 2, 3))
    mk = lambda v, s: bench_suite.Run(np.full((2, 2, 3), v), None, 4, s, 16.0 * s, 0.0, None)
    res = bench_suite.Result("x", "same", 2, 2, 4, 2, ours=mk(1.1, 1.0), mitsuba=mk(1.2, 2.0), reference="r",
                             ref_floor=0.0)
    res.ours_all, res.mitsuba_all = [mk(1.1, 1.0)] * 3, [mk(1.2, 2.0)] * 3
    r = bench_suite.row(res, ref)
    assert r["relmse_more"] == 0 and not bench_suite.more_note([r])
    assert not bench_suite.undecided(r)  # every image alike: the interval is 0.125 alone
    # Images of another speed: their relMSE counts, their seconds do not (the scale stays 2).
    res.ours_more = [mk(1.3, 50.0)]
    res.mitsuba_more = [mk(1.0, 0.1)]
    r = bench_suite.row(res, ref)
    assert r["relmse_images"] == 4 and r["relmse_more"] == 1
    assert r["ours_eqtime_relmse"] == pytest.approx((3 * 0.01 + 0.09) / 4 / 1.01)
    assert r["mitsuba_eqtime_relmse"] == pytest.approx((3 * 0.04 + 0.0) / 4 / 1.01 * 2.0)
    assert bench_suite.more_note([r]) == ["- relMSE over more images, where the interval over the first ones "
                                          "contained 1: x (4 a side, 3 before)"]
    assert bench_suite.undecided({"relmse_ratio_lo": 0.5, "relmse_ratio_hi": 1.0})
    assert not bench_suite.undecided({"relmse_ratio_lo": 1.01, "relmse_ratio_hi": 3.0})
    assert not bench_suite.undecided({"relmse_ratio": 1.0})  # no interval: nothing to decide


def _fake_suite(monkeypatch, ours_values, mi_values):
    """measure_scene with the renderers and the reference replaced: each timed or error render returns
    the next value of its list as a flat image; the --undecided-images renders are recorded."""
    ref = np.ones((2, 2, 3))
    mk = lambda v: bench_suite.Run(np.full((2, 2, 3), v), None, 4, 1.0, 16.0, 0.0, None)
    it_o, it_m, calls = iter(ours_values), iter(mi_values), []
    monkeypatch.setattr(bench_suite, "run_ours", lambda *a, **k: mk(next(it_o)))
    monkeypatch.setattr(bench_suite, "run_peer", lambda *a, **k: mk(next(it_m)))
    monkeypatch.setattr(bench_suite, "run_ours_images", lambda sc, f, seed, n, *a: calls.append(("ours", seed, n))
                        or [mk(1.0)] * n)
    monkeypatch.setattr(bench_suite, "run_peer_images", lambda py, sc, f, seed, n, *a: calls.append(("mi", seed, n))
                        or [mk(1.5)] * n)
    monkeypatch.setattr(bench_suite._bench, "cached_reference", lambda *a, **k: (ref, None, "ref.exr"))
    return calls


@pytest.mark.parametrize("decided", [False, True])
def test_measure_scene_adds_images_only_where_the_interval_contains_1(monkeypatch, tmp_path, decided):
    import argparse
    # undecided: pellucid's images 0.01, 0.04, 0.25 against Mitsuba's 0.04 each (the ratio's
    # interval spans 1); decided: pellucid's 0.01 each
    ours = [1.1, 1.1, 1.1] if decided else [1.1, 1.2, 1.5]
    calls = _fake_suite(monkeypatch, ours, [1.2, 1.2, 1.2])
    args = argparse.Namespace(spp=None, quick=True, repeats=2, error_repeats=1, seed=3, threads=2,
                              reference_spp=None, reference_renderer="ours", cache_dir=tmp_path,
                              no_agreement=True, undecided_images=10)
    entry = {"name": "cornell_lambert", "file": "cornell_lambert.json", "peer": "same"}
    res, extra = bench_suite.measure_scene(entry, SUITE, args, pathlib.Path("py"), tmp_path, log=lambda *a: None)
    r = bench_suite.row(res, extra["ref"])
    if decided:
        assert calls == [] and r["relmse_images"] == 3
    else:
        assert calls == [("ours", 900_003, 7), ("mi", 900_004, 7)]
        assert r["relmse_images"] == 10 and r["relmse_more"] == 7
        assert r["ours_relmse"] == pytest.approx((0.01 + 0.04 + 0.25) / 1.01 / 10)
    args.undecided_images = 0  # off: no more images, even where the interval contains 1
    calls = _fake_suite(monkeypatch, ours, [1.2, 1.2, 1.2])
    bench_suite.measure_scene(entry, SUITE, args, pathlib.Path("py"), tmp_path, log=lambda *a: None)
    assert calls == []


def test_worker_renders_several_images_with_their_own_seeds(tmp_path):
    """--images n renders seeds seed * n + k in one process: each image is the single render of that seed."""
    scene = bench_suite.prepare(SCENES["cornell_lambert"], 2, True)
    runs = bench_suite.run_ours_images(scene, SUITE, 5, 3, 2, tmp_path)
    assert len(runs) == 3 and all(r.seconds > 0 and r.spp == 2 for r in runs)
    sc = pellucid.load_dict(scene, SUITE)
    for k, r in enumerate(runs):
        np.testing.assert_array_equal(r.image, np.asarray(pellucid.render(sc, seed=5 * 3 + k, threads=2)))
    assert not np.array_equal(runs[0].image, runs[1].image)


def test_peer_images_are_the_single_renders_of_their_seeds(tmp_path):
    """Mitsuba's --undecided-images renders (the runner's and the twin's --each-dir): image k is the
    single render of seed seed * n + k (another seed differs by far more than rounding)."""
    py = bench.mitsuba_python()
    if py is None:
        pytest.skip("Mitsuba 3 is not set up (bench/peers/setup_mitsuba.sh)")
    for e in [x for x in MANIFEST if x["name"] in ("principled", "subsurface")]:
        scene = bench_suite.prepare(SCENES[e["name"]], 4, True)
        twin = SUITE / e["twin"] if e.get("twin") else None
        runs = bench_suite.run_peer_images(py, scene, SUITE, 7, 3, 2, False, tmp_path, twin)
        assert len(runs) == 3 and all(r.spp == 4 and r.image.shape == (32, 32, 3) for r in runs)
        for k in (0, 2):
            one = bench_suite.run_peer(py, scene, SUITE, 7 * 3 + k, 2, 1, False, tmp_path, twin)
            # the same seed: equal up to float rounding (Mitsuba's sums are not bit-reproducible)
            np.testing.assert_allclose(runs[k].image, one.image, rtol=1e-5, atol=1e-6)
        assert not np.array_equal(runs[0].image, runs[1].image)


def test_runner_quick_without_peer(tmp_path):
    out, cache = tmp_path / "out", tmp_path / "cache"
    cmd = [sys.executable, "-m", "pellucid", "bench", "--suite", "--quick", "--no-peer",
           "--scenes", "env_diffuse,cornell_lambert", "--out-dir", str(out), "--cache-dir", str(cache)]
    r = subprocess.run(cmd, capture_output=True, text=True, timeout=120, cwd=tmp_path)
    assert r.returncode == 0, r.stderr[-3000:]
    rows = list(csv.DictReader((out / "suite.csv").read_text().splitlines()))
    assert [x["scene"] for x in rows] == ["cornell_lambert", "env_diffuse"]  # manifest order
    for x in rows:
        assert float(x["ours_samples_per_second"]) > 0 and x["ratio"] == "" and x["spp"] == "4"
        assert int(x["width"]) <= 32 and float(x["ours_eqtime_relmse"]) >= 0
        assert "pellucid mis" in x["reference"] and x["ours_invalid_samples"] == "0"
        if os.path.exists("/proc/self/status"):
            assert 10 < float(x["ours_peak_rss_mb"]) < 10_000
    text = (out / "summary.md").read_text()
    assert "pellucid only" in text and (out / "suite.png").stat().st_size > 1000
    assert len(list(cache.glob("ref_*.exr"))) == 4  # two references, each with its variance



def test_runner_rejects_unknown_scenes(capsys, tmp_path):
    assert bench.main(["--suite", "--no-peer", "--scenes", "cornell_lambert,nosuch", "--out-dir", str(tmp_path)]) == 2
    assert "--scenes: unknown scene(s) nosuch" in capsys.readouterr().err
    assert not any(tmp_path.iterdir())
    assert bench.main(["--suite", "--no-peer", "--error-repeats", "-1", "--out-dir", str(tmp_path)]) == 2
    assert "--error-repeats and --undecided-images must be >= 0" in capsys.readouterr().err
    assert not any(tmp_path.iterdir())
    assert bench.main(["--suite", "--no-peer", "--undecided-images", "-1", "--out-dir", str(tmp_path)]) == 2
    assert "--undecided-images must be >= 0" in capsys.readouterr().err
    assert not any(tmp_path.iterdir())
