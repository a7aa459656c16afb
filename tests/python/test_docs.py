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


# ---- docs/mitsuba-import.md: what it says the importer accepts, the importer accepts ------------
# Every Mitsuba plugin named in the first column of its tables is imported and built, every plugin it
# lists as unsupported is rejected, and its stated defaults and name tables are checked, from the
# text of the doc itself: a row added to the doc for a plugin the importer lacks fails here.
MI_DOC = (ROOT / "docs" / "mitsuba-import.md").read_text()

# Children a plugin needs to be valid in Mitsuba (wrappers); other plugins are imported bare.
_MI_BSDF_CHILDREN = {
    "twosided": '<bsdf type="diffuse"/>',
    # Mitsuba's documentation example names the bump texture "arbitrary".
    "bumpmap": '<texture type="checkerboard" name="arbitrary"/><bsdf type="diffuse"/>',
    "normalmap": '<texture type="checkerboard" name="normalmap"/><bsdf type="diffuse"/>',
}


def _mi_section(heading: str) -> str:
    text = _section(heading, MI_DOC)
    assert text, f"docs/mitsuba-import.md has no section '{heading}'"
    return text


def _mi_first_column(heading: str) -> List[str]:
    """The backticked names in the first cell of each table row of a section."""
    names = []
    for line in _mi_section(heading).splitlines():
        if line.startswith("| `"):
            names += re.findall(r"`([^`]+)`", line.split("|")[1])
    return names


def _mi_listed(pattern: str, text: str = "") -> List[str]:
    m = re.search(pattern, text or MI_DOC, flags=re.S)
    assert m, f"docs/mitsuba-import.md no longer says: {pattern}"
    return re.findall(r"`([^`]+)`", m.group(1))


def _mi_load(tmp_path, body: str, lenient: bool = False):
    path = tmp_path / "scene.xml"
    path.write_text(f'<scene version="3.0.0">\n{body}\n</scene>\n')
    return pellucid.load_file(path, lenient=lenient)


def _mi_fails(tmp_path, body: str, expected: str) -> None:
    with pytest.raises(pellucid.Error) as e:
        _mi_load(tmp_path, body)
    assert expected in str(e.value), str(e.value)


def _mi_files(tmp_path) -> None:
    obj, ply = _mesh_files(tmp_path)
    pellucid.write_image(tmp_path / "tex.exr", np.full((4, 6, 3), 0.5, np.float32))


def test_mitsuba_doc_bsdf_rows_import(tmp_path) -> None:
    names = _mi_first_column("## BSDFs")
    assert "diffuse" in names and "bumpmap" in names
    for name in names:
        # Also the rough plugins without a distribution: the importer writes Mitsuba's "beckmann",
        # which all our rough materials have (the doc says so).
        _mi_load(tmp_path, f'<shape type="sphere"><bsdf type="{name}">{_MI_BSDF_CHILDREN.get(name, "")}</bsdf></shape>')


def test_mitsuba_doc_unsupported_bsdfs_are_rejected(tmp_path) -> None:
    names = _mi_listed(r"Any other bsdf \(([^)]*)\) is\s+unsupported")
    assert len(names) >= 5
    for name in names:
        _mi_fails(tmp_path, f'<shape type="sphere"><bsdf type="{name}"/></shape>', f"unsupported bsdf plugin '{name}'")


def test_mitsuba_doc_shape_rows_import(tmp_path) -> None:
    _mi_files(tmp_path)
    names = _mi_first_column("## Shapes")
    assert {"obj", "ply", "sphere", "cube"} <= set(names)
    for name in names:
        extra = {"obj": '<string name="filename" value="tri.obj"/>',
                 "ply": '<string name="filename" value="tri.ply"/>'}.get(name, "")
        _mi_load(tmp_path, f'<shape type="{name}">{extra}</shape>')
    for name in _mi_listed(r"Mitsuba's\s+(`serialized`.*?) are unsupported"):
        _mi_fails(tmp_path, f'<shape type="{name}"/>', f"unsupported shape plugin '{name}'")


def test_mitsuba_doc_sphere_transforms(tmp_path) -> None:
    """`sphere` row: to_world must be a similarity, an error names the key; Transforms: a <rotate>
    axis that is not of unit length is normalised (else the sphere would fail that check)."""
    row = next(ln for ln in _mi_section("## Shapes").splitlines() if ln.startswith("| `sphere`"))
    assert "similarity" in row and "error naming the key" in row
    _mi_fails(tmp_path, '<shape type="sphere"><transform name="to_world">'
                        '<matrix value="1 0 0 0  0 1 0.6 0  0 0 0.8 0  0 0 0 1"/></transform></shape>',
              "to_world: a sphere's transform must be a similarity")
    assert "we normalise the axis" in MI_DOC
    _mi_load(tmp_path, '<shape type="sphere"><transform name="to_world">'
                       '<rotate x="1" y="2" z="0.5" angle="50"/><scale value="2"/></transform></shape>')


def test_mitsuba_doc_emitter_and_texture_rows_import(tmp_path) -> None:
    _mi_files(tmp_path)
    emitters = _mi_first_column("## Emitters")
    assert {"area", "point", "envmap"} <= set(emitters)
    for name in emitters:
        if name == "area":
            _mi_load(tmp_path, '<shape type="sphere"><emitter type="area"/></shape>')
        else:
            extra = '<string name="filename" value="tex.exr"/>' if name == "envmap" else ""
            _mi_load(tmp_path, f'<emitter type="{name}">{extra}</emitter>')
    textures = _mi_first_column("## Textures")
    assert textures == ["bitmap", "checkerboard"]
    for name in textures:
        extra = '<string name="filename" value="tex.exr"/>' if name == "bitmap" else ""
        _mi_load(tmp_path, f'<shape type="sphere"><bsdf type="diffuse"><texture type="{name}" name="reflectance">'
                           f'{extra}</texture></bsdf></shape>')


def test_mitsuba_doc_sensor_film_sampler_integrator(tmp_path) -> None:
    sec = _mi_section("## Sensor, film, sampler, integrator")
    sampler_rows = [ln for ln in sec.splitlines() if re.search(r"\| `sampler`", ln)]
    samplers = [n for ln in sampler_rows for n in re.findall(r"`([^`]+)`", ln.split("|")[1])
                if n not in ("sample_count", "seed", "jitter", "dimension")]
    assert {"independent", "stratified", "ldsampler"} <= set(samplers)
    for s in samplers + ["independent"]:
        _mi_load(tmp_path, f'<sensor type="perspective"><sampler type="{s}"/></sensor>')
    for f in ("box", "tent", "gaussian"):
        assert f"`{f}`" in sec
        _mi_load(tmp_path, f'<sensor type="perspective"><film type="hdrfilm"><rfilter type="{f}"/></film></sensor>')
    for f in _mi_listed(r"others \((`mitchell`.*?)\) unsupported", sec):
        _mi_fails(tmp_path, f'<sensor type="perspective"><film type="hdrfilm"><rfilter type="{f}"/></film></sensor>',
                  f"unsupported rfilter plugin '{f}'")
    for s in _mi_listed(r"Other sensors \(([^)]*)\)", sec):
        _mi_fails(tmp_path, f'<sensor type="{s}"/>', f"unsupported sensor plugin '{s}'")
    for i in ("path", "volpath"):
        _mi_load(tmp_path, f'<integrator type="{i}"/>')
    for i in _mi_listed(r"other integrators \((`direct`.*?)\) \|", sec):
        _mi_fails(tmp_path, f'<integrator type="{i}"/>', f"unsupported integrator plugin '{i}'")
    # "`hdrfilm` is 768 × 576 and `independent` takes 4 samples per pixel in Mitsuba", written explicitly.
    m = re.search(r"`hdrfilm` is (\d+) × (\d+) and `independent` takes (\d+) samples per pixel", MI_DOC)
    assert m
    scene = _mi_load(tmp_path, '<sensor type="perspective"><film type="hdrfilm"/><sampler type="independent"/></sensor>')
    assert (scene.width, scene.height, scene.spp) == tuple(int(g) for g in m.groups())


def test_mitsuba_doc_material_and_ior_names(tmp_path) -> None:
    metals = _mi_listed(r"\*\*Conductor names\*\*: (.*?)\n- ")
    metals = [m for m in metals if m != "material" and re.fullmatch(r"[A-Za-z][A-Za-z0-9_-]*", m)]
    assert {"a-C", "W", "none", "Fe", "Ti", "Ni"} <= set(metals)
    for name in metals:
        _mi_load(tmp_path, f'<shape type="sphere"><bsdf type="conductor"><string name="material" value="{name}"/>'
                           '</bsdf></shape>')
    shared = _mi_listed(r"\*\*IOR names\*\* are passed through unchanged\..*?same value: (.*?) are in both tables")
    ours_only = _mi_listed(r"(`glass`, `fused-quartz`, `acrylic`\s+and `sapphire`) are ours only")
    assert len(shared) == 23 and "fused quartz" in shared and "acrylic glass" in shared
    for name in shared + ours_only:
        _mi_load(tmp_path, f'<shape type="sphere"><bsdf type="dielectric"><string name="int_ior" value="{name}"/>'
                           '</bsdf></shape>')
    _mi_fails(tmp_path, '<shape type="sphere"><bsdf type="dielectric"><string name="int_ior" value="unobtainium"/>'
                        '</bsdf></shape>', "known")


def test_mitsuba_doc_bumpmap_children(tmp_path) -> None:
    """The bump map rows: one texture child under any name or none; two are an error naming the line."""
    row = next(ln for ln in _mi_section("## Textures, bump maps and normal maps").splitlines()
               if ln.startswith("| `bumpmap`"))
    assert "any `name`" in row and "two textures" in row
    for tex in ('<texture type="checkerboard" name="arbitrary"/>', '<texture type="checkerboard"/>'):
        _mi_load(tmp_path, f'<shape type="sphere"><bsdf type="bumpmap">{tex}<bsdf type="diffuse"/></bsdf></shape>')
    _mi_fails(tmp_path, '<shape type="sphere"><bsdf type="bumpmap">\n<texture type="checkerboard" name="a"/>\n'
                        '<texture type="checkerboard"/><bsdf type="diffuse"/></bsdf></shape>',
              "takes exactly one nested texture (under any name); the first is on line 3")
    _mi_fails(tmp_path, '<shape type="sphere"><bsdf type="bumpmap"><bsdf type="diffuse"/></bsdf></shape>',
              "needs exactly one nested texture")
