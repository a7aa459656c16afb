"""The sampler choice from Python, both command lines and the bench: sobol vs independent."""
from __future__ import annotations

import copy
import subprocess
import sys

import numpy as np
import pytest

import pellucid
from pellucid import bench

from conftest import ROOT

CLI = ROOT / "build" / "py" / "cpp" / "pellucid-render"


def test_render_sampler_keyword(tiny_scene_path, tiny_scene_dict) -> None:
    scene = pellucid.load_file(tiny_scene_path)
    ind = pellucid.render(scene, spp=8, seed=2)
    assert np.array_equal(ind, pellucid.render(scene, spp=8, seed=2, sampler="independent"))
    sob1 = pellucid.render(scene, spp=8, seed=2, sampler="sobol", threads=1)
    sob2 = pellucid.render(scene, spp=8, seed=2, sampler="sobol", threads=2)
    assert np.array_equal(sob1, sob2)
    assert not np.array_equal(sob1, ind)
    # The JSON sampler.type gives the same image as the keyword.
    d = copy.deepcopy(tiny_scene_dict)
    d.setdefault("sampler", {})["type"] = "sobol"
    assert np.array_equal(pellucid.render(pellucid.load_dict(d, tiny_scene_path.parent), spp=8, seed=2), sob1)
    with pytest.raises(pellucid.Error, match="unknown sampler 'halton'"):
        pellucid.render(scene, spp=1, sampler="halton")
    d["sampler"]["type"] = "halton"
    with pytest.raises(pellucid.Error, match=r"sampler\.type.*halton"):
        pellucid.load_dict(d, tiny_scene_path.parent)


@pytest.mark.skipif(not CLI.exists(), reason="pellucid-render is built by `make`")
def test_both_clis_take_sampler(tmp_path, tiny_scene_path) -> None:
    a, b = tmp_path / "py.exr", tmp_path / "cpp.exr"
    args = ["render", str(tiny_scene_path), "--spp", "4", "--seed", "5", "--sampler", "sobol", "-q"]
    r1 = subprocess.run([sys.executable, "-m", "pellucid", *args, "-o", str(a)], capture_output=True, text=True,
                        timeout=120)
    r2 = subprocess.run([str(CLI), *args, "-o", str(b)], capture_output=True, text=True, timeout=120)
    assert r1.returncode == 0, r1.stderr
    assert r2.returncode == 0, r2.stderr
    ia, ib = pellucid.read_image(str(a)), pellucid.read_image(str(b))
    assert np.array_equal(ia, ib)
    scene = pellucid.load_file(tiny_scene_path)
    assert np.array_equal(ia, pellucid.render(scene, spp=4, seed=5, sampler="sobol"))
    for cmd in ([sys.executable, "-m", "pellucid"], [str(CLI)]):
        r = subprocess.run([*cmd, "render", str(tiny_scene_path), "-o", str(a), "--sampler", "sobl"],
                           capture_output=True, text=True, timeout=120)
        assert r.returncode == 2 and "sobl" in r.stderr, r.stderr


def test_bench_method_sampler_suffix() -> None:
    assert bench.parse_methods("mis,mis+sobol,llvm_ad_rgb") == ["mis", "mis+sobol", "llvm_ad_rgb"]
    assert bench.parse_methods("mis,nee+independent,scalar_rgb", "sobol") == ["mis+sobol", "nee+independent",
                                                                              "scalar_rgb"]
    assert bench.parse_methods("ours+sobol") == ["bsdf+sobol", "nee+sobol", "mis+sobol"]
    assert bench.split_method("mis+sobol") == ("mis", "sobol")
    assert bench.split_method("direct") == ("direct", None)
    for bad in ("mis+halton", "llvm_ad_rgb+sobol", "mitsuba+sobol", "foo+sobol"):
        with pytest.raises(ValueError):
            bench.parse_methods(bad)
    with pytest.raises(ValueError):
        bench.parse_methods("mis", "halton")


def test_bench_renders_mis_sobol(tmp_path) -> None:
    # A tiny scene on the spp ladder: the sobol rows exist, are labelled, and sobol's error is lower
    # than independent's at 64 spp on this smooth, directly lit scene (measured ratio 0.36; 0.8 is
    # far outside the run-to-run noise of a 24x24 image).
    scene = pellucid.scenes.cornell_box(film={"width": 24, "height": 24},
                                        integrator={"max_depth": 2}, sampler={"sample_count": 4, "seed": 0})
    ref = bench.run_ours(scene, ROOT, "mis", 77, 0, spp=2048, warm=False)
    rows = bench.run_ladder(scene, ROOT, "t", ["mis", "mis+sobol"], ref.image, ref.variance, spp_ladder=[64],
                            with_flip=False, log=lambda s: None)
    by = {r.method: r for r in rows}
    assert set(by) == {"mis", "mis+sobol"} and by["mis+sobol"].spp == 64
    assert by["mis+sobol"].relmse < 0.8 * by["mis"].relmse, (by["mis+sobol"].relmse, by["mis"].relmse)
