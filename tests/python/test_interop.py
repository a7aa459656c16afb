"""Mitsuba 3 XML scenes and mesh files load through the same IR as JSON."""
from __future__ import annotations

import numpy as np
import pytest

import pellucid


def test_mitsuba_xml_scene_renders(root) -> None:
    scene = pellucid.load_file(root / "tests" / "data" / "mitsuba" / "spheres.xml")
    img = pellucid.render(scene, spp=2)
    assert img.ndim == 3 and np.isfinite(img).all() and img.mean() > 0


def test_bad_xml_names_file_and_line(tmp_path) -> None:
    bad = tmp_path / "bad.xml"
    bad.write_text('<scene version="3.0.0">\n  <shape type="sphere">\n    <bsdf type="hair"/>\n  </shape>\n</scene>\n')
    with pytest.raises(pellucid.Error, match=r"bad\.xml:3: unsupported bsdf plugin 'hair'"):
        pellucid.load_file(bad)


def test_obj_mesh_and_missing_file(tmp_path) -> None:
    (tmp_path / "q.obj").write_text("v -1 -1 0\nv 1 -1 0\nv 1 1 0\nv -1 1 0\nvt 0 0\nvt 1 0\nvt 1 1\nvt 0 1\nf 1/1 2/2 3/3 4/4\n")
    d = {"camera": {"type": "perspective", "fov": 40,
                    "to_world": [{"look_at": {"origin": [0, 0, 4], "target": [0, 0, 0], "up": [0, 1, 0]}}]},
         "film": {"width": 16, "height": 16},
         "shapes": [{"type": "obj", "filename": "q.obj"}],
         "lights": [{"type": "constant", "radiance": 1.0}]}
    img = pellucid.render(pellucid.load_dict(d, base_dir=tmp_path), spp=2)
    assert img[8, 8].mean() > 0.1
    d["shapes"][0] = {"type": "ply", "filename": "missing.ply"}
    with pytest.raises(pellucid.Error, match=r"shapes\[0\]\.filename: .*missing\.ply"):
        pellucid.load_dict(d, base_dir=tmp_path)
