"""Mitsuba 3's RGB (η, k) of every named conductor, for tests/python/test_conductor_names.py
(committed as conductor_rgb.json beside this file).

Run once with the peer venv (bench/peers/setup_mitsuba.sh):

    /path/to/.venv-mitsuba/bin/python tests/data/mitsuba/conductor_rgb.py [--out FILE]

The names are the NAME of every NAME.eta.spd that the mitsuba package ships in data/ior/ (what a
`conductor`'s `material` may name), plus "none". Each comes from
`mi.load_dict({"type": "conductor", "material": name})` in the scalar_rgb variant, read back by
`mi.traverse`: the `eta.value` / `k.value` colours of the unbounded srgb textures it builds.
The test imports `mitsuba_conductor_rgb` and `mitsuba_normal_albedo` from this file when `mitsuba`
is importable in its own interpreter.
"""
from __future__ import annotations

import argparse
import json
import pathlib
import sys
from typing import Dict, List

HERE = pathlib.Path(__file__).resolve().parent


def mitsuba_names() -> List[str]:
    import mitsuba as mi

    data = pathlib.Path(mi.__file__).resolve().parent / "data" / "ior"
    names = sorted(p.name[: -len(".eta.spd")] for p in data.glob("*.eta.spd"))
    return names + ["none"]


def rgb(value) -> List[float]:
    """A Color3f (srgb texture) or a float (uniform texture, as for "none") as [r, g, b]."""
    if isinstance(value, float):
        return [value] * 3
    return [float(c) for c in value]


def mitsuba_conductor_rgb() -> Dict[str, Dict[str, List[float]]]:
    """{name: {"eta": [r, g, b], "k": [r, g, b]}} as Mitsuba's RGB variants evaluate them."""
    import mitsuba as mi

    if mi.variant() is None:
        mi.set_variant("scalar_rgb")
    out = {}
    for name in mitsuba_names():
        params = mi.traverse(mi.load_dict({"type": "conductor", "material": name}))
        out[name] = {key: rgb(params[f"{key}.value"]) for key in ("eta", "k")}
    return out


def mitsuba_normal_albedo(name: str) -> List[float]:
    """Sample weight of Mitsuba's smooth `conductor` named `name` at normal incidence: its reflectance
    F(cos θ = 1) per RGB channel."""
    import mitsuba as mi

    if mi.variant() is None:
        mi.set_variant("scalar_rgb")
    bsdf = mi.load_dict({"type": "conductor", "material": name})
    si = mi.SurfaceInteraction3f()
    si.wi = mi.Vector3f(0.0, 0.0, 1.0)
    si.sh_frame = mi.Frame3f(mi.Vector3f(0.0, 0.0, 1.0))
    _, weight = bsdf.sample(mi.BSDFContext(), si, 0.5, mi.Point2f(0.5, 0.5))
    return rgb(weight)


def main() -> int:
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--out", type=pathlib.Path, default=HERE / "conductor_rgb.json")
    args = ap.parse_args()
    import mitsuba as mi

    table = mitsuba_conductor_rgb()
    # One conductor a line; 7 significant digits keep the float32 values.
    rows = [f"  {json.dumps(n)}: {json.dumps({key: [float(f'{c:.7g}') for c in v] for key, v in e.items()})}"
            for n, e in table.items()]
    head = f'{{"mitsuba": {json.dumps(mi.__version__)}, "variant": {json.dumps(mi.variant())}, "conductors": {{\n'
    args.out.write_text(head + ",\n".join(rows) + "\n}}\n")
    print(f"wrote {len(table)} conductors to {args.out}")
    return 0


if __name__ == "__main__":
    sys.exit(main())
