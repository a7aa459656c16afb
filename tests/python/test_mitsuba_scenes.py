"""Issue 6 check: Mitsuba 3 scenes we wrote (tests/data/mitsuba/*.xml), rendered by pellucid through
its XML importer, agree with Mitsuba 3 under a per-pixel z-test on at least 99 % of pixel channels.

The reference is Mitsuba itself when ``mitsuba`` is importable here (rendered by
tests/data/mitsuba/make_refs.py's ``render_reference``), otherwise the committed
tests/data/mitsuba/ref/<scene>.exr (mean of 16 passes x 256 spp, Mitsuba 3.9.1 llvm_ad_rgb) and
<scene>.var.exr (variance of that mean), produced by the same script with the peer venv.

The z-test is tests/python/zcheck.py's: z = |ours - ref| / sqrt(var_ours + var_ref + floor) per
pixel channel, ours with the film's variance of the mean; the critical |z| is two-sided α = 0.01
Šidák-corrected over all channels of the image (as bench/cornell.py and Mitsuba's own render
tests). Each scene is 32x32 (cube_uv, aniso_sphere and principled 48x32, spheres 64x48) at its $spp
default (256: below ~128 spp the per-pixel variance estimates of small highlights are too noisy for
the test; at 256 the pass fraction over seeds 0-9 is 0.995-1.000; cube_uv's is 0.999-1.000 over
seeds 0-4; aniso_sphere's 0.998-1.000, plastics' 0.998-1.000, principled's 0.9967-0.9996 and
spheres' 0.9996-1.000 over seeds 0-9), so the module takes a few seconds.

Scope: each scene exercises importer features whose definition we match: metals.xml explicit eta/k;
spheres.xml the named metal `Cu` (RGB (eta, k) reduced from Mitsuba's spectral data as Mitsuba does,
docs/materials.md) and Mitsuba's default gaussian rfilter, which the importer reconstructs as
Mitsuba does (splatting, with a Gaussian that reaches 0 at its radius); plastics.xml plastic and
roughplastic with Mitsuba's default nonlinear=false (our "linear" variant, the rough coat's
tabulated transmittance, separable Smith shadowing); principled.xml the 2015 Disney BSDF and
principledthin; aniso_sphere.xml anisotropic roughness and a texture on rotated spheres;
bumpmap.xml (48x32) Mitsuba's bumpmap and normalmap (bump_model "mitsuba", invalid_normals
"mirror", terminator_model "estevez", sRGB-decoded heights). At 256 spp
the per-pixel test on spheres.xml does not detect a change of a few percent in Cu's reflectance
(the sphere covers few pixels): the named-metal data are checked by test_conductor_names.py. The
generated parity matrix (test_parity_matrix.py) covers every importer mapping.

What these scenes found, now fixed (docs/mitsuba-import.md): OBJ/PLY files without vertex normals
get computed smooth normals in Mitsuba, and emitting shapes without a bsdf are black in Mitsuba;
cube_uv.xml: the cube's per-face uv layout differed from Mitsuba's (71 % of channels passed);
aniso_sphere.xml: a rotated sphere's uv and tangents followed the world z axis instead of the
sphere's own (85 %); plastics.xml: nonlinear=false was imported as the coupled plastic (88 %, image
mean -4.5 %); spheres.xml with the gaussian rfilter: filter sampling with a truncated Gaussian
(98.3-98.7 %, max |z| 49, at the floor's far edge and the sphere's rim); bumpmap.xml: our default
bump model, invalid-normal treatment and terminator term, and heights read linearly (93 %, image
mean -3.7 %).
"""
from __future__ import annotations

import importlib.util
import pathlib
import sys

import numpy as np
import pytest

import pellucid
from zcheck import z_pass_fraction

DATA = pathlib.Path(__file__).resolve().parents[2] / "tests" / "data" / "mitsuba"
SCENES = ["aniso_sphere", "bumpmap", "cornell_mini", "cube_uv", "glass", "metals", "plastics", "principled", "spheres", "textures"]
SEED = 7


def reference(name: str):
    if importlib.util.find_spec("mitsuba") is not None:
        sys.path.insert(0, str(DATA))
        try:
            from make_refs import render_reference
        finally:
            sys.path.pop(0)
        return render_reference(name)
    ref = DATA / "ref"
    if not (ref / f"{name}.exr").exists():
        pytest.skip(f"no Mitsuba and no committed reference for {name}")
    return pellucid.read_image(ref / f"{name}.exr"), pellucid.read_image(ref / f"{name}.var.exr")


@pytest.mark.parametrize("name", SCENES)
def test_scene_matches_mitsuba(name: str) -> None:
    scene = pellucid.load_file(DATA / f"{name}.xml")
    img, var, _ = pellucid.render_with_stats(scene, seed=SEED)
    img, var = np.array(img), np.array(var)
    ref, ref_var = reference(name)
    assert img.shape == ref.shape, f"{name}: pellucid {img.shape} vs Mitsuba {ref.shape}"
    assert np.all(np.isfinite(img)) and np.all(var >= 0)
    frac, zc = z_pass_fraction(img, var, ref, ref_var)
    rel = float(np.abs(img.mean() - ref.mean()) / ref.mean())
    assert frac >= 0.99, (f"{name}: only {100 * frac:.2f}% of pixel channels within |z| <= {zc:.2f} "
                          f"(image means: pellucid {img.mean():.4f}, Mitsuba {ref.mean():.4f}, rel. diff {rel:.3%})")


def test_z_test_can_fail() -> None:
    """The check has teeth: a 3 % brightness change in one scene fails it."""
    scene = pellucid.load_file(DATA / "metals.xml")
    img, var, _ = pellucid.render_with_stats(scene, seed=SEED)
    ref, ref_var = pellucid.read_image(DATA / "ref" / "metals.exr"), pellucid.read_image(DATA / "ref" / "metals.var.exr")
    frac, _ = z_pass_fraction(np.array(img) * 1.03, np.array(var) * 1.03**2, ref, ref_var)
    assert frac < 0.99
