"""The Mitsuba parity matrix (tests/parity/): every generated Mitsuba 3 scene, imported and rendered
by pellucid, agrees with Mitsuba 3.9.1's rendering of it under a per-pixel z-test, or is listed with
its measured difference and its reason in docs/mitsuba-import.md ("Parity matrix").

Each row (tests/parity/scenes/<row>.xml, written by tests/parity/make_matrix.py) is rendered at its
256 spp with seed SEED and per-pixel variance of the mean (render_with_stats). The reference is the
committed tests/parity/ref/<row>.exr (the mean of 16 Mitsuba passes of 512 spp, float16) with
<row>.std.exr (the standard deviation of that mean); the reference's variance is that std squared
plus the variance of its float16 rounding (zcheck.half_rounding_variance). The z-test is
tests/python/zcheck.py's: |z| per pixel channel, Šidák-corrected over the channels of the image at
two-sided α = ALPHA = 0.01.

The rule: a row passes when at least PASS_FRACTION = 99 % of its channels are within the critical
|z| (the rule of test_mitsuba_scenes.py), not when all are (a true family-wise test). Both variances
are estimates, ours from the 256 samples of each pixel: where a pixel's paths have a rare bright
contribution (a small highlight, light through glass), most renders under-estimate its variance,
so the tails of z are far heavier than the normal's and a family-wise test fails correct renders.
At seed 7, 128 of the 158 passing rows have at least one channel beyond the critical |z|, most of
them one to a few. The 1 % allowance absorbs those pixels, and also small real differences
confined to them (the dielectric rows' torus silhouettes, docs/mitsuba-import.md). A difference
that covers more than 1 % of the channels fails, and test_a_3_percent_change_fails_a_row shows
that a 3 % brightness change does. Over seeds 0-4 every passing row passes, the lowest pass
fraction being 0.990 (bsdf_dielectric_ext_ior; seeds 0-4 were run before the plastic rows passed,
whose lowest over seeds 0-4 and 7 is 0.999). The module takes 70-110 s on two cores.

Rows that differ are allowed only where the doc's table lists them; they are expected failures,
and strictly so: a listed row that passes fails test_row_matches_mitsuba, so the doc stays true.
test_every_importer_mapping_is_exercised checks the matrix against the importer's own table
(pellucid._core.mitsuba_import_table()): every plugin and parameter it maps is used by some row,
except those Mitsuba 3.9.1 itself rejects (make_matrix.NOT_IN_MITSUBA).

Run as a script, it prints each row's measurement and the pass rate (for the doc's table):

    python tests/python/test_parity_matrix.py [row ...]
"""
from __future__ import annotations

import pathlib
import re
import sys
import xml.etree.ElementTree as ET
from dataclasses import dataclass
from typing import Dict, List, Optional, Set, Tuple

import numpy as np
import pytest

import pellucid
from pellucid import _core

from zcheck import half_rounding_variance, z_pass_fraction

ROOT = pathlib.Path(__file__).resolve().parents[2]
PARITY = ROOT / "tests" / "parity"
SCENES = PARITY / "scenes"
REF = PARITY / "ref"
DOC = ROOT / "docs" / "mitsuba-import.md"
SEED = 7
ALPHA = 0.01
PASS_FRACTION = 0.99

sys.path.insert(0, str(PARITY))
try:
    import make_matrix
finally:
    sys.path.pop(0)

ROWS = sorted(make_matrix.ROWS)


@dataclass
class Measure:
    row: str
    passed: bool
    frac: float = 0.0       # fraction of channels within the critical |z|
    zc: float = 0.0
    rel_mean: float = 0.0   # (mean ours - mean Mitsuba) / mean Mitsuba over the image
    error: str = ""         # pellucid's import or build error, if any

    def describe(self) -> str:
        if self.error:
            return f"import fails: {self.error}"
        return (f"image mean {100 * self.rel_mean:+.1f} %, {100 * (1 - self.frac):.1f} % of channels "
                f"with z > {self.zc:.2f}")


def reference(row: str) -> Tuple[np.ndarray, np.ndarray]:
    mean = np.asarray(pellucid.read_image(REF / f"{row}.exr"), np.float64)
    std = np.asarray(pellucid.read_image(REF / f"{row}.std.exr"), np.float64)
    return mean, std * std + half_rounding_variance(mean)


def render(row: str) -> Tuple[np.ndarray, np.ndarray]:
    img, var, _ = pellucid.render_with_stats(pellucid.load_file(SCENES / f"{row}.xml"), seed=SEED)
    return np.asarray(img, np.float64), np.asarray(var, np.float64)


def compare(row: str, img: np.ndarray, var: np.ndarray) -> Measure:
    ref, ref_var = reference(row)
    if img.shape != ref.shape:
        return Measure(row, False, error=f"image {img.shape} vs Mitsuba's {ref.shape}")
    frac, zc = z_pass_fraction(img, var, ref, ref_var, ALPHA)
    return Measure(row, frac >= PASS_FRACTION, frac, zc, float(img.mean() / ref.mean() - 1))


def measure(row: str) -> Measure:
    try:
        img, var = render(row)
    except pellucid.Error as e:
        return Measure(row, False, error=str(e).replace(str(SCENES) + "/", ""))
    return compare(row, img, var)


def doc_differences() -> Dict[str, Tuple[str, str]]:
    """The rows of the doc's "Parity matrix" table: row -> (measured difference, reason)."""
    text = DOC.read_text()
    start = text.index("## Parity matrix")
    end = text.find("\n## ", start + 1)
    section = text[start:end if end >= 0 else len(text)]
    rows = {}
    for line in section.splitlines():
        m = re.match(r"\|\s*`([a-z0-9_]+)`\s*\|(.*)\|(.*)\|\s*$", line)
        if m:
            assert m.group(1) not in rows, f"{m.group(1)} is listed twice in {DOC.name}"
            rows[m.group(1)] = (m.group(2).strip(), m.group(3).strip())
    return rows


DIFFERENCES = doc_differences()


@pytest.mark.parametrize("row", ROWS)
def test_row_matches_mitsuba(row: str) -> None:
    m = measure(row)
    if row in DIFFERENCES:
        if m.passed:
            pytest.fail(f"{row} is listed in {DOC.name} as differing but now passes ({m.describe()}): "
                        "remove it from the table")
        pytest.xfail(f"{row}: {m.describe()} (listed: {DIFFERENCES[row][1]})")
    assert m.passed, f"{row}: {m.describe()}"


def test_a_3_percent_change_fails_a_row() -> None:
    """The row test has teeth: a passing row, 3 % brighter, fails it."""
    row = "bsdf_diffuse"
    img, var = render(row)
    assert compare(row, img, var).passed
    m = compare(row, img * 1.03, var * 1.03 ** 2)
    assert not m.passed, m.describe()


def test_committed_scenes_are_the_generators() -> None:
    bad = make_matrix.check_scenes()
    assert not bad, f"tests/parity/scenes differs from make_matrix.py's output (rerun it): {bad}"


def test_every_row_has_a_reference() -> None:
    missing = [r for r in ROWS if not (REF / f"{r}.exr").is_file() or not (REF / f"{r}.std.exr").is_file()]
    assert not missing, f"rows without a Mitsuba reference (run make_matrix.py --refs --missing): {missing}"
    extra = sorted({p.name.split(".")[0] for p in REF.glob("*.exr")} - set(ROWS))
    assert not extra, f"references of rows that no longer exist: {extra}"


def test_listed_differences_are_rows() -> None:
    unknown = sorted(set(DIFFERENCES) - set(ROWS))
    assert not unknown, f"{DOC.name} lists differences of rows the matrix does not have: {unknown}"
    for row, (diff, reason) in DIFFERENCES.items():
        assert diff and reason, f"{DOC.name}: {row} needs a measured difference and a reason"


# ---- coverage -------------------------------------------------------------------------------
KINDS = ("bsdf", "texture", "shape", "emitter", "sensor", "film", "rfilter", "sampler", "integrator", "medium", "phase")
PROPERTY_TAGS = ("float", "integer", "boolean", "string", "rgb", "spectrum", "point", "vector", "transform")


def exercised(xml_text: str) -> Set[Tuple[str, str, Optional[str]]]:
    """(kind, plugin, None) for every plugin in a scene and (kind, plugin, parameter) for every
    parameter given to it (a property, a named nested texture or medium, or a named reference)."""
    out = set()
    for el in ET.fromstring(xml_text).iter():
        if el.tag not in KINDS or "type" not in el.attrib:
            continue
        kind, plugin = el.tag, el.attrib["type"]
        out.add((kind, plugin, None))
        for child in el:
            if child.tag in PROPERTY_TAGS or (child.tag in ("texture", "ref", "medium") and "name" in child.attrib):
                out.add((kind, plugin, child.attrib["name"]))
    return out


def test_every_importer_mapping_is_exercised() -> None:
    used = set()
    for row in ROWS:
        used |= exercised((SCENES / f"{row}.xml").read_text())
    exempt = make_matrix.NOT_IN_MITSUBA
    missing = []
    for entry in _core.mitsuba_import_table():
        kind, plugin = entry["kind"], entry["plugin"]
        if (kind, plugin, None) in exempt:
            continue
        if (kind, plugin, None) not in used:
            missing.append(f"{kind} {plugin}")
        for mitsuba, _ours in entry["params"]:
            if (kind, plugin, mitsuba) not in used and (kind, plugin, mitsuba) not in exempt:
                missing.append(f"{kind} {plugin} {mitsuba}")
    assert not missing, f"importer mappings that no parity row exercises: {missing}"


def test_exemptions_are_importer_mappings() -> None:
    """NOT_IN_MITSUBA names only what the importer's table has (else it hides nothing and is stale)."""
    table = {(e["kind"], e["plugin"]): {m for m, _ in e["params"]} for e in _core.mitsuba_import_table()}
    for kind, plugin, param in make_matrix.NOT_IN_MITSUBA:
        assert (kind, plugin) in table, (kind, plugin)
        assert param is None or param in table[(kind, plugin)], (kind, plugin, param)


def test_coverage_can_fail() -> None:
    """The coverage parser sees what a row uses, and nothing it does not."""
    got = exercised('<scene><bsdf type="bumpmap"><texture type="bitmap" name="arbitrary">'
                    '<string name="filename" value="h.png"/></texture><bsdf type="diffuse"/></bsdf></scene>')
    assert got == {("bsdf", "bumpmap", None), ("bsdf", "bumpmap", "arbitrary"), ("texture", "bitmap", None),
                   ("texture", "bitmap", "filename"), ("bsdf", "diffuse", None)}


def main(rows: List[str]) -> int:
    results = [measure(r) for r in rows or ROWS]
    for m in results:
        listed = "listed" if m.row in DIFFERENCES else ""
        print(f"{m.row:45s} {'pass' if m.passed else 'FAIL':4s} {listed:6s} {m.describe()}")
    passed = sum(m.passed for m in results)
    print(f"{passed} / {len(results)} rows pass ({100 * passed / len(results):.0f} %)")
    return 0


if __name__ == "__main__":
    sys.exit(main(sys.argv[1:]))
