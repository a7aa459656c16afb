"""Stability sweeps (pellucid.stability, ``python -m pellucid stability``) and the dropped-sample
count that every render reports: in Python (stats and a logged warning), on both command lines and
in the image's metadata."""
from __future__ import annotations

import json
import logging
import math
import subprocess
import sys
import time

import numpy as np
import pytest

import pellucid
from pellucid import _core, scenes, stability
from pellucid.__main__ import main as cli_main

from conftest import ROOT

CLI = ROOT / "build" / "py" / "cpp" / "pellucid-render"


def test_every_registered_model_has_a_grid() -> None:
    models = stability.registered_models()
    assert models["materials"] == _core.registry_types()["materials"]
    for family, names in models.items():
        missing = [n for n in names if n not in stability.GRIDS]
        assert not missing, f"add a parameter grid for {missing} to GRIDS in pellucid/stability.py"


def test_quick_sweep_is_clean() -> None:
    """The reduced grid (CI): every registered model, eval/pdf/sample and renders, all counts 0."""
    t0 = time.perf_counter()
    report = stability.sweep(quick=True)
    seconds = time.perf_counter() - t0
    table = stability.format_table(report)
    assert report.failures == 0, table
    models = stability.registered_models()
    assert {r.model for r in report.results} == {n for names in models.values() for n in names}
    assert {r.kind for r in report.results if r.family == "materials"} == {"eval", "render:plain"}
    if models["phase_functions"]:
        assert {r.kind for r in report.results if r.family == "phase_functions"} == {"eval", "render:sigma_t=1"}
    assert {r.model for r in report.results if r.family == "bssrdf_profiles"} == {"dipole", "better_dipole"}
    assert sum(r.evaluations for r in report.results) > 10**6
    assert seconds < 60, f"the quick grid took {seconds:.1f} s"


def test_hard_directions_reach_grazing_and_critical_angles() -> None:
    d = stability.hard_directions([1.5])
    assert np.allclose(np.linalg.norm(d, axis=1), 1, atol=1e-6)
    z = np.abs(d[:, 2].astype(np.float64))
    for c in (1e-6, 1e-3, 0.0):
        assert (np.abs(z - c) <= 1e-7 + 1e-3 * c).any(), c
    assert (d[:, 2] < 0).any() and (d[:, 2] > 0).any()
    sin_t = np.sqrt(np.maximum(0.0, 1 - z * z))
    crit = 1 / 1.5
    assert (np.abs(sin_t - crit * (1 + 1e-6)) < 1e-7).any() and (np.abs(sin_t - crit * (1 - 1e-4)) < 1e-6).any()


class _BrokenProbe:
    """A probe with one bug of each kind the sweep counts: NaN eval at grazing wi, negative pdf
    below the horizon, infinite sample weights for u_lobe = 0, samples claiming a lobe with pdf 0."""

    def eval(self, wo: np.ndarray, wi: np.ndarray) -> np.ndarray:
        f = np.full((len(wo), 3), 0.1, dtype=np.float32)
        f[np.abs(wi[:, 2]) < 1e-5] = np.nan
        return f

    def pdf(self, wo: np.ndarray, wi: np.ndarray) -> np.ndarray:
        return np.where(wi[:, 2] < 0, -1.0, 0.5).astype(np.float32)

    def sample(self, wo: np.ndarray, u: np.ndarray):
        n = len(wo)
        wi = np.tile(np.array([0, 0, 1], dtype=np.float32), (n, 1))
        weight = np.ones((n, 3), dtype=np.float32)
        weight[u[:, 0] == 0] = np.inf
        pdf = np.where(u[:, 1] == 0.5, 0.0, 1.0).astype(np.float32)
        return wi, weight, pdf, np.ones(n, dtype=np.uint32)


def test_sweep_counts_each_kind_of_bad_value() -> None:
    res = stability.PointResult("materials", "broken", {"int_ior": 1.5}, "eval")
    stability._sweep_probe(res, _BrokenProbe(), "radiance", res.params, True, np.random.default_rng(1))
    assert res.nan > 0 and res.inf > 0 and res.negative > 0 and res.invalid > 0
    assert res.example["call"] == "eval" and math.isnan(res.example["value"][0])
    assert abs(res.example["wi"][2]) < 1e-5


def test_cli_exit_status_table_and_json(tmp_path, monkeypatch, capsys) -> None:
    out = tmp_path / "stability.json"
    assert cli_main(["stability", "--quick", "--models", "lambertian,conductor", "--json", str(out)]) == 0
    text = capsys.readouterr().out
    assert "lambertian" in text and "no NaN, Inf, negative or invalid values" in text
    data = json.loads(out.read_text())
    assert data["failures"] == 0 and data["points"] == len(data["results"]) > 0
    assert {r["model"] for r in data["results"]} == {"lambertian", "conductor"}
    # A model that returns NaN makes the command fail and name the point.
    broken = stability.Family("materials", lambda desc, mode: _BrokenProbe(), None)
    monkeypatch.setattr(stability, "FAMILIES", (broken,))
    assert cli_main(["stability", "--quick", "--models", "dielectric", "--json", str(out)]) == 1
    text = capsys.readouterr().out
    assert "points with findings:" in text and "dielectric [eval] int_ior=1.0" in text
    assert json.loads(out.read_text())["totals"]["nan"] > 0
    assert cli_main(["stability", "--models", "velvet"]) == 2
    assert "'velvet' is not a registered model" in capsys.readouterr().err


# --- Dropped samples: every render reports them -------------------------------------------------

def _overflow_scene(tmp_path):
    """A white furnace lit at 3e38, rendered with the nee strategy: a light sample of the environment
    weighs its radiance by f cos / pdf, up to 4 with the uniform sphere's pdf 1/4π, which overflows a
    float to +Inf; the film drops those samples and counts them (a deterministic count per seed).
    (Under mis the environment is BSDF sampling's alone, and every path is exactly 3e38.)"""
    d = scenes.furnace(radiance=3e38, width=8, height=8, spp=4)
    d["integrator"]["strategy"] = "nee"
    path = tmp_path / "overflow.json"
    path.write_text(json.dumps(d))
    return d, path


def test_dropped_samples_are_reported_in_python_both_clis_and_the_exr(tmp_path, caplog) -> None:
    d, path = _overflow_scene(tmp_path)
    with caplog.at_level(logging.WARNING, logger="pellucid"):
        image, _, stats = pellucid.render_with_stats(pellucid.load_dict(d), seed=3)
    n = stats["invalid_samples"]
    assert 0 < n < stats["samples"] and np.isfinite(image).all()
    assert f"{n} NaN/Inf/negative samples were discarded" in caplog.text
    caplog.clear()
    with caplog.at_level(logging.WARNING, logger="pellucid"):
        pellucid.render(pellucid.load_dict(d), seed=3)
    assert f"{n} NaN/Inf/negative samples were discarded" in caplog.text

    cmds = {"py": [sys.executable, "-m", "pellucid", "render"]}
    if CLI.exists():
        cmds["cpp"] = [str(CLI)]
    for name, cmd in cmds.items():
        exr = tmp_path / f"{name}.exr"
        r = subprocess.run([*cmd, str(path), "-o", str(exr), "--seed", "3"], capture_output=True, text=True,
                           timeout=120)
        assert r.returncode == 0, r.stderr
        assert f"warning: {n} NaN/Inf/negative samples were discarded" in r.stderr, (name, r.stderr)
        assert f"{n} invalid samples dropped" in r.stderr, (name, r.stderr)
        assert pellucid.read_image_attributes(exr)["pellucid:invalid_samples"] == n, name
        # -q drops the summary line, never the warning.
        r = subprocess.run([*cmd, str(path), "-o", str(exr), "--seed", "3", "-q"], capture_output=True, text=True,
                           timeout=120)
        assert r.returncode == 0 and f"warning: {n} NaN/Inf/negative" in r.stderr, (name, r.stderr)
    if "cpp" not in cmds:
        pytest.skip("pellucid-render is built by `make`; only the Python command line was checked")


def test_clean_render_reports_zero_and_warns_nothing(tmp_path, caplog) -> None:
    with caplog.at_level(logging.WARNING, logger="pellucid"):
        _, _, stats = pellucid.render_with_stats(pellucid.load_dict(scenes.furnace(width=8, height=8, spp=2)))
    assert stats["invalid_samples"] == 0 and "discarded" not in caplog.text
