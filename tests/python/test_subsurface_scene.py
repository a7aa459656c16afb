"""scenes/subsurface.json (the scene of bench/subsurface_charts.py): the render log states auto's choice
for each object with its reason, the torus mesh is its generator's output, and every model renders
the scene without invalid samples."""
from __future__ import annotations

import importlib.util
import json
import logging
import re

import numpy as np
import pytest

import pellucid
from conftest import ROOT

SCENE = ROOT / "scenes" / "subsurface.json"
# shape index -> (object, auto's model, the rule's word, the object's mean chord length 4V/A)
EXPECTED = {
    1: ("torus", "better_dipole", "thick", 2 * 0.2),            # 4V/A = 2r for a torus
    2: ("slab", "random_walk", "thin", 4 * 0.02 / 2.08),        # 1 x 1 x 0.02 box
    3: ("small sphere", "random_walk", "thin", 4 * 0.15 / 3),   # 4r/3
    4: ("large sphere", "better_dipole", "thick", 4 * 0.8 / 3),
}
LINE = re.compile(r"shapes\[(\d+)\] \(material 'wax'\): subsurface model (\w+) \((\w+): (.*)\)$")
NUM = r"([0-9.eE+-]+)"


def _scene(**film) -> dict:
    d = json.loads(SCENE.read_text())
    d["film"].update(film)
    return d


def _load_logged(d: dict, caplog) -> tuple:
    caplog.clear()
    with caplog.at_level(logging.INFO, logger="pellucid"):
        sc = pellucid.load_dict(d, base_dir=SCENE.parent)
    return sc, [r for r in caplog.records if r.name == "pellucid"]


def test_the_log_states_autos_choice_and_reason_per_object(caplog) -> None:
    _, records = _load_logged(_scene(), caplog)
    assert not [r.getMessage() for r in records if r.levelno >= logging.WARNING]  # closed meshes, sane lengths
    seen = {}
    for r in records:
        m = LINE.search(r.getMessage())
        if m:
            seen[int(m.group(1))] = m.groups()[1:]
    assert sorted(seen) == sorted(EXPECTED), seen
    for shape, (obj, model, rule, thickness) in EXPECTED.items():
        got_model, got_rule, reason = seen[shape]
        assert (got_model, got_rule) == (model, rule), f"{obj}: {seen[shape]}"
        # The reason gives the numbers it compared: thickness 4V/A against 4 diffusion lengths.
        m = re.search(rf"thickness (?:4V/A = )?{NUM} (<|>=) {NUM} diffusion lengths \({NUM}\)", reason)
        assert m, f"{obj}: {reason}"
        t, op, ratio, ld = float(m.group(1)), m.group(2), float(m.group(3)), float(m.group(4))
        assert t == pytest.approx(thickness, rel=0.01), f"{obj}: 4V/A {t}, expected {thickness}"
        assert (t < ratio * ld) == (op == "<") == (rule == "thin"), f"{obj}: {reason}"
        # Margins of at least 25 % either way, so the choice does not hang on rounding.
        assert max(t, ratio * ld) / min(t, ratio * ld) > 1.25, f"{obj}: {reason}"


def test_the_torus_is_its_generators_output() -> None:
    spec = importlib.util.spec_from_file_location("make_torus", ROOT / "scenes" / "meshes" / "make_torus.py")
    mod = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(mod)
    text = mod.torus_obj(1.0, 0.4, 64, 32)
    assert (ROOT / "scenes" / "meshes" / "torus.obj").read_text() == text
    assert sum(line.startswith("f ") for line in text.splitlines()) == 4096


@pytest.mark.parametrize("model", ["auto", "dipole", "better_dipole", "random_walk"])
def test_every_model_renders_the_scene(model: str, caplog) -> None:
    d = _scene(width=32, height=24)
    d["materials"]["wax"]["model"] = model
    sc, records = _load_logged(d, caplog)
    img, var, st = pellucid.render_with_stats(sc, spp=4, seed=1, threads=2)
    a = np.asarray(img)
    assert st["invalid_samples"] == 0 and st["spp"] == 4
    assert np.isfinite(a).all() and (a >= 0).all()
    assert np.isfinite(np.asarray(var)).all()
    assert 0.05 < a.mean() < 1.0, a.mean()  # lit: the scene's mean radiance is about 0.21
    assert not [r.getMessage() for r in records if r.levelno >= logging.WARNING]
