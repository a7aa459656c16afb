"""Regenerate the BxDF charts and CSV tables in bench/results/bxdf/ (one command, ~1 minute on 2 cores):

    python bench/bxdf/make_charts.py

Everything goes through ``pellucid.bsdf`` (C++ loops, GIL released). Albedos are directional
albedos ρ(wo) = mean sample weight (pellucid's ``albedo``: fixed seed, delta lobes included),
in Radiance mode unless a chart says otherwise; "white" configurations set every reflectance to 1
so that the value is the energy the model keeps. Timings come from ``bsdf.benchmark(n)``: a
single-thread C++ loop over n pre-generated random inputs (no Python in the timed loop), wall
nanoseconds per call on whatever machine runs this script.
"""
from __future__ import annotations

import csv
import pathlib
import platform
import sys
import time

import numpy as np

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402

import pellucid  # noqa: E402

OUT = pathlib.Path(__file__).resolve().parents[1] / "results" / "bxdf"
N_SAMPLES = 65536  # per wo row: Monte Carlo standard error ~0.002 or less for most models
COS = np.linspace(0.02, 1.0, 25)

# One representative configuration per model (also the timing table's rows).
MODELS = {
    "lambertian": {"type": "lambertian", "reflectance": 1.0},
    "oren_nayar classic σ=30°": {"type": "oren_nayar", "variant": "classic", "sigma": 30, "reflectance": 1.0},
    "oren_nayar eon r=0.5": {"type": "oren_nayar", "variant": "eon", "roughness": 0.5, "reflectance": 1.0},
    "conductor Au": {"type": "conductor", "material": "Au"},
    "rough_conductor Au α=0.3": {"type": "rough_conductor", "material": "Au", "alpha": 0.3},
    "rough_conductor Au α=0.3 ms": {"type": "rough_conductor", "material": "Au", "alpha": 0.3,
                                    "multiple_scattering": True},
    "rough_conductor beckmann α=0.3": {"type": "rough_conductor", "material": "Au", "alpha": 0.3,
                                       "distribution": "beckmann"},
    "dielectric bk7": {"type": "dielectric"},
    "rough_dielectric α=0.3": {"type": "rough_dielectric", "alpha": 0.3},
    "rough_dielectric α=0.3 ms": {"type": "rough_dielectric", "alpha": 0.3, "multiple_scattering": True},
    "rough_dielectric beckmann α=0.3": {"type": "rough_dielectric", "alpha": 0.3, "distribution": "beckmann"},
    "thin_dielectric": {"type": "thin_dielectric"},
    "plastic white": {"type": "plastic", "diffuse_reflectance": 1.0},
    "rough_plastic white α=0.3": {"type": "rough_plastic", "diffuse_reflectance": 1.0, "alpha": 0.3},
    "rough_plastic beckmann α=0.3": {"type": "rough_plastic", "diffuse_reflectance": 1.0, "alpha": 0.3,
                                     "distribution": "beckmann"},
    "principled": {"type": "principled", "base_color": 1.0, "roughness": 0.5},
}


def wo_rows(cos: np.ndarray) -> np.ndarray:
    cos = np.asarray(cos, dtype=np.float64)
    return np.stack([np.sqrt(1 - cos**2), np.zeros_like(cos), cos], axis=1).astype(np.float32)


def albedo(desc: dict, cos: np.ndarray = COS, mode: str = "radiance", channel: int | None = None) -> np.ndarray:
    a = pellucid.bsdf(desc, mode).albedo(wo_rows(cos), N_SAMPLES)
    return a.mean(axis=1) if channel is None else a[:, channel]


def write_csv(name: str, header: list[str], rows) -> None:
    with open(OUT / f"{name}.csv", "w", newline="") as f:
        w = csv.writer(f)
        w.writerow(header)
        for r in rows:
            w.writerow([f"{v:.6g}" if isinstance(v, (float, np.floating)) else v for v in r])


def save(fig, name: str) -> None:
    fig.tight_layout()
    fig.savefig(OUT / f"{name}.png", dpi=110)
    plt.close(fig)


def curves_csv(name: str, x_name: str, x: np.ndarray, curves: dict) -> None:
    write_csv(name, [x_name] + list(curves), [[xi] + [c[i] for c in curves.values()] for i, xi in enumerate(x)])


# ---- charts ------------------------------------------------------------------------------------------------
def chart_albedo_vs_cos(notes: list) -> None:
    curves = {name: albedo(d) for name, d in MODELS.items()}
    curves_csv("albedo_vs_cos", "cos_theta_o", COS, curves)
    fig, ax = plt.subplots(figsize=(8, 5))
    for i, (name, a) in enumerate(curves.items()):
        ax.plot(COS, a, label=name, color=plt.cm.tab20(i / 20), ls="--" if "dielectric" in name else "-")
    ax.set(xlabel="cos θo", ylabel="directional albedo (mean over RGB)", ylim=(0, 1.5),
           title="Directional albedo per model (white / Au; radiance mode: glass transmits T/η²)")
    ax.legend(fontsize=7, ncol=2)
    save(fig, "albedo_vs_cos")
    p = curves["principled"]
    notes.append(f"principled (base 1, roughness 0.5): albedo {p[0]:.3f} at cos θo = {COS[0]:.2f}, "
                 f"{p[-1]:.3f} at normal incidence (Burley's retro-reflection exceeds 1 at grazing)")


def chart_roughness_ladder(notes: list) -> None:
    alphas = [0.01, 0.05, 0.1, 0.25, 0.5, 0.75, 1.0]
    fams = {
        "rough_conductor (F=1, single scattering)": lambda a: {"type": "rough_conductor", "alpha": a},
        "rough_conductor (F=1, Kulla–Conty)": lambda a: {"type": "rough_conductor", "alpha": a,
                                                        "multiple_scattering": True},
        "rough_dielectric bk7 (importance mode)": lambda a: {"type": "rough_dielectric", "alpha": a},
        "rough_plastic white coupled": lambda a: {"type": "rough_plastic", "alpha": a, "diffuse_reflectance": 1.0},
    }
    fig, axes = plt.subplots(2, 2, figsize=(10, 7), sharex=True)
    rows = []
    for ax, (fam, make) in zip(axes.flat, fams.items()):
        mode = "importance" if "importance" in fam else "radiance"
        for a in alphas:
            v = albedo(make(a), mode=mode)
            rows += [[fam, a, c, x] for c, x in zip(COS, v)]
            ax.plot(COS, v, label=f"α={a}", color=plt.cm.viridis(a))
        ax.set(title=fam, ylim=(0, 1.1), xlabel="cos θo", ylabel="albedo")
        ax.legend(fontsize=7)
    save(fig, "roughness_ladder")
    write_csv("roughness_ladder", ["family", "alpha", "cos_theta_o", "albedo"], rows)
    ss = {(r[1], r[2]): r[3] for r in rows if r[0].endswith("single scattering)")}
    notes.append(f"white GGX conductor loses energy with α: albedo at normal incidence {ss[(0.25, 1.0)]:.3f} "
                 f"(α=0.25), {ss[(0.5, 1.0)]:.3f} (α=0.5), {ss[(1.0, 1.0)]:.3f} (α=1)")


def chart_fresnel(notes: list) -> None:
    metals = ["Au", "Ag", "Cu", "Al", "Fe", "Cr"]
    cos = np.linspace(0.01, 1.0, 100)
    wo = wo_rows(cos)
    u = np.full((len(cos), 3), 0.5, dtype=np.float32)
    fig, (ax, ax2) = plt.subplots(1, 2, figsize=(11, 4.5))
    rows, worst = [], {}
    for i, m in enumerate(metals):
        col = f"C{i}"
        exact = pellucid.bsdf({"type": "conductor", "material": m}).sample(wo, u).weight.mean(axis=1)
        schl = pellucid.bsdf({"type": "conductor", "material": m, "fresnel": "schlick"}).sample(wo, u).weight.mean(axis=1)
        theta = np.degrees(np.arccos(cos))
        ax.plot(theta, exact, color=col, label=f"{m} exact")
        ax.plot(theta, schl, color=col, ls="--")
        ax2.plot(theta, schl - exact, color=col, label=m)
        worst[m] = (np.max(np.abs(schl - exact)), theta[np.argmax(np.abs(schl - exact))])
        rows += [[m, t, e, s] for t, e, s in zip(theta, exact, schl)]
    ax.set(xlabel="θ (degrees)", ylabel="F (mean RGB)", title="Conductor Fresnel: exact (solid) vs Schlick (dashed)")
    ax.legend(fontsize=7)
    ax2.axhline(0, color="k", lw=0.5)
    ax2.set(xlabel="θ (degrees)", ylabel="Schlick − exact", title="Schlick error (R0 = exact F(0°))")
    ax2.legend(fontsize=7)
    save(fig, "fresnel_schlick_vs_exact")
    write_csv("fresnel_schlick_vs_exact", ["metal", "theta_deg", "F_exact", "F_schlick"], rows)
    notes.append("Schlick vs exact conductor Fresnel, max |ΔF| (mean RGB): " +
                 ", ".join(f"{m} {w:.3f} at {t:.0f}°" for m, (w, t) in worst.items()))


def chart_oren_nayar(notes: list) -> None:
    fig, (ax, ax2) = plt.subplots(1, 2, figsize=(11, 4.5))
    rows = []
    for s in [0, 15, 30, 60, 90]:
        v = albedo({"type": "oren_nayar", "variant": "classic", "sigma": s, "reflectance": 1.0})
        ax.plot(COS, v, label=f"classic σ={s}°", color=plt.cm.Reds(0.3 + s / 130))
        rows += [["classic", s, c, x] for c, x in zip(COS, v)]
    for r in [0.25, 0.5, 1.0]:
        v = albedo({"type": "oren_nayar", "variant": "eon", "roughness": r, "reflectance": 1.0})
        ax.plot(COS, v, ls="--", label=f"eon r={r}", color=plt.cm.Blues(0.4 + r / 2))
        rows += [["eon", r, c, x] for c, x in zip(COS, v)]
    ax.set(xlabel="cos θo", ylabel="albedo (ρ = 1)", ylim=(0.5, 1.05), title="Oren–Nayar: white furnace")
    ax.legend(fontsize=7)
    # In-plane BRDF slice f·cos θi at θo = 60°, wi in the plane of incidence (θi < 0 = back side).
    th = np.radians(np.linspace(-89, 89, 179))
    wi = np.stack([np.sin(th), np.zeros_like(th), np.cos(th)], 1).astype(np.float32)
    wo = np.repeat(wo_rows([0.5]), len(th), axis=0)
    for desc, lab, ls in [({"type": "lambertian", "reflectance": 1.0}, "lambertian", ":"),
                          ({"type": "oren_nayar", "variant": "classic", "sigma": 30, "reflectance": 1.0}, "classic σ=30°", "-"),
                          ({"type": "oren_nayar", "variant": "eon", "roughness": 0.5, "reflectance": 1.0}, "eon r=0.5", "--"),
                          ({"type": "oren_nayar", "variant": "eon", "roughness": 1.0, "reflectance": 1.0}, "eon r=1", "--")]:
        f = pellucid.bsdf(desc).eval(wo, wi).mean(axis=1) / np.maximum(np.cos(th), 1e-6)
        ax2.plot(np.degrees(th), f * np.pi, ls=ls, label=lab)
    ax2.set(xlabel="θi in the plane of incidence (°; wo at +60°)", ylabel="π f / ρ", title="In-plane BRDF, θo = 60°")
    ax2.legend(fontsize=7)
    save(fig, "oren_nayar_classic_vs_eon")
    write_csv("oren_nayar_classic_vs_eon", ["variant", "sigma_deg_or_r", "cos_theta_o", "albedo"], rows)
    c30 = [r[3] for r in rows if r[0] == "classic" and r[1] == 30]
    e1 = [r[3] for r in rows if r[0] == "eon" and r[1] == 1.0]
    notes.append(f"Oren–Nayar white furnace: classic σ=30° albedo {min(c30):.3f}–{max(c30):.3f}; "
                 f"EON r=1 {min(e1):.4f}–{max(e1):.4f}")


def chart_kulla_conty(notes: list) -> None:
    fig, ax = plt.subplots(figsize=(7, 4.5))
    rows = []
    for i, a in enumerate([0.1, 0.25, 0.5, 1.0]):
        for ms in (False, True):
            for metal in ("none", "Au"):
                v = albedo({"type": "rough_conductor", "material": metal, "alpha": a, "multiple_scattering": ms})
                rows += [[metal, a, ms, c, x] for c, x in zip(COS, v)]
                if metal == "none":
                    ax.plot(COS, v, color=f"C{i}", ls="-" if ms else "--", label=f"α={a} {'KC' if ms else 'single'}")
    ax.set(xlabel="cos θo", ylabel="albedo (F = 1)", ylim=(0, 1.1),
           title="GGX conductor, Kulla–Conty on (solid) / off (dashed)")
    ax.legend(fontsize=7, ncol=2)
    save(fig, "kulla_conty")
    write_csv("kulla_conty", ["metal", "alpha", "multiple_scattering", "cos_theta_o", "albedo"], rows)
    on = [r[4] for r in rows if r[0] == "none" and r[2]]
    au = {(r[1], r[2]): r[4] for r in rows if r[0] == "Au" and r[3] == COS[-1]}
    notes.append(f"Kulla–Conty white furnace over α∈[0.1,1], all cos θo: {min(on):.4f}–{max(on):.4f}; "
                 f"gold α=1 at normal incidence {au[(1.0, False)]:.3f} → {au[(1.0, True)]:.3f}")


def chart_kulla_conty_dielectric(notes: list) -> None:
    """White rough glass (GGX, η = 1.5) R+T in Importance mode (energy), from outside (cos θo > 0) and
    inside (cos θo < 0), Kulla–Conty off (dashed) and on (solid)."""
    fig, axes = plt.subplots(1, 2, figsize=(11, 4.5), sharey=True)
    rows = []
    for ax, side in zip(axes, (1.0, -1.0)):
        for i, a in enumerate([0.1, 0.3, 0.6, 1.0]):
            for ms in (False, True):
                v = albedo({"type": "rough_dielectric", "int_ior": 1.5, "ext_ior": 1.0, "alpha": a,
                            "multiple_scattering": ms}, cos=side * COS, mode="importance")
                rows += [[a, ms, side * c, x] for c, x in zip(COS, v)]
                ax.plot(COS, v, color=f"C{i}", ls="-" if ms else "--", label=f"α={a} {'KC' if ms else 'single'}")
        ax.set(xlabel="|cos θo|", ylabel="R + T (importance mode)", ylim=(0.3, 1.05),
               title=f"GGX glass η=1.5, wo {'outside' if side > 0 else 'inside'}; KC solid, single dashed")
        ax.legend(fontsize=7, ncol=2)
    save(fig, "kulla_conty_dielectric")
    write_csv("kulla_conty_dielectric", ["alpha", "multiple_scattering", "cos_theta_o", "albedo_R_plus_T"], rows)
    on = [r[3] for r in rows if r[1] and abs(r[2]) >= 0.1]
    off = [r[3] for r in rows if not r[1] and abs(r[2]) >= 0.1]
    notes.append(f"rough dielectric (GGX, η=1.5) white furnace R+T over α∈[0.1,1], |cos θo|∈[0.1,1], both sides: "
                 f"single scattering {min(off):.3f}–{max(off):.3f}, Kulla–Conty {min(on):.4f}–{max(on):.4f}")


def chart_plastic(notes: list) -> None:
    fig, axes = plt.subplots(1, 2, figsize=(11, 4.5), sharey=True)
    rows, diffs = [], []
    for ax, (kind, extra) in zip(axes, [("plastic", {}), ("rough_plastic", {"alpha": 0.3})]):
        for i, kd in enumerate([0.2, 0.5, 0.9]):
            vals = {}
            for var in ("coupled", "sum"):
                d = {"type": kind, "diffuse_reflectance": kd, "specular_reflectance": 1.0, "variant": var, **extra}
                vals[var] = albedo(d)
                ax.plot(COS, vals[var], color=f"C{i}", ls="-" if var == "coupled" else "--",
                        label=f"Kd={kd} {var}")
                rows += [[kind, kd, var, c, x] for c, x in zip(COS, vals[var])]
            diffs.append((kind, kd, np.max(np.abs(vals["sum"] - vals["coupled"])),
                          np.max(vals["sum"] / np.maximum(vals["coupled"], 1e-6))))
        ax.set(title=f"{kind}: coupled (solid) vs sum (dashed), Ks = 1", xlabel="cos θo", ylabel="albedo")
        ax.legend(fontsize=7)
    save(fig, "plastic_sum_vs_coupled")
    write_csv("plastic_sum_vs_coupled", ["model", "Kd", "variant", "cos_theta_o", "albedo"], rows)
    write_csv("plastic_sum_vs_coupled_summary", ["model", "Kd", "max_abs_diff", "max_ratio_sum_over_coupled"], diffs)
    notes.append("plastic sum vs coupled, max |Δalbedo|: " +
                 ", ".join(f"{k} Kd={kd}: {d:.3f} (×{r:.2f})" for k, kd, d, r in diffs))


def chart_timing(notes: list) -> list:
    rows = []
    for name, d in MODELS.items():
        t = pellucid.bsdf(d).benchmark(200_000)
        rows.append([name, t["ns_eval"], t["ns_pdf"], t["ns_sample"]])
    write_csv("timing_ns", ["model", "ns_eval", "ns_pdf", "ns_sample"], rows)
    fig, ax = plt.subplots(figsize=(9, 5))
    y = np.arange(len(rows))
    for k, lab in enumerate(["eval", "pdf", "sample"]):
        ax.barh(y + (k - 1) * 0.27, [r[k + 1] for r in rows], height=0.27, label=lab)
    ax.set_yticks(y, [r[0] for r in rows], fontsize=7)
    ax.invert_yaxis()
    ax.set(xlabel="ns per call (single thread, C++ loop)", title=f"BxDF cost ({platform.processor() or platform.machine()})")
    ax.legend()
    save(fig, "timing_ns")
    return rows


def main() -> int:
    OUT.mkdir(parents=True, exist_ok=True)
    t0 = time.time()
    notes: list = []
    for chart in (chart_albedo_vs_cos, chart_roughness_ladder, chart_fresnel, chart_oren_nayar, chart_kulla_conty,
                  chart_kulla_conty_dielectric, chart_plastic):
        chart(notes)
        print(f"{chart.__name__}: {time.time() - t0:.1f} s", flush=True)
    timing = chart_timing(notes)
    lines = ["# BxDF charts (generated by bench/bxdf/make_charts.py; do not edit)", "",
             f"pellucid {pellucid.__version__}, {N_SAMPLES} samples per albedo point, "
             f"{time.time() - t0:.0f} s total.", "", "## Highlights", ""]
    lines += [f"- {n}" for n in notes]
    lines += ["", "## ns per call (single thread, C++ loop over 200k random inputs; `bsdf.benchmark`)", "",
              "| model | eval | pdf | sample |", "|---|---|---|---|"]
    lines += [f"| {r[0]} | {r[1]:.1f} | {r[2]:.1f} | {r[3]:.1f} |" for r in timing]
    (OUT / "README.md").write_text("\n".join(lines) + "\n")
    print("\n".join(lines))
    return 0


if __name__ == "__main__":
    sys.exit(main())
