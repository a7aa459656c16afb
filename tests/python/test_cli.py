"""Both command lines write files, agree for the same seed, and fail cleanly on bad input."""
from __future__ import annotations

import subprocess
import sys

import numpy as np
import pytest

import pellucid

from conftest import ROOT

CLI = ROOT / "build" / "py" / "cpp" / "pellucid-render"


def _py(*args: str) -> subprocess.CompletedProcess:
    return subprocess.run([sys.executable, "-m", "pellucid", *args], capture_output=True, text=True, timeout=120)


def _cpp(*args: str) -> subprocess.CompletedProcess:
    return subprocess.run([str(CLI), *args], capture_output=True, text=True, timeout=120)


@pytest.mark.skipif(not CLI.exists(), reason="pellucid-render is built by `make`")
def test_both_clis_write_the_same_image(tmp_path, tiny_scene_path) -> None:
    a, b = tmp_path / "py.exr", tmp_path / "cpp.exr"
    r1 = _py("render", str(tiny_scene_path), "-o", str(a), "--spp", "3", "--seed", "5")
    r2 = _cpp("render", str(tiny_scene_path), "-o", str(b), "--spp", "3", "--seed", "5")
    assert r1.returncode == 0, r1.stderr
    assert r2.returncode == 0, r2.stderr
    ia, ib = pellucid.read_image(str(a)), pellucid.read_image(str(b))
    assert np.array_equal(ia, ib)
    # Quiet when stderr is not a terminal: no progress bar escape sequences.
    assert "\r" not in r1.stderr and "\r" not in r2.stderr


@pytest.mark.skipif(not CLI.exists(), reason="pellucid-render is built by `make`")
@pytest.mark.parametrize("run", [_py, _cpp])
def test_clis_fail_cleanly(run, tmp_path, tiny_scene_path) -> None:
    out = str(tmp_path / "x.exr")
    missing = run("render", str(tmp_path / "missing.json"), "-o", out)
    assert missing.returncode != 0 and "cannot open scene file" in missing.stderr
    bad = tmp_path / "bad.json"
    bad.write_text("{ not json")
    r = run("render", str(bad), "-o", out)
    assert r.returncode != 0 and "malformed JSON" in r.stderr
    r = run("render", str(tiny_scene_path), "-o", out, "--spp", "0")
    assert r.returncode != 0 and "--spp" in r.stderr
    bad.write_text('{"film": {"width": 0}}')
    r = run("render", str(bad), "-o", out)
    assert r.returncode != 0 and "film.width: resolution 0" in r.stderr
    # Missing folders are created; a folder that cannot be (a file is in the way) is an error.
    r = run("render", str(tiny_scene_path), "-o", str(tmp_path / "no_dir" / "x.exr"), "--spp", "1")
    assert r.returncode == 0 and (tmp_path / "no_dir" / "x.exr").exists(), r.stderr
    r = run("render", str(tiny_scene_path), "-o", str(bad / "x.exr"), "--spp", "1")
    assert r.returncode != 0 and "is not a directory" in r.stderr
