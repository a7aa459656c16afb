"""pellucid's BxDFs against Mitsuba 3's: directional albedo vs cos θo and in-plane lobe slices.

    bench/.venv-mitsuba/bin/python bench/bxdf/compare_mitsuba.py     # or
    .venv/bin/python bench/bxdf/compare_mitsuba.py

Either interpreter works: the Mitsuba side runs in the peer venv (bench/peers/setup_mitsuba.sh;
MITSUBA_PY overrides its path), the pellucid side and the chart in the project's .venv (PELLUCID_PY
overrides), and the two exchange one .npz file. Writes bench/results/bxdf/mitsuba_albedo.csv,
mitsuba_lobes.csv, mitsuba_summary.csv, mitsuba_comparison.png and prints the summary table that
docs/materials.md quotes.

Conventions: both `eval` return f·|cos θi|; Mitsuba's si.wi is our wo and its `wo` argument our wi;
both work in the local frame with z = normal and the tangent (alpha_u) along x; Radiance mode in
both (refraction scaled by 1/η'²). Albedo = mean sample weight over N_SAMPLES samples per cos θo
(delta lobes included). Lobe slices: wo at θo ∈ {30°, 60°} in the xz plane (φ = 0), wi in the same
plane at signed θi ∈ (−180°, 180°) (θi < 0 = the side away from wo, θi beyond ±90° = transmission).
Every model is configured with the same explicit parameters on both sides (η, k, α, colours), so a
difference is a difference in the definition, listed in NOTES.
"""
from __future__ import annotations

import csv
import os
import pathlib
import subprocess
import sys
import tempfile

import numpy as np

ROOT = pathlib.Path(__file__).resolve().parents[2]
OUT = ROOT / "bench" / "results" / "bxdf"
MITSUBA_PY = os.environ.get("MITSUBA_PY", str(ROOT / "bench" / ".venv-mitsuba" / "bin" / "python"))
PELLUCID_PY = os.environ.get("PELLUCID_PY", str(ROOT / ".venv" / "bin" / "python"))
N_SAMPLES = 1 << 16
COS = np.linspace(0.05, 1.0, 20)
THETA_O = (30.0, 60.0)
THETA_I = np.linspace(-179, 179, 180)  # 2° steps

ETA_K = ([0.2, 0.45, 1.4], [3.6, 2.4, 1.8])  # an explicit gold-like complex IOR


def _rgb(v):
    return {"type": "rgb", "value": [float(v)] * 3 if np.isscalar(v) else [float(x) for x in v]}


# name -> (pellucid dict, Mitsuba dict, note on the definitions)
MODELS = {
    "diffuse": ({"type": "lambertian", "reflectance": 0.8},
                {"type": "diffuse", "reflectance": _rgb(0.8)}, "same definition"),
    "conductor eta/k": ({"type": "conductor", "eta": ETA_K[0], "k": ETA_K[1]},
                        {"type": "conductor", "eta": _rgb(ETA_K[0]), "k": _rgb(ETA_K[1])}, "same definition"),
    "conductor Au (named)": ({"type": "conductor", "material": "Au"}, {"type": "conductor", "material": "Au"},
                             "named-metal data: ours RGB = (η, k) at 650/550/450 nm (Johnson & Christy); "
                             "Mitsuba integrates its spectral table against the RGB response"),
    "roughconductor ggx α=0.3": ({"type": "rough_conductor", "eta": ETA_K[0], "k": ETA_K[1], "alpha": 0.3},
                                 {"type": "roughconductor", "eta": _rgb(ETA_K[0]), "k": _rgb(ETA_K[1]),
                                  "distribution": "ggx", "alpha": 0.3}, "G"),
    "roughconductor beckmann α=0.3": ({"type": "rough_conductor", "eta": ETA_K[0], "k": ETA_K[1], "alpha": 0.3,
                                       "distribution": "beckmann"},
                                      {"type": "roughconductor", "eta": _rgb(ETA_K[0]), "k": _rgb(ETA_K[1]),
                                       "distribution": "beckmann", "alpha": 0.3}, "G"),
    "roughconductor ggx α=0.1×0.4": ({"type": "rough_conductor", "eta": ETA_K[0], "k": ETA_K[1], "alpha_u": 0.1,
                                      "alpha_v": 0.4},
                                     {"type": "roughconductor", "eta": _rgb(ETA_K[0]), "k": _rgb(ETA_K[1]),
                                      "distribution": "ggx", "alpha_u": 0.1, "alpha_v": 0.4}, "G"),
    "roughconductor beckmann α=0.1×0.4": ({"type": "rough_conductor", "eta": ETA_K[0], "k": ETA_K[1],
                                           "alpha_u": 0.1, "alpha_v": 0.4, "distribution": "beckmann"},
                                          {"type": "roughconductor", "eta": _rgb(ETA_K[0]), "k": _rgb(ETA_K[1]),
                                           "distribution": "beckmann", "alpha_u": 0.1, "alpha_v": 0.4}, "G"),
    "dielectric η=1.5": ({"type": "dielectric", "int_ior": 1.5, "ext_ior": 1.0},
                         {"type": "dielectric", "int_ior": 1.5, "ext_ior": 1.0}, "same definition"),
    "thindielectric η=1.5": ({"type": "thin_dielectric", "int_ior": 1.5, "ext_ior": 1.0},
                             {"type": "thindielectric", "int_ior": 1.5, "ext_ior": 1.0}, "same definition"),
    "roughdielectric ggx α=0.3": ({"type": "rough_dielectric", "int_ior": 1.5, "ext_ior": 1.0, "alpha": 0.3},
                                  {"type": "roughdielectric", "int_ior": 1.5, "ext_ior": 1.0, "distribution": "ggx",
                                   "alpha": 0.3}, "G"),
    "roughdielectric beckmann α=0.3": ({"type": "rough_dielectric", "int_ior": 1.5, "ext_ior": 1.0, "alpha": 0.3,
                                        "distribution": "beckmann"},
                                       {"type": "roughdielectric", "int_ior": 1.5, "ext_ior": 1.0,
                                        "distribution": "beckmann", "alpha": 0.3}, "G"),
    "plastic": ({"type": "plastic", "diffuse_reflectance": 0.5, "int_ior": 1.5, "ext_ior": 1.0},
                {"type": "plastic", "diffuse_reflectance": _rgb(0.5), "int_ior": 1.5, "ext_ior": 1.0,
                 "nonlinear": True}, "same definition (Mitsuba with nonlinear = true; its default false uses "
                                     "Kd/(1 − F_dri) instead of Kd/(1 − Kd F_dri))"),
    "roughplastic ggx α=0.2": ({"type": "rough_plastic", "diffuse_reflectance": 0.5, "int_ior": 1.5,
                                "ext_ior": 1.0, "alpha": 0.2},
                               {"type": "roughplastic", "diffuse_reflectance": _rgb(0.5), "int_ior": 1.5,
                                "ext_ior": 1.0, "distribution": "ggx", "alpha": 0.2, "nonlinear": True}, "RP"),
    "roughplastic beckmann α=0.2": ({"type": "rough_plastic", "diffuse_reflectance": 0.5, "int_ior": 1.5,
                                     "ext_ior": 1.0, "alpha": 0.2, "distribution": "beckmann"},
                                    {"type": "roughplastic", "diffuse_reflectance": _rgb(0.5), "int_ior": 1.5,
                                     "ext_ior": 1.0, "distribution": "beckmann", "alpha": 0.2, "nonlinear": True},
                                    "RP"),
    "principled dielectric r=0.5": ({"type": "principled", "base_color": 0.8, "roughness": 0.5, "metallic": 0.0,
                                     "specular": 0.5, "specular_tint": 0.0, "sheen": 0.0, "clearcoat": 0.0},
                                    {"type": "principled", "base_color": _rgb(0.8), "roughness": 0.5,
                                     "metallic": 0.0, "specular": 0.5, "spec_tint": 0.0, "sheen": 0.0,
                                     "clearcoat": 0.0}, "PR"),
    "principled metal r=0.4": ({"type": "principled", "base_color": [0.9, 0.6, 0.3], "roughness": 0.4,
                                "metallic": 1.0, "specular": 0.5, "specular_tint": 0.0, "sheen": 0.0, "clearcoat": 0.0},
                               {"type": "principled", "base_color": _rgb([0.9, 0.6, 0.3]), "roughness": 0.4,
                                "metallic": 1.0, "specular": 0.5, "spec_tint": 0.0, "sheen": 0.0, "clearcoat": 0.0},
                               "PR"),
}
NOTES = {
    "G": "Smith G: ours height-correlated 1/(1 + Λo + Λi) (Heitz 2014 eq. 99), Mitsuba separable G1·G1 "
         "(eq. 98): Mitsuba is darker at grazing pairs; the sampled lobes are the same VNDF",
    "RP": "diffuse base: Mitsuba weights it by its tabulated rough-coat transmittance 1 − E_coat(θ) (energy the "
          "rough coat does not reflect, masking losses included: its albedo rises at grazing), ours by the "
          "smooth-interface 1 − F(θ) (plastic.h; loses energy at grazing); plus G as above",
    "PR": "Mitsuba's principled is the 2015 Disney BSDF (its own Fresnel blend of dielectric and Schlick "
          "terms, separable G, GTR2 specular lobes mixed differently); ours is Burley 2012 (principled.h)",
}


def wo_dirs(cos):
    cos = np.asarray(cos, dtype=np.float64)
    return np.stack([np.sqrt(np.maximum(0.0, 1 - cos**2)), np.zeros_like(cos), cos], axis=1).astype(np.float32)


def slice_dirs():
    """(len(THETA_O) * len(THETA_I), 3) wo and wi arrays of the in-plane slices."""
    wo, wi = [], []
    for to in THETA_O:
        t = np.radians(to)
        for ti in THETA_I:
            s = np.radians(ti)
            wo.append([np.sin(t), 0.0, np.cos(t)])
            wi.append([-np.sin(s), 0.0, np.cos(s)])  # θi > 0: the mirror side of wo
    return np.array(wo, np.float32), np.array(wi, np.float32)


# ---- Mitsuba side (peer venv) ------------------------------------------------------------------
def mitsuba_side(out: str) -> None:
    for p in ("/usr/lib/x86_64-linux-gnu/libLLVM.so.19.1", "/usr/lib/x86_64-linux-gnu/libLLVM-19.so.1"):
        if "DRJIT_LIBLLVM_PATH" not in os.environ and os.path.exists(p):
            os.environ["DRJIT_LIBLLVM_PATH"] = p
    import drjit as dr
    import mitsuba as mi

    mi.set_variant("llvm_ad_rgb")
    rng = np.random.default_rng(1)
    res = {"version": np.array(mi.__version__)}

    def interaction(wo):
        si = dr.zeros(mi.SurfaceInteraction3f, len(wo))
        si.wi = mi.Vector3f(*[wo[:, k].astype(np.float32) for k in range(3)])
        si.sh_frame = mi.Frame3f(mi.Vector3f(0, 0, 1))
        si.n = mi.Normal3f(0, 0, 1)
        return si

    ctx = mi.BSDFContext()
    wos = np.repeat(wo_dirs(COS), N_SAMPLES, axis=0)
    swo, swi = slice_dirs()
    for name, (_, desc, _) in MODELS.items():
        bsdf = mi.load_dict(desc)
        u1 = rng.random(len(wos), dtype=np.float32)
        u2 = rng.random((len(wos), 2), dtype=np.float32)
        _, w = bsdf.sample(ctx, interaction(wos), mi.Float(u1), mi.Point2f(u2[:, 0], u2[:, 1]))
        # (a Dr.Jit literal, e.g. the zero eval of a delta lobe, comes back with width 1: broadcast)
        w = np.nan_to_num(np.broadcast_to(np.array(w).T, (len(wos), 3)), nan=0.0, posinf=0.0)
        w = w.reshape(len(COS), N_SAMPLES, 3).astype(np.float64)  # float32 sums along axis 1 lose 1e-3
        res[f"albedo/{name}"] = w.mean(axis=1)
        res[f"albedo_se/{name}"] = w.std(axis=1) / np.sqrt(N_SAMPLES)
        f = bsdf.eval(ctx, interaction(swo), mi.Vector3f(*[swi[:, k] for k in range(3)]))
        res[f"lobe/{name}"] = np.broadcast_to(np.array(f).T, (len(swo), 3)).copy()
        print(f"mitsuba: {name}", flush=True)
    np.savez(out, **res)


# ---- pellucid side, comparison and chart (project venv) ------------------------------------------
def report(mitsuba_npz: str) -> int:
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    import pellucid

    mi_res = np.load(mitsuba_npz)
    rng = np.random.default_rng(2)
    OUT.mkdir(parents=True, exist_ok=True)
    swo, swi = slice_dirs()
    th = np.degrees(np.arccos(np.clip(swo[:, 2], -1, 1)))
    alb_rows, lobe_rows, summary = [], [], []
    n = len(MODELS)
    cols = 4
    fig, axes = plt.subplots(int(np.ceil(n / cols)) * 2, cols, figsize=(16, 3.2 * 2 * int(np.ceil(n / cols))))
    for idx, (name, (ours_desc, _, note_key)) in enumerate(MODELS.items()):
        b = pellucid.bsdf(ours_desc)
        w = b.sample(np.repeat(wo_dirs(COS), N_SAMPLES, axis=0),
                     rng.random((len(COS) * N_SAMPLES, 3), dtype=np.float32)).weight
        w = np.nan_to_num(w.reshape(len(COS), N_SAMPLES, 3).astype(np.float64))
        ours_a, ours_se = w.mean(axis=1), w.std(axis=1) / np.sqrt(N_SAMPLES)
        ours_f = b.eval(swo, swi)
        mi_a, mi_se, mi_f = mi_res[f"albedo/{name}"], mi_res[f"albedo_se/{name}"], mi_res[f"lobe/{name}"]
        diff = np.abs(ours_a - mi_a)
        z = float((diff / np.sqrt(ours_se**2 + mi_se**2 + 1e-12)).max())
        da = diff.max(axis=1)
        k = int(np.argmax(da))
        peak = max(float(np.abs(mi_f).max()), float(np.abs(ours_f).max()), 1e-12)
        dl = float(np.abs(ours_f - mi_f).max() / peak) if peak > 1e-9 else 0.0
        note = NOTES.get(note_key, note_key)
        summary.append([name, float(da[k]), float(COS[k]), z, dl, note])
        for c, oa, ma, os_, ms_ in zip(COS, ours_a, mi_a, ours_se, mi_se):
            alb_rows.append([name, c, *oa, *ma, *os_, *ms_])
        for i in range(len(swo)):
            lobe_rows.append([name, th[i], THETA_I[i % len(THETA_I)], *ours_f[i], *mi_f[i]])
        r, c = divmod(idx, cols)
        ax = axes[2 * r, c]
        ax.plot(COS, ours_a.mean(axis=1), "C0-", label="pellucid")
        ax.plot(COS, mi_a.mean(axis=1), "C3--", label="Mitsuba")
        ax.set_title(name, fontsize=8)
        ax.set_xlabel("cos θo", fontsize=7)
        ax.set_ylabel("albedo (mean RGB)", fontsize=7)
        ax.legend(fontsize=6)
        ax = axes[2 * r + 1, c]
        m = len(THETA_I)
        for j, to in enumerate(THETA_O):
            ax.plot(THETA_I, ours_f[j * m:(j + 1) * m].mean(axis=1), f"C{j}-", lw=1, label=f"ours θo={to:.0f}°")
            ax.plot(THETA_I, mi_f[j * m:(j + 1) * m].mean(axis=1), f"C{j}--", lw=1, label=f"Mitsuba θo={to:.0f}°")
        ax.set_yscale("symlog", linthresh=1e-2)
        ax.set_xlabel("signed θi in the plane (°)", fontsize=7)
        ax.set_ylabel("f·|cos θi|", fontsize=7)
        ax.legend(fontsize=5)
    for r in range(axes.shape[0] // 2):
        for c in range(cols):
            if r * cols + c >= n:
                axes[2 * r, c].axis("off")
                axes[2 * r + 1, c].axis("off")
    fig.suptitle(f"pellucid {pellucid.__version__} vs Mitsuba {mi_res['version']} (llvm_ad_rgb), "
                 f"{N_SAMPLES} samples per albedo point; lobes at θo = 30°, 60°", fontsize=10)
    fig.tight_layout(rect=(0, 0, 1, 0.985))
    fig.savefig(OUT / "mitsuba_comparison.png", dpi=70)

    def write(name, header, rows):
        with open(OUT / name, "w", newline="") as f:
            w = csv.writer(f)
            w.writerow(header)
            for row in rows:
                w.writerow([f"{v:.6g}" if isinstance(v, (float, np.floating)) else v for v in row])

    write("mitsuba_albedo.csv", ["model", "cos_theta_o", "ours_r", "ours_g", "ours_b", "mitsuba_r", "mitsuba_g",
                                 "mitsuba_b", "ours_se_r", "ours_se_g", "ours_se_b", "mitsuba_se_r", "mitsuba_se_g",
                                 "mitsuba_se_b"], alb_rows)
    write("mitsuba_lobes.csv", ["model", "theta_o_deg", "theta_i_signed_deg", "ours_r", "ours_g", "ours_b",
                                "mitsuba_r", "mitsuba_g", "mitsuba_b"], lobe_rows)
    write("mitsuba_summary.csv", ["model", "max_abs_albedo_diff", "at_cos_theta_o", "max_albedo_z",
                                  "max_lobe_diff_rel_peak", "explanation"], summary)
    lines = ["| model | max \\|Δ albedo\\| (at cos θo) | max z | max \\|Δ f·cos\\| / peak | explanation |",
             "|---|---|---|---|---|"]
    for name, da, c, z, dl, note in summary:
        lines.append(f"| {name} | {da:.4f} ({c:.2f}) | {z:.1f} | {dl:.3f} | {note} |")
    print("\n".join(lines))
    print("z = |Δ albedo| / combined Monte Carlo standard error, max over cos θo and RGB "
          f"({len(COS) * 3} comparisons: |z| < 4 is agreement within noise)")
    return 0


def main() -> int:
    if len(sys.argv) == 3 and sys.argv[1] == "--mitsuba-side":
        mitsuba_side(sys.argv[2])
        return 0
    if len(sys.argv) == 3 and sys.argv[1] == "--report":
        return report(sys.argv[2])
    with tempfile.TemporaryDirectory() as td:
        npz = os.path.join(td, "mitsuba.npz")
        try:
            import mitsuba  # noqa: F401

            mitsuba_side(npz)
        except ImportError:
            subprocess.run([MITSUBA_PY, __file__, "--mitsuba-side", npz], check=True)
        try:
            import matplotlib  # noqa: F401
            import pellucid  # noqa: F401

            return report(npz)
        except ImportError:
            return subprocess.run([PELLUCID_PY, __file__, "--report", npz]).returncode


if __name__ == "__main__":
    sys.exit(main())
