"""``pellucid.bssrdf``: diffusion profiles of subsurface scattering and their random-walk ground truth.

A testing and plotting surface (the loops run in C++ with the GIL released)::

    import numpy as np, pellucid
    p = pellucid.bssrdf.profile("better_dipole", sigma_a=0.01, sigma_s=1.0, g=0.0, eta=1.33)
    r = np.linspace(0, 10, 101)
    p.eval(r)                 # R(r) in 1/length², exitance per unit area per unit entered flux
    p.total                   # ∫ 2πr R(r) dr, the total diffuse reflectance
    p.sample(np.random.rand(1000))   # radii with density p.pdf(r) per unit area, all ≤ p.r_max
    sa, ss = pellucid.bssrdf.from_diffuse("dipole", albedo=0.8, mfp=0.1, g=0.0, eta=1.33)
    walk = pellucid.bssrdf.searchlight(0.01, 1.0, eta=1.33, photons=100000, r_edges=[0, 1, 2, 4])
    walk["reflectance"], walk["exitance"]

Models: ``"dipole"`` (Jensen et al. 2001) and ``"better_dipole"`` (d'Eon 2012). Units: σ in 1/length,
r in length. Conventions: cpp/pellucid/bssrdf/profile.h and searchlight.h; accuracy:
docs/subsurface.md.
"""
from __future__ import annotations

import math as _math
from typing import Any, Dict, Optional, Sequence, Tuple

import numpy as _np

from . import _core

#: The diffusion models.
MODELS: Tuple[str, ...] = ("dipole", "better_dipole")


class Profile:
    """One colour channel's radial profile R(r) of a semi-infinite medium. Build with :func:`profile`."""

    def __init__(self, model: str, sigma_a: float, sigma_s: float, g: float = 0.0, eta: float = 1.0) -> None:
        self._p = _core.BSSRDFProfile(model, float(sigma_a), float(sigma_s), float(g), float(eta))

    def eval(self, r: Any) -> _np.ndarray:
        """R(r) ≥ 0 in 1/length², float32, the shape of ``r``."""
        return self._p.eval(_np.asarray(r, dtype=_np.float32))

    def pdf(self, r: Any) -> _np.ndarray:
        """Density of :meth:`sample` per unit area at radius r (the radial density is 2πr·pdf)."""
        return self._p.pdf(_np.asarray(r, dtype=_np.float32))

    def sample(self, u: Any) -> _np.ndarray:
        """Radii in [0, r_max] for u in [0, 1), by the exact inverse CDF of 2πr R(r) truncated at r_max."""
        return self._p.sample(_np.asarray(u, dtype=_np.float32))

    @property
    def model(self) -> str:
        return self._p.model

    @property
    def total(self) -> float:
        """∫0^∞ 2πr R(r) dr (closed form): the total diffuse reflectance."""
        return self._p.total

    @property
    def r_max(self) -> float:
        """The radius holding 99.9 % of the profile's mass; samples never exceed it."""
        return self._p.r_max

    @property
    def diffusion_length(self) -> float:
        """1/σtr of the model (inf when σa = 0)."""
        return self._p.diffusion_length

    @property
    def mean_free_path(self) -> float:
        """1/σ't = 1/(σa + σs(1 − g))."""
        return self._p.mean_free_path

    @property
    def reduced_albedo(self) -> float:
        """α' = σ's/σ't."""
        return self._p.reduced_albedo

    def __repr__(self) -> str:
        return (f"Profile(model={self.model!r}, total={self.total:.6g}, mean_free_path={self.mean_free_path:.6g}, "
                f"diffusion_length={self.diffusion_length:.6g})")


def profile(model: str, sigma_a: float, sigma_s: float, g: float = 0.0, eta: float = 1.0) -> Profile:
    """The ``model`` (``"dipole"`` or ``"better_dipole"``) profile of a medium with absorption ``sigma_a``,
    scattering ``sigma_s`` (1/length), HG asymmetry ``g`` and relative index ``eta``."""
    return Profile(model, sigma_a, sigma_s, g, eta)


def from_diffuse(model: str, albedo: float, mfp: float, g: float = 0.0, eta: float = 1.0) -> Tuple[float, float]:
    """``(sigma_a, sigma_s)`` whose ``model`` profile has total ``albedo`` ∈ [0, 1) and mean free path
    1/σ't = ``mfp``. Raises pellucid.Error for values out of range."""
    return _core.bssrdf_from_diffuse(model, float(albedo), float(mfp), float(g), float(eta))


def total(model: str, reduced_albedo: Any, eta: float = 1.0) -> _np.ndarray:
    """The profile's total for reduced albedos α' (it does not depend on the mean free path)."""
    a = _np.asarray(reduced_albedo, dtype=float)
    return _np.vectorize(lambda x: _core.bssrdf_total(model, float(x), float(eta)))(a)


def fresnel_moment(i: int, eta: float, internal: bool = True) -> float:
    """C_i = ∫0^1 F(μ) μ^i dμ of a boundary with relative index ``eta`` (``internal``: light arriving
    from inside, total internal reflection included)."""
    return _core.fresnel_moment(int(i), float(eta), bool(internal))


def exit_lobe_norm(eta: float) -> float:
    """c = 1 − 2·C1(eta, external): (1 − F(cos θ))/(c π) integrates to 1 against cos θ dω."""
    return _core.exit_lobe_norm(float(eta))


def searchlight(sigma_a: float, sigma_s: float, g: float = 0.0, eta: float = 1.0, thickness: float = _math.inf,
                photons: int = 100000, seed: int = 1, r_edges: Optional[Sequence[float]] = None,
                max_collisions: int = 10_000_000, threads: int = 0) -> Dict[str, Any]:
    """The random-walk ground truth: a slab of ``thickness`` (inf: a half-space) of (σa, σs, g) under a
    smooth boundary of relative index ``eta``, lit by a normal searchlight at r = 0, normalised per
    entered photon. Returns a dict: ``reflectance``, ``transmittance``, ``absorbed``, ``lost``,
    ``reflectance_single`` (after exactly one scattering), ``mean_collisions``, and per bin of
    ``r_edges``: ``exitance`` and ``exitance_single`` (per unit area per photon), ``counts``,
    ``counts_single``; ``chunk_reflectance`` per chunk of 4096 photons. Deterministic for a seed
    at any thread count."""
    edges = [float(x) for x in (r_edges if r_edges is not None else [])]
    return _core.bssrdf_searchlight(float(sigma_a), float(sigma_s), float(g), float(eta), float(thickness), int(photons),
                                    int(seed), edges, int(max_collisions), int(threads))


__all__ = ["MODELS", "Profile", "exit_lobe_norm", "fresnel_moment", "from_diffuse", "profile", "searchlight", "total"]
