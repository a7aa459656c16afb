"""Issue 6 check: Mitsuba 3 scenes we wrote (tests/data/mitsuba/*.xml), rendered by pellucid through
its XML importer, agree with Mitsuba 3 under a per-pixel z-test on at least 99 % of pixel channels.

The reference is Mitsuba itself when ``mitsuba`` is importable here (rendered by
tests/data/mitsuba/make_refs.py's ``render_reference``), otherwise the committed
tests/data/mitsuba/ref/<scene>.exr (mean of 16 passes x 256 spp, Mitsuba 3.9.1 llvm_ad_rgb) and
<scene>.var.exr (variance of that mean), produced by the same script with the peer venv.

z = |ours - ref| / sqrt(var_ours + var_ref + (1e-5 max(|ours|, |ref|))^2) per pixel channel, ours with the film's variance of the
mean; the critical |z| is two-sided α = 0.01 Šidák-corrected over all channels of the image (as
bench/cornell.py and Mitsuba's own render tests). Each scene is 32x32 (cube_uv and aniso_sphere 48x32,
spheres 64x48) at its $spp default (256: below ~128 spp the per-pixel variance estimates of small highlights
are too noisy for the test; at 256 the pass fraction over seeds 0-9 is 0.995-1.000; cube_uv's is
0.999-1.000 over seeds 0-4; aniso_sphere's and spheres' 0.998-1.000 over seeds 0-9), so the module takes about three
seconds.

Scope: what the scenes use has the same definition in both renderers (metals.xml's explicit eta/k;
spheres.xml's named metal `Cu`, whose RGB (eta, k) we reduce from Mitsuba's spectral data as Mitsuba
does, docs/materials.md; isotropic roughness on the cube; Mitsuba's plastic with nonlinear=true; see
docs/materials.md "Mitsuba 3 comparison"). At 256 spp the per-pixel test on spheres.xml does not
detect a change of a few percent in Cu's reflectance (the sphere covers few pixels): the named-metal
data are checked by test_conductor_names.py. spheres.xml uses a box filter; with a gaussian filter
only 98.6 % of its channels pass: at high-contrast edges (the highlight on the sphere's rim, the
floor's far edge) Mitsuba's splatted gaussian reconstruction and our filter-importance-sampled one
differ. Writing these scenes found two importer differences, now fixed (docs/mitsuba-import.md):
OBJ/PLY files without vertex normals get computed smooth normals in Mitsuba, and emitting shapes
without a bsdf are black in Mitsuba. cube_uv.xml found a third, now fixed: the cube's per-face uv
layout (hence its tangents and the orientation of anisotropic roughness) differed from Mitsuba's;
with the old layout only 71 % of its pixel channels passed. aniso_sphere.xml found a fourth, now
fixed: a rotated sphere's uv and tangents
(hence its texture and the orientation of anisotropic roughness) followed the world z axis instead of
the sphere's own; with that, 85 % of its pixel channels passed. bumpmap.xml (48x32) checks Mitsuba's
bumpmap and normalmap, which the importer maps to bump_model "mitsuba", invalid_normals "mirror"
and terminator_model "estevez" (docs/scene-format.md); with our default bump model, invalid-normal
treatment and terminator term, and heights read linearly without `raw`, its image mean was 3.7 %
below Mitsuba's and 93 % of its pixel channels passed.
"""
from __future__ import annotations

import importlib.util
import math
import pathlib
import sys

import numpy as np
import pytest

import pellucid

DATA = pathlib.Path(__file__).resolve().parents[2] / "tests" / "data" / "mitsuba"
SCENES = ["aniso_sphere", "bumpmap", "cornell_mini", "cube_uv", "glass", "metals", "plastics", "principled", "spheres", "textures"]
SEED = 7


def critical_z(n: int, alpha: float = 0.01) -> float:
    """|z| with two-sided tail probability 1 - (1 - alpha)^(1/n) (bisection on erfc)."""
    a1 = 1.0 - (1.0 - alpha) ** (1.0 / n)
    lo, hi = 0.0, 40.0
    for _ in range(200):
        mid = 0.5 * (lo + hi)
        lo, hi = (mid, hi) if math.erfc(mid / math.sqrt(2.0)) > a1 else (lo, mid)
    return lo


def z_pass_fraction(a, va, b, vb) -> tuple[float, float]:
    # Pixels that see only a constant emitter have zero variance in both renderers; their means then
    # differ only by float summation order, hence the 1e-5 relative floor on the deviation.
    floor = (1e-5 * np.maximum(np.abs(a), np.abs(b))) ** 2 + 1e-12
    z = np.abs(a - b) / np.sqrt(va + vb + floor)
    zc = critical_z(a.size)
    return float(np.mean(z <= zc)), zc


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
