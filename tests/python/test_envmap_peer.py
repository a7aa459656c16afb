"""The envmap light against Mitsuba 3 (optional peer): bench/envmap_check.py renders a diffuse
sphere under a rotated, asymmetric, texel-checkered lat-long map with both renderers and requires
every pixel channel to pass a z-test at α = 0.01 (Šidák over all channels). A 1° rotation of the
map, a half-texel shift or a mirrored map fails thousands of channels. Skips without Mitsuba."""
from __future__ import annotations

import pathlib
import subprocess
import sys

import pytest

ROOT = pathlib.Path(__file__).resolve().parents[2]


def test_envmap_matches_mitsuba() -> None:
    r = subprocess.run([sys.executable, str(ROOT / "bench" / "envmap_check.py"), "--spp", "256"],
                       capture_output=True, text=True)
    if r.returncode == 77:
        pytest.skip(r.stdout.strip())
    assert r.returncode == 0, r.stdout + r.stderr
