"""``pellucid.bsdf``: evaluate one material's BxDF from Python, vectorised over numpy arrays.

A testing and plotting surface (the loops run in C++ with the GIL released)::

    import numpy as np, pellucid
    b = pellucid.bsdf({"type": "rough_conductor", "material": "Au", "alpha": 0.2})
    wo = np.array([[0.0, 0.6, 0.8]], dtype=np.float32)
    wi, weight, pdf, lobe = b.sample(wo, np.random.rand(1, 3))
    b.eval(wo, wi)            # f·|cos θi|, (N, 3)
    b.albedo(wo, 4096)        # directional albedo, (N, 3)

Directions are (N, 3) arrays in the LOCAL shading frame (z = normal, both pointing away from the
surface, ``wo`` toward the viewer); they are normalised first. Conventions: ``eval`` returns
f·|cos θi|, ``pdf`` is per solid angle, ``sample`` returns weight = f·|cos θi|/pdf; delta lobes
appear only in ``sample`` (their eval/pdf are 0). Failed samples have pdf 0, weight 0, lobe 0.
The material dict uses the scene format (docs/scene-format.md, ``## materials``).
"""
from __future__ import annotations

from typing import Any, Dict, NamedTuple

import numpy as _np

from . import _core



def __getattr__(name: str) -> Any:
    # ``FLAGS``: lobe flag bits of ``BSDFSample.lobe`` and ``BSDF.flags`` (bxdf/bxdf_types.h), read
    # from _core on first use so that importing pellucid never depends on this attribute.
    if name == "FLAGS":
        return dict(_core.BXDF_FLAGS)
    raise AttributeError(name)


class BSDFSample(NamedTuple):
    wi: _np.ndarray      #: (N, 3) sampled directions (0 where sampling failed)
    weight: _np.ndarray  #: (N, 3) f·|cos θi|/pdf
    pdf: _np.ndarray     #: (N,) solid-angle pdf, or the discrete lobe probability for delta lobes
    lobe: _np.ndarray    #: (N,) uint32 lobe flags (see FLAGS)


def _rows(a: Any) -> _np.ndarray:
    return _np.atleast_2d(_np.asarray(a, dtype=_np.float32))


class BSDF:
    """One material's BxDF at a default hit point. Build with :func:`pellucid.bsdf`."""

    def __init__(self, desc: Dict[str, Any], mode: str = "radiance") -> None:
        if not isinstance(desc, dict):
            raise _core.Error(f"<dict>: expected a material dict, got {type(desc).__name__}")
        self._p = _core.BSDFProbe(desc, mode)

    def eval(self, wo: Any, wi: Any) -> _np.ndarray:
        """f(wo, wi)·|cos θi| per row, float32 (N, 3)."""
        return self._p.eval(_rows(wo), _rows(wi))

    def pdf(self, wo: Any, wi: Any) -> _np.ndarray:
        """Solid-angle density of sampling wi from wo, float32 (N,)."""
        return self._p.pdf(_rows(wo), _rows(wi))

    def sample(self, wo: Any, u: Any) -> BSDFSample:
        """Sample wi for each row of wo; u is (N, 3) uniform numbers (u_lobe, u1, u2)."""
        return BSDFSample(*self._p.sample(_rows(wo), _rows(u)))

    def albedo(self, wo: Any, n_samples: int = 4096, seed: int = 1, threads: int = 0) -> _np.ndarray:
        """Directional albedo per row of wo: the mean of ``n_samples`` sample weights (delta lobes
        included, failures count 0), float32 (N, 3). Fixed seed; independent of ``threads``."""
        return self._p.albedo(_rows(wo), int(n_samples), int(seed), int(threads))

    def benchmark(self, n: int = 200_000) -> Dict[str, float]:
        """Single-thread C++ timing: ``{"ns_eval", "ns_pdf", "ns_sample"}`` nanoseconds per call,
        each averaged over ``n`` calls on pre-generated random inputs (no Python in the loop)."""
        return self._p.benchmark(int(n))

    @property
    def flags(self) -> int:
        """Union of the lobe flags this BxDF can produce (see FLAGS)."""
        return self._p.flags

    def __repr__(self) -> str:
        return repr(self._p)


def bsdf(desc: Dict[str, Any], mode: str = "radiance") -> BSDF:
    """Build the BxDF of one material description, e.g. ``{"type": "plastic", "int_ior": 1.5}``.

    ``mode`` is ``"radiance"`` (camera paths; refraction scaled by 1/η²) or ``"importance"``.
    Raises pellucid.Error naming the parameter (``<dict>: alpha: value -0.1 must be >= 0``).
    """
    return BSDF(desc, mode)
