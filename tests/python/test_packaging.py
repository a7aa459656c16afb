"""What the installed package carries: the pellucid-render console script (running the packaged C++
executable), the LICENSE with Apache-2.0 licence metadata, and a pyproject that builds out of the
source tree without the C++ tests (make turns them on for its own build in build/py)."""
from __future__ import annotations

import importlib.metadata
import pathlib
import subprocess
import sys

import numpy as np
import pytest

import pellucid
from pellucid import _render_exe

from conftest import ROOT

SCRIPT = pathlib.Path(sys.executable).parent / "pellucid-render"


def test_console_script_runs_the_packaged_executable(tiny_scene_path, tmp_path) -> None:
    exe = _render_exe.executable()
    assert exe is not None and exe.name == "pellucid-render"
    assert SCRIPT.is_file(), "pellucid-render is not installed next to this interpreter"
    out = tmp_path / "box.exr"
    r = subprocess.run([str(SCRIPT), str(tiny_scene_path), "-o", str(out), "--spp", "2", "--seed", "3", "-q"],
                       capture_output=True, text=True, timeout=120)
    assert r.returncode == 0, r.stderr
    img = pellucid.read_image(out)
    assert img.shape == (24, 32, 3) and np.isfinite(img).all() and img.mean() > 0
    # Same scene, seed and spp through Python: the same image.
    same = pellucid.render(pellucid.load_file(tiny_scene_path), spp=2, seed=3)
    assert np.array_equal(img, same)


def test_console_script_passes_arguments_and_exit_status_through() -> None:
    r = subprocess.run([str(SCRIPT), str(ROOT / "scenes" / "cornell_box.json"), "-o", "x.exr", "--no-such-flag"],
                       capture_output=True, text=True, timeout=60)
    assert r.returncode == 2
    assert "pellucid-render: error:" in r.stderr and "--no-such-flag" in r.stderr


def test_licence_file_and_metadata() -> None:
    assert (ROOT / "LICENSE").read_text().lstrip().startswith("Apache License\n                           Version 2.0")
    md = importlib.metadata.metadata("pellucid")
    assert md["License-Expression"] == "Apache-2.0"
    assert md.get_all("License-File") == ["LICENSE"]
    files = [str(f) for f in importlib.metadata.files("pellucid") or []]
    assert any(f.endswith("licenses/LICENSE") for f in files), files
    # Every source file's SPDX line names the same licence.
    spdx = {line.split("SPDX-License-Identifier:", 1)[1].strip()
            for p in (ROOT / "cpp").rglob("*.[ch]*") for line in p.read_text().splitlines()[:12]
            if "SPDX-License-Identifier:" in line}
    assert spdx == {"Apache-2.0"}


def test_pyproject_builds_out_of_tree_without_the_cpp_tests() -> None:
    tomllib = pytest.importorskip("tomllib")
    cfg = tomllib.loads((ROOT / "pyproject.toml").read_text())
    skb = cfg["tool"]["scikit-build"]
    assert "build-dir" not in skb, "a fixed build-dir puts pip's build inside the source tree"
    assert skb["cmake"]["define"]["PELLUCID_BUILD_TESTS"] == "OFF"
    assert "-Ccmake.define.PELLUCID_BUILD_TESTS=ON" in (ROOT / "Makefile").read_text()
    assert cfg["project"]["scripts"]["pellucid-render"] == "pellucid._render_exe:main"
    assert set(cfg["project"]["optional-dependencies"]) >= {"charts", "peers"}
