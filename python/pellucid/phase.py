"""``pellucid.phase``: evaluate and sample a phase function from Python, vectorised over numpy arrays.

A testing and plotting surface (the loops run in C++ with the GIL released)::

    import numpy as np, pellucid
    p = pellucid.phase("hg", g=0.7)
    wo = np.array([[0.0, 0.0, 1.0]], dtype=np.float32)
    s = p.sample(wo, np.random.rand(1, 2))
    p.eval(wo, s.wi)          # p(wo, wi) in 1/sr, (N,)

Directions are (N, 3) arrays in any frame, both pointing away from the scattering point (``wo``
toward the previous vertex); they are normalised first. The scattering angle θ has
cos θ = −dot(wo, wi), so g > 0 scatters forward (wi near −wo). ``eval`` equals ``pdf`` (sampling is
exact) and ``sample`` returns weight = eval/pdf = 1; hg with |g| = 1 is a delta: eval and pdf are
0 and samples have ``delta`` True with pdf 1. Conventions: cpp/pellucid/medium/phase.h; the scene
format of phase functions: docs/media.md.
"""
from __future__ import annotations

from typing import Any, NamedTuple

import numpy as _np

from . import _core


class PhaseSample(NamedTuple):
    wi: _np.ndarray      #: (N, 3) sampled directions
    weight: _np.ndarray  #: (N,) eval/pdf (1)
    pdf: _np.ndarray     #: (N,) solid-angle pdf, or 1 for the delta
    delta: _np.ndarray   #: (N,) bool, True for the delta of |g| = 1


def _rows(a: Any, width: int) -> _np.ndarray:
    r = _np.asarray(a, dtype=_np.float32)
    return r.reshape(1, width) if r.ndim == 1 else r


class Phase:
    """One phase function. Build with :func:`pellucid.phase`."""

    def __init__(self, type: str = "isotropic", **params: Any) -> None:
        self._p = _core.PhaseProbe(dict(type=type, **params))

    def eval(self, wo: Any, wi: Any) -> _np.ndarray:
        """p(wo, wi) in 1/sr per row, float32 (N,)."""
        return self._p.eval(_rows(wo, 3), _rows(wi, 3))

    def pdf(self, wo: Any, wi: Any) -> _np.ndarray:
        """Solid-angle density of sampling wi from wo, float32 (N,)."""
        return self._p.pdf(_rows(wo, 3), _rows(wi, 3))

    def sample(self, wo: Any, u: Any) -> PhaseSample:
        """Sample wi for each row of wo; u is (N, 2) uniform numbers in [0, 1)."""
        return PhaseSample(*self._p.sample(_rows(wo, 3), _rows(u, 2)))

    def __repr__(self) -> str:
        return repr(self._p)


def phase(type: str = "isotropic", **params: Any) -> Phase:
    """A phase function: ``phase("hg", g=0.7)`` or ``phase("isotropic")``.

    Raises pellucid.Error naming the parameter (``<dict>: g: value 1.5 is out of range [-1, 1] ...``).
    """
    return Phase(type, **params)
