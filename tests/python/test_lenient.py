"""--lenient / lenient=True: unsupported Mitsuba XML elements become logged warnings, not errors."""
from __future__ import annotations

import logging
import subprocess
import sys

import numpy as np
import pytest

import pellucid

from conftest import ROOT

CLI = ROOT / "build" / "py" / "cpp" / "pellucid-render"

XML = """<scene version="3.0.0">
  <sensor type="perspective">
    <float name="fov" value="40"/>
    <transform name="to_world"><lookat origin="0, 0, 4" target="0, 0, 0" up="0, 1, 0"/></transform>
    <film type="hdrfilm"><integer name="width" value="16"/><integer name="height" value="12"/></film>
    <sampler type="independent"><integer name="sample_count" value="2"/></sampler>
  </sensor>
  <bsdf type="hair" id="fur"/>
  <shape type="sphere">
    <float name="wobble" value="1"/>
    <bsdf type="diffuse"/>
  </shape>
  <emitter type="constant"><rgb name="radiance" value="1"/></emitter>
</scene>
"""


@pytest.fixture()
def xml_path(tmp_path):
    p = tmp_path / "scene.xml"
    p.write_text(XML)
    return p


def test_strict_mode_names_element_and_line(xml_path) -> None:
    with pytest.raises(pellucid.Error, match=r"scene\.xml:8: unsupported bsdf plugin 'hair'"):
        pellucid.load_file(xml_path)


def test_lenient_mode_warns_and_renders(xml_path, caplog) -> None:
    with caplog.at_level(logging.WARNING, logger="pellucid"):
        scene = pellucid.load_file(xml_path, lenient=True)
    msgs = [r.getMessage() for r in caplog.records if r.name == "pellucid"]
    assert any(m.endswith("scene.xml:8: unsupported bsdf plugin 'hair' (skipped)") for m in msgs), msgs
    assert any(m.endswith("scene.xml:10: unsupported parameter 'wobble' of shape plugin 'sphere' (skipped)")
               for m in msgs), msgs
    img = pellucid.render(scene, spp=1)
    assert img.shape == (12, 16, 3) and img.mean() > 0.1
    # Lenient mode does not excuse broken input: malformed XML is still an error with a line.
    xml_path.write_text("<scene version='3.0.0'>\n<shape type='sphere'>\n</scene>\n")
    with pytest.raises(pellucid.Error, match=r"scene\.xml:\d+: malformed XML"):
        pellucid.load_file(xml_path, lenient=True)


def _py(*args: str) -> subprocess.CompletedProcess:
    return subprocess.run([sys.executable, "-m", "pellucid", *args], capture_output=True, text=True, timeout=120)


def _cpp(*args: str) -> subprocess.CompletedProcess:
    return subprocess.run([str(CLI), *args], capture_output=True, text=True, timeout=120)


@pytest.mark.skipif(not CLI.exists(), reason="pellucid-render is built by `make`")
@pytest.mark.parametrize("run", [_py, _cpp])
def test_both_clis_take_lenient(run, xml_path, tmp_path) -> None:
    out = tmp_path / "out.exr"
    strict = run("render", str(xml_path), "-o", str(out), "-q")
    assert strict.returncode == 1 and "scene.xml:8: unsupported bsdf plugin 'hair'" in strict.stderr
    assert not out.exists()
    lenient = run("render", str(xml_path), "-o", str(out), "-q", "--lenient")
    assert lenient.returncode == 0, lenient.stderr
    assert "scene.xml:8: unsupported bsdf plugin 'hair' (skipped)" in lenient.stderr
    assert "scene.xml:10: unsupported parameter 'wobble'" in lenient.stderr
    img = pellucid.read_image(out)
    assert img.shape == (12, 16, 3) and np.isfinite(img).all()
