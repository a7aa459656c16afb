"""Write torus.obj: a smooth closed torus with per-vertex normals, for scenes/subsurface.json.
SPDX-License-Identifier: Apache-2.0

    python3 scenes/meshes/make_torus.py [--major 1] [--minor 0.4] [--nu 64] [--nv 32]

The torus lies around the z axis: major radius R (centre of the tube), minor radius r (the tube),
nu segments around z and nv around the tube, 2·nu·nv triangles. The grid wraps in both directions
onto shared vertices, so the mesh is closed (every edge has two triangles), and the normals are the
exact ones of the torus at each vertex. Deterministic: the same arguments give the same file.
"""
from __future__ import annotations

import argparse
import math
import pathlib


def torus_obj(major: float, minor: float, nu: int, nv: int) -> str:
    lines = [f"# torus: R = {major:g}, r = {minor:g}, {nu} x {nv} segments, {2 * nu * nv} triangles "
             "(written by make_torus.py)"]
    for i in range(nu):
        u = 2.0 * math.pi * i / nu
        cu, su = math.cos(u), math.sin(u)
        for j in range(nv):
            v = 2.0 * math.pi * j / nv
            cv, sv = math.cos(v), math.sin(v)
            n = (cv * cu, cv * su, sv)
            p = ((major + minor * cv) * cu, (major + minor * cv) * su, minor * sv)
            lines.append("v {:.6f} {:.6f} {:.6f}".format(*p))
            lines.append("vn {:.6f} {:.6f} {:.6f}".format(*n))
    idx = lambda i, j: (i % nu) * nv + (j % nv) + 1  # noqa: E731  (OBJ indices start at 1)
    for i in range(nu):
        for j in range(nv):
            a, b, c, d = idx(i, j), idx(i + 1, j), idx(i + 1, j + 1), idx(i, j + 1)
            # counter-clockwise seen from outside: (∂p/∂u × ∂p/∂v) points along the outward normal
            lines.append(f"f {a}//{a} {b}//{b} {c}//{c}")
            lines.append(f"f {a}//{a} {c}//{c} {d}//{d}")
    return "\n".join(lines) + "\n"


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("--major", type=float, default=1.0)
    ap.add_argument("--minor", type=float, default=0.4)
    ap.add_argument("--nu", type=int, default=64)
    ap.add_argument("--nv", type=int, default=32)
    ap.add_argument("--out", default=str(pathlib.Path(__file__).resolve().parent / "torus.obj"))
    a = ap.parse_args()
    pathlib.Path(a.out).write_text(torus_obj(a.major, a.minor, a.nu, a.nv))


if __name__ == "__main__":
    main()
