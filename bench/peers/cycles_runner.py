#!/usr/bin/env python3
"""Render a pellucid JSON scene with Blender Cycles through `bpy` (experimental peer, benchmarks only).
SPDX-License-Identifier: Apache-2.0

Run with its own venv (bench/.venv-cycles: `pip install "numpy<2" bpy`); never imports pellucid:

    bench/.venv-cycles/bin/python bench/peers/cycles_runner.py SCENE.json --spp N --seed S --out OUT.exr \
        [--threads T] [--passes K] [--json-report REPORT.json]

Maps a subset: perspective camera, rectangle/cube/mesh shapes, `lambertian` materials, `area` emitters,
`constant` lights. Anything else raises NotImplementedError. See bench/peers/README.md for the status of
its agreement with pellucid.
"""
from __future__ import annotations

import argparse
import json
import math
import sys
import time

import numpy as np
import bpy  # noqa: E402
import mathutils  # noqa: E402


def _vec3(v):
    return np.full(3, float(v)) if isinstance(v, (int, float)) else np.asarray(v, dtype=np.float64)


def _rgb(v):
    c = _vec3(v)
    return (float(c[0]), float(c[1]), float(c[2]), 1.0)


def _transform(ops):
    """pellucid to_world op list (first op applied first) as a 4x4 matrix, Mitsuba's conventions."""
    m = np.eye(4)
    if ops is None:
        return m
    for op in [ops] if isinstance(ops, dict) else ops:
        (k, v), = op.items()
        t = np.eye(4)
        if k == "scale":
            t[:3, :3] = np.diag(_vec3(v))
        elif k == "translate":
            t[:3, 3] = _vec3(v)
        elif k == "rotate":  # Rodrigues' formula, right-handed, degrees
            a = _vec3(v["axis"])
            a = a / np.linalg.norm(a)
            th = math.radians(float(v["angle"]))
            K = np.array([[0, -a[2], a[1]], [a[2], 0, -a[0]], [-a[1], a[0], 0]])
            t[:3, :3] = np.eye(3) + math.sin(th) * K + (1 - math.cos(th)) * K @ K
        elif k == "look_at":  # columns: left, up, forward, origin (Mitsuba's look_at)
            o, tg, up = _vec3(v["origin"]), _vec3(v["target"]), _vec3(v["up"])
            d = (tg - o) / np.linalg.norm(tg - o)
            left = np.cross(up, d)
            left /= np.linalg.norm(left)
            t[:3, 0], t[:3, 1], t[:3, 2], t[:3, 3] = left, np.cross(d, left), d, o
        elif k == "matrix":
            t = np.asarray(v, dtype=np.float64).reshape(4, 4)
        else:
            raise NotImplementedError(f"to_world op {k!r}")
        m = t @ m
    return m


_RECT = (np.array([[-1, -1, 0], [1, -1, 0], [1, 1, 0], [-1, 1, 0]], float), [[0, 1, 2, 3]])
_CUBE_V = np.array([[x, y, z] for x in (-1, 1) for y in (-1, 1) for z in (-1, 1)], float)
_CUBE_F = [[0, 1, 3, 2], [4, 6, 7, 5], [0, 4, 5, 1], [2, 3, 7, 6], [0, 2, 6, 4], [1, 5, 7, 3]]  # outward


def _material(name, mat, emitter):
    if mat.get("type", "lambertian") != "lambertian":
        raise NotImplementedError(f"material type {mat.get('type')!r}")
    m = bpy.data.materials.new(name)
    m.use_nodes = True
    nt = m.node_tree
    nt.nodes.clear()
    out = nt.nodes.new("ShaderNodeOutputMaterial")
    dif = nt.nodes.new("ShaderNodeBsdfDiffuse")
    dif.inputs["Color"].default_value = _rgb(mat.get("reflectance", 0.5))
    dif.inputs["Roughness"].default_value = 0.0  # Lambertian (no Oren-Nayar)
    shader = dif.outputs["BSDF"]
    if emitter is not None:
        if emitter.get("type", "area") != "area" or emitter.get("two_sided", False):
            raise NotImplementedError("only one-sided area emitters")
        em = nt.nodes.new("ShaderNodeEmission")
        em.inputs["Color"].default_value = _rgb(emitter.get("radiance", 1.0))
        em.inputs["Strength"].default_value = 1.0  # radiance = strength * colour
        add = nt.nodes.new("ShaderNodeAddShader")
        nt.links.new(shader, add.inputs[0])
        nt.links.new(em.outputs["Emission"], add.inputs[1])
        # Cycles emits from both sides of a mesh; pellucid's (and Mitsuba's) area emitters only along the
        # normal: the back side gets the plain diffuse shader.
        geo = nt.nodes.new("ShaderNodeNewGeometry")
        mix = nt.nodes.new("ShaderNodeMixShader")
        nt.links.new(geo.outputs["Backfacing"], mix.inputs["Fac"])
        nt.links.new(add.outputs["Shader"], mix.inputs[1])
        nt.links.new(shader, mix.inputs[2])
        shader = mix.outputs["Shader"]
    nt.links.new(shader, out.inputs["Surface"])
    return m


def build(sj):
    bpy.ops.wm.read_factory_settings(use_empty=True)
    sc = bpy.context.scene
    sc.render.engine = "CYCLES"
    cy = sc.cycles
    cy.device = "CPU"
    cy.use_adaptive_sampling = False
    cy.use_denoising = False
    cy.sample_clamp_direct = cy.sample_clamp_indirect = 0.0
    cy.caustics_reflective = cy.caustics_refractive = True
    cy.blur_glossy = 0.0
    depth = int(sj.get("integrator", {}).get("max_depth", -1))
    bounces = 1024 if depth < 0 else max(0, depth - 2)  # Cycles counts bounces after the first hit
    cy.max_bounces = cy.diffuse_bounces = cy.glossy_bounces = cy.transmission_bounces = bounces
    sc.view_settings.view_transform = "Standard"
    sc.view_settings.look = "None"
    film = sj.get("film", {})
    W, H = int(film.get("width", 256)), int(film.get("height", 256))
    sc.render.resolution_x, sc.render.resolution_y, sc.render.resolution_percentage = W, H, 100
    f = film.get("filter") or {"type": "gaussian", "stddev": 0.5}
    if f.get("type") == "box":
        cy.pixel_filter_type = "BOX"
        sc.render.filter_size = 2.0 * float(f.get("radius", 0.5))
    else:
        raise NotImplementedError("Cycles runner: only the box filter is mapped (use pellucid bench --filter box)")

    cam = sj.get("camera", {})
    cd = bpy.data.cameras.new("cam")
    axis = cam.get("fov_axis", "x")
    if axis == "smaller":
        axis = "x" if W <= H else "y"
    if axis not in ("x", "y"):
        raise NotImplementedError(f"fov_axis {axis!r}")
    cd.sensor_fit = "HORIZONTAL" if axis == "x" else "VERTICAL"
    cd.angle = math.radians(float(cam.get("fov", 45.0)))
    cd.clip_start, cd.clip_end = 1e-3, 1e4
    co = bpy.data.objects.new("cam", cd)
    M = _transform(cam.get("to_world")) @ np.diag([-1.0, 1.0, -1.0, 1.0])  # Blender looks along -z, x right
    co.matrix_world = mathutils.Matrix(M.tolist())
    sc.collection.objects.link(co)
    sc.camera = co

    world = bpy.data.worlds.new("world")
    world.use_nodes = True
    bg = world.node_tree.nodes["Background"]
    bg.inputs["Color"].default_value = (0, 0, 0, 1)
    for l in sj.get("lights", []):
        if l.get("type") != "constant":
            raise NotImplementedError(f"light type {l.get('type')!r}")
        bg.inputs["Color"].default_value = _rgb(l.get("radiance", 1.0))
    bg.inputs["Strength"].default_value = 1.0
    sc.world = world

    mats = sj.get("materials", {})
    for i, s in enumerate(sj.get("shapes", [])):
        t = s.get("type")
        if t == "rectangle":
            v, faces = _RECT
        elif t == "cube":
            v, faces = _CUBE_V, _CUBE_F
        elif t == "mesh":
            v = np.asarray(s["positions"], float).reshape(-1, 3)
            faces = np.asarray(s["indices"], int).reshape(-1, 3).tolist()
        else:
            raise NotImplementedError(f"shape type {t!r}")
        M = _transform(s.get("to_world"))
        pw = (np.c_[v, np.ones(len(v))] @ M.T)[:, :3]
        me = bpy.data.meshes.new(f"shape_{i}")
        me.from_pydata([tuple(p) for p in pw], [], faces)
        me.update()
        m = s.get("material")
        mat = mats[m] if isinstance(m, str) else (m or {"type": "lambertian", "reflectance": 0.5})
        me.materials.append(_material(f"mat_{i}", mat, s.get("emitter")))
        ob = bpy.data.objects.new(f"shape_{i}", me)
        sc.collection.objects.link(ob)
    return sc, W, H


def render(sc, spp, seed, path):
    sc.cycles.samples = spp
    sc.cycles.seed = seed
    sc.render.filepath = path
    sc.render.image_settings.file_format = "OPEN_EXR"
    sc.render.image_settings.color_depth = "32"
    sc.render.image_settings.color_mode = "RGB"
    t0 = time.perf_counter()
    bpy.ops.render.render(write_still=True)
    return time.perf_counter() - t0


def main(argv=None):
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("scene")
    ap.add_argument("--spp", type=int, required=True)
    ap.add_argument("--seed", type=int, default=0)
    ap.add_argument("--out", required=True)
    ap.add_argument("--threads", type=int, default=0)
    ap.add_argument("--passes", type=int, default=1)
    ap.add_argument("--json-report", default=None)
    a = ap.parse_args(argv)
    with open(a.scene) as f:
        sj = json.load(f)
    sc, W, H = build(sj)
    if a.threads > 0:
        sc.render.threads_mode = "FIXED"
        sc.render.threads = a.threads
    spp_pass = a.spp // a.passes
    render(sc, 1, a.seed + 1_000_003, a.out)  # warm-up: kernels, BVH
    imgs, secs = [], []
    for k in range(a.passes):
        secs.append(render(sc, spp_pass, a.seed * a.passes + k, a.out))
        img = bpy.data.images.load(a.out)
        px = np.array(img.pixels[:], dtype=np.float64).reshape(H, W, -1)[::-1, :, :3]  # bottom-up rows
        bpy.data.images.remove(img)
        imgs.append(px)
    stack = np.stack(imgs)
    np.save(a.out + ".mean.npy", stack.mean(0))
    if a.passes > 1:
        np.save(a.out + ".var.npy", stack.var(0, ddof=1) / a.passes)
    rep = {"renderer": "cycles", "blender": bpy.app.version_string, "spp": a.spp, "passes": a.passes, "width": W,
           "height": H, "seconds": sum(secs), "note": "seconds include Cycles' per-render scene sync"}
    if a.json_report:
        with open(a.json_report, "w") as f:
            json.dump(rep, f)
    print(json.dumps(rep))
    return 0


if __name__ == "__main__":
    sys.exit(main())
