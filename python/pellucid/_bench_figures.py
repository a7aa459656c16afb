"""Figures of the speed-against-accuracy harness (pellucid.bench): error chart and equal-time crops.
SPDX-License-Identifier: Apache-2.0
"""
from __future__ import annotations

import pathlib
from typing import Optional, Sequence, Tuple

import numpy as np

from .image import srgb_encode

MITSUBA = ("scalar_rgb", "llvm_ad_rgb")


_STYLE = {"bsdf": ("tab:orange", "o"), "nee": ("tab:green", "s"), "mis": ("tab:blue", "D"),
          "direct": ("tab:gray", "v"), "scalar_rgb": ("tab:red", "^"), "llvm_ad_rgb": ("tab:purple", "P")}


def label(method: str) -> str:
    return f"Mitsuba 3 {method}" if method in MITSUBA else f"pellucid {method}"


def plot_chart(rows: Sequence, path: pathlib.Path, title: str) -> None:
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    has_flip = any(r.flip is not None for r in rows)
    fig, axes = plt.subplots(1, 2 if has_flip else 1, figsize=(11 if has_flip else 6.5, 4.6), squeeze=False)
    for ax, key, ylabel in zip(axes[0], ("relmse", "flip"), ("relMSE  (x-r)²/(r²+0.01)", "mean HDR-FLIP")):
        for m in dict.fromkeys(r.method for r in rows):
            pts = sorted((r.seconds, getattr(r, key)) for r in rows if r.method == m and getattr(r, key) is not None)
            if not pts:
                continue
            c, mk = _STYLE.get(m, (None, "x"))
            ax.loglog(*zip(*pts), marker=mk, color=c, label=label(m))
        if key == "relmse" and rows and rows[0].ref_relmse_floor > 0:
            ax.axhline(rows[0].ref_relmse_floor, color="k", ls=":", lw=1, label="reference noise floor")
        ax.set_xlabel("render time [s]")
        ax.set_ylabel(ylabel)
        ax.grid(True, which="both", alpha=0.3)
        ax.legend(fontsize=8)
    fig.suptitle(title, fontsize=10)
    fig.tight_layout()
    path.parent.mkdir(parents=True, exist_ok=True)
    fig.savefig(path, dpi=90)
    plt.close(fig)


def tonemap(img: np.ndarray, exposure: float = 1.0) -> np.ndarray:
    """Clamp and sRGB-encode linear radiance to [0, 1]."""
    return srgb_encode(np.clip(np.nan_to_num(np.asarray(img, np.float64) * exposure), 0.0, 1.0))


def plot_crops(rows: Sequence, reference, path: pathlib.Path, rung: int,
               crop: Optional[Tuple[int, int, int, int]] = None, exposure: float = 1.0, title: str = "") -> None:
    """A strip of crops at one rung (equal time when the ladder is in seconds), reference last."""
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    sel = [r for r in rows if r.rung == rung and r.image is not None]
    if not sel:
        return
    H, W = sel[0].image.shape[:2]
    x, y, w, h = crop if crop else (W // 4, H // 4, W // 2, H // 2)
    tiles = [(f"{label(r.method)}\n{r.seconds:.1f} s, {r.spp} spp\nrelMSE {r.relmse:.2e}", r.image) for r in sel]
    if np.ndim(reference):
        tiles.append(("reference", np.asarray(reference)))
    fig, axes = plt.subplots(1, len(tiles), figsize=(2.3 * len(tiles), 2.3 * h / w + 0.9), squeeze=False)
    for ax, (lab, im) in zip(axes[0], tiles):
        ax.imshow(tonemap(im[y:y + h, x:x + w], exposure), interpolation="nearest")
        ax.set_title(lab, fontsize=7)
        ax.axis("off")
    if title:
        fig.suptitle(title, fontsize=9)
    fig.tight_layout()
    path.parent.mkdir(parents=True, exist_ok=True)
    fig.savefig(path, dpi=100)
    plt.close(fig)
