"""Reduce measured spectral (η, k) of named conductors to linear sRGB; print the C++ table of
cpp/pellucid/bxdf/ior.cpp.

    python tools/conductor_rgb.py DIR [DIR ...] [--cpp FILE] [--json FILE]

Each DIR holds pairs NAME.eta.spd / NAME.k.spd: lines "wavelength_nm value", '#' starts a comment.
Mitsuba 3's data/ior/ folder (the luxpop.com set) is one such directory, tools/ior/ (Fe, Ti, Ni
from Johnson & Christy 1974) another; a name in a later DIR replaces the same name in an earlier one.

The reduction, per spectrum v(λ) (η or k):
  1. λ_i = 360 + 470 i / 999 nm, i = 0..999; samples outside the data's [λ_min, λ_max] are skipped
     (they count as v = 0), inside v is linearly interpolated between the tabulated points;
  2. XYZ = Σ_i cmf(λ_i) v(λ_i) / Σ_i ȳ(λ_i), the sums over all i, with cmf the CIE 1931 2°
     colour-matching functions (1 nm table, linearly interpolated) and no illuminant, so v ≡ 1
     gives Y = 1;
  3. linear sRGB = M XYZ, with M the inverse of the RGB → XYZ matrix of the ITU-R BT.709 primaries
     and the D65 white point (IEC 61966-2-1), computed below;
  4. negative channels are clamped to 0.
This is the procedure of Mitsuba 3's `spectrum_list_to_srgb` (src/core/spectrum.cpp, v3.9.1) with
its constants derived instead of tabulated: its normalisation 470/1000 / 106.75026 equals our
1 / Σ ȳ(λ_i) to 2e-6; it interpolates the CIE's 5 nm table (the 1 nm one at every fifth node) and
uses a rounded M. Those two make the only difference: at most 0.3 % in a channel of η or k above
0.05 and 2.4e-4 in the normal-incidence reflectance, over all of Mitsuba's names.

The CIE 1931 2° table comes from the `colour-science` package (`pip install colour-science`, a
tool-only dependency): colour.MSDS_CMFS["CIE 1931 2 Degree Standard Observer"], the CIE's 1 nm
tabulation 360-830 nm (CIE 015:2004 / ISO/CIE 11664-1, as distributed by the CVRL database).

The source of each name is read from its file's header (see SOURCES).
"""
from __future__ import annotations

import argparse
import json
import pathlib
import re
import sys
import textwrap
from typing import Dict, List, Tuple

import numpy as np

LAMBDA_MIN, LAMBDA_MAX, STEPS = 360.0, 830.0, 1000

# Source tags written next to each table row; the text is the citation block of the C++ table.
SOURCES = {
    "P85": "E. D. Palik (ed.), Handbook of Optical Constants of Solids, Academic Press, 1985",
    "P91": "E. D. Palik (ed.), Handbook of Optical Constants of Solids II, Academic Press, 1991",
    "PAL": "Palik's handbooks (P85 or P91, the file does not say which); in an X_llnl_cxro + X_palik "
           "file the CXRO/LLNL X-ray data lie below the visible",
    "LUX": "luxpop.com export with no source line (Mitsuba 3's documentation attributes its luxpop set "
           "to Palik's handbooks; Cu coincides with Cu_palik, P85, at Palik's wavelengths)",
    "JC74": "P. B. Johnson, R. W. Christy, \"Optical constants of transition metals: Ti, V, Cr, Mn, Fe, Co, "
            "Ni, and Pd\", Phys. Rev. B 9, 5056 (1974), via the refractiveindex.info database (CC0)",
}


def read_spd(path: pathlib.Path) -> Tuple[np.ndarray, np.ndarray, str]:
    """(wavelengths nm, values, header comment text) of one .spd file."""
    lam, val, header = [], [], []
    for line in path.read_text().splitlines():
        body, _, comment = line.partition("#")
        if comment:
            header.append(comment)
        parts = body.split()
        if not parts:
            continue
        if len(parts) != 2:
            raise ValueError(f"{path}: expected 'wavelength value', got {line!r}")
        lam.append(float(parts[0]))
        val.append(float(parts[1]))
    lam_a, val_a = np.array(lam), np.array(val)
    if lam_a.size < 2 or np.any(np.diff(lam_a) <= 0):
        raise ValueError(f"{path}: need at least two strictly increasing wavelengths")
    return lam_a, val_a, "\n".join(header)


def source_tag(name: str, header: str, directory: pathlib.Path) -> str:
    if "Johnson" in header and "Christy" in header and "1974" in header:
        return "JC74"
    if "Handbook of Optical Constants of Solids II" in header:
        return "P91"
    if "Handbook of Optical Constants of Solids'" in header:
        return "P85"
    m = re.search(r"(\S+)_llnl_cxro \+ (\S+)", header)
    if m:
        # X-ray data (CXRO/LLNL) joined to Palik's; 360-830 nm lies in Palik's part.
        palik = directory / f"{m.group(2)}.eta.spd"
        tag = source_tag(m.group(2), read_spd(palik)[2], directory) if palik.exists() else "PAL"
        return tag if tag in ("P85", "P91") else "PAL"
    return "PAL" if name.endswith("_palik") else "LUX"


def cie1931() -> Tuple[np.ndarray, np.ndarray]:
    """(wavelengths, (N, 3) x̄ ȳ z̄) of the CIE 1931 2° observer, 1 nm, 360-830 nm."""
    try:
        import colour
    except ImportError:
        sys.exit("conductor_rgb.py needs the CIE 1931 table of colour-science: pip install colour-science")
    cmfs = colour.MSDS_CMFS["CIE 1931 2 Degree Standard Observer"]
    return np.asarray(cmfs.wavelengths, dtype=float), np.asarray(cmfs.values, dtype=float)


def xyz_to_srgb_matrix() -> np.ndarray:
    """Inverse of the BT.709/D65 RGB → XYZ matrix, from the chromaticities (IEC 61966-2-1)."""
    prim = np.array([[0.64, 0.33], [0.30, 0.60], [0.15, 0.06]])
    white = np.array([0.3127, 0.3290])

    def xyz(c):
        return np.array([c[0] / c[1], 1.0, (1.0 - c[0] - c[1]) / c[1]])

    p = np.stack([xyz(c) for c in prim], axis=1)  # columns: primaries at Y = 1
    s = np.linalg.solve(p, xyz(white))  # scale so that R = G = B = 1 is the white point
    return np.linalg.inv(p * s)


class Reducer:
    def __init__(self) -> None:
        self.lam = LAMBDA_MIN + np.arange(STEPS) / (STEPS - 1) * (LAMBDA_MAX - LAMBDA_MIN)
        wl, cmf = cie1931()
        self.cmf = np.stack([np.interp(self.lam, wl, cmf[:, j]) for j in range(3)], axis=1)
        self.norm = 1.0 / self.cmf[:, 1].sum()
        self.m = xyz_to_srgb_matrix()

    def srgb(self, lam: np.ndarray, val: np.ndarray) -> np.ndarray:
        inside = (self.lam >= lam[0]) & (self.lam <= lam[-1])
        v = np.where(inside, np.interp(self.lam, lam, val), 0.0)
        xyz = (self.cmf * v[:, None]).sum(axis=0) * self.norm
        return np.maximum(self.m @ xyz, 0.0)


def sort_key(name: str):
    return (name.lower(), name)


def reduce_dirs(dirs: List[pathlib.Path]) -> Dict[str, dict]:
    red = Reducer()
    out: Dict[str, dict] = {}
    for d in dirs:
        for eta_file in sorted(d.glob("*.eta.spd")):
            name = eta_file.name[: -len(".eta.spd")]
            k_file = d / f"{name}.k.spd"
            if not k_file.exists():
                raise FileNotFoundError(f"{k_file} (pair of {eta_file})")
            le, ve, header = read_spd(eta_file)
            lk, vk, _ = read_spd(k_file)
            out[name] = {"eta": red.srgb(le, ve).tolist(), "k": red.srgb(lk, vk).tolist(),
                         "source": source_tag(name, header, d),
                         "range_nm": [float(max(le[0], lk[0])), float(min(le[-1], lk[-1]))]}
    return dict(sorted(out.items(), key=lambda kv: sort_key(kv[0])))


def fmt(x: float) -> str:
    s = f"{x:.6g}"
    return s + ("f" if "." in s or "e" in s else ".f")


def cpp_table(table: Dict[str, dict]) -> str:
    def comment(text: str) -> List[str]:
        return textwrap.wrap(text, 100, initial_indent="// ", subsequent_indent="//   ")

    lines = ["// Generated by tools/conductor_rgb.py; sources:"]
    for tag in sorted({e["source"] for e in table.values()}):
        lines += comment(f"{tag}: {SOURCES[tag]}.")
    partial = [n for n, e in table.items() if e["range_nm"][0] > LAMBDA_MIN or e["range_nm"][1] < LAMBDA_MAX]
    if partial:
        lines += comment("Data not covering 360-830 nm (the missing part counts as 0): " + ", ".join(partial) + ".")
    lines.append("const NamedConductor kConductors[] = {")
    for name, e in table.items():
        eta = ", ".join(fmt(x) for x in e["eta"])
        k = ", ".join(fmt(x) for x in e["k"])
        lines.append(f'    {{"{name}", {{{{{eta}}}, {{{k}}}}}, "{e["source"]}"}},')
    lines.append('    {"none", {{0.f, 0.f, 0.f}, {1.f, 1.f, 1.f}}, "ideal mirror"},')
    lines.append("};")
    return "\n".join(lines) + "\n"


def main() -> int:
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("dirs", nargs="+", type=pathlib.Path, help="directories with NAME.{eta,k}.spd files")
    ap.add_argument("--cpp", type=pathlib.Path, help="write the C++ table here (default: stdout)")
    ap.add_argument("--json", type=pathlib.Path, help="also write {name: {eta, k, source, range_nm}} as JSON")
    args = ap.parse_args()
    for d in args.dirs:
        if not d.is_dir():
            ap.error(f"{d} is not a directory")
    table = reduce_dirs(args.dirs)
    if not table:
        ap.error("no NAME.eta.spd files found")
    text = cpp_table(table)
    if args.cpp:
        args.cpp.write_text(text)
    else:
        sys.stdout.write(text)
    if args.json:
        args.json.write_text(json.dumps(table, indent=1) + "\n")
    return 0


if __name__ == "__main__":
    sys.exit(main())
