"""``python -m pellucid stability``: sweeps every registered scattering model over the parameter
values where methods fail, and counts the numbers that would spoil an image.

For each model and parameter point the sweep

- evaluates ``eval``, ``pdf`` and ``sample`` (BxDFs through :func:`pellucid.bsdf` in both transport
  modes, phase functions through ``_core.PhaseProbe``) at random directions and at the hard ones:
  the normal, grazing angles (cos θ = 1e-6, 1e-3 and 0), the lower hemisphere, and directions
  within 1e-6 and 1e-4 (relative) of the critical angle of total internal reflection for each η
  of the point; ``sample`` also gets the edge values 0, ½ and 1 − 2⁻²⁴ of its random numbers;
- renders a tiny scene, a few samples per pixel, and reads the render's dropped-sample count: for
  a material, a sphere of it on a floor under an area light and a constant environment (also with
  a normal map whose normals lie in the tangent plane, so that shading normals face away from the
  viewer, under each ``invalid_normals`` treatment); for a phase function, a cube of homogeneous
  medium of albedo 1 with it, behind a null boundary, at σt = 1e-6, 1 and 1000;
- for a diffusion profile (``dipole``, ``better_dipole`` of :mod:`pellucid.bssrdf`), evaluates
  ``eval`` and ``pdf`` at r = 0, tiny, r_max, far beyond and random radii, and ``sample`` at edge and
  random u, with albedo 0 and 1, σt from 1e-3 to 1e6 per scene unit, g = ±0.99 and η = 1, 1 ± 1e-4.

It counts per point: **NaN**, **Inf** and **negative** values (rows of ``eval``/``pdf``/``sample``
output, and image values), and **invalid** results: for ``sample``, a sample that claims a lobe but
has a pdf ≤ 0 or a direction that is not a unit vector, or that fails (lobe 0) with a non-zero
weight; for renders, the samples the renderer dropped as NaN, infinite or negative
(``invalid_samples``). Every count must be zero.

The models come from the registry (``_core.registry_types()``): :data:`FAMILIES` maps a family to
its probe, scene and render variants, and :data:`GRIDS` gives each model's parameter points. A
registered model with no grid is swept at its defaults and reported as missing a grid (a failure),
so a new model shows up here as soon as it is registered. BSSRDFs join through the hook marked
``HOOK`` below.

The parameter grid is REFERENCE §7.2's: α ∈ {0, 1e-4, 1e-3, 1e-2} (and 9.99e-4, 0.5, 1),
η ∈ {1, 1 ± 1e-4} besides ordinary and inverted IORs, conductors with k = 0 and k at its upper
limit, reflectances 0 and 1, back-facing shading normals, HG g ∈ {±1, ±0.999, ±1e-7, 0}, albedo 1
with σt → 0 and σt large. ``quick=True`` keeps a subset of each grid (the CI test,
tests/python/test_stability.py).
"""
from __future__ import annotations

import argparse
import json
import math
import sys
import time
from dataclasses import dataclass, field
from itertools import product
from typing import Any, Callable, Dict, Iterable, List, Optional, Sequence, Tuple

import numpy as np

import pellucid
from . import _core, scenes

Params = Dict[str, Any]

# ---------------------------------------------------------------------------------------------
# Parameter grids (REFERENCE §7.2). Each entry: model type -> function(quick) -> parameter dicts.
# ---------------------------------------------------------------------------------------------

#: α values of §7.2 (continuity with the delta lobe at 1e-3), plus ordinary and maximal roughness.
ALPHAS_FULL = (0.0, 1e-4, 9.99e-4, 1e-3, 1e-2, 0.5, 1.0)
ALPHAS_QUICK = (0.0, 1e-4, 1e-3, 1e-2, 1.0)
#: Relative IORs: index-matched (1, 1 ± 1e-4), glass from either side, and the upper limit.
ETAS_FULL = (1.0, 1.0001, 0.9999, 1.5, 1.0 / 1.5, 10.0)
ETAS_QUICK = (1.0, 1.0001, 0.9999, 1.5)


def _alphas(quick: bool) -> Sequence[float]:
    return ALPHAS_QUICK if quick else ALPHAS_FULL


def _etas(quick: bool) -> Sequence[float]:
    return ETAS_QUICK if quick else ETAS_FULL


def _grid_profile(quick: bool) -> List[Params]:
    albedos = (0.0, 0.5, 1.0) if quick else (0.0, 1e-4, 0.5, 0.999, 1.0)
    sigma_ts = (1e-3, 1e4) if quick else (1e-3, 1.0, 1e4, 1e6)
    gs = (-0.99, 0.99) if quick else (-0.99, 0.0, 0.99)
    etas = (1.0, 1.0001, 1.33) if quick else (1.0, 1.0001, 0.9999, 1.33, 10.0)
    return [{"albedo": a, "sigma_t": t, "g": g, "eta": e} for a, t, g, e in product(albedos, sigma_ts, gs, etas)]


def _grid_lambertian(quick: bool) -> List[Params]:
    return [{"reflectance": r} for r in (0.0, 1.0)]


def _grid_oren_nayar(quick: bool) -> List[Params]:
    out: List[Params] = []
    for r in (0.0, 1.0):
        out += [{"variant": "eon", "roughness": s, "reflectance": r} for s in (0.0, 0.5, 1.0)]
        out += [{"variant": "classic", "sigma": s, "reflectance": r} for s in (0.0, 20.0, 90.0)]
    return out


#: Conductor IORs: a measured metal, index-matched with k = 0 (F = 0 at normal incidence), a small
#: η with k = 0, and k at its upper limit (100).
_CONDUCTORS = ({"material": "Au"}, {"eta": 1.0, "k": 0.0}, {"eta": 0.2, "k": 0.0}, {"eta": 1.5, "k": 100.0},
               {"material": "none"})


def _grid_conductor(quick: bool) -> List[Params]:
    out = [dict(c) for c in _CONDUCTORS]
    out += [dict(c, fresnel="schlick") for c in _CONDUCTORS[:4]]
    out.append({"material": "Au", "specular_reflectance": 0.0})
    return out


def _grid_rough_conductor(quick: bool) -> List[Params]:
    iors = _CONDUCTORS[:2] if quick else _CONDUCTORS[:4]
    dists = ("ggx",) if quick else ("ggx", "beckmann")
    out = [dict(c, alpha=a, distribution=d) for a, c, d in product(_alphas(quick), iors, dists)]
    out += [{"material": "Au", "alpha_u": au, "alpha_v": av, "distribution": d}
            for (au, av), d in product(((1e-4, 1.0), (1.0, 1e-4), (1e-3, 1e-2)), dists)]
    out += [{"material": "Au", "alpha": a, "multiple_scattering": True} for a in _alphas(quick)]
    if not quick:
        out += [{"material": "Au", "alpha": a, "shadowing": "separable"} for a in _alphas(quick)]
    return out


def _grid_dielectric(quick: bool) -> List[Params]:
    out: List[Params] = [{"int_ior": e, "ext_ior": 1.0} for e in _etas(quick)]
    out += [{"int_ior": 1.5, "ext_ior": 1.0, "specular_reflectance": 0.0},
            {"int_ior": 1.5, "ext_ior": 1.0, "specular_transmittance": 0.0}]
    return out


def _grid_rough_dielectric(quick: bool) -> List[Params]:
    dists = ("ggx",) if quick else ("ggx", "beckmann")
    out = [{"int_ior": e, "ext_ior": 1.0, "alpha": a, "distribution": d}
           for e, a, d in product(_etas(quick), _alphas(quick), dists)]
    out += [{"int_ior": 1.5, "ext_ior": 1.0, "alpha_u": 1e-4, "alpha_v": 1.0, "distribution": d} for d in dists]
    out += [{"int_ior": e, "ext_ior": 1.0, "alpha": a, "multiple_scattering": True}
            for e, a in product((1.0001, 1.5) if quick else _etas(quick), _alphas(quick))]
    if not quick:
        out += [{"int_ior": 1.5, "ext_ior": 1.0, "alpha": a, "shadowing": "separable"} for a in _alphas(quick)]
    return out


def _grid_thin_dielectric(quick: bool) -> List[Params]:
    return [{"int_ior": e, "ext_ior": 1.0} for e in _etas(quick)]


def _grid_plastic(quick: bool) -> List[Params]:
    etas = (1.0, 1.0001, 1.5) if quick else (1.0, 1.0001, 0.9999, 1.5, 10.0)
    return [{"variant": v, "int_ior": e, "ext_ior": 1.0, "diffuse_reflectance": kd}
            for v, e, kd in product(("coupled", "linear", "sum"), etas, (0.0, 1.0))]


def _grid_rough_plastic(quick: bool) -> List[Params]:
    etas = (1.0, 1.5) if quick else (1.0, 1.0001, 0.9999, 1.5, 10.0)
    out = [{"int_ior": e, "ext_ior": 1.0, "alpha": a, "diffuse_reflectance": 1.0, "coat_transmittance": ct}
           for e, a, ct in product(etas, _alphas(quick), ("smooth", "rough"))]
    out += [{"variant": v, "alpha": a, "diffuse_reflectance": kd}
            for v, a, kd in product(("linear", "sum"), (0.0, 1e-2) if quick else _alphas(quick), (0.0, 1.0))]
    if not quick:
        out += [{"alpha": a, "distribution": "beckmann"} for a in _alphas(quick)]
    return out


def _grid_principled(quick: bool) -> List[Params]:
    rough = (0.0, 1e-2, 0.5, 1.0)
    out: List[Params] = [{"roughness": r, "metallic": m, "anisotropic": an}
                         for r, m, an in product(rough, (0.0, 1.0), (0.0, 1.0))]
    out += [{"base_color": b, "roughness": 0.5, "sheen": 1.0, "clearcoat": 1.0, "clearcoat_gloss": g,
             "specular": s, "specular_tint": 1.0}
            for b, g, s in product((0.0, 1.0), (0.0, 1.0), (0.0, 1.0))]
    etas = (1.0, 1.0001, 1.5) if quick else (1.0, 1.0001, 0.9999, 1.5, 1.0 / 1.5, 10.0)
    out += [{"variant": "2015", "specular_transmission": 1.0, "eta": e, "roughness": r}
            for e, r in product(etas, rough)]
    out += [{"variant": "2015", "flatness": 1.0, "roughness": r, "metallic": m} for r, m in product(rough, (0.0, 1.0))]
    out += [{"variant": "2015", "thin": True, "diffuse_transmission": dt, "specular_transmission": st,
             "roughness": r, "eta": e}
            for dt, st, r, e in product((0.0, 1.0, 2.0), (0.0, 1.0), (0.0, 0.5) if quick else rough,
                                        (1.0, 1.5) if quick else (1.0, 1.0001, 1.5))]
    return out


def _grid_subsurface(quick: bool) -> List[Params]:
    """Every model at albedo 0 and 1 with mean free paths far below a pixel footprint and far above
    the object's size (REFERENCE §7.2), g = ±0.99, η = 1 and 1 ± 1e-4, no scattering, a rough boundary."""
    models = ("dipole", "better_dipole", "random_walk", "auto") if quick else (
        "dipole", "better_dipole", "random_walk", "coated", "auto")
    albedos = (0.0, 1.0) if quick else (0.0, 0.5, 1.0)
    mfps = (1e-6, 1.0) if quick else (1e-6, 1e-3, 1.0, 1e3)
    out: List[Params] = [{"model": m, "albedo": a, "mfp": f} for m, a, f in product(models, albedos, mfps)]
    etas = (1.0, 1.0001) if quick else (1.0, 1.0001, 0.9999)
    out += [{"model": "better_dipole", "albedo": 0.5, "mfp": 0.01, "int_ior": e, "ext_ior": 1.0} for e in etas]
    out += [{"model": m, "albedo": 0.8, "mfp": 0.01, "g": g} for m, g in product(("dipole", "random_walk"), (-0.99, 0.99))]
    out += [{"sigma_a": 1.0, "sigma_s": 0.0}, {"model": "dipole", "sigma_a": 0.0, "sigma_s": 1e4},
            {"model": "better_dipole", "albedo": 0.8, "mfp": 0.01, "alpha": 0.3}]
    return out


def _grid_hg(quick: bool) -> List[Params]:
    gs = (-1.0, -0.999, 0.0, 0.999, 1.0) if quick else (-1.0, -0.999, -0.5, -1e-7, 0.0, 1e-7, 0.5, 0.999, 1.0)
    return [{"g": g} for g in gs]


#: THE table of parameter grids: one entry per registered model type. A model added to the registry
#: needs an entry here (until then it is swept at its defaults and reported as missing a grid).
GRIDS: Dict[str, Callable[[bool], List[Params]]] = {
    "lambertian": _grid_lambertian,
    "oren_nayar": _grid_oren_nayar,
    "conductor": _grid_conductor,
    "rough_conductor": _grid_rough_conductor,
    "dielectric": _grid_dielectric,
    "rough_dielectric": _grid_rough_dielectric,
    "thin_dielectric": _grid_thin_dielectric,
    "plastic": _grid_plastic,
    "rough_plastic": _grid_rough_plastic,
    "principled": _grid_principled,
    "subsurface": _grid_subsurface,
    # Phase functions: g at and next to the delta (±1, ±0.999) and next to isotropic (±1e-7).
    "hg": _grid_hg,
    "isotropic": lambda quick: [{}],
    # Diffusion profiles (pellucid.bssrdf): albedo 0 and 1, σt from 1e-3 to 1e6 per scene unit
    # (mean free paths far above an object's size and far below a pixel's), g = ±0.99, η = 1, 1 ± 1e-4.
    "dipole": lambda quick: _grid_profile(quick),
    "better_dipole": lambda quick: _grid_profile(quick),
}

# ---------------------------------------------------------------------------------------------
# Families: where the model names come from and how one model is probed and rendered.
# ---------------------------------------------------------------------------------------------


def _bsdf_probe(desc: Params, mode: str) -> Any:
    """A probe with ``eval(wo, wi)``, ``pdf(wo, wi)`` and ``sample(wo, u) -> (wi, weight, pdf, lobe)``."""
    return pellucid.bsdf(desc, mode)


def _material_scene(desc: Params, variant: str, spp: int) -> Dict[str, Any]:
    """A tiny scene: a sphere of the material on a floor, an area light and a dim environment.
    ``variant`` "plain", or "normal_map:<treatment>": a normal map whose normals lie in the tangent
    plane (checkerboard of ±x), so that shading normals face away from the viewer on much of the
    sphere, treated by ``invalid_normals`` = <treatment>."""
    mat = dict(desc)
    if variant.startswith("normal_map:"):
        mat["normal_map"] = {"type": "checkerboard", "color0": [1.0, 0.5, 0.5], "color1": [0.0, 0.5, 0.5],
                             "filtered": False, "to_uv": [{"scale": [16, 8, 1]}]}
        mat["invalid_normals"] = variant.split(":", 1)[1]
    return scenes.material_ball(mat, width=16, height=12, spp=spp)


def _material_variants(quick: bool) -> List[str]:
    return ["plain"] if quick else ["plain", "normal_map:bend", "normal_map:mirror", "normal_map:keep"]


class _PhaseProbe:
    """A phase function (``_core.PhaseProbe``) behind the BSDF probe's interface: ``eval`` and
    ``pdf`` as they are, ``sample(wo, u)`` with u (N, 3) of which (u1, u2) are used, returning
    ``(wi, weight (N, 1), pdf, lobe)`` with lobe 1 for every sample (phase sampling cannot fail)."""

    def __init__(self, desc: Params) -> None:
        self._p = _core.PhaseProbe(desc)  # type: ignore[attr-defined]

    def eval(self, wo: np.ndarray, wi: np.ndarray) -> np.ndarray:
        return self._p.eval(wo, wi)

    def pdf(self, wo: np.ndarray, wi: np.ndarray) -> np.ndarray:
        return self._p.pdf(wo, wi)

    def sample(self, wo: np.ndarray, u: np.ndarray) -> Tuple[np.ndarray, ...]:
        wi, weight, pdf, _delta = self._p.sample(wo, np.ascontiguousarray(u[:, 1:3]))
        return wi, weight.reshape(-1, 1), pdf, np.ones(len(wo), dtype=np.uint32)


def _phase_probe(desc: Params, mode: str) -> Any:
    return _PhaseProbe(desc)


def _medium_scene(desc: Params, variant: str, spp: int) -> Dict[str, Any]:
    """A cube of homogeneous medium with the phase function, inside a null boundary, on a floor
    under an area light. ``variant`` "sigma_t=<value>": the extinction, with albedo 1 (no
    absorption: every path ends by leaving the medium or at max_depth 32)."""
    sigma_t = float(variant.split("=", 1)[1])
    return {
        "camera": {"type": "perspective", "fov": 40,
                   "to_world": [{"look_at": {"origin": [0, 0.5, 4], "target": [0, 0, 0], "up": [0, 1, 0]}}]},
        "film": {"width": 16, "height": 12},
        "sampler": {"sample_count": spp},
        "integrator": {"type": "path", "max_depth": 32},
        "media": {"m": {"type": "homogeneous", "sigma_t": sigma_t, "albedo": 1.0, "phase": dict(desc)}},
        "materials": {"boundary": {"type": "null"}},
        "shapes": [
            {"type": "cube", "material": "boundary", "interior": "m", "to_world": [{"scale": 0.7}]},
            {"type": "rectangle", "material": {"type": "lambertian", "reflectance": 0.5},
             "to_world": [{"scale": 4}, {"rotate": {"axis": [1, 0, 0], "angle": -90}}, {"translate": [0, -0.7, 0]}]},
            {"type": "rectangle", "material": {"type": "lambertian", "reflectance": 0.0},
             "to_world": [{"rotate": {"axis": [1, 0, 0], "angle": 90}}, {"translate": [0, 2.5, 0]}],
             "emitter": {"type": "area", "radiance": 5.0}},
        ],
        "lights": [{"type": "constant", "radiance": 0.2}],
    }


def _medium_variants(quick: bool) -> List[str]:
    """σt → 0, ordinary, and optically thick (REFERENCE §7.2: σt → 0 and ∞, albedo 1)."""
    return ["sigma_t=1"] if quick else ["sigma_t=1e-06", "sigma_t=1", "sigma_t=1000"]


def _phase_names() -> List[str]:
    """Phase-function types: the registry's "phase_functions" family where it lists one, else the
    types this build's ``_core.PhaseProbe`` knows (none without it)."""
    return ["hg", "isotropic"] if hasattr(_core, "PhaseProbe") else []


@dataclass(frozen=True)
class Family:
    """One family of scattering models that the sweep covers."""

    registry_key: str                                     #: key of _core.registry_types()
    probe: Optional[Callable[[Params, str], Any]]         #: (desc, mode) -> probe; None: no evaluation
    scene: Optional[Callable[[Params, str, int], Dict[str, Any]]]  #: (desc, variant, spp) -> scene dict
    modes: Tuple[str, ...] = ("radiance", "importance")   #: transport modes evaluated
    variants: Callable[[bool], List[str]] = _material_variants  #: (quick) -> render variants
    #: model names when the registry has no such family (None: the registry's list only)
    fallback_names: Optional[Callable[[], List[str]]] = None
    #: (result, desc, quick, rng): evaluates one point in place of the direction probe (profiles)
    sweep_point: Optional[Callable[..., None]] = None


def _sweep_profile(res: Any, desc: Params, quick: bool, rng: np.random.Generator) -> None:
    """A diffusion profile at one point: eval and pdf at r = 0, tiny, r_max, far beyond and random
    radii; sample at edge and random u. Invalid: a sample beyond r_max, pdf ≤ 0 at a sample of a
    profile with mass, a total outside [0, 1], r_max not finite."""
    from . import bssrdf
    a, st = float(desc["albedo"]), float(desc["sigma_t"])
    p = bssrdf.profile(desc["type"], (1.0 - a) * st, a * st, float(desc["g"]), float(desc["eta"]))
    rm = p.r_max
    r = np.concatenate([[0.0, 1e-30, 1e-12 * rm, rm, 10.0 * rm, 1e30, np.inf],
                        rng.random(256 if quick else 4096) * 2.0 * rm]).astype(np.float32)
    _tally(res, p.eval(r), "eval", {"r": r})
    _tally(res, p.pdf(r), "pdf", {"r": r})
    u = np.concatenate([[0.0, 2.0 ** -32, 0.5, 1.0 - 2.0 ** -24], rng.random(256 if quick else 4096)]).astype(np.float32)
    rs = p.sample(u)
    _tally(res, rs, "sample", {"u": u})
    bad = (rs > rm) | ((p.total > 0) & (u > 0) & ~(p.pdf(rs) > 0))
    res.invalid += int(bad.sum()) + int(not 0.0 <= p.total <= 1.0) + int(not math.isfinite(rm))
    _note_example(res, bad, "sample", {"u": u}, rs)


def _profile_names() -> List[str]:
    from . import bssrdf
    return list(bssrdf.MODELS)


#: THE families swept, by registry key. HOOK (BSSRDFs): add the subsurface family here with its
#: registry key, a probe (or None) and a scene builder, e.g. Family("bssrdfs", None, _bssrdf_scene).
FAMILIES: Tuple[Family, ...] = (
    Family("materials", _bsdf_probe, _material_scene),
    Family("phase_functions", _phase_probe, _medium_scene, ("radiance",), _medium_variants, _phase_names),
    Family("bssrdf_profiles", None, None, ("radiance",), fallback_names=_profile_names, sweep_point=_sweep_profile),
)

# ---------------------------------------------------------------------------------------------
# Directions and random numbers
# ---------------------------------------------------------------------------------------------


def _unit(x: float, y: float, z: float) -> Tuple[float, float, float]:
    n = math.sqrt(x * x + y * y + z * z)
    return (x / n, y / n, z / n)


def _ring(cos_theta: float, phis: Iterable[float]) -> List[Tuple[float, float, float]]:
    s = math.sqrt(max(0.0, 1.0 - cos_theta * cos_theta))
    return [(s * math.cos(p), s * math.sin(p), cos_theta) for p in phis]


def _etas_of(params: Params) -> List[float]:
    """The relative IORs a parameter point sets (int/ext, eta), for the critical-angle directions."""
    out = []
    ii, ee = params.get("int_ior"), params.get("ext_ior", 1.0)
    if isinstance(ii, (int, float)) and isinstance(ee, (int, float)) and ee > 0:
        out.append(float(ii) / float(ee))
    e = params.get("eta")
    if isinstance(e, (int, float)):
        out.append(float(e))
    return out


def hard_directions(etas: Sequence[float] = ()) -> np.ndarray:
    """The directions where methods fail, both hemispheres: the normal, cos θ ∈ {1e-6, 1e-3, 0}
    (grazing) at several azimuths, and for each relative IOR η ≠ 1 the directions whose sin θ is
    within 0, 1e-6 and 1e-4 (relative) of the critical angle's 1/max(η, 1/η)."""
    phis = (0.0, math.pi / 4, math.pi / 2, 2.0, math.pi)
    up: List[Tuple[float, float, float]] = [(0.0, 0.0, 1.0)]
    for c in (1e-6, 1e-3, 0.0, 0.5):
        up += _ring(c, phis)
    for eta in etas:
        big = max(eta, 1.0 / eta)
        if big <= 1.0:
            continue
        for d in (-1e-4, -1e-6, 0.0, 1e-6, 1e-4):
            s = min(1.0, (1.0 / big) * (1.0 + d))
            up += _ring(math.sqrt(1.0 - s * s), (0.3, 1.9))
    both = up + [(x, y, -z) for x, y, z in up]
    return np.array([_unit(*d) for d in both], dtype=np.float32)


def random_directions(n: int, rng: np.random.Generator) -> np.ndarray:
    v = rng.normal(size=(n, 3))
    return (v / np.linalg.norm(v, axis=1, keepdims=True)).astype(np.float32)


_EDGE_U = np.array(list(product((0.0, 0.5, 1.0 - 2.0 ** -24), repeat=3)), dtype=np.float32)

# ---------------------------------------------------------------------------------------------
# Counting
# ---------------------------------------------------------------------------------------------

COUNTS = ("nan", "inf", "negative", "invalid")


@dataclass
class PointResult:
    """Counts of one model at one parameter point (evaluation or render)."""

    family: str
    model: str
    params: Params
    kind: str  #: "eval" (eval/pdf/sample) or "render:<variant>"
    evaluations: int = 0
    nan: int = 0
    inf: int = 0
    negative: int = 0
    invalid: int = 0
    error: str = ""  #: a failure to build or run the point (counts as a finding)
    example: Dict[str, Any] = field(default_factory=dict)  #: the first offending input, if any
    seconds: float = 0.0

    @property
    def failures(self) -> int:
        return self.nan + self.inf + self.negative + self.invalid + (1 if self.error else 0)

    def to_json(self) -> Dict[str, Any]:
        d = {k: getattr(self, k) for k in ("family", "model", "params", "kind", "evaluations", *COUNTS,
                                            "error", "example", "seconds")}
        d["params"] = {k: _jsonable(v) for k, v in self.params.items()}
        return d


def _jsonable(v: Any) -> Any:
    if isinstance(v, float) and not math.isfinite(v):
        return repr(v)
    if isinstance(v, np.ndarray):
        return [_jsonable(x) for x in v.tolist()]
    if isinstance(v, (list, tuple)):
        return [_jsonable(x) for x in v]
    if isinstance(v, dict):
        return {k: _jsonable(x) for k, x in v.items()}
    if isinstance(v, (np.floating, np.integer)):
        return _jsonable(v.item())
    return v


def _rows_bad(values: np.ndarray) -> Tuple[np.ndarray, np.ndarray, np.ndarray]:
    """Per row: any NaN, any ±Inf, any negative (finite) value."""
    v = values.reshape(len(values), -1)
    nan = np.isnan(v).any(axis=1)
    inf = np.isinf(v).any(axis=1)
    neg = (v < 0).any(axis=1) & ~nan
    return nan, inf, neg


def _tally(res: PointResult, values: np.ndarray, call: str, inputs: Dict[str, np.ndarray],
           negative_ok: bool = False) -> None:
    nan, inf, neg = _rows_bad(values)
    if negative_ok:
        neg = np.zeros_like(neg)
    res.evaluations += len(values)
    res.nan += int(nan.sum())
    res.inf += int(inf.sum())
    res.negative += int(neg.sum())
    _note_example(res, nan | inf | neg, call, inputs, values)


def _note_example(res: PointResult, bad: np.ndarray, call: str, inputs: Dict[str, np.ndarray],
                  values: np.ndarray) -> None:
    if res.example or not bad.any():
        return
    i = int(np.flatnonzero(bad)[0])
    res.example = {"call": call, **{k: v[i].tolist() for k, v in inputs.items()}, "value": np.atleast_1d(values[i]).tolist()}


def _sweep_probe(res: PointResult, probe: Any, mode: str, params: Params, quick: bool, rng: np.random.Generator) -> None:
    hard = hard_directions(_etas_of(params))
    n_rand = 256 if quick else 2048
    rand = random_directions(n_rand, rng)
    # eval and pdf: every hard wo against every hard and some random wi, plus random pairs.
    wi_set = np.concatenate([hard, rand[: (64 if quick else 512)]])
    wo = np.repeat(hard, len(wi_set), axis=0)
    wi = np.tile(wi_set, (len(hard), 1))
    wo = np.concatenate([wo, rand, np.repeat(rand[:32], 32, axis=0)])
    wi = np.concatenate([wi, random_directions(n_rand, rng), np.tile(rand[32:64], (32, 1))])
    tag = {"mode": np.array([mode] * len(wo))}
    _tally(res, probe.eval(wo, wi), "eval", {"wo": wo, "wi": wi, **tag})
    _tally(res, probe.pdf(wo, wi), "pdf", {"wo": wo, "wi": wi, **tag})
    # sample: every hard and some random wo, each with random and edge u.
    wo_s = np.concatenate([hard, rand[: (64 if quick else 256)]])
    u_set = np.concatenate([_EDGE_U, rng.random((16 if quick else 64, 3), dtype=np.float32)])
    wo_r = np.repeat(wo_s, len(u_set), axis=0)
    u = np.tile(u_set, (len(wo_s), 1))
    wi_s, weight, pdf, lobe = probe.sample(wo_r, u)
    inputs = {"wo": wo_r, "u": u, "mode": np.array([mode] * len(wo_r))}
    _tally(res, weight, "sample.weight", inputs)
    _tally(res, pdf, "sample.pdf", inputs)
    res.evaluations -= 2 * len(wo_r)  # the two tallies above count one sample call
    nan_wi, inf_wi, _ = _rows_bad(wi_s)
    res.nan += int(nan_wi.sum())
    res.inf += int(inf_wi.sum())
    _note_example(res, nan_wi | inf_wi, "sample.wi", inputs, wi_s)
    ok = lobe != 0
    norm = np.linalg.norm(wi_s.astype(np.float64), axis=1)
    invalid = (ok & (~(pdf > 0) | ~(np.abs(norm - 1.0) < 1e-3))) | (~ok & (np.abs(weight) > 0).any(axis=1))
    res.invalid += int(invalid.sum())
    _note_example(res, invalid, "sample (lobe, pdf, |wi| or failed-sample weight)",
                  {**inputs, "wi": wi_s, "pdf": pdf, "lobe": lobe}, weight)
    res.evaluations += len(wo_r)


def _render_point(res: PointResult, fam: Family, desc: Params, variant: str, spp: int, seed: int) -> None:
    scene = pellucid.load_dict(fam.scene(desc, variant, spp))  # type: ignore[misc]
    image, _, stats = pellucid.render_with_stats(scene, spp=spp, seed=seed)
    img = np.asarray(image)
    res.evaluations += int(stats["samples"])
    res.invalid += int(stats["invalid_samples"])
    px = img.reshape(-1, img.shape[-1])
    _tally(res, px, "image", {"pixel": np.arange(len(px))})
    res.evaluations -= len(px)
    if stats["invalid_samples"] and not res.example:
        res.example = {"call": "render", "dropped_samples": int(stats["invalid_samples"]), "spp": spp, "seed": seed}


# ---------------------------------------------------------------------------------------------
# The sweep
# ---------------------------------------------------------------------------------------------


@dataclass
class Report:
    results: List[PointResult]
    missing_grids: List[str]
    skipped_families: List[str]
    seconds: float
    quick: bool

    @property
    def failures(self) -> int:
        return sum(r.failures for r in self.results) + len(self.missing_grids)

    def to_json(self) -> Dict[str, Any]:
        return {
            "quick": self.quick,
            "seconds": round(self.seconds, 3),
            "points": len(self.results),
            "evaluations": sum(r.evaluations for r in self.results),
            "totals": {c: sum(getattr(r, c) for r in self.results) for c in COUNTS},
            "errors": sum(1 for r in self.results if r.error),
            "missing_grids": self.missing_grids,
            "skipped_families": self.skipped_families,
            "failures": self.failures,
            "results": [r.to_json() for r in self.results],
        }


def registered_models() -> Dict[str, List[str]]:
    """The model names of each swept family, as the registry lists them."""
    types = _core.registry_types()
    out = {}
    for f in FAMILIES:
        names = list(types.get(f.registry_key, []))
        if not names and f.fallback_names is not None:
            names = f.fallback_names()
        out[f.registry_key] = names
    return out


def sweep(quick: bool = False, models: Optional[Sequence[str]] = None, render: bool = True, spp: Optional[int] = None,
          seed: int = 7, progress: Optional[Callable[[str], None]] = None) -> Report:
    """Run the sweep (``models``: only these types). Returns a :class:`Report`."""
    t0 = time.perf_counter()
    rng = np.random.default_rng(seed)
    spp = spp or (2 if quick else 8)
    results: List[PointResult] = []
    missing: List[str] = []
    skipped: List[str] = []
    registered = registered_models()
    known = {n for v in registered.values() for n in v}
    for m in models or ():
        if m not in known:
            raise pellucid.Error(f"models: '{m}' is not a registered model (known: {', '.join(sorted(known))})")
    for fam in FAMILIES:
        names = registered[fam.registry_key]
        if not names:
            skipped.append(fam.registry_key)
            continue
        for name in names:
            if models and name not in models:
                continue
            grid = GRIDS.get(name)
            points = grid(quick) if grid else [{}]
            if grid is None:
                missing.append(name)
            if progress:
                progress(f"{name}: {len(points)} points")
            for i, params in enumerate(points):
                desc = {"type": name, **params}
                if fam.sweep_point is not None:
                    res = PointResult(fam.registry_key, name, params, "eval")
                    t = time.perf_counter()
                    try:
                        fam.sweep_point(res, desc, quick, rng)
                    except Exception as e:  # noqa: BLE001 - any failure of a grid point is a finding
                        res.error = f"{type(e).__name__}: {e}"
                    res.seconds = time.perf_counter() - t
                    results.append(res)
                if fam.probe is not None:
                    res = PointResult(fam.registry_key, name, params, "eval")
                    t = time.perf_counter()
                    try:
                        for mode in fam.modes:
                            _sweep_probe(res, fam.probe(desc, mode), mode, params, quick, rng)
                    except Exception as e:  # noqa: BLE001 - any failure of a grid point is a finding
                        res.error = f"{type(e).__name__}: {e}"
                    res.seconds = time.perf_counter() - t
                    results.append(res)
                if fam.scene is not None and render:
                    # Quick grids render every other point; the full grid renders every point in
                    # every variant.
                    for variant in fam.variants(quick) if not quick or i % 2 == 0 else []:
                        res = PointResult(fam.registry_key, name, params, f"render:{variant}")
                        t = time.perf_counter()
                        try:
                            _render_point(res, fam, desc, variant, spp, seed + i)
                        except Exception as e:  # noqa: BLE001
                            res.error = f"{type(e).__name__}: {e}"
                        res.seconds = time.perf_counter() - t
                        results.append(res)
    return Report(results, missing, skipped, time.perf_counter() - t0, quick)


def _params_text(p: Params) -> str:
    return ", ".join(f"{k}={v}" for k, v in p.items()) or "(defaults)"


def format_table(report: Report, verbose: bool = False) -> str:
    """Per model: points, evaluations and the four counts; then every point with a non-zero count
    (every point with ``verbose``)."""
    lines = []
    hdr = f"{'model':<18} {'kind':<8} {'points':>6} {'evaluations':>12} {'NaN':>6} {'Inf':>6} {'neg':>6} {'invalid':>8} {'errors':>6}"
    lines.append(hdr)
    lines.append("-" * len(hdr))
    by: Dict[Tuple[str, str], List[PointResult]] = {}
    for r in report.results:
        by.setdefault((r.model, r.kind.split(":")[0]), []).append(r)
    for (model, kind), rs in by.items():
        lines.append(f"{model:<18} {kind:<8} {len(rs):>6} {sum(r.evaluations for r in rs):>12} "
                     f"{sum(r.nan for r in rs):>6} {sum(r.inf for r in rs):>6} {sum(r.negative for r in rs):>6} "
                     f"{sum(r.invalid for r in rs):>8} {sum(1 for r in rs if r.error):>6}")
    lines.append("-" * len(hdr))
    tot = report.to_json()
    lines.append(f"{'total':<18} {'':<8} {tot['points']:>6} {tot['evaluations']:>12} {tot['totals']['nan']:>6} "
                 f"{tot['totals']['inf']:>6} {tot['totals']['negative']:>6} {tot['totals']['invalid']:>8} "
                 f"{tot['errors']:>6}")
    shown = [r for r in report.results if verbose or r.failures]
    if shown:
        lines.append("")
        lines.append("points with findings:" if not verbose else "every point:")
        for r in shown:
            lines.append(f"  {r.model} [{r.kind}] {_params_text(r.params)}: NaN {r.nan}, Inf {r.inf}, "
                         f"negative {r.negative}, invalid {r.invalid}" + (f", error: {r.error}" if r.error else ""))
            if r.example:
                lines.append(f"    first: {json.dumps(_jsonable(r.example))}")
    for m in report.missing_grids:
        lines.append(f"{m}: no parameter grid (swept at its defaults): add it to GRIDS in pellucid/stability.py")
    for f in report.skipped_families:
        lines.append(f"family '{f}': nothing registered, skipped")
    lines.append(f"{'quick' if report.quick else 'full'} grid, {report.seconds:.1f} s: "
                 + ("no NaN, Inf, negative or invalid values" if report.failures == 0
                    else f"{report.failures} findings"))
    return "\n".join(lines)


def build_parser(p: Optional[argparse.ArgumentParser] = None) -> argparse.ArgumentParser:
    p = p or argparse.ArgumentParser(prog="pellucid stability", description=__doc__.splitlines()[0])
    p.add_argument("--quick", action="store_true", help="the reduced grid (CI)")
    p.add_argument("--json", default=None, metavar="FILE", help="also write the report as JSON")
    p.add_argument("--models", default=None, metavar="A,B", help="only these model types (comma-separated)")
    p.add_argument("--no-render", action="store_true", help="evaluate only; no renders")
    p.add_argument("--spp", type=int, default=None, help="samples per pixel of the renders (default 8; quick 2)")
    p.add_argument("--seed", type=int, default=7, help="seed of the random directions and renders")
    p.add_argument("-v", "--verbose", action="store_true", help="list every point, not only those with findings")
    return p


def main(args: argparse.Namespace) -> int:
    """Run the sweep of the parsed arguments; print the table; exit status 1 if any count is non-zero."""
    models = [m for m in args.models.split(",") if m] if args.models else None
    report = sweep(quick=args.quick, models=models, render=not args.no_render, spp=args.spp, seed=args.seed,
                   progress=lambda s: print(s, file=sys.stderr) if args.verbose else None)
    print(format_table(report, args.verbose))
    if args.json:
        with open(args.json, "w", encoding="utf-8") as f:
            json.dump(_jsonable(report.to_json()), f, indent=1)
    return 1 if report.failures else 0
