"""Benchmark suite: every scene of bench/suite/ rendered by pellucid and by Mitsuba 3 llvm_ad_rgb.
SPDX-License-Identifier: Apache-2.0

    python -m pellucid bench --suite [--scenes a,b] [--spp N] [--threads 2] [--quick] [--repeats R]
        [--error-repeats E] [--undecided-images N] [--reference-spp 1024] [--reference-renderer ours|mitsuba] [--no-peer] [--no-agreement]
        [--out-dir bench/results/suite] [--cache-dir bench/cache] [--mitsuba-python PY]

For each scene of the manifest (bench/suite/suite.json, written with the scenes by
bench/suite/make_suite.py) both renderers render the same spp with the same number of threads (2 by
default), each in its own process and each warm: pellucid renders 1 spp untimed first, Mitsuba renders
the timed configuration once untimed (its JIT compiles per spp and film). Only the render is timed,
never loading. ``--repeats R`` alternates R timed runs of each renderer, each with its own seed: samples/s
is the median run's, relMSE the mean over the R images. ``--error-repeats E`` adds E more renders of
each renderer, each with its own seed, whose images count in relMSE only: where a few rare bright
paths dominate an image's error (caustics through near-specular glass, say), the ratio of a handful
of images can land far from that of many, either way, so the ratio is given with a 90 % bootstrap
interval over the images. Where that interval still contains 1 (the images cannot tell which
renderer has less error), ``--undecided-images N`` (default 160) renders more images of that scene, for
relMSE only, until each renderer has N: each renderer's in one process, one seed an image (their render
seconds are not used: the time scale below comes from the other images, each rendered in a fresh
process as the timed ones are). The rule is the same for every scene and both renderers, and the
count is fixed in advance, so it never stops on a lucky image. Mitsuba 3 is optional
(bench/peers/setup_mitsuba.sh); without it the suite reports pellucid alone. Per scene it reports:

* samples/s of each renderer and their ratio (pellucid / Mitsuba), and the geometric mean of the ratio;
* equal-time relMSE against a reference: a high-spp render (by pellucid ``mis`` or, with
  ``--reference-renderer mitsuba``, by Mitsuba; rendered once and cached in the cache folder).
  relMSE above the reference's own noise falls as 1/time for an unbiased renderer, so Mitsuba's excess
  relMSE is scaled by its render time over pellucid's: both numbers are then at pellucid's time;
* agreement with Mitsuba: the per-pixel z-test of ``pellucid.bench.z_test`` between pellucid's render
  and a 16-pass Mitsuba render of the same spp, on the scenes whose models both renderers have (the
  manifest's ``peer: "same"``; ``"substitute"`` scenes are timed against the nearest Mitsuba models);
* peak resident memory of each renderer's process (its VmHWM; Mitsuba's includes its JIT compiler).

Writes ``suite.csv``, ``summary.md`` and ``suite.png`` (ratio per scene, equal-time relMSE ratio) into
``--out-dir``.
"""
from __future__ import annotations

import argparse
import csv
import dataclasses
import importlib.util
import json
import math
import os
import pathlib
import shlex
import subprocess
import sys
import tempfile
import time
from typing import Any, Dict, List, Optional, Sequence, Tuple

import numpy as np

from . import bench as _bench

AGREEMENT_BAR = 0.99  # share of pixel channels within the critical |z| (Mitsuba's render tests use 99 %)
AGREEMENT_PASSES = 16
QUICK_SIZE, QUICK_SPP, QUICK_REF_SPP = 32, 4, 64
CSV_FIELDS = ("scene", "peer", "width", "height", "spp", "threads",
              "ours_seconds", "ours_samples_per_second", "ours_load_seconds", "ours_peak_rss_mb",
              "ours_invalid_samples",
              "mitsuba_seconds", "mitsuba_samples_per_second", "mitsuba_load_seconds", "mitsuba_peak_rss_mb",
              "ratio", "ours_relmse", "mitsuba_relmse", "ref_relmse_floor", "ours_eqtime_relmse",
              "mitsuba_eqtime_relmse", "relmse_ratio", "relmse_ratio_lo", "relmse_ratio_hi", "relmse_images",
              "ztest_pass_fraction", "ztest_critical_z", "agreement",
              "mean_ratio", "reference")


# --------------------------------------------------------------------------------------- suite
def suite_dir() -> pathlib.Path:
    return _bench.repo_root() / "bench" / "suite"


def load_manifest(folder: pathlib.Path) -> List[Dict[str, Any]]:
    path = folder / "suite.json"
    try:
        entries = json.loads(path.read_text())["scenes"]
    except (OSError, ValueError, KeyError) as e:
        raise ValueError(f"{path}: cannot read the suite manifest ({e})") from None
    for i, e in enumerate(entries):
        for key in ("name", "file", "peer"):
            if key not in e:
                raise ValueError(f"{path}: scenes[{i}]: missing key {key!r}")
        if e["peer"] not in ("same", "substitute"):
            raise ValueError(f"{path}: scenes[{i}].peer: unknown value {e['peer']!r} (known: same, substitute)")
    return entries


def generator(folder: pathlib.Path):
    """bench/suite/make_suite.py as a module (it writes the generated assets)."""
    path = folder / "make_suite.py"
    spec = importlib.util.spec_from_file_location("pellucid_make_suite", path)
    if spec is None or spec.loader is None:
        raise ValueError(f"{path}: cannot load the suite generator")
    mod = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(mod)
    return mod


def prepare(scene: dict, spp: Optional[int], quick: bool) -> dict:
    """The scene as both renderers get it: spp set, and in quick mode a film of at most 32 pixels a side."""
    d = json.loads(json.dumps(scene))
    film = d.setdefault("film", {})
    if quick:
        w, h = int(film.get("width", 256)), int(film.get("height", 256))
        s = QUICK_SIZE / max(w, h)
        film["width"], film["height"] = max(1, round(w * s)), max(1, round(h * s))
    samp = d.setdefault("sampler", {})
    samp["sample_count"] = int(spp if spp is not None else (QUICK_SPP if quick else samp.get("sample_count", 64)))
    return d


# --------------------------------------------------------------------------------------- processes
@dataclasses.dataclass
class Run:
    image: np.ndarray
    variance: Optional[np.ndarray]
    spp: int
    seconds: float
    samples: float
    load_seconds: float
    peak_rss_mb: Optional[float]
    invalid_samples: int = 0  # NaN/Inf/negative samples the render dropped (pellucid's renders)

    @property
    def samples_per_second(self) -> float:
        return self.samples / self.seconds if self.seconds > 0 else float("nan")


def peak_rss_mb() -> Optional[float]:
    """This process's peak resident memory in MB (VmHWM of /proc/self/status; Linux), else None. A child's
    rusage would not do: Linux carries the parent's peak across fork and exec into the child's ru_maxrss."""
    try:
        with open("/proc/self/status") as f:
            for line in f:
                if line.startswith("VmHWM:"):
                    return int(line.split()[1]) / 1024.0
    except OSError:
        pass
    return None


def run_child(cmd: Sequence[str], what: str) -> None:
    r = subprocess.run(list(cmd), capture_output=True, text=True)
    if r.returncode != 0:
        raise RuntimeError(f"{what} failed ({' '.join(shlex.quote(c) for c in cmd)}):\n" + (r.stderr or r.stdout)[-3000:])


def run_ours(scene: dict, base_dir: pathlib.Path, seed: int, threads: int, workdir: pathlib.Path,
             variance: bool = False) -> Run:
    """pellucid in its own process (``python -m pellucid.bench_suite --worker``); the film keeps each
    pixel's variance only with `variance` (for the z-test; Mitsuba's timed renders estimate none)."""
    import pellucid

    with tempfile.TemporaryDirectory(dir=workdir) as td:
        tmp = pathlib.Path(td)
        (tmp / "scene.json").write_text(json.dumps(scene))
        cmd = [sys.executable, "-m", "pellucid.bench_suite", "--worker", str(tmp / "scene.json"),
               "--base-dir", str(base_dir), "--seed", str(seed), "--threads", str(threads),
               "--out", str(tmp / "out.exr"), "--report", str(tmp / "report.json")] + (["--variance"] if variance else [])
        run_child(cmd, "pellucid")
        st = json.loads((tmp / "report.json").read_text())
        img = pellucid.read_image(tmp / "out.exr").copy()
        var = pellucid.read_image(tmp / "out.var.exr").copy() if variance else None
    return Run(img, var, int(st["spp"]), float(st["seconds"]), float(st["samples"]), float(st["load_seconds"]),
               st.get("peak_rss_mb"), int(st.get("invalid_samples", 0)))


def run_peer(py: pathlib.Path, scene: dict, base_dir: pathlib.Path, seed: int, threads: int, passes: int,
             substitute: bool, workdir: pathlib.Path, twin: Optional[pathlib.Path] = None,
             each_dir: Optional[pathlib.Path] = None) -> Run:
    """Mitsuba 3 llvm_ad_rgb through bench/peers/mitsuba_runner.py (the same converter as pellucid.bench),
    or, for a scene whose manifest entry names a Mitsuba XML `twin` (scenes with media or subsurface
    scattering), that XML through bench/suite/mitsuba_twin.py at the scene's spp and film size."""
    import pellucid

    d = json.loads(json.dumps(scene))
    d.setdefault("integrator", {"type": "path"}).pop("strategy", None)  # Mitsuba's path is MIS
    d["integrator"].pop("light_selection", None)
    spp = int(d["sampler"]["sample_count"])
    with tempfile.TemporaryDirectory(dir=workdir) as td:
        tmp = pathlib.Path(td)
        (tmp / "scene.json").write_text(json.dumps(d))
        out, rep = tmp / "out.exr", tmp / "report.json"
        cmd = [str(py), str(_bench.mitsuba_runner()), str(tmp / "scene.json"), "--variant", "llvm_ad_rgb",
               "--spp", str(spp), "--seed", str(seed), "--out", str(out), "--passes", str(passes),
               "--json-report", str(rep), "--base-dir", str(base_dir), "--threads", str(threads), "--quiet"]
        if twin is not None:
            cmd = [str(py), str(suite_dir() / "mitsuba_twin.py"), str(twin), "--spp", str(spp),
                   "--width", str(d["film"]["width"]), "--height", str(d["film"]["height"]), "--seed", str(seed),
                   "--out", str(out), "--passes", str(passes), "--json-report", str(rep), "--threads", str(threads)]
        elif substitute:
            cmd.append("--substitute")
        if each_dir is not None:
            cmd += ["--each-dir", str(each_dir)]
        run_child(cmd, "Mitsuba llvm_ad_rgb")
        st = json.loads(rep.read_text())
        img = pellucid.read_image(out).copy()
        var = pellucid.read_image(tmp / "out.var.exr").copy() if passes > 1 else None
    return Run(img, var, spp, float(st["seconds"]), float(st["width"] * st["height"] * spp),
               float(st["load_seconds"]), st.get("peak_rss_mb"))


def run_ours_images(scene: dict, base_dir: pathlib.Path, seed: int, n: int, threads: int,
                    workdir: pathlib.Path) -> List[Run]:
    """`n` images of pellucid in one worker process, seeds seed * n + k (k < n), each as a Run."""
    import pellucid

    with tempfile.TemporaryDirectory(dir=workdir) as td:
        tmp = pathlib.Path(td)
        (tmp / "scene.json").write_text(json.dumps(scene))
        run_child([sys.executable, "-m", "pellucid.bench_suite", "--worker", str(tmp / "scene.json"),
                   "--base-dir", str(base_dir), "--seed", str(seed), "--threads", str(threads), "--images", str(n),
                   "--out", str(tmp / "each"), "--report", str(tmp / "report.json")], "pellucid")
        st = json.loads((tmp / "report.json").read_text())
        return [Run(pellucid.read_image(tmp / "each" / f"{k}.exr").copy(), None, int(st["spp"]), sec,
                    float(st["samples"]), float(st["load_seconds"]), st.get("peak_rss_mb"))
                for k, sec in enumerate(st["pass_seconds"])]


def run_peer_images(py: pathlib.Path, scene: dict, base_dir: pathlib.Path, seed: int, n: int, threads: int,
                    substitute: bool, workdir: pathlib.Path, twin: Optional[pathlib.Path] = None) -> List[Run]:
    """`n` images of Mitsuba 3 in one process (the runner's or the twin's `--passes n --each-dir`, each
    pass at the scene's spp), seeds seed * n + k (k < n), each as a Run."""
    import pellucid

    d = json.loads(json.dumps(scene))
    spp = int(d["sampler"]["sample_count"])
    d["sampler"]["sample_count"] = spp * n
    with tempfile.TemporaryDirectory(dir=workdir) as td:
        each = pathlib.Path(td) / "each"
        run = run_peer(py, d, base_dir, seed, threads, n, substitute, workdir, twin, each_dir=each)
        return [Run(pellucid.read_image(each / f"{k}.exr").copy(), None, spp, run.seconds / n, run.samples / n,
                    run.load_seconds, run.peak_rss_mb) for k in range(n)]


def worker(argv: Sequence[str]) -> int:
    """The pellucid process: load, render 1 spp untimed (warm), render the scene's spp timed, write
    the image, its variance (with --variance) and a JSON report."""
    import pellucid

    ap = argparse.ArgumentParser(prog="pellucid.bench_suite --worker")
    ap.add_argument("scene")
    ap.add_argument("--base-dir", required=True)
    ap.add_argument("--seed", type=int, default=0)
    ap.add_argument("--threads", type=int, default=2)
    ap.add_argument("--out", required=True)
    ap.add_argument("--report", required=True)
    ap.add_argument("--variance", action="store_true", help="keep and write each pixel's variance")
    ap.add_argument("--images", type=int, default=0,
                    help="render this many images instead, seeds seed * images + k, as <out>/<k>.exr")
    a = ap.parse_args(argv)
    d = json.loads(pathlib.Path(a.scene).read_text())
    t0 = time.perf_counter()
    sc = pellucid.load_dict(d, pathlib.Path(a.base_dir))
    load_s = time.perf_counter() - t0
    pellucid.render_with_stats(sc, spp=1, seed=a.seed + 1_000_003, threads=a.threads, variance=a.variance)
    if a.images > 0:
        out_dir, secs = pathlib.Path(a.out), []
        out_dir.mkdir(parents=True, exist_ok=True)
        for k in range(a.images):
            img, _, st = pellucid.render_with_stats(sc, seed=a.seed * a.images + k, threads=a.threads, variance=False)
            pellucid.write_image(out_dir / f"{k}.exr", img)
            secs.append(float(st["seconds"]))
        pathlib.Path(a.report).write_text(json.dumps({"spp": int(st["spp"]), "pass_seconds": secs,
                                                      "samples": float(st["samples"]), "load_seconds": load_s,
                                                      "peak_rss_mb": peak_rss_mb()}))
        return 0
    img, var, st = pellucid.render_with_stats(sc, seed=a.seed, threads=a.threads, variance=a.variance)
    out = pathlib.Path(a.out)
    pellucid.write_image(out, img)
    if var is not None:
        pellucid.write_image(out.with_name(out.stem + ".var.exr"), var)
    pathlib.Path(a.report).write_text(json.dumps({"spp": int(st["spp"]), "seconds": float(st["seconds"]),
                                                  "samples": float(st["samples"]), "load_seconds": load_s,
                                                  "invalid_samples": int(st["invalid_samples"]),
                                                  "peak_rss_mb": peak_rss_mb()}))
    return 0


# --------------------------------------------------------------------------------------- one scene
@dataclasses.dataclass
class Result:
    scene: str
    peer: str
    width: int
    height: int
    spp: int
    threads: int
    ours: Run
    mitsuba: Optional[Run]
    reference: str
    ref_floor: float
    ztest: Optional[Tuple[float, float]] = None
    ours_all: List[Run] = dataclasses.field(default_factory=list)  # every repeat (ours / mitsuba: the median)
    mitsuba_all: List[Run] = dataclasses.field(default_factory=list)
    ours_err: List[Run] = dataclasses.field(default_factory=list)  # --error-repeats: images for relMSE only
    mitsuba_err: List[Run] = dataclasses.field(default_factory=list)
    ours_more: List[Run] = dataclasses.field(default_factory=list)  # --undecided-images: relMSE only, not time
    mitsuba_more: List[Run] = dataclasses.field(default_factory=list)

    @property
    def ratio(self) -> Optional[float]:
        if self.mitsuba is None:
            return None
        return self.ours.samples_per_second / self.mitsuba.samples_per_second


def _median_run(runs: List[Run]) -> Run:
    """The run of median speed."""
    order = sorted(runs, key=lambda r: r.samples_per_second)
    return order[len(order) // 2]


def measure_scene(entry: Dict[str, Any], folder: pathlib.Path, args, mi_py: Optional[pathlib.Path],
                  workdir: pathlib.Path, log) -> Tuple[Result, Dict[str, Any]]:
    path = folder / entry["file"]
    try:
        scene = json.loads(path.read_text())
    except (OSError, ValueError) as e:
        raise ValueError(f"{path}: cannot read the scene ({e})") from None
    if entry.get("assets"):
        generator(folder).ensure_assets(entry["assets"], log=log)
    scene = prepare(scene, args.spp, args.quick)
    W, H, spp = int(scene["film"]["width"]), int(scene["film"]["height"]), int(scene["sampler"]["sample_count"])
    substitute = entry["peer"] == "substitute"
    twin = folder / entry["twin"] if entry.get("twin") else None
    ours_runs, mi_runs = [], []
    for r in range(args.repeats):  # alternate the renderers, so slow spells of the machine hit both
        ours_runs.append(run_ours(scene, folder, args.seed + 7919 * r, args.threads, workdir))
        if mi_py is not None:
            mi_runs.append(run_peer(mi_py, scene, folder, args.seed + 1 + 7919 * r, args.threads, 1, substitute,
                                    workdir, twin))
    ours_err, mi_err = [], []
    for r in range(args.error_repeats):  # images for relMSE only, their seeds apart from the timed ones'
        ours_err.append(run_ours(scene, folder, 50_000 + args.seed + 7919 * r, args.threads, workdir))
        if mi_py is not None:
            mi_err.append(run_peer(mi_py, scene, folder, 50_001 + args.seed + 7919 * r, args.threads, 1, substitute,
                                   workdir, twin))
    ours = _median_run(ours_runs)
    mi = _median_run(mi_runs) if mi_runs else None

    ref_spp = args.reference_spp if args.reference_spp else (QUICK_REF_SPP if args.quick else 1024)
    ref_scene = json.loads(json.dumps(scene))  # the cache key must not depend on the timed spp
    ref_scene["sampler"]["sample_count"] = ref_spp
    ref, ref_var, ref_path = _bench.cached_reference(ref_scene, folder, args.reference_renderer, ref_spp, 10_000 + args.seed,
                                                     args.threads, args.cache_dir, mi_py, log=log)
    ref_spp_real = ref_spp if args.reference_renderer == "ours" else -(-ref_spp // 16) * 16
    ref_desc = (f"{ref_spp_real} spp by " + ("pellucid mis" if args.reference_renderer == "ours"
                                               else "Mitsuba llvm_ad_rgb") + f" ({pathlib.Path(ref_path).name})")
    res = Result(entry["name"], entry["peer"], W, H, spp, args.threads, ours, mi, ref_desc,
                 _bench.ref_relmse_floor(ref, ref_var), ours_all=ours_runs, mitsuba_all=mi_runs, ours_err=ours_err,
                 mitsuba_err=mi_err)
    if mi_py is not None and args.undecided_images:
        first = row(res, ref)
        have = min(len(ours_runs) + len(ours_err), len(mi_runs) + len(mi_err))
        if undecided(first) and args.undecided_images > have:
            n = args.undecided_images - have
            log(f"{entry['name']}: relMSE ratio {first['relmse_ratio']:.2f} ({first['relmse_ratio_lo']:.2f}-"
                f"{first['relmse_ratio_hi']:.2f}) over {have} images a side contains 1: {n} more a side")
            # seeds (B + seed) * n + k, k < n: apart from the timed and error images' for n >= 1
            res.ours_more = run_ours_images(scene, folder, 900_000 + args.seed, n, args.threads, workdir)
            res.mitsuba_more = run_peer_images(mi_py, scene, folder, 900_001 + args.seed, n, args.threads,
                                               substitute, workdir, twin)
    if mi_py is not None and entry["peer"] == "same" and not args.no_agreement:
        agree = json.loads(json.dumps(scene))
        agree["sampler"]["sample_count"] = -(-spp // AGREEMENT_PASSES) * AGREEMENT_PASSES
        theirs = run_peer(mi_py, agree, folder, 30_000 + args.seed, args.threads, AGREEMENT_PASSES, False, workdir,
                          twin)
        # pellucid at the spp of the 16-pass render, with the variance the timed renders do not keep
        mine = run_ours(agree, folder, 20_000 + args.seed, args.threads, workdir, variance=True)
        res.ztest = _bench.z_test(mine.image, mine.variance, theirs.image, theirs.variance)
    return res, {"ref": ref}


def undecided(r: Dict[str, Any]) -> bool:
    """Whether a row's equal-time relMSE ratio has a 90 % interval that contains 1."""
    return "relmse_ratio_lo" in r and r["relmse_ratio_lo"] <= 1.0 <= r["relmse_ratio_hi"]


def _relmse_and_time(runs: Sequence[Run], ref: np.ndarray) -> Tuple[List[float], float]:
    """Each image's relMSE, and the mean render seconds (each image renders its own seed, so the mean
    relMSE is a steadier estimate where a few rare bright paths dominate one image's error)."""
    return [_bench.rel_mse(r.image, ref) for r in runs], float(np.mean([r.seconds for r in runs]))


BOOTSTRAP_DRAWS, BOOTSTRAP_SEED = 2000, 12345


def relmse_ratio_interval(ours: Sequence[float], theirs: Sequence[float], floor: float, time_scale: float,
                          level: float = 0.9) -> Optional[Tuple[float, float]]:
    """The central `level` interval of the equal-time relMSE ratio, (mean(ours) - floor) /
    ((mean(theirs) - floor) * time_scale), over bootstrap resamples of each renderer's per-image relMSE
    (drawn apart: the images are independent), with a fixed seed; None with fewer than 3 images a side."""
    if len(ours) < 3 or len(theirs) < 3:
        return None
    rng = np.random.default_rng(BOOTSTRAP_SEED)
    o, t = np.asarray(ours, np.float64), np.asarray(theirs, np.float64)
    mo = o[rng.integers(0, len(o), (BOOTSTRAP_DRAWS, len(o)))].mean(1)
    mt = t[rng.integers(0, len(t), (BOOTSTRAP_DRAWS, len(t)))].mean(1)
    num = np.maximum(mo - floor, 0.0)
    den = np.maximum(mt - floor, 0.0) * time_scale
    ratio = np.where(den > 0, num / np.where(den > 0, den, 1.0), np.inf)
    lo, hi = np.quantile(ratio, [(1 - level) / 2, (1 + level) / 2])
    return float(lo), float(hi)


def row(res: Result, ref: np.ndarray) -> Dict[str, Any]:
    """One CSV row. Samples/s: the median timed repeat. relMSE: the mean over the images (the timed
    repeats' and the error repeats'). relMSE above the reference's noise floor scales as 1/time, so
    Mitsuba's is scaled to pellucid's render time: ``mitsuba_eqtime_relmse = (relMSE - floor) *
    t_mitsuba / t_ours`` (t: mean seconds of the images). The --undecided-images images count in
    relMSE, not in t: they are rendered in one process a renderer, the others each in a fresh one."""
    o, m = res.ours, res.mitsuba
    ours_imgs = (res.ours_all or [o]) + res.ours_err
    ours_each, ours_t = _relmse_and_time(ours_imgs, ref)
    ours_each += [_bench.rel_mse(r.image, ref) for r in res.ours_more]
    ours_rel = float(np.mean(ours_each))
    d: Dict[str, Any] = {
        "scene": res.scene, "peer": res.peer, "width": res.width, "height": res.height, "spp": res.spp,
        "threads": res.threads, "ours_seconds": o.seconds, "ours_samples_per_second": o.samples_per_second,
        "ours_load_seconds": o.load_seconds, "ours_peak_rss_mb": o.peak_rss_mb, "ours_relmse": ours_rel,
        "ours_invalid_samples": sum(r.invalid_samples for r in res.ours_all or [o]),
        "ref_relmse_floor": res.ref_floor, "ours_eqtime_relmse": max(ours_rel - res.ref_floor, 0.0),
        "reference": res.reference, "relmse_images": len(ours_each),
        "relmse_more": len(res.ours_more)}
    if m is not None:
        mi_imgs = (res.mitsuba_all or [m]) + res.mitsuba_err
        mi_each, mi_t = _relmse_and_time(mi_imgs, ref)
        mi_each += [_bench.rel_mse(r.image, ref) for r in res.mitsuba_more]
        mi_rel = float(np.mean(mi_each))
        eq = max(mi_rel - res.ref_floor, 0.0) * mi_t / ours_t
        iv = relmse_ratio_interval(ours_each, mi_each, res.ref_floor, mi_t / ours_t)
        if iv is not None:
            d["relmse_ratio_lo"], d["relmse_ratio_hi"] = iv
        d.update({"mitsuba_seconds": m.seconds, "mitsuba_samples_per_second": m.samples_per_second,
                  "mitsuba_load_seconds": m.load_seconds, "mitsuba_peak_rss_mb": m.peak_rss_mb, "ratio": res.ratio,
                  "mitsuba_relmse": mi_rel, "mitsuba_eqtime_relmse": eq,
                  "relmse_ratio": d["ours_eqtime_relmse"] / eq if eq > 0 else float("nan"),
                  "mean_ratio": float(np.mean(o.image)) / max(float(np.mean(m.image)), 1e-30)})
    if res.ztest is not None:
        frac, zc = res.ztest
        d.update({"ztest_pass_fraction": frac, "ztest_critical_z": zc,
                  "agreement": "PASS" if frac >= AGREEMENT_BAR else "FAIL"})
    elif m is not None:
        d["agreement"] = "n/a (models differ)" if res.peer == "substitute" else "not run"
    return d


def geomean(values: Sequence[float]) -> Optional[float]:
    v = [x for x in values if x is not None and x > 0 and math.isfinite(x)]
    return math.exp(sum(math.log(x) for x in v) / len(v)) if v else None


# --------------------------------------------------------------------------------------- outputs
def _fmt(v: Any) -> str:
    if v is None:
        return ""
    return f"{v:.6g}" if isinstance(v, float) else str(v)


def write_csv(rows: Sequence[Dict[str, Any]], path: pathlib.Path) -> None:
    with open(path, "w", newline="") as f:
        w = csv.DictWriter(f, fieldnames=CSV_FIELDS)
        w.writeheader()
        for r in rows:
            w.writerow({k: _fmt(r.get(k)) for k in CSV_FIELDS})


def _mb(v: Optional[float]) -> str:
    return "?" if v is None else f"{v:.0f}"


def load_1min() -> Optional[float]:
    try:
        return os.getloadavg()[0]
    except OSError:
        return None


def busy_note(loads: Sequence[Optional[float]], cpus: int, threads: int) -> str:
    """A line for the summary: whether other work shared the cores during the run. The run's own
    renders add about `threads` to the load average."""
    known = [x for x in loads if x is not None]
    if not known:
        return "- load of the machine unknown"
    if max(known) > min(threads, cpus) + 1.0:
        return (f"- **the machine was busy**: the 1-minute load average reached {max(known):.1f} on {cpus} CPUs, "
                f"of which about {min(threads, cpus)} is this run's own rendering. Other jobs shared the cores, so "
                "samples/s are lower and noisier than on an idle machine, for both renderers (they alternate "
                "within each scene)")
    return f"- the machine was otherwise idle (1-minute load average at most {max(known):.1f} on {cpus} CPUs)"


def invalid_note(rows: Sequence[Dict[str, Any]]) -> str:
    """A line for the summary: the NaN/Inf/negative samples pellucid's timed renders dropped (an
    estimator defect wherever it is not zero)."""
    bad = [(r["scene"], r.get("ours_invalid_samples") or 0) for r in rows if r.get("ours_invalid_samples")]
    if not bad:
        return "- NaN/Inf/negative samples in pellucid's timed renders: none"
    return ("- **NaN/Inf/negative samples in pellucid's timed renders**, dropped from the film: "
            + ", ".join(f"{n} in {s}" for s, n in bad))


def more_note(rows: Sequence[Dict[str, Any]]) -> List[str]:
    """A line for the summary naming the scenes whose relMSE took --undecided-images images."""
    more = [r for r in rows if r.get("relmse_more")]
    if not more:
        return []
    return ["- relMSE over more images, where the interval over the first ones contained 1: " + ", ".join(
        f"{r['scene']} ({r['relmse_images']} a side, {r['relmse_images'] - r['relmse_more']} before)" for r in more)]


def summary(rows: Sequence[Dict[str, Any]], argv: Sequence[str], machine: Tuple[str, str], wall: float,
            peer: Optional[str], loads: Sequence[Optional[float]] = ()) -> str:
    has_peer = any("ratio" in r for r in rows)
    g = geomean([r.get("ratio") for r in rows])
    g_rel = geomean([r.get("relmse_ratio") for r in rows])
    lines = ["# Benchmark suite", "", "Regenerate with:", "",
             "    python -m pellucid bench --suite " + " ".join(shlex.quote(a) for a in argv), "",
             f"- machine at start: {machine[0]}; at end: {machine[1]}",
             busy_note(loads, os.cpu_count() or 1, rows[0]["threads"] if rows else 1),
             "- timings are comparable within this table; between runs only on the same, idle machine",
             f"- peer: {peer or 'none (Mitsuba 3 not set up: bench/peers/setup_mitsuba.sh); pellucid only'}",
             f"- threads: {rows[0]['threads'] if rows else '?'} for both renderers; both warm; only the render is "
             "timed", f"- reference: {rows[0]['reference'].split(' (')[0] if rows else '?'}, per scene, cached",
             f"- wall time of the whole run: {wall:.0f} s", invalid_note(rows)] + more_note(rows) + [""]
    if has_peer:
        lines += [f"**Geometric mean of samples/s pellucid / Mitsuba llvm_ad_rgb: {g:.2f}x** over "
                  f"{sum(1 for r in rows if 'ratio' in r)} scenes; scenes at >= 1.0x: "
                  f"{sum(1 for r in rows if r.get('ratio', 0) >= 1.0)}. Equal-time relMSE pellucid / Mitsuba, geometric mean: "
                  + (f"{g_rel:.2f}" if g_rel else "n/a") + " (< 1: pellucid has less error).", "",
                  "Targets of the suite: geometric mean >= 1.5x and >= 1.0x on every scene; equal-time relMSE no "
                  "higher than Mitsuba's on every scene.", ""]
        lines += ["| scene | spp | pellucid M samples/s | Mitsuba M samples/s | ratio | relMSE pellucid | "
                  "relMSE Mitsuba (at pellucid's time) | relMSE ratio | agreement (z-test) | mean ratio | "
                  "peak MB pellucid / Mitsuba |", "|---|---|---|---|---|---|---|---|---|---|---|"]
        for r in rows:
            if "ratio" not in r:
                continue
            z = r.get("agreement", "")
            if "ztest_pass_fraction" in r:
                z = f"{100 * r['ztest_pass_fraction']:.2f} % {z}"
            lines.append(f"| {r['scene']} | {r['spp']} | {r['ours_samples_per_second'] / 1e6:.3f} | "
                         f"{r['mitsuba_samples_per_second'] / 1e6:.3f} | {r['ratio']:.2f}x | "
                         f"{r['ours_eqtime_relmse']:.3e} | {r['mitsuba_eqtime_relmse']:.3e} | "
                         f"{_ratio_with_interval(r)} | {z} | {r['mean_ratio']:.4f} | "
                         f"{_mb(r['ours_peak_rss_mb'])} / {_mb(r['mitsuba_peak_rss_mb'])} |")
    else:
        lines += ["| scene | spp | pellucid M samples/s | relMSE (above the reference's noise) | load s | peak MB |",
                  "|---|---|---|---|---|---|"]
        for r in rows:
            lines.append(f"| {r['scene']} | {r['spp']} | {r['ours_samples_per_second'] / 1e6:.3f} | "
                         f"{r['ours_eqtime_relmse']:.3e} | {r['ours_load_seconds']:.2f} | {_mb(r['ours_peak_rss_mb'])} |")
    lines += ["", "Columns: samples/s = width x height x spp / render seconds (loading and the warm-up render "
              "excluded; the median of the repeats). relMSE = mean (x - r)^2 / (r^2 + 0.01) against the reference, "
              "averaged over the images (the timed repeats' and the --error-repeats'), minus the reference's own "
              "noise floor; Mitsuba's is scaled by its render time over pellucid's (the images' mean seconds), so "
              "both are at pellucid's time; in brackets, the ratio's 90 % bootstrap interval over the images "
              "(with 3 or more a side); where that interval contained 1, over --undecided-images images a side. Agreement: share of pixel channels whose |z| between pellucid and a 16-pass Mitsuba render "
              "is within the Sidak-corrected critical value (alpha = 0.01), PASS at >= 99 %; 'models differ' "
              "scenes are timed against Mitsuba's nearest models. Mean ratio: image mean pellucid / Mitsuba. "
              "Peak MB: maximum resident memory of each renderer's process (Mitsuba's includes its LLVM JIT).", ""]
    return "\n".join(lines)


def _ratio_with_interval(r: Dict[str, Any]) -> str:
    if "relmse_ratio_lo" not in r:
        return f"{r['relmse_ratio']:.2f}"
    return f"{r['relmse_ratio']:.2f} ({r['relmse_ratio_lo']:.2f}-{r['relmse_ratio_hi']:.2f})"


def plot(rows: Sequence[Dict[str, Any]], path: pathlib.Path, title: str) -> None:
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    names = [r["scene"] for r in rows]
    x = np.arange(len(rows))
    has_peer = any("ratio" in r for r in rows)
    fig, axes = plt.subplots(1, 2, figsize=(13, 4.8))
    ax = axes[0]
    if has_peer:
        vals = [r.get("ratio", 0.0) for r in rows]
        ax.bar(x, vals, color=["tab:blue" if v >= 1 else "tab:orange" for v in vals])
        ax.axhline(1.0, color="k", lw=1)
        ax.axhline(1.5, color="k", lw=1, ls="--", label="target geometric mean 1.5x")
        g = geomean(vals)
        if g:
            ax.axhline(g, color="tab:green", lw=1.5, label=f"geometric mean {g:.2f}x")
        ax.set_ylabel("samples/s  pellucid / Mitsuba llvm_ad_rgb")
        ax.legend(fontsize=8)
    else:
        ax.bar(x, [r["ours_samples_per_second"] / 1e6 for r in rows])
        ax.set_ylabel("pellucid M samples/s")
    ax.set_xticks(x, names, rotation=60, ha="right", fontsize=8)
    ax = axes[1]
    if has_peer:
        vals = [r.get("relmse_ratio", float("nan")) for r in rows]
        ax.bar(x, [v if math.isfinite(v) else 0 for v in vals],
               color=["tab:blue" if v <= 1 else "tab:orange" for v in vals])
        # The 90 % bootstrap interval over the images, where the run has one.
        iv = [(k, r) for k, r in enumerate(rows) if "relmse_ratio_lo" in r and math.isfinite(vals[k])]
        if iv:
            ax.errorbar([k for k, _ in iv], [vals[k] for k, _ in iv],
                        yerr=[[vals[k] - r["relmse_ratio_lo"] for k, r in iv],
                              [r["relmse_ratio_hi"] - vals[k] for k, r in iv]],
                        fmt="none", ecolor="k", elinewidth=1, capsize=2, label="90 % interval over the images")
            ax.legend(fontsize=8)
        ax.set_yscale("log")
        ax.axhline(1.0, color="k", lw=1)
        ax.set_ylabel("equal-time relMSE  pellucid / Mitsuba\n(< 1: pellucid better)")
    else:
        ax.bar(x, [max(r["ours_eqtime_relmse"], 1e-12) for r in rows])
        ax.set_yscale("log")
        ax.set_ylabel("pellucid relMSE")
    ax.set_xticks(x, names, rotation=60, ha="right", fontsize=8)
    fig.suptitle(title, fontsize=10)
    fig.tight_layout()
    fig.savefig(path, dpi=110)
    plt.close(fig)


# --------------------------------------------------------------------------------------- main
def _parser() -> argparse.ArgumentParser:
    p = argparse.ArgumentParser(prog="pellucid bench --suite", description=__doc__.split("\n")[0],
                                epilog="See bench/README.md, section Suite.")
    p.add_argument("--scenes", default=None, help="comma list of scene names (default: all of the manifest)")
    p.add_argument("--spp", type=int, default=None, help="samples per pixel for both renderers (default: the scene's)")
    p.add_argument("--threads", type=int, default=2, help="threads for both renderers (default 2)")
    p.add_argument("--repeats", type=int, default=1, help="timed runs per renderer, alternated; median speed")
    p.add_argument("--error-repeats", type=int, default=0,
                   help="more renders per renderer, each its own seed, for relMSE only (default 0)")
    p.add_argument("--undecided-images", type=int, default=160,
                   help="images a side for relMSE where the ratio's 90 %% interval contains 1 (default 160; 0: never)")
    p.add_argument("--quick", action="store_true",
                   help=f"films of at most {QUICK_SIZE} pixels a side, {QUICK_SPP} spp, {QUICK_REF_SPP}-spp references")
    p.add_argument("--reference-spp", type=int, default=None, help="reference spp (default 1024; quick 64)")
    p.add_argument("--reference-renderer", choices=["ours", "mitsuba"], default="ours",
                   help="who renders the references: pellucid mis (default) or Mitsuba llvm_ad_rgb")
    p.add_argument("--no-peer", action="store_true", help="pellucid only, even when Mitsuba 3 is set up")
    p.add_argument("--no-agreement", action="store_true", help="skip the z-tests against Mitsuba")
    p.add_argument("--seed", type=int, default=0)
    p.add_argument("--suite-dir", default=None, help="folder of the scenes and suite.json (default bench/suite)")
    p.add_argument("--out-dir", default=None, help="results folder (default bench/results/suite)")
    p.add_argument("--cache-dir", default=None, help="reference cache (default bench/cache)")
    p.add_argument("--mitsuba-python", default=None, help="the Mitsuba peer's python (default: bench/.venv-mitsuba)")
    return p


def main(argv: Optional[Sequence[str]] = None) -> int:
    argv = list(sys.argv[1:] if argv is None else argv)
    if argv[:1] == ["--worker"]:
        return worker(argv[1:])
    args = _parser().parse_args(argv)
    import pellucid

    t_start = time.perf_counter()
    machine_start, loads = _bench.machine_note(), [load_1min()]
    root = _bench.repo_root()
    folder = pathlib.Path(args.suite_dir) if args.suite_dir else suite_dir()
    out_dir = pathlib.Path(args.out_dir) if args.out_dir else root / "bench" / "results" / "suite"
    args.cache_dir = pathlib.Path(args.cache_dir) if args.cache_dir else root / "bench" / "cache"
    try:
        if args.threads < 1 or args.repeats < 1 or (args.spp is not None and args.spp < 1):
            raise ValueError("--threads, --repeats and --spp must be >= 1")
        if args.error_repeats < 0 or args.undecided_images < 0:
            raise ValueError("--error-repeats and --undecided-images must be >= 0")
        entries = load_manifest(folder)
        if args.scenes:
            wanted = [s.strip() for s in args.scenes.split(",") if s.strip()]
            known = {e["name"] for e in entries}
            unknown = [s for s in wanted if s not in known]
            if unknown:
                raise ValueError(f"--scenes: unknown scene(s) {', '.join(unknown)} (known: {', '.join(sorted(known))})")
            entries = [e for e in entries if e["name"] in wanted]
    except ValueError as e:
        print(f"pellucid bench --suite: error: {e}", file=sys.stderr)
        return 2
    mi_py = None if args.no_peer else _bench.mitsuba_python(args.mitsuba_python)
    if mi_py is None and args.reference_renderer == "mitsuba":
        print("pellucid bench --suite: error: --reference-renderer mitsuba needs Mitsuba 3", file=sys.stderr)
        return 2
    peer = "Mitsuba 3 llvm_ad_rgb" if mi_py is not None else None
    print(f"suite: {len(entries)} scenes; peer: {peer or 'none (pellucid only)'}")
    rows = []
    out_dir.mkdir(parents=True, exist_ok=True)
    with tempfile.TemporaryDirectory() as td:
        for e in entries:
            try:
                res, extra = measure_scene(e, folder, args, mi_py, pathlib.Path(td), log=print)
            except (ValueError, pellucid.Error, RuntimeError) as err:
                print(f"pellucid bench --suite: error: {e['name']}: {err}", file=sys.stderr)
                return 1
            r = row(res, extra["ref"])
            rows.append(r)
            loads.append(load_1min())
            msg = f"{r['scene']:16s} pellucid {r['ours_samples_per_second'] / 1e6:6.3f} M/s"
            if "ratio" in r:
                msg += (f"  Mitsuba {r['mitsuba_samples_per_second'] / 1e6:6.3f} M/s  ratio {r['ratio']:.2f}x  "
                        f"relMSE ratio {r['relmse_ratio']:.2f}  agreement {r.get('agreement', '')}")
            print(msg, flush=True)
    csv_p, md_p, png_p = out_dir / "suite.csv", out_dir / "summary.md", out_dir / "suite.png"
    write_csv(rows, csv_p)
    text = summary(rows, argv, (machine_start, _bench.machine_note()), time.perf_counter() - t_start, peer, loads)
    md_p.write_text(text)
    g = geomean([r.get("ratio") for r in rows])
    plot(rows, png_p, "pellucid bench --suite" + (f": geometric mean {g:.2f}x Mitsuba llvm_ad_rgb" if g else ""))
    for p in (csv_p, md_p, png_p):
        print("wrote", p)
    print(text)
    return 0


if __name__ == "__main__":
    sys.exit(main())
