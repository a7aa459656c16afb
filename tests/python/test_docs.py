"""docs/scene-format.md documents every registered type and every parameter its builder reads.

Types come from ``_core.registry_types()``. Parameters come from the builders themselves: the scenes
below are built with ``_core.record_parameters``, which returns, for every object, the keys its
builder looked up (read or tested, present or not). Each key must appear in backticks in the
type's part of the docs: its ``### `type` `` subsection, else its table row ``| `type` |``, else its
family's section; plus the family's preamble (text before the first ``###``), plus the parts of
types it names as "All `x` parameters" / "Same parameters as `x`".
"""
from __future__ import annotations

import re
from typing import Dict, List, Set, Tuple

import numpy as np
import pytest

import pellucid
from pellucid import _core

from conftest import ROOT

DOC = (ROOT / "docs" / "scene-format.md").read_text()

# Family -> the "## heading" of its section ("emitters" live in a subsection of shapes).
SECTIONS = {
    "materials": "## materials",
    "shapes": "## shapes",
    "emitters": "### emitter (on a shape)",
    "lights": "## lights",
    "filters": "## film",
    "cameras": "## camera",
    "integrators": "## integrator",
    "samplers": "## sampler",
    "film": "## film",
    "top": "## Top level",
}


def _section(heading: str, doc: str) -> str:
    """Text from `heading` to the next heading of the same or a higher level."""
    level = len(heading.split(" ")[0])
    lines = doc.splitlines()
    for i, line in enumerate(lines):
        if line.strip() == heading:
            out = []
            for nxt in lines[i + 1:]:
                m = re.match(r"^(#+) ", nxt)
                if m and len(m.group(1)) <= level:
                    break
                out.append(nxt)
            return "\n".join(out)
    return ""


def _family_section(family: str, doc: str = DOC) -> str:
    heading = SECTIONS.get(family, f"## {family}")
    text = _section(heading, doc)
    assert text, f"docs/scene-format.md has no section '{heading}' for the registered family '{family}'"
    return text


def _type_region(family: str, type_name: str, doc: str, seen: Tuple[str, ...] = ()) -> str:
    sec = _family_section(family, doc)
    preamble = re.split(r"^### ", sec, flags=re.M)[0]
    sub = _section(f"### `{type_name}`", doc) if f"### `{type_name}`" in sec else ""
    rows = [ln for ln in sec.splitlines() if ln.startswith(f"| `{type_name}`")]
    region = sub or "\n".join(rows) or sec
    parts = [preamble, region]
    for m in re.finditer(r"[Aa]ll `(\w+)` parameters|[Ss]ame parameters as `(\w+)`", region):
        base = m.group(1) or m.group(2)
        if base not in seen and base != type_name:
            parts.append(_type_region(family, base, doc, seen + (type_name,)))
    return "\n".join(parts)


def _mesh_files(tmp_path) -> Tuple[str, str]:
    obj = tmp_path / "tri.obj"
    obj.write_text("v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\n")
    ply = tmp_path / "tri.ply"
    ply.write_text("ply\nformat ascii 1.0\nelement vertex 3\nproperty float x\nproperty float y\n"
                   "property float z\nelement face 1\nproperty list uchar int vertex_indices\nend_header\n"
                   "0 0 0\n1 0 0\n0 1 0\n3 0 1 2\n")
    return str(obj), str(ply)


# Parameters that a default instance cannot reach (required keys); everything else is built with
# {"type": name} only, so that every optional key is looked up.
def _shape_example(type_name: str, obj: str, ply: str) -> dict:
    return {
        "mesh": {"type": "mesh", "positions": [0, 0, 0, 1, 0, 0, 0, 1, 0], "indices": [0, 1, 2]},
        "obj": {"type": "obj", "filename": obj},
        "ply": {"type": "ply", "filename": ply},
    }.get(type_name, {"type": type_name})


def _family_of(path: str) -> str:
    if "to_world" in path:
        return ""  # transform operations: documented under "Units and conventions"
    last = path.split(".")[-1]
    if path == "":
        return "top"
    if path in ("camera", "film", "sampler", "integrator"):
        return {"camera": "cameras", "sampler": "samplers", "integrator": "integrators", "film": "film"}[path]
    if path == "film.filter":
        return "filters"
    if last == "emitter":
        return "emitters"
    if path.startswith("materials.") and path.count(".") == 1 or last == "material":
        return "materials"
    if re.fullmatch(r"shapes\[\d+\]", path):
        return "shapes"
    if re.fullmatch(r"lights\[\d+\]", path):
        return "lights"
    return "textures"  # a nested object under a material parameter


def _scenes(tmp_path) -> List[dict]:
    types = _core.registry_types()
    obj, ply = _mesh_files(tmp_path)
    mats = {f"m_{t}": {"type": t} for t in types["materials"]}
    image = tmp_path / "tex.exr"
    pellucid.write_image(image, np.full((4, 6, 3), 0.5, np.float32))
    # Textures with required keys get them; every optional key is still looked up.
    required = {"image": {"filename": str(image)}, "scale": {"texture": 0.5}}
    for t in types.get("textures", []):
        mats[f"tex_{t}"] = {"type": "lambertian", "reflectance": dict({"type": t}, **required.get(t, {}))}
    # The keys every material takes (bump and normal maps) are looked up only when one is given.
    mats["m_bumped"] = {"type": "lambertian", "bump_map": {"type": "checkerboard"}}
    shapes = [_shape_example(t, obj, ply) for t in types["shapes"]]
    shapes[0]["emitter"] = {"type": "area"}
    shapes[0]["material"] = "m_lambertian"
    lights = [dict({"type": t}, **({"filename": str(image)} if t == "envmap" else {})) for t in types["lights"]]
    base = {"camera": {"type": "perspective"}, "sampler": {"type": "independent"},
            "integrator": {"type": "path"}, "materials": mats, "shapes": shapes, "lights": lights}
    out = [dict(base, film={"filter": {"type": f}}) for f in types["filters"]]
    out += [dict(base, integrator={"type": t, "aov": "albedo"}) for t in types["integrators"] if t == "aov"]
    return out


def _records(tmp_path) -> Dict[Tuple[str, str], Set[str]]:
    out: Dict[Tuple[str, str], Set[str]] = {}
    for scene in _scenes(tmp_path):
        for path, type_name, keys in _core.record_parameters(scene, str(tmp_path)):
            family = _family_of(path)
            if family:
                out.setdefault((family, type_name), set()).update(set(keys) - {"type"})
    return out


def test_every_registered_type_is_documented() -> None:
    missing = []
    for family, names in _core.registry_types().items():
        sec = _family_section(family)
        missing += [f"{family}: `{n}`" for n in names if f"`{n}`" not in sec]
    assert not missing, "types missing from docs/scene-format.md: " + ", ".join(missing)


def _missing_parameters(records: Dict[Tuple[str, str], Set[str]], doc: str) -> List[str]:
    missing = []
    for (family, type_name), keys in sorted(records.items()):
        region = _type_region(family, type_name, doc) if type_name else _family_section(family, doc)
        missing += [f"{family}/{type_name or '-'}: `{k}`" for k in sorted(keys) if f"`{k}`" not in region]
    return missing


def test_every_parameter_of_every_type_is_documented(tmp_path) -> None:
    records = _records(tmp_path)
    types = _core.registry_types()
    # Every registered type was built (so its parameters were seen).
    built = set(records)
    for family in ("materials", "shapes", "lights", "filters", "emitters", "cameras", "integrators", "textures"):
        for t in types.get(family, []):
            assert (family, t) in built, f"{family} type '{t}' was not built by the docs test"
    missing = _missing_parameters(records, DOC)
    assert not missing, "parameters missing from docs/scene-format.md: " + ", ".join(missing)


def test_the_check_would_catch_an_undocumented_parameter(tmp_path) -> None:
    """The checker is not vacuous: rename one documented parameter and it is reported."""
    records = _records(tmp_path)
    assert ("materials", "rough_conductor") in records
    assert "multiple_scattering" in records[("materials", "rough_conductor")]
    doc = DOC.replace("`multiple_scattering`", "`multiple_scatterin`")
    assert _missing_parameters(records, doc) == ["materials/rough_conductor: `multiple_scattering`",
                                                 "materials/rough_dielectric: `multiple_scattering`"]
    doc = DOC.replace("`stddev`", "`std`")
    assert "filters/gaussian: `stddev`" in _missing_parameters(records, doc)


@pytest.mark.parametrize("family,scene,known", [
    ("lights", {"lights": [{"type": "nope"}]}, "lights[0].type"),
    ("shapes", {"shapes": [{"type": "nope"}]}, "shapes[0].type"),
    ("materials", {"materials": {"m": {"type": "nope"}}}, "materials.m.type"),
    ("filters", {"film": {"filter": {"type": "nope"}}}, "film.filter.type"),
    ("integrators", {"integrator": {"type": "nope"}}, "integrator.type"),
    ("cameras", {"camera": {"type": "nope"}}, "camera.type"),
    ("samplers", {"sampler": {"type": "nope"}}, "sampler.type"),
    ("emitters", {"shapes": [{"type": "sphere", "emitter": {"type": "nope"}}]}, "shapes[0].emitter.type"),
])
def test_registry_lists_match_the_builders_known_lists(family, scene, known) -> None:
    """registry_types() lists the families built inline in scene/build.cpp by hand; the builders'
    own "(known: ...)" error lists must agree with it."""
    with pytest.raises(pellucid.Error) as e:
        pellucid.load_dict(scene)
    msg = str(e.value)
    assert known in msg, msg
    listed = re.search(r"\(known: ([^)]*)\)", msg).group(1).split(", ")
    assert sorted(listed) == sorted(_core.registry_types()[family]), msg
