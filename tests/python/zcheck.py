"""The per-pixel z-test of a render against a reference render, shared by the Mitsuba comparisons
(tests/python/test_mitsuba_scenes.py and test_parity_matrix.py).

For each pixel channel, z = |a - b| / sqrt(var_a + var_b + floor), with var_a and var_b the
variances of the two means. The floor, (1e-5 max(|a|, |b|))^2 + 1e-12, covers pixels that see only a
constant emitter: both variances are zero there and the means differ only by float summation order.
The critical |z| is the two-sided α Šidák-corrected over the n channels of the image:
P(|Z| > z_c) = 1 - (1 - α)^(1/n) (pellucid.bench.critical_z).
"""
from __future__ import annotations

from typing import Tuple

import numpy as np

from pellucid.bench import critical_z


def z_scores(a: np.ndarray, va: np.ndarray, b: np.ndarray, vb: np.ndarray) -> np.ndarray:
    """|a - b| / sqrt(va + vb + floor) per channel (the floor as in the module docstring)."""
    a, va, b, vb = (np.asarray(x, np.float64) for x in (a, va, b, vb))
    floor = (1e-5 * np.maximum(np.abs(a), np.abs(b))) ** 2 + 1e-12
    return np.abs(a - b) / np.sqrt(va + vb + floor)


def z_pass_fraction(a, va, b, vb, alpha: float = 0.01) -> Tuple[float, float]:
    """(fraction of channels with |z| <= z_c, z_c) for the Šidák-corrected critical z_c at alpha."""
    zc = critical_z(np.asarray(a).size, alpha)
    return float(np.mean(z_scores(a, va, b, vb) <= zc)), zc


def half_rounding_variance(x: np.ndarray) -> np.ndarray:
    """The variance that storing x as float16 adds: rounding to nearest is an error uniform over one
    float16 spacing s, variance s^2 / 12."""
    s = np.spacing(np.abs(np.asarray(x, np.float32)).astype(np.float16)).astype(np.float64)
    return s * s / 12.0
