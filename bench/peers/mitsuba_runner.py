#!/usr/bin/env python3
"""Render a pellucid JSON scene with Mitsuba 3 (peer renderer for benchmarks).

Run with the dedicated venv (see setup_mitsuba.sh); this script never imports pellucid:

    bench/.venv-mitsuba/bin/python bench/peers/mitsuba_runner.py SCENE.json \
        --variant {scalar_rgb,llvm_ad_rgb} --spp N --seed S --out OUT.exr \
        [--threads T] [--passes K] [--max-depth D] [--json-report REPORT.json] [--each-dir DIR]

`to_mitsuba_dict(scene_json)` converts a parsed pellucid scene into a Mitsuba scene
dict; a Mitsuba variant must be set before calling it (it builds ScalarTransform4f
objects and, for meshes, mi.Mesh objects).

Materials, textures and bump maps map to the Mitsuba plugin of the same model (docs/mitsuba-import.md
lists the correspondence in the other direction): pellucid's options that choose Mitsuba's definition
(`shadowing: "separable"`, `coat_transmittance: "rough"`, `bump_model: "mitsuba"`,
`terminator_model: "estevez"`, image `filter: "bilinear"`, checkerboard `filtered: false`) make the two
renderers compute the same image; other values still convert, to the nearest Mitsuba model. Two models
have no Mitsuba 3 plugin: `oren_nayar` and `principled` `variant: "2012"`. They are an error unless
`substitute=True` (`--substitute`), which renders them as Mitsuba's `diffuse` and `principled` (for
timing; the images then differ).
"""
from __future__ import annotations

import argparse
import json
import os
import sys
import time

# Mitsuba's llvm_* variants need LLVM >= 16-ish (LLVM 15 aborts); Debian 12's libllvm19
# installs /usr/lib/x86_64-linux-gnu/libLLVM.so.19.1. Point Dr.Jit at it explicitly
# (must happen before drjit is imported) unless the caller chose a library already.
_LLVM_CANDIDATES = (
    "/usr/lib/x86_64-linux-gnu/libLLVM.so.19.1",
    "/usr/lib/x86_64-linux-gnu/libLLVM-19.so.1",
    "/usr/lib/x86_64-linux-gnu/libLLVM-19.so",
    "/usr/lib/llvm-19/lib/libLLVM.so.1",
)
if "DRJIT_LIBLLVM_PATH" not in os.environ:
    for _p in _LLVM_CANDIDATES:
        if os.path.exists(_p):
            os.environ["DRJIT_LIBLLVM_PATH"] = _p
            break

import numpy as np  # noqa: E402
import drjit as dr  # noqa: E402
import mitsuba as mi  # noqa: E402


# --------------------------------------------------------------------------- helpers
def _rgb3(v, what):
    if isinstance(v, (int, float)):
        return [float(v)] * 3
    v = [float(x) for x in v]
    if len(v) == 1:
        return v * 3
    if len(v) != 3:
        raise ValueError(f"{what}: expected a scalar or a 3-vector, got {v!r}")
    return v


def _rgb(v, what):
    return {"type": "rgb", "value": _rgb3(v, what)}


def _vec3(v, what):
    if isinstance(v, (int, float)):
        return [float(v)] * 3
    v = [float(x) for x in v]
    if len(v) != 3:
        raise ValueError(f"{what}: expected a 3-vector, got {v!r}")
    return v


def _transform(ops, what="to_world"):
    """List of ops, first applied first: M = op_n @ ... @ op_1 (like nested XML tags)."""
    T = mi.ScalarTransform4f
    if ops is None:
        return T()
    if isinstance(ops, dict):
        ops = [ops]
    m = T()
    for op in ops:
        if len(op) != 1:
            raise ValueError(f"{what}: each op must have exactly one key, got {op!r}")
        (k, v), = op.items()
        if k == "scale":
            t = T().scale(_vec3(v, f"{what}.scale"))
        elif k == "translate":
            t = T().translate(_vec3(v, f"{what}.translate"))
        elif k == "rotate":
            t = T().rotate(_vec3(v["axis"], f"{what}.rotate.axis"), float(v["angle"]))
        elif k == "look_at":
            t = T().look_at(origin=_vec3(v["origin"], "origin"),
                            target=_vec3(v["target"], "target"),
                            up=_vec3(v["up"], "up"))
        elif k == "matrix":
            a = np.asarray(v, dtype=np.float64).reshape(4, 4)  # row-major
            t = T(a)
        else:
            raise ValueError(f"{what}: unknown transform op {k!r}")
        m = t @ m
    return m


# pellucid's RGB complex IORs (cpp/pellucid/bxdf/ior.cpp, tools/conductor_rgb.py), passed explicitly:
# for Mitsuba's own `material` names they equal its RGB reduction of the same spectra (reflectance
# within 2.4e-4); Fe, Ti, Ni are not Mitsuba names.
_METALS = {
    "Au": ([0.143142, 0.374951, 1.44202], [3.98377, 2.38569, 1.60271]),
    "Ag": ([0.155288, 0.116722, 0.138337], [4.82908, 3.1222, 2.14627]),
    "Cu": ([0.20047, 0.924021, 1.10186], [3.91354, 2.45282, 2.14151]),
    "Al": ([1.65771, 0.880357, 0.521064], [9.22527, 6.26944, 4.83547]),
    "Cr": ([4.37035, 2.91666, 1.65418], [5.20723, 4.23131, 3.75376]),
    "Fe": ([3.51496, 2.76985, 2.3011], [3.6956, 2.78608, 2.49224]),
    "Ti": ([3.27592, 2.37974, 2.0241], [4.57313, 3.22448, 2.72688]),
    "Ni": ([2.42358, 1.80444, 1.56296], [4.97373, 3.38453, 2.60247]),
}
_IORS = {"vacuum": 1.0, "air": 1.000277, "water": 1.333, "ethanol": 1.361, "glass": 1.5046, "bk7": 1.5046,
         "fused-quartz": 1.458, "acrylic": 1.49, "polypropylene": 1.49, "sapphire": 1.77, "diamond": 2.419}


def _ior(v, what):
    if isinstance(v, str):
        if v not in _IORS:
            raise ValueError(f"{what}: unknown IOR name {v!r}")
        return _IORS[v]
    return float(v)


def _conductor_ior(mat, what):
    if "eta" in mat:
        return _rgb(mat["eta"], f"{what}.eta"), _rgb(mat.get("k", 0.0), f"{what}.k")
    name = mat.get("material", "none")
    if name == "none":
        return None, None
    if name not in _METALS:
        raise ValueError(f"{what}.material: unknown metal {name!r}")
    eta, k = _METALS[name]
    return _rgb(eta, f"{what}.eta"), _rgb(k, f"{what}.k")


def _alpha(mat, d, what):
    """pellucid roughness keys -> Mitsuba alpha / alpha_u, alpha_v (roughness r means alpha = r^2)."""
    if "alpha_u" in mat:
        d["alpha_u"] = float(mat["alpha_u"])
        d["alpha_v"] = float(mat.get("alpha_v", mat["alpha_u"]))
    elif "roughness" in mat:
        d["alpha"] = float(mat["roughness"]) ** 2
    else:
        d["alpha"] = float(mat.get("alpha", 0.1))
    dist = mat.get("distribution", "ggx")
    if dist not in ("ggx", "beckmann"):
        raise ValueError(f"{what}.distribution: unknown {dist!r}")
    d["distribution"] = dist  # Mitsuba's default is beckmann, pellucid's ggx: always explicit


class _Ctx:
    """What a material needs besides itself: the scene's named textures, the folder that relative file
    names are resolved against, and whether models without a Mitsuba plugin are substituted."""

    def __init__(self, textures=None, base_dir=".", substitute=False):
        self.textures, self.base_dir, self.substitute = textures or {}, base_dir, substitute


def _texture(v, what, ctx, raw=False):
    """A pellucid texture (inline object or the name of a top-level texture) -> Mitsuba texture dict."""
    if isinstance(v, str):
        if v not in ctx.textures:
            raise KeyError(f"{what}: no texture {v!r}")
        what, v = f"textures.{v}", ctx.textures[v]
    t = v.get("type")
    if t == "image":
        fn = v["filename"]
        path = fn if os.path.isabs(fn) else os.path.join(ctx.base_dir, fn)
        if not os.path.exists(path):
            raise FileNotFoundError(f"{what}.filename: no such file {path!r}")
        d = {"type": "bitmap", "filename": path,
             "filter_type": "nearest" if v.get("filter") == "nearest" else "bilinear"}
        wrap = v.get("wrap_mode", "repeat")
        if wrap not in ("repeat", "mirror", "clamp"):
            raise NotImplementedError(f"{what}.wrap_mode: {wrap!r} is not mapped")
        d["wrap_mode"] = wrap
        cs = v.get("color_space", "auto")
        if cs == "linear" or (raw and cs == "auto"):
            d["raw"] = True
        if "to_uv" in v:
            d["to_uv"] = _transform(v["to_uv"], f"{what}.to_uv")
        return d
    if t == "checkerboard":
        d = {"type": "checkerboard", "color0": _rgb(v.get("color0", 0.4), f"{what}.color0"),
             "color1": _rgb(v.get("color1", 0.2), f"{what}.color1")}
        if "to_uv" in v:
            d["to_uv"] = _transform(v["to_uv"], f"{what}.to_uv")
        return d
    raise NotImplementedError(f"{what}: texture type {t!r} is not mapped")


def _color(mat, key, default, what, ctx):
    v = mat.get(key, default)
    if isinstance(v, (str, dict)):
        return _texture(v, f"{what}.{key}", ctx or _Ctx())
    return _rgb(v, f"{what}.{key}")


def _float(mat, key, default, what):
    v = mat.get(key, default)
    if isinstance(v, (str, dict)):
        raise NotImplementedError(f"{what}.{key}: textured float parameters are not mapped")
    return float(v)


def _bsdf(mat, what, ctx=None):
    """pellucid material -> Mitsuba BSDF. pellucid's opaque materials reflect on both sides of a surface
    unless `two_sided` is false, Mitsuba's on the front only, so two-sided ones are wrapped in `twosided`
    (dielectrics and principled are two-sided already). A bump or normal map wraps the result."""
    ctx = ctx or _Ctx()
    d = _bsdf_one_sided(mat, what, ctx)
    if d["type"] not in ("dielectric", "roughdielectric", "thindielectric", "principled", "principledthin") \
            and mat.get("two_sided", True):
        d = {"type": "twosided", "bsdf": d}
    for key, plugin, slot in (("normal_map", "normalmap", "normalmap"), ("bump_map", "bumpmap", "arbitrary")):
        if key in mat:  # pellucid applies the normal map first, then the bump map: bump is outermost
            d = {"type": plugin, slot: _texture(mat[key], f"{what}.{key}", ctx, raw=True), "bsdf": d,
                 "use_shadowing_function": bool(mat.get("terminator_softening", True)),
                 "flip_invalid_normals": mat.get("invalid_normals", "bend") == "mirror"}
            if plugin == "bumpmap":
                d["scale"] = _float(mat, "bump_scale", 1.0, what)
    return d


def _principled(mat, what, ctx):
    """principled -> Mitsuba principled / principledthin, every value written (the defaults differ)."""
    thin = bool(mat.get("thin", False))
    d = {"type": "principledthin" if thin else "principled",
         "base_color": _color(mat, "base_color", 0.8, what, ctx)}
    keys = [("roughness", "roughness", 0.5), ("anisotropic", "anisotropic", 0.0),
            ("specular_tint", "spec_tint", 0.0), ("sheen", "sheen", 0.0), ("sheen_tint", "sheen_tint", 0.5)]
    if mat.get("variant", "2012") == "2015":
        keys += [("specular_transmission", "spec_trans", 0.0), ("flatness", "flatness", 0.0)]
        keys += [("diffuse_transmission", "diff_trans", 0.0)] if thin else []
    if not thin:
        keys += [("metallic", "metallic", 0.0), ("clearcoat", "clearcoat", 0.0),
                 ("clearcoat_gloss", "clearcoat_gloss", 1.0)]
    for ours, theirs, default in keys:
        d[theirs] = _float(mat, ours, default, what)
    if "eta" in mat:
        d["eta"] = _float(mat, "eta", 1.5, what)
    elif thin:  # principledthin takes no `specular`: the same eta, ((eta - 1)/(eta + 1))^2 = 0.08 specular
        f0 = (0.08 * _float(mat, "specular", 0.5, what)) ** 0.5
        d["eta"] = (1.0 + f0) / (1.0 - f0)
    else:
        d["specular"] = _float(mat, "specular", 0.5, what)
    return d


def _bsdf_one_sided(mat, what, ctx=None):
    ctx = ctx or _Ctx()
    t = mat.get("type")
    if t in ("lambertian", "diffuse"):
        return {"type": "diffuse", "reflectance": _color(mat, "reflectance", 0.5, what, ctx)}
    if t == "oren_nayar":
        if not ctx.substitute:
            raise NotImplementedError(f"{what}: oren_nayar has no Mitsuba 3 plugin (substitute: diffuse)")
        return {"type": "diffuse", "reflectance": _color(mat, "reflectance", 0.5, what, ctx)}
    if t == "principled":
        if mat.get("variant", "2012") != "2015" and not ctx.substitute:
            raise NotImplementedError(f"{what}: principled 2012 has no Mitsuba 3 plugin (substitute: principled)")
        return _principled(mat, what, ctx)
    if t in ("plastic", "rough_plastic"):
        variant = mat.get("variant", "coupled")
        if variant not in ("coupled", "linear"):
            raise NotImplementedError(f"{what}.variant: {variant!r} has no Mitsuba equivalent")
        d = {"type": "plastic" if t == "plastic" else "roughplastic",
             "diffuse_reflectance": _color(mat, "diffuse_reflectance", 0.5, what, ctx),
             "int_ior": _ior(mat.get("int_ior", "polypropylene"), f"{what}.int_ior"),
             "ext_ior": _ior(mat.get("ext_ior", "air"), f"{what}.ext_ior"),
             "nonlinear": variant == "coupled"}
        if "specular_reflectance" in mat:
            d["specular_reflectance"] = _color(mat, "specular_reflectance", 1.0, what, ctx)
        if t == "rough_plastic":
            _alpha(mat, d, what)
            if "alpha_u" in d:
                raise NotImplementedError(f"{what}: Mitsuba's roughplastic is isotropic")
        return d
    if t in ("conductor", "rough_conductor"):
        if mat.get("fresnel", "exact") != "exact":
            raise NotImplementedError(f"{what}.fresnel: only 'exact' has a Mitsuba equivalent")
        if mat.get("multiple_scattering", False):
            raise NotImplementedError(f"{what}.multiple_scattering: Mitsuba has no energy compensation")
        d = {"type": "conductor" if t == "conductor" else "roughconductor"}
        eta, k = _conductor_ior(mat, what)
        if eta is None:
            d["material"] = "none"
        else:
            d["eta"], d["k"] = eta, k
        if "specular_reflectance" in mat:
            d["specular_reflectance"] = _color(mat, "specular_reflectance", 1.0, what, ctx)
        if t == "rough_conductor":
            _alpha(mat, d, what)
        return d
    if t in ("dielectric", "rough_dielectric", "thin_dielectric"):
        d = {"type": {"dielectric": "dielectric", "rough_dielectric": "roughdielectric",
                      "thin_dielectric": "thindielectric"}[t],
             "int_ior": _ior(mat.get("int_ior", "bk7"), f"{what}.int_ior"),
             "ext_ior": _ior(mat.get("ext_ior", "air"), f"{what}.ext_ior")}
        for key in ("specular_reflectance", "specular_transmittance"):
            if key in mat:
                d[key] = _color(mat, key, 1.0, what, ctx)
        if t == "rough_dielectric":
            _alpha(mat, d, what)
        return d
    raise NotImplementedError(f"{what}: material type {t!r} is not mapped to Mitsuba")


def _emitter(em, what):
    t = em.get("type", "area")
    if t != "area":
        raise NotImplementedError(f"{what}: shape emitter type {t!r} is not mapped")
    if em.get("two_sided", False):
        raise NotImplementedError(f"{what}: two_sided area emitters have no Mitsuba equivalent")
    return {"type": "area", "radiance": _rgb(em["radiance"], f"{what}.radiance")}


def _filter(f):
    if f is None:
        return {"type": "gaussian"}  # Mitsuba default (stddev 0.5)
    t = f.get("type", "gaussian")
    if t == "box":
        return {"type": "box"}
    if t == "tent":
        d = {"type": "tent"}
        if "radius" in f:
            d["radius"] = float(f["radius"])
        return d
    if t == "gaussian":
        d = {"type": "gaussian"}
        if "stddev" in f:
            d["stddev"] = float(f["stddev"])
        return d
    raise NotImplementedError(f"film.filter type {t!r} is not mapped")


def _mesh(shape, to_world, name, bsdf, emitter):
    pos = np.asarray(shape["positions"], dtype=np.float64).reshape(-1, 3)
    idx = np.asarray(shape["indices"], dtype=np.uint32).reshape(-1, 3)
    nrm = shape.get("normals")
    uvs = shape.get("uvs")
    nrm = None if nrm is None or len(nrm) == 0 else np.asarray(nrm, np.float64).reshape(-1, 3)
    uvs = None if uvs is None or len(uvs) == 0 else np.asarray(uvs, np.float64).reshape(-1, 2)
    # Bake to_world into the vertex data (normals with the inverse transpose).
    M = np.array(to_world.matrix, dtype=np.float64).reshape(4, 4)
    p4 = np.c_[pos, np.ones(len(pos))] @ M.T
    pos = p4[:, :3] / p4[:, 3:4]
    if nrm is not None:
        nrm = nrm @ np.linalg.inv(M[:3, :3])  # == (inv(M)^T @ n^T)^T
        nrm /= np.maximum(np.linalg.norm(nrm, axis=1, keepdims=True), 1e-30)
    props = mi.Properties()
    if shape.get("flip_normals", False):
        props["flip_normals"] = True
    props["bsdf"] = mi.load_dict(bsdf)
    if emitter is not None:
        props["emitter"] = mi.load_dict(emitter)
    mesh = mi.Mesh(name, len(pos), len(idx), props,
                   has_vertex_normals=nrm is not None,
                   has_vertex_texcoords=uvs is not None)
    params = mi.traverse(mesh)
    params["vertex_positions"] = dr.ravel(mi.TensorXf(pos.astype(np.float32).ravel()))
    params["faces"] = dr.ravel(mi.TensorXu(idx.ravel()))
    if nrm is not None:
        params["vertex_normals"] = dr.ravel(mi.TensorXf(nrm.astype(np.float32).ravel()))
    if uvs is not None:
        params["vertex_texcoords"] = dr.ravel(mi.TensorXf(uvs.astype(np.float32).ravel()))
    params.update()
    return mesh


def _ply(shape, to_world, bsdf, emitter, what, base_dir):
    """A PLY file. pellucid shades a file without vertex normals flat unless `smooth_normals`; Mitsuba
    computes smooth ones unless `face_normals`: the header says which the file is."""
    fn = shape["filename"]
    path = fn if os.path.isabs(fn) else os.path.join(base_dir, fn)
    if not os.path.exists(path):
        raise FileNotFoundError(f"{what}.filename: no such file {path!r}")
    with open(path, "rb") as f:
        header = f.read(4096).split(b"end_header")[0]
    has_normals = b"property float nx" in header or b"property double nx" in header
    flat = shape.get("face_normals", False) or (not has_normals and not shape.get("smooth_normals", False))
    d = {"type": "ply", "filename": path, "to_world": to_world, "bsdf": bsdf, "face_normals": bool(flat)}
    if shape.get("flip_normals", False):
        d["flip_normals"] = True
    if emitter is not None:
        d["emitter"] = emitter
    return d


def _light(l, what, base_dir):
    t = l.get("type")
    if t == "constant":
        return {"type": "constant", "radiance": _rgb(l.get("radiance", 1.0), f"{what}.radiance")}
    if t == "point":
        d = {"type": "point", "intensity": _rgb(l.get("intensity", 1.0), f"{what}.intensity")}
        if "position" in l:
            d["position"] = _vec3(l["position"], f"{what}.position")
        else:
            d["to_world"] = _transform(l.get("to_world"), f"{what}.to_world")
        return d
    if t == "spot":
        # Both emit along the local +z axis of to_world. The falloff between beam_width and
        # cutoff_angle is a smooth ramp in both, not necessarily the same curve: compare spots with care.
        cutoff = float(l.get("cutoff_angle", 20.0))
        return {"type": "spot", "intensity": _rgb(l.get("intensity", 1.0), f"{what}.intensity"),
                "cutoff_angle": cutoff, "beam_width": float(l.get("beam_width", 0.75 * cutoff)),
                "to_world": _transform(l.get("to_world"), f"{what}.to_world")}
    if t == "directional":
        d = {"type": "directional", "irradiance": _rgb(l.get("irradiance", 1.0), f"{what}.irradiance")}
        if "direction" in l:
            d["direction"] = _vec3(l["direction"], f"{what}.direction")
        else:
            d["to_world"] = _transform(l.get("to_world"), f"{what}.to_world")
        return d
    if t == "envmap":
        fn = l.get("filename")
        if not isinstance(fn, str):
            raise ValueError(f"{what}.filename: expected a path string, got {fn!r}")
        path = fn if os.path.isabs(fn) else os.path.join(base_dir, fn)
        if not os.path.exists(path):
            raise FileNotFoundError(f"{what}.filename: no such file {path!r}")
        return {"type": "envmap", "filename": path, "scale": float(l.get("scale", 1.0)),
                "to_world": _transform(l.get("to_world"), f"{what}.to_world")}
    raise NotImplementedError(f"{what}: light type {t!r} is not mapped")


# --------------------------------------------------------------------------- conversion
def to_mitsuba_dict(scene_json: dict, base_dir: str = ".", substitute: bool = False) -> dict:
    """Convert a pellucid JSON scene (parsed) into a Mitsuba 3 scene dict.

    Requires a Mitsuba variant to be set (mi.set_variant) beforehand. Relative file names (envmap,
    textures, ply) are resolved against `base_dir` (the scene file's folder). `substitute`: render
    the models that Mitsuba 3 lacks as their nearest Mitsuba plugin (module docstring).
    """
    if mi.variant() is None:
        raise RuntimeError("call mi.set_variant(...) before to_mitsuba_dict()")
    sj = scene_json
    cam = sj.get("camera", {})
    film = sj.get("film", {})
    samp = sj.get("sampler", {})
    integ = sj.get("integrator", {})

    if cam.get("type", "perspective") != "perspective":
        raise NotImplementedError(f"camera type {cam.get('type')!r} is not mapped")
    sensor = {
        "type": "perspective",
        "fov": float(cam.get("fov", 45.0)),
        "fov_axis": cam.get("fov_axis", "x"),
        "to_world": _transform(cam.get("to_world"), "camera.to_world"),
        "sampler": {"type": "independent",
                    "sample_count": int(samp.get("sample_count", 16)),
                    "seed": int(samp.get("seed", 0))},
        "film": {"type": "hdrfilm",
                 "width": int(film.get("width", 256)),
                 "height": int(film.get("height", 256)),
                 "rfilter": _filter(film.get("filter")),
                 "pixel_format": "rgb",
                 "component_format": "float32"},
    }
    for k in ("near_clip", "far_clip"):
        if k in cam:
            sensor[k] = float(cam[k])

    if integ.get("type", "path") != "path":
        raise NotImplementedError(f"integrator type {integ.get('type')!r} is not mapped")
    if integ.get("strategy", "mis") != "mis":
        raise NotImplementedError("integrator.strategy: Mitsuba's path tracer is MIS only")
    out = {
        "type": "scene",
        "integrator": {"type": "path",
                       "max_depth": int(integ.get("max_depth", -1)),
                       "rr_depth": int(integ.get("rr_depth", 5))},
        "sensor": sensor,
    }
    if "hide_emitters" in integ:
        out["integrator"]["hide_emitters"] = bool(integ["hide_emitters"])

    ctx = _Ctx(sj.get("textures", {}), base_dir, substitute)
    mats = sj.get("materials", {})
    mat_ids = {}
    for i, (name, m) in enumerate(mats.items()):
        key = f"mat_{i}_{name}"
        out[key] = _bsdf(m, f"materials.{name}", ctx)
        mat_ids[name] = key

    for i, s in enumerate(sj.get("shapes", [])):
        what = f"shapes[{i}]"
        m = s.get("material")
        if isinstance(m, str):
            if m not in mat_ids:
                raise KeyError(f"{what}: unknown material {m!r}")
            bsdf = {"type": "ref", "id": mat_ids[m]}
            bsdf_full = out[mat_ids[m]]
        elif isinstance(m, dict):
            bsdf = bsdf_full = _bsdf(m, f"{what}.material", ctx)
        elif m is None:
            bsdf = bsdf_full = {"type": "twosided", "bsdf": {"type": "diffuse"}}
        else:
            raise ValueError(f"{what}: bad material {m!r}")
        em = _emitter(s["emitter"], f"{what}.emitter") if s.get("emitter") else None
        tw = _transform(s.get("to_world"), f"{what}.to_world")
        t = s.get("type")
        if t in ("rectangle", "cube", "sphere"):
            d = {"type": t, "to_world": tw, "bsdf": bsdf}
            if t == "sphere":
                # Mitsuba: to_world @ translate(center) @ scale(radius)
                d["center"] = _vec3(s.get("center", [0, 0, 0]), f"{what}.center")
                d["radius"] = float(s.get("radius", 1.0))
            elif "center" in s or "radius" in s:
                raise ValueError(f"{what}: center/radius only supported on spheres")
            if s.get("flip_normals", False):
                d["flip_normals"] = True
            if em is not None:
                d["emitter"] = em
            out[f"shape_{i}"] = d
        elif t == "mesh":
            out[f"shape_{i}"] = _mesh(s, tw, f"shape_{i}", bsdf_full, em)
        elif t == "ply":
            out[f"shape_{i}"] = _ply(s, tw, bsdf, em, what, base_dir)
        else:
            raise NotImplementedError(f"{what}: shape type {t!r} is not mapped")

    for i, l in enumerate(sj.get("lights", [])):
        out[f"light_{i}"] = _light(l, f"lights[{i}]", base_dir)
    return out


# --------------------------------------------------------------------------- rendering
def _peak_rss_mb():
    """This process's peak resident memory (VmHWM; Linux), None where /proc is missing. Unlike the
    rusage of a child, it does not include the parent's memory at the fork."""
    try:
        with open("/proc/self/status") as f:
            for line in f:
                if line.startswith("VmHWM:"):
                    return int(line.split()[1]) / 1024.0
    except OSError:
        pass
    return None


def _write_exr(path, arr):
    arr = np.ascontiguousarray(arr, dtype=np.float32)
    mi.Bitmap(arr, mi.Bitmap.PixelFormat.RGB).write(path)


def _render(scene, spp, seed):
    img = mi.render(scene, spp=spp, seed=seed)
    dr.eval(img)
    dr.sync_thread()
    return img


def main(argv=None):
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("scene")
    ap.add_argument("--variant", choices=["scalar_rgb", "llvm_ad_rgb"], required=True)
    ap.add_argument("--spp", type=int, required=True)
    ap.add_argument("--seed", type=int, default=0)
    ap.add_argument("--out", required=True, help="output EXR (mean image)")
    ap.add_argument("--threads", type=int, default=None, help="default: all cores")
    ap.add_argument("--passes", type=int, default=1)
    ap.add_argument("--max-depth", type=int, default=None)
    ap.add_argument("--json-report", default=None)
    ap.add_argument("--each-dir", default=None,
                    help="also write each pass's image as EACH_DIR/<k>.exr (k = 0 .. passes-1)")
    ap.add_argument("--base-dir", default=None, help="folder for relative file names (default: the scene's)")
    ap.add_argument("--warmup", choices=["auto", "full", "tiny", "none"], default="auto",
                    help="auto: 'full' for llvm (same spp/pass + film, untimed), 'none' for scalar; "
                         "'tiny' = spp=1 (does not avoid recompiling the timed kernel)")
    ap.add_argument("--substitute", action="store_true",
                    help="render models without a Mitsuba plugin as the nearest one (for timing)")
    ap.add_argument("--quiet", action="store_true")
    a = ap.parse_args(argv)

    K = a.passes
    if K < 1 or a.spp < 1 or a.spp % K:
        ap.error("--spp must be a positive multiple of --passes")
    spp_pass = a.spp // K

    mi.set_variant(a.variant)
    mi.set_log_level(mi.LogLevel.Warn)

    with open(a.scene) as f:
        sj = json.load(f)
    if a.max_depth is not None:
        sj.setdefault("integrator", {"type": "path"})["max_depth"] = a.max_depth

    t0 = time.perf_counter()
    base_dir = a.base_dir or os.path.dirname(os.path.abspath(a.scene))
    scene = mi.load_dict(to_mitsuba_dict(sj, base_dir, a.substitute))
    load_s = time.perf_counter() - t0
    # Set the render's thread count only after loading: Mitsuba 3.9's EXR reader and writer
    # (OpenEXR/IlmThread on Dr.Jit's pool) deadlock when the pool has a single thread, and an
    # envmap is read while loading.
    if a.threads is not None:
        dr.set_thread_count(a.threads)
    film_size = scene.sensors()[0].film().size()
    W, H = int(film_size[0]), int(film_size[1])

    # JIT warm-up (llvm only). Dr.Jit bakes spp and the film size into the kernel as
    # literals, so a spp=1 warm-up does NOT compile the kernel used by the timed render
    # (measured: ~0.11 s of LLVM compile lands in the timed render on a cold kernel cache).
    # Hence the default "full" warm-up renders once with the exact timed configuration.
    is_llvm = a.variant.startswith("llvm")
    warmup = a.warmup if a.warmup != "auto" else ("full" if is_llvm else "none")
    warm_s = 0.0
    if warmup != "none":
        t0 = time.perf_counter()
        _render(scene, 1 if warmup == "tiny" else spp_pass, a.seed + 1_000_003)
        warm_s = time.perf_counter() - t0
    if is_llvm:
        dr.set_flag(dr.JitFlag.KernelHistory, True)
        dr.kernel_history()  # clear

    seeds = [a.seed] if K == 1 else [a.seed * K + k for k in range(K)]
    imgs, secs = [], []
    for s in seeds:
        t0 = time.perf_counter()
        img = _render(scene, spp_pass, s)
        secs.append(time.perf_counter() - t0)
        imgs.append(np.array(img, dtype=np.float64))
    seconds = float(sum(secs))
    jit_compile_s = None
    if is_llvm:
        hist = dr.kernel_history()
        dr.set_flag(dr.JitFlag.KernelHistory, False)
        jit_compile_s = sum(k.get("codegen_time", 0.0) + k.get("backend_time", 0.0)
                            for k in hist if k.get("type") == dr.KernelType.JIT) / 1000.0

    n_threads = int(dr.thread_count())
    # Mitsuba 3.9's EXR writer (OpenEXR/IlmThread on Dr.Jit's pool) deadlocks when the
    # pool has a single thread, so widen the pool again for the (untimed) file output.
    if n_threads < 2:
        dr.set_thread_count(2)

    stack = np.stack(imgs)
    mean = stack.mean(axis=0)
    out_dir = os.path.dirname(os.path.abspath(a.out))
    os.makedirs(out_dir, exist_ok=True)
    _write_exr(a.out, mean)
    if a.each_dir:
        os.makedirs(a.each_dir, exist_ok=True)
        for k, im in enumerate(imgs):
            _write_exr(os.path.join(a.each_dir, f"{k}.exr"), im)
    var_path = None
    if K > 1:
        var_path = (a.out[:-4] if a.out.lower().endswith(".exr") else a.out) + ".var.exr"
        _write_exr(var_path, stack.var(axis=0, ddof=1) / K)  # variance of the mean

    report = {
        "renderer": "mitsuba",
        "mitsuba_version": mi.__version__,
        "variant": a.variant,
        "spp": a.spp,
        "passes": K,
        "seed": a.seed,
        "pass_seeds": seeds,
        "width": W,
        "height": H,
        "seconds": seconds,
        "pass_seconds": secs,
        "samples_per_second": W * H * a.spp / seconds if seconds > 0 else None,
        "threads": n_threads,
        "warmup": warmup,
        "warmup_seconds": warm_s,
        "jit_compile_seconds_in_timed": jit_compile_s,
        "load_seconds": load_s,
        "peak_rss_mb": _peak_rss_mb(),
        "max_depth": int(sj.get("integrator", {}).get("max_depth", -1)),
        "out": a.out,
        "var_out": var_path,
    }
    if a.json_report:
        with open(a.json_report, "w") as f:
            json.dump(report, f, indent=2)
    if not a.quiet:
        print(json.dumps(report))
    return 0


if __name__ == "__main__":
    sys.exit(main())
