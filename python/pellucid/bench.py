"""Speed-against-accuracy harness: error against render time for pellucid's strategies and peers.
SPDX-License-Identifier: Apache-2.0

    python -m pellucid bench SCENE.json [--methods bsdf,nee,mis,mis+sobol,scalar_rgb,llvm_ad_rgb]
        [--sampler independent|sobol]
        [--budgets 1,2,5,10 | --spp-ladder 4,16,64] [--reference IMAGE | --reference-constant V]
        [--reference-renderer ours|mitsuba] [--reference-spp 4096] [--out-dir bench/results]
        [--name NAME] [--threads T] [--seed S] [--agreement-spp N]

For one scene it renders every method on a ladder of time budgets (or of sample counts), measures
each image against a reference and writes, under ``--out-dir``:

* ``NAME.csv``: one row per (method, rung): time, spp, samples/s, relMSE, RMSE, FLIP (when the
  ``flip-evaluator`` package is importable), and the reference's own noise floor;
* ``NAME_error.png``: log-log chart of relMSE (and FLIP) against seconds;
* ``NAME_crops.png``: a strip of equal-time crops, one per method, with the reference last;
* ``NAME_summary.md``: the command, the machine's load, the reference, and equal-time ratios.

Methods: ``bsdf``, ``nee``, ``mis``, ``direct`` (pellucid's ``integrator.strategy``, rendered in
this process with ``time_budget``) and the peers ``scalar_rgb``, ``llvm_ad_rgb`` (Mitsuba 3, run
in a subprocess with the peer's own Python, bench/peers/mitsuba_runner.py; Mitsuba is never
imported here). A pellucid method may name its sampler after a ``+``: ``mis+sobol`` renders
``mis`` with the Owen-scrambled Sobol sampler, ``mis+independent`` with i.i.d. samples; a bare
``mis`` uses ``--sampler`` when given (and is then reported as ``mis+SAMPLER``), else the scene's
sampler. The reference is always rendered with the scene's sampler. A peer renders a fixed spp, so each budget is turned into an spp from the peer's
measured samples/s (a probe render, refined after every rung); the time recorded is the time the
render took, never the budget. Peers that are not installed are skipped with a note.

References: an image file (``--reference``), an analytic constant (``--reference-constant``), or a
high-spp render by pellucid's ``mis`` or by Mitsuba ``llvm_ad_rgb`` (``--reference-renderer``),
cached in ``--cache-dir`` (default bench/cache, git-ignored) under a hash of the scene and the
settings.

Metrics (per pixel and channel, averaged): relMSE = (x - r)^2 / (r^2 + 0.01) (the denominator's
0.01 keeps dark pixels from dominating, as in Rousselle et al. 2011 and most denoising papers),
RMSE = sqrt(mean (x - r)^2). A reference rendered by Monte Carlo has its own noise: the row's
``ref_relmse_floor`` = mean(Var[r] / (r^2 + 0.01)) is the relMSE a perfect image would still get.
"""
from __future__ import annotations

import argparse
import csv
import dataclasses
import hashlib
import json
import math
import os
import pathlib
import shlex
import statistics
import subprocess
import sys
import tempfile
import time
from typing import Any, Callable, Dict, List, Optional, Sequence, Tuple

import numpy as np

from ._bench_figures import label as _label, plot_chart, plot_crops, tonemap  # noqa: F401 (re-exported)
from .image import RELMSE_EPSILON, rel_mse as _image_rel_mse

RELMSE_EPS = RELMSE_EPSILON
OURS = ("bsdf", "nee", "mis", "direct")
SAMPLERS = ("independent", "sobol")
MITSUBA = ("scalar_rgb", "llvm_ad_rgb")
CSV_FIELDS = ("scene", "method", "renderer", "rung", "budget_s", "spp", "seconds", "samples_per_second",
              "relmse", "rmse", "flip", "ref_relmse_floor", "threads", "seed")


# --------------------------------------------------------------------------------------- metrics
def _pair(image: np.ndarray, reference: np.ndarray) -> Tuple[np.ndarray, np.ndarray]:
    a = np.asarray(image, dtype=np.float64)
    r = np.asarray(reference, dtype=np.float64)
    if r.ndim == 0:
        r = np.broadcast_to(r, a.shape)
    if a.shape != r.shape:
        raise ValueError(f"image shape {a.shape} differs from the reference's {r.shape}")
    return a, r


def rel_mse(image: np.ndarray, reference, eps: float = RELMSE_EPS) -> float:
    """Mean over pixels and channels of (x - r)^2 / (r^2 + eps) (pellucid.image.rel_mse, with the
    shapes checked and a scalar reference broadcast)."""
    a, r = _pair(image, reference)
    return _image_rel_mse(a, r, eps)


def rmse(image: np.ndarray, reference) -> float:
    """Root of the mean over pixels and channels of (x - r)^2."""
    a, r = _pair(image, reference)
    return float(np.sqrt(np.mean((a - r) ** 2)))


def ref_relmse_floor(reference: np.ndarray, variance: Optional[np.ndarray], eps: float = RELMSE_EPS) -> float:
    """The relMSE that the reference's own Monte Carlo noise adds to every measurement:
    E[(x - r)^2] = Var[x] + Var[r] for independent x and r."""
    if variance is None:
        return 0.0
    r = np.asarray(reference, dtype=np.float64)
    return float(np.mean(np.asarray(variance, dtype=np.float64) / (r * r + eps)))


def flip_available() -> bool:
    try:
        import flip_evaluator  # noqa: F401
    except ImportError:
        return False
    return True


def flip_error(image: np.ndarray, reference) -> Optional[float]:
    """Mean HDR-FLIP (Andersson et al. 2021) when ``flip-evaluator`` is installed, else None."""
    try:
        import flip_evaluator as flip
    except ImportError:
        return None
    a, r = _pair(image, reference)
    _, mean, _ = flip.evaluate(np.ascontiguousarray(r, np.float32), np.ascontiguousarray(a, np.float32), "HDR")
    return float(mean)


def critical_z(n: int, alpha: float = 0.01) -> float:
    """The two-sided critical |z| at level alpha Sidak-corrected over n tests: P(|Z| > z) = alpha_1
    with alpha_1 = 1 - (1 - alpha)^(1/n) (computed without cancellation for large n)."""
    alpha_1 = -math.expm1(math.log1p(-alpha) / n)
    return -statistics.NormalDist().inv_cdf(0.5 * alpha_1)


def z_test(a: np.ndarray, va: np.ndarray, b: np.ndarray, vb: np.ndarray, alpha: float = 0.01) -> Tuple[float, float]:
    """Per-pixel two-sided z-test of two independent Monte Carlo images (means a, b; variances of the
    means va, vb), at level alpha Sidak-corrected over all pixel channels. Returns the fraction of pixel
    channels that pass and the critical |z|; Mitsuba's render tests ask for >= 99 % passing."""
    a, b = np.asarray(a, np.float64), np.asarray(b, np.float64)
    zc = critical_z(a.size, alpha)
    z = np.abs(a - b) / np.sqrt(np.asarray(va, np.float64) + np.asarray(vb, np.float64) + 1e-12)
    return float(np.mean(z <= zc)), zc


# --------------------------------------------------------------------------------------- peers
def repo_root() -> pathlib.Path:
    """The source checkout this package runs from (editable install), else the working directory."""
    here = pathlib.Path(__file__).resolve().parents[2]
    return here if (here / "bench" / "peers").is_dir() else pathlib.Path.cwd()


def mitsuba_python(explicit: Optional[str] = None) -> Optional[pathlib.Path]:
    """The Mitsuba peer's interpreter: --mitsuba-python, $PELLUCID_MITSUBA_PYTHON, or
    bench/.venv-mitsuba/bin/python (made by bench/peers/setup_mitsuba.sh); None if none exists."""
    for c in (explicit, os.environ.get("PELLUCID_MITSUBA_PYTHON"),
              repo_root() / "bench" / ".venv-mitsuba" / "bin" / "python"):
        if c and pathlib.Path(c).exists():
            return pathlib.Path(c)
    return None


def mitsuba_runner() -> pathlib.Path:
    return repo_root() / "bench" / "peers" / "mitsuba_runner.py"


@dataclasses.dataclass
class Render:
    image: np.ndarray
    variance: Optional[np.ndarray]
    spp: int
    seconds: float
    samples: float


def run_mitsuba(py: pathlib.Path, scene: dict, base_dir: pathlib.Path, variant: str, spp: int, seed: int,
                threads: int, passes: int = 1, workdir: Optional[pathlib.Path] = None) -> Render:
    """Render `scene` (a pellucid scene dict) with Mitsuba 3 in a subprocess (bench/peers/mitsuba_runner.py)."""
    import pellucid

    d = json.loads(json.dumps(scene))
    d.setdefault("integrator", {"type": "path"}).pop("strategy", None)  # Mitsuba's path is MIS
    d["integrator"].pop("light_selection", None)
    with tempfile.TemporaryDirectory(dir=workdir) as td:
        tmp = pathlib.Path(td)
        (tmp / "scene.json").write_text(json.dumps(d))
        out, rep = tmp / "out.exr", tmp / "report.json"
        cmd = [str(py), str(mitsuba_runner()), str(tmp / "scene.json"), "--variant", variant, "--spp", str(spp),
               "--seed", str(seed), "--out", str(out), "--passes", str(passes), "--json-report", str(rep),
               "--base-dir", str(base_dir), "--quiet"]
        if threads > 0:
            cmd += ["--threads", str(threads)]
        r = subprocess.run(cmd, capture_output=True, text=True)
        if r.returncode != 0:
            raise RuntimeError(f"mitsuba {variant} failed ({' '.join(shlex.quote(c) for c in cmd)}):\n"
                               + (r.stderr or r.stdout)[-3000:])
        st = json.loads(rep.read_text())
        img = pellucid.read_image(out).copy()
        var = pellucid.read_image(tmp / "out.var.exr").copy() if passes > 1 else None
    return Render(img, var, spp, float(st["seconds"]), float(st["width"] * st["height"] * spp))


def split_method(method: str) -> Tuple[str, Optional[str]]:
    """``"mis+sobol"`` -> ``("mis", "sobol")``; ``"mis"`` -> ``("mis", None)`` (the scene's sampler)."""
    strategy, _, sampler = method.partition("+")
    return strategy, (sampler or None)


def run_ours(scene: dict, base_dir: pathlib.Path, strategy: str, seed: int, threads: int,
             spp: Optional[int] = None, budget: Optional[float] = None, warm: bool = True,
             sampler: Optional[str] = None, variance: bool = False) -> Render:
    """Render with pellucid in this process, the strategy set in integrator.strategy and the sampler
    type `sampler` (None: the scene's); the film keeps each pixel's variance only with `variance`
    (Mitsuba's timed renders estimate none either)."""
    import pellucid

    d = json.loads(json.dumps(scene))
    d.setdefault("integrator", {"type": "path"})["strategy"] = strategy
    sc = pellucid.load_dict(d, base_dir)
    if warm:  # untimed, as the peers get (page in the BVH and the code)
        pellucid.render_with_stats(sc, spp=1, seed=seed + 1_000_003, threads=threads, sampler=sampler,
                                   variance=variance)
    img, var, st = pellucid.render_with_stats(sc, spp=spp, seed=seed, threads=threads, time_budget=budget,
                                              sampler=sampler, variance=variance)
    return Render(np.array(img), None if var is None else np.array(var), int(st["spp"]), float(st["seconds"]),
                  float(st["samples"]))


# --------------------------------------------------------------------------------------- reference
def reference_key(scene: dict, settings: Dict[str, Any]) -> str:
    """Hash of the scene (canonical JSON), the files it names (their bytes) and the settings."""
    h = hashlib.sha256()
    h.update(json.dumps(scene, sort_keys=True).encode())
    h.update(json.dumps(settings, sort_keys=True).encode())
    return h.hexdigest()[:20]


def _referenced_files(scene: dict, base_dir: pathlib.Path) -> List[pathlib.Path]:
    files = []

    def walk(x):
        if isinstance(x, dict):
            for k, v in x.items():
                if k == "filename" and isinstance(v, str):
                    files.append((base_dir / v) if not os.path.isabs(v) else pathlib.Path(v))
                else:
                    walk(v)
        elif isinstance(x, list):
            for v in x:
                walk(v)

    walk(scene)
    return files


def cached_reference(scene: dict, base_dir: pathlib.Path, renderer: str, spp: int, seed: int, threads: int,
                     cache_dir: pathlib.Path, mi_py: Optional[pathlib.Path],
                     log: Callable[[str], None] = print) -> Tuple[np.ndarray, Optional[np.ndarray], str]:
    """A high-spp reference (mean, variance of the mean), rendered once and kept in cache_dir."""
    import pellucid

    if renderer == "mitsuba":
        spp = -(-spp // 16) * 16  # 16 passes (for the variance), so a multiple of 16
    files = {str(p): hashlib.sha256(p.read_bytes()).hexdigest() for p in _referenced_files(scene, base_dir)
             if p.exists()}
    settings = {"renderer": renderer, "spp": spp, "seed": seed, "files": files,
                "version": pellucid.__version__ if renderer == "ours" else "mitsuba"}
    key = reference_key(scene, settings)
    cache_dir.mkdir(parents=True, exist_ok=True)
    img_p, var_p, meta_p = (cache_dir / f"ref_{key}.exr", cache_dir / f"ref_{key}.var.exr",
                            cache_dir / f"ref_{key}.json")
    if img_p.exists() and var_p.exists():
        log(f"reference: cached {img_p}")
        return pellucid.read_image(img_p).copy(), pellucid.read_image(var_p).copy(), str(img_p)
    log(f"reference: rendering {spp} spp with {renderer} (cached as {img_p.name}) ...")
    t0 = time.perf_counter()
    if renderer == "ours":
        r = run_ours(scene, base_dir, "mis", seed, threads, spp=spp, warm=False, variance=True)
    elif renderer == "mitsuba":
        if mi_py is None:
            raise RuntimeError("--reference-renderer mitsuba: Mitsuba is not set up (bench/peers/setup_mitsuba.sh)")
        r = run_mitsuba(mi_py, scene, base_dir, "llvm_ad_rgb", spp, seed, threads, passes=16)
    else:
        raise ValueError(f"--reference-renderer: unknown {renderer!r} (known: ours, mitsuba)")
    pellucid.write_image(img_p, r.image)
    pellucid.write_image(var_p, r.variance)
    meta_p.write_text(json.dumps({**settings, "seconds": time.perf_counter() - t0, "scene": scene}, indent=1))
    return r.image, r.variance, str(img_p)


# --------------------------------------------------------------------------------------- ladder
@dataclasses.dataclass
class Row:
    scene: str
    method: str
    renderer: str
    rung: int
    budget_s: Optional[float]
    spp: int
    seconds: float
    samples_per_second: float
    relmse: float
    rmse: float
    flip: Optional[float]
    ref_relmse_floor: float
    threads: int
    seed: int
    image: Optional[np.ndarray] = dataclasses.field(default=None, repr=False)

    def csv_row(self) -> Dict[str, str]:
        def f(v):
            if v is None:
                return ""
            return f"{v:.6g}" if isinstance(v, float) else str(v)
        return {k: f(getattr(self, k)) for k in CSV_FIELDS}


def parse_methods(spec: str, sampler: Optional[str] = None) -> List[str]:
    """Method names from a comma list. pellucid methods take an optional ``+SAMPLER`` suffix
    (``mis+sobol``); bare ones get ``+sampler`` when `sampler` is given (``--sampler``)."""
    if sampler is not None and sampler not in SAMPLERS:
        raise ValueError(f"--sampler: unknown sampler {sampler!r} (known: {', '.join(SAMPLERS)})")
    known = OURS + MITSUBA
    out = []
    for m in (x.strip() for x in spec.split(",") if x.strip()):
        base, plus, suffix = m.partition("+")
        if plus:
            if base not in OURS and base != "ours":
                raise ValueError(f"--methods: {m!r}: only pellucid methods ({', '.join(OURS)}, ours) take a +sampler")
            if suffix not in SAMPLERS:
                raise ValueError(f"--methods: {m!r}: unknown sampler {suffix!r} (known: {', '.join(SAMPLERS)})")
        if base == "ours":
            names = ["bsdf", "nee", "mis"]
        elif base == "mitsuba" and not plus:
            names = list(MITSUBA)
        elif base in known:
            names = [base]
        else:
            raise ValueError(f"--methods: unknown method {m!r} (known: {', '.join(known)}, ours, mitsuba; "
                             f"pellucid methods may end in +{'/+'.join(SAMPLERS)})")
        s = suffix if plus else sampler
        out += [f"{n}+{s}" if s and n in OURS else n for n in names]
    return list(dict.fromkeys(out))


def parse_floats(spec: str, what: str) -> List[float]:
    try:
        v = [float(x) for x in spec.split(",") if x.strip()]
    except ValueError:
        raise ValueError(f"{what}: expected comma-separated numbers, got {spec!r}") from None
    if not v or any(not (x > 0 and math.isfinite(x)) for x in v):
        raise ValueError(f"{what}: values must be finite and > 0, got {spec!r}")
    return sorted(v)


def run_ladder(scene: dict, base_dir: pathlib.Path, name: str, methods: Sequence[str], reference,
               ref_variance: Optional[np.ndarray], budgets: Optional[Sequence[float]] = None,
               spp_ladder: Optional[Sequence[int]] = None, threads: int = 0, seed: int = 0,
               mi_py: Optional[pathlib.Path] = None, with_flip: bool = True, budget_mode: str = "calibrated",
               log: Callable[[str], None] = print) -> List[Row]:
    """Render every method on every rung and measure it. Exactly one of budgets / spp_ladder.

    budget_mode "calibrated": every renderer turns a budget into spp from its measured samples/s (a 4-spp
    probe, then the previous rung) and renders that spp, so all of them stop near the budget the same way;
    "native": pellucid renders with its own time_budget (it stops after the pass that crosses the budget,
    which can overshoot by up to the last pass), peers as in "calibrated"."""
    if (budgets is None) == (spp_ladder is None):
        raise ValueError("give exactly one of budgets and spp_ladder")
    if budget_mode not in ("calibrated", "native"):
        raise ValueError(f"budget_mode: unknown {budget_mode!r} (known: calibrated, native)")
    rungs = list(budgets if budgets is not None else spp_ladder)
    floor = ref_relmse_floor(reference, ref_variance) if np.ndim(reference) else 0.0
    W, H = int(scene["film"]["width"]), int(scene["film"]["height"])
    n_threads = threads if threads > 0 else (os.cpu_count() or 1)
    rows: List[Row] = []
    for method in methods:
        peer = method in MITSUBA
        if peer and mi_py is None:
            log(f"{method}: Mitsuba 3 is not set up (bench/peers/setup_mitsuba.sh); skipped")
            continue
        def render(spp=None, budget=None, s=seed):
            if peer:
                return run_mitsuba(mi_py, scene, base_dir, method, spp, s, threads)
            strategy, sampler = split_method(method)
            return run_ours(scene, base_dir, strategy, s, threads, spp=spp, budget=budget, sampler=sampler)

        sps = None
        if budgets is not None and (peer or budget_mode == "calibrated"):
            probe = render(spp=4, s=seed + 999)  # speed probe: turns seconds into spp
            sps = probe.samples / probe.seconds
        for i, rung in enumerate(rungs):
            s = seed + 7919 * i
            try:
                if budgets is None:
                    r = render(spp=int(rung), s=s)
                elif sps is not None:
                    r = render(spp=max(1, int(round(rung * sps / (W * H)))), s=s)
                    sps = r.samples / r.seconds
                else:
                    r = render(budget=float(rung), s=s)
            except Exception as e:  # a peer that cannot render this scene is reported, not fatal
                if not peer:
                    raise
                log(f"{method}: skipped ({str(e).strip().splitlines()[-1]})")
                break
            row = Row(scene=name, method=method, renderer="mitsuba" if peer else "pellucid", rung=i,
                      budget_s=float(rung) if budgets is not None else None, spp=r.spp, seconds=r.seconds,
                      samples_per_second=r.samples / r.seconds if r.seconds > 0 else float("nan"),
                      relmse=rel_mse(r.image, reference), rmse=rmse(r.image, reference),
                      flip=flip_error(r.image, reference) if with_flip else None,
                      ref_relmse_floor=floor, threads=n_threads, seed=s, image=r.image)
            rows.append(row)
            log(f"{method:12s} rung {i}: {row.seconds:7.2f} s {row.spp:6d} spp {row.samples_per_second / 1e6:6.2f} "
                f"M/s relMSE {row.relmse:.3e} RMSE {row.rmse:.3e}" + (f" FLIP {row.flip:.4f}" if row.flip else ""))
    return rows


def write_csv(rows: Sequence[Row], path: pathlib.Path) -> None:
    path.parent.mkdir(parents=True, exist_ok=True)
    with open(path, "w", newline="") as f:
        w = csv.DictWriter(f, fieldnames=CSV_FIELDS)
        w.writeheader()
        for r in rows:
            w.writerow(r.csv_row())


def read_csv(path: pathlib.Path) -> List[Dict[str, str]]:
    with open(path, newline="") as f:
        return list(csv.DictReader(f))


# --------------------------------------------------------------------------------------- summary
def equal_time_ratios(rows: Sequence[Row], rung: int, base: str = "mis") -> List[str]:
    """Lines comparing `base` with every other method at one rung; relMSE x seconds (inverse efficiency)
    corrects for the small differences between the times actually taken."""
    by = {r.method: r for r in rows if r.rung == rung}
    if base not in by:  # e.g. only mis+sobol was run: compare with the first pellucid method
        base = next((m for m, r in by.items() if r.renderer == "pellucid"), base)
    if base not in by:
        return []
    b = by[base]
    out = [f"| method | seconds | spp | samples/s | relMSE | relMSE x s | samples/s {base} / this | "
           f"relMSE {base} / this (< 1: {base} better) |", "|---|---|---|---|---|---|---|---|"]
    def ratio(x: float, y: float) -> str:
        return f"{x / y:.2f}" if y > 0 else ("1.00" if x == y else "inf")

    for m, r in by.items():
        out.append(f"| {_label(m)} | {r.seconds:.2f} | {r.spp} | {r.samples_per_second / 1e6:.3f} M | {r.relmse:.3e} | "
                   f"{r.relmse * r.seconds:.3e} | {ratio(b.samples_per_second, r.samples_per_second)}x | "
                   f"{ratio(b.relmse, r.relmse)} |")
    return out


def cpu_model() -> str:
    """The processor's name (Linux: /proc/cpuinfo's first "model name"), else platform.processor().
    Timings, and ratios against a peer, hold for this processor only."""
    try:
        with open("/proc/cpuinfo", encoding="utf-8", errors="replace") as f:
            for line in f:
                if line.startswith("model name"):
                    return line.split(":", 1)[1].strip()
    except OSError:
        pass
    import platform
    return platform.processor() or "unknown processor"


def machine_note() -> str:
    try:
        load = os.getloadavg()
        load_s = f"load average {load[0]:.2f} {load[1]:.2f} {load[2]:.2f}"
    except OSError:
        load_s = "load average unknown"
    return f"{os.cpu_count()} logical CPUs ({cpu_model()}), {load_s}"


# --------------------------------------------------------------------------------------- main
def _parser() -> argparse.ArgumentParser:
    p = argparse.ArgumentParser(prog="pellucid bench", description=__doc__.split("\n")[0],
                                epilog="See bench/README.md.")
    p.add_argument("scene", help="scene file (.json)")
    p.add_argument("--suite", action="store_true",
                   help="run the benchmark suite of bench/suite/ instead (no SCENE; `bench --suite --help`)")
    p.add_argument("--methods", default="bsdf,nee,mis,scalar_rgb,llvm_ad_rgb",
                   help="comma list of bsdf, nee, mis, direct, scalar_rgb, llvm_ad_rgb (or 'ours', 'mitsuba'); "
                        "pellucid methods may name a sampler: mis+sobol, mis+independent")
    p.add_argument("--sampler", choices=list(SAMPLERS), default=None,
                   help="sampler of the pellucid methods without a +sampler suffix (default: the scene's)")
    g = p.add_mutually_exclusive_group()
    g.add_argument("--budgets", default=None, help="time budgets in seconds (default 0.5,1,2,5,10)")
    g.add_argument("--spp-ladder", default=None, help="sample counts instead of time budgets, e.g. 4,16,64")
    r = p.add_mutually_exclusive_group()
    r.add_argument("--reference", default=None, help="reference image (.exr); default: render one")
    r.add_argument("--reference-constant", type=float, default=None, help="analytic answer for every pixel")
    p.add_argument("--reference-renderer", choices=["ours", "mitsuba"], default="ours",
                   help="who renders the reference: pellucid mis or Mitsuba llvm_ad_rgb (default ours)")
    p.add_argument("--reference-spp", type=int, default=4096)
    p.add_argument("--cache-dir", default=None, help="reference cache (default: bench/cache)")
    p.add_argument("--out-dir", default="bench/results")
    p.add_argument("--name", default=None, help="output file stem (default: the scene's)")
    p.add_argument("--budget-mode", choices=["calibrated", "native"], default="calibrated",
                   help="calibrated: every renderer turns budgets into spp from its measured speed (default); "
                        "native: pellucid uses its own time_budget")
    p.add_argument("--filter", choices=["scene", "box", "gaussian"], default="scene",
                   help="override the film's pixel filter for every renderer (box: each sample feeds one pixel)")
    p.add_argument("--threads", type=int, default=0, help="threads for every renderer (0 = all cores)")
    p.add_argument("--seed", type=int, default=0)
    p.add_argument("--crop", default=None, help="x,y,w,h of the crop strip (default: the central quarter)")
    p.add_argument("--crop-rung", type=int, default=-1, help="ladder rung of the crop strip (default: the last)")
    p.add_argument("--exposure", type=float, default=1.0, help="exposure of the crops")
    p.add_argument("--no-flip", action="store_true", help="skip FLIP even when flip-evaluator is installed")
    p.add_argument("--mitsuba-python", default=None, help="the Mitsuba peer's python (default: bench/.venv-mitsuba)")
    p.add_argument("--agreement-spp", type=int, default=0,
                   help="also z-test pellucid mis against Mitsuba llvm_ad_rgb at this spp (16 passes)")
    return p


def main(argv: Optional[Sequence[str]] = None) -> int:
    argv = list(sys.argv[1:] if argv is None else argv)
    if "--suite" in argv:  # the benchmark suite has its own runner and options
        from . import bench_suite
        return bench_suite.main([a for a in argv if a != "--suite"])
    args = _parser().parse_args(argv)
    import pellucid

    t_start = time.perf_counter()
    machine_at_start = machine_note()
    try:
        scene_path = pathlib.Path(args.scene)
        try:
            scene = json.loads(scene_path.read_text())
        except (OSError, json.JSONDecodeError) as e:
            raise pellucid.Error(f"{scene_path}: cannot read the scene ({e})") from None
        base_dir = scene_path.resolve().parent
        if args.filter != "scene":
            scene.setdefault("film", {})["filter"] = ({"type": "box", "radius": 0.5} if args.filter == "box"
                                                      else {"type": "gaussian", "stddev": 0.5})
        pellucid.load_dict(scene, base_dir)  # fail early, with pellucid's message, on a bad scene
        name = args.name or scene_path.stem
        methods = parse_methods(args.methods, args.sampler)
        budgets = spp_ladder = None
        if args.spp_ladder:
            spp_ladder = [int(x) for x in parse_floats(args.spp_ladder, "--spp-ladder")]
        else:
            budgets = parse_floats(args.budgets or "0.5,1,2,5,10", "--budgets")
        crop = None
        if args.crop:
            crop = tuple(int(v) for v in args.crop.split(","))
            if len(crop) != 4:
                raise ValueError(f"--crop: expected x,y,w,h, got {args.crop!r}")
    except ValueError as e:
        print(f"pellucid bench: error: {e}", file=sys.stderr)
        return 2
    except pellucid.Error as e:
        print(f"pellucid bench: error: {e}", file=sys.stderr)
        return 1

    mi_py = mitsuba_python(args.mitsuba_python)
    if mi_py is None and any(m in MITSUBA for m in methods):
        print("note: Mitsuba 3 is not set up (bash bench/peers/setup_mitsuba.sh); peers skipped")
    cache_dir = pathlib.Path(args.cache_dir) if args.cache_dir else repo_root() / "bench" / "cache"
    out_dir = pathlib.Path(args.out_dir)

    ref_var = None
    if args.reference_constant is not None:
        reference, ref_desc = np.float64(args.reference_constant), f"analytic constant {args.reference_constant}"
    elif args.reference:
        reference, ref_desc = pellucid.read_image(args.reference).copy(), f"image {args.reference}"
    else:
        reference, ref_var, path = cached_reference(scene, base_dir, args.reference_renderer, args.reference_spp,
                                                    10_000 + args.seed, args.threads, cache_dir, mi_py)
        ref_spp = args.reference_spp if args.reference_renderer == "ours" else -(-args.reference_spp // 16) * 16
        ref_desc = (f"{ref_spp} spp by " +
                    ("pellucid mis" if args.reference_renderer == "ours" else "Mitsuba llvm_ad_rgb") +
                    f" (cached {pathlib.Path(path).name})")

    with_flip = not args.no_flip and flip_available()
    rows = run_ladder(scene, base_dir, name, methods, reference, ref_var, budgets=budgets, spp_ladder=spp_ladder,
                      threads=args.threads, seed=args.seed, mi_py=mi_py, with_flip=with_flip,
                      budget_mode=args.budget_mode)
    if not rows:
        print("pellucid bench: nothing was rendered", file=sys.stderr)
        return 1
    csv_p, chart_p, crops_p, summ_p = (out_dir / f"{name}.csv", out_dir / f"{name}_error.png",
                                       out_dir / f"{name}_crops.png", out_dir / f"{name}_summary.md")
    write_csv(rows, csv_p)
    ladder = (f"budgets {', '.join(f'{b:g}' for b in budgets)} s" if budgets else
              f"spp {', '.join(str(s) for s in spp_ladder)}")
    plot_chart(rows, chart_p, f"{name}: error against time ({ladder}; reference {ref_desc})")
    rung = args.crop_rung if args.crop_rung >= 0 else len(budgets or spp_ladder) - 1
    plot_crops(rows, reference, crops_p, rung, crop, args.exposure,
               f"{name}: " + ("equal time" if budgets else "equal spp") + f", rung {rung}")

    lines = [f"# {name}", "", "Regenerate with:", "", "    python -m pellucid bench " + " ".join(shlex.quote(a) for a in argv),
             "", f"- machine at start: {machine_at_start}; at end: {machine_note()}",
             f"- reference: {ref_desc}; its noise floor (relMSE): {rows[0].ref_relmse_floor:.3e}",
             f"- film filter: {json.dumps(scene.get('film', {}).get('filter', 'default'))}; budget mode: "
             f"{args.budget_mode if budgets else 'n/a'}",
             f"- ladder: {ladder}; threads: {args.threads or os.cpu_count()}; FLIP: {'yes' if with_flip else 'no (flip-evaluator not installed)'}",
             f"- wall time of the whole run: {time.perf_counter() - t_start:.0f} s", ""]
    for i in range(len(budgets or spp_ladder)):
        lines += [f"## rung {i} ({'budget %g s' % budgets[i] if budgets else '%d spp' % spp_ladder[i]})", ""]
        lines += equal_time_ratios(rows, i) + [""]

    if args.agreement_spp > 0:
        if mi_py is None:
            lines += ["Agreement: Mitsuba not set up; skipped.", ""]
        else:
            ours = run_ours(scene, base_dir, "mis", 20_000 + args.seed, args.threads, spp=args.agreement_spp,
                            variance=True)
            theirs = run_mitsuba(mi_py, scene, base_dir, "llvm_ad_rgb", -(-args.agreement_spp // 16) * 16,
                                 30_000 + args.seed, args.threads, passes=16)
            frac, zc = z_test(ours.image, ours.variance, theirs.image, theirs.variance)
            verdict = "PASS" if frac >= 0.99 else "FAIL"
            msg = (f"Agreement with Mitsuba llvm_ad_rgb ({args.agreement_spp} spp each, Mitsuba's variance from 16 "
                   f"passes): {100 * frac:.2f} % of pixel channels within |z| <= {zc:.2f} (two-sided alpha = 0.01, "
                   f"Sidak-corrected) -> {verdict} (threshold 99 %)")
            print(msg)
            lines += ["## Agreement", "", msg, ""]
            ratio = np.mean(ours.image) / max(np.mean(theirs.image), 1e-30)
            lines += [f"Mean image ratio pellucid / Mitsuba: {ratio:.4f}", ""]
    summ_p.write_text("\n".join(lines))
    for p in (csv_p, chart_p, crops_p, summ_p):
        print("wrote", p)
    print("\n".join(lines))
    return 0


if __name__ == "__main__":
    sys.exit(main())
