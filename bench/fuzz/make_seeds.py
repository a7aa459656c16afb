"""Write the fuzzers' assets (bench/fuzz/assets: the files seed scenes name), seed corpora
(bench/fuzz/corpus/<harness>/) and the inputs of the regression tests (tests/data/fuzz/). Deterministic; run again after changing it, and commit the output.
Needs numpy and OpenImageIO's oiiotool (openimageio-tools)."""
from __future__ import annotations

import json
import re
import shutil
import struct
import subprocess
from pathlib import Path

HERE = Path(__file__).resolve().parent
ROOT = HERE.parents[1]
ASSETS = HERE / "assets"
CORPUS = HERE / "corpus"


def write(path: Path, data: bytes | str) -> None:
    path.parent.mkdir(parents=True, exist_ok=True)
    path.write_bytes(data.encode() if isinstance(data, str) else data)


def oiio(*args: str) -> None:
    subprocess.run(["oiiotool", *args], check=True)


PLY_ASCII = """ply
format ascii 1.0
element vertex 4
property float x
property float y
property float z
property float nx
property float ny
property float nz
property float u
property float v
element face 2
property list uchar int vertex_indices
end_header
0 0 0 0 0 1 0 0
1 0 0 0 0 1 1 0
1 1 0 0 0 1 1 1
0 1 0 0 0 1 0 1
3 0 1 2
4 0 1 2 3
"""


def ply_binary(big_endian: bool) -> bytes:
    e = ">" if big_endian else "<"
    head = ("ply\nformat binary_%s_endian 1.0\nelement vertex 3\nproperty float x\nproperty float y\n"
            "property float z\nelement face 1\nproperty list uchar uint vertex_indices\nend_header\n"
            % ("big" if big_endian else "little")).encode()
    body = b"".join(struct.pack(e + "fff", *p) for p in [(0, 0, 0), (1, 0, 0), (0, 1, 0)])
    return head + body + struct.pack(e + "BIII", 3, 0, 1, 2)


OBJ = """# a quad and a triangle, with uv and normals
v 0 0 0
v 1 0 0
v 1 1 0
v 0 1 0
vt 0 0
vt 1 0
vt 1 1
vt 0 1
vn 0 0 1
usemtl a
f 1/1/1 2/2/1 3/3/1 4/4/1
usemtl b
f -4 -3 -2
"""


def json_seeds() -> dict[str, dict]:
    cam = {"type": "perspective", "fov": 40,
           "to_world": [{"look_at": {"origin": [0, 0, 4], "target": [0, 0, 0], "up": [0, 1, 0]}}]}
    film = {"width": 8, "height": 6}
    base = {"camera": cam, "film": film, "sampler": {"sample_count": 1}}
    return {
        "spheres": {**base, "materials": {"m": {"type": "rough_conductor", "material": "Au", "alpha": 0.2}},
                    "shapes": [{"type": "sphere", "radius": 1, "material": "m"}],
                    "lights": [{"type": "constant", "radiance": 1}]},
        "meshes": {**base, "materials": {"d": {"type": "lambertian", "reflectance": [0.2, 0.5, 0.7]}},
                   "shapes": [{"type": "ply", "filename": "mesh.ply", "material": "d"},
                              {"type": "obj", "filename": "mesh.obj", "material": "d",
                               "to_world": [{"translate": [0, 0, -1]}]},
                              {"type": "rectangle", "to_world": [{"scale": 0.3}, {"translate": [0, 1, 1]}],
                               "emitter": {"type": "area", "radiance": [4, 4, 4]}}]},
        "textures": {**base,
                     "textures": {"img": {"type": "image", "filename": "tex.png", "filter": "trilinear"}},
                     "materials": {"p": {"type": "rough_plastic", "diffuse_reflectance": "img",
                                         "alpha": {"type": "mix", "texture0": 0.05, "texture1": 0.3,
                                                   "amount": {"type": "noise", "variant": "fbm", "scale": 4}},
                                         "bump_map": {"type": "checkerboard", "to_uv": [{"scale": [8, 8, 1]}]},
                                         "bump_scale": 0.01},
                                   "g": {"type": "dielectric", "int_ior": "water"},
                                   "s": {"type": "principled", "base_color": {"type": "scale", "texture": "img",
                                                                              "scale": 0.5},
                                         "metallic": 0.3}},
                     "shapes": [{"type": "sphere", "radius": 1, "material": "p"},
                                {"type": "sphere", "center": [1, 0, 1], "radius": 0.3, "material": "g"},
                                {"type": "disk", "material": "s", "to_world": [{"translate": [0, -1, 0]}]}],
                     "lights": [{"type": "envmap", "filename": "env.exr", "scale": 0.5},
                                {"type": "point", "position": [0, 3, 3], "intensity": 5}]},
    }


def png(width: int, height: int, bit_depth: int, colour_type: int, raw: bytes) -> bytes:
    """A PNG file of the given IHDR and (already filtered) image data."""
    import zlib

    def chunk(kind: bytes, data: bytes) -> bytes:
        return struct.pack(">I", len(data)) + kind + data + struct.pack(">I", zlib.crc32(kind + data))

    ihdr = struct.pack(">IIBBBBB", width, height, bit_depth, colour_type, 0, 0, 0)
    return (b"\x89PNG\r\n\x1a\n" + chunk(b"IHDR", ihdr) + chunk(b"IDAT", zlib.compress(raw, 9))
            + chunk(b"IEND", b""))


def regressions() -> None:
    """Inputs that crashed, aborted or exhausted memory before their fix (tests/data/fuzz/README.md)."""
    out = ROOT / "tests" / "data" / "fuzz"
    # Deep nesting past the scene depth limit (256): JSON arrays, Mitsuba twosided wrappers.
    write(out / "deep_nesting.json", '{"film": ' + "[" * 1000 + "]" * 1000 + "}\n")
    inner = '<bsdf type="diffuse"/>'
    nest = '<bsdf type="twosided">' * 300 + inner + "</bsdf>" * 300
    write(out / "deep_twosided.xml", '<scene version="3.0.0">\n<shape type="sphere">' + nest + "</shape>\n</scene>\n")
    # Decompression bomb: a 1-bit greyscale PNG of 16384 x 16384 pixels (2^28, 4x the texture limit)
    # whose zeros compress to a few tens of KB; decoded to float RGB it would take 3 GB.
    side = 16384
    write(out / "bomb.png", png(side, side, 1, 0, (b"\x00" * (1 + side // 8)) * side))
    # PLY headers claiming 2^32 vertices (past the mesh element limit) and 10^8 (within it, but far
    # more than the data holds): both were std::bad_alloc without a file name.
    head = "ply\nformat binary_little_endian 1.0\nelement vertex {}\nproperty float x\nproperty float y\n" \
           "property float z\nelement face {}\nproperty list uchar int vertex_indices\nend_header\n"
    write(out / "huge_count.ply", head.format(2**32, 2**31).encode() + bytes(12))
    write(out / "truncated_count.ply", head.format(10**8, 10**8).encode() + bytes(12))
    # A float image with a NaN texel (PFM: 2x2 RGB, little-endian), and a scene using it.
    vals = [0.5, 0.5, 0.5, 0.25, float("nan"), 0.25, 0.1, 0.2, 0.3, 1.0, 1.0, 1.0]
    write(out / "nan_texel.pfm", b"PF\n2 2\n-1.0\n" + struct.pack("<12f", *vals))
    # Found by the image harness: a BMP header alone (no pixel data) claiming 4 x 1023410179 pixels of
    # 24 bits with RLE8 compression. OpenImageIO's reader decodes RLE images in ImageInput::open and
    # sizes its buffer in 32-bit arithmetic, which overflows: std::length_error, before the header's
    # size can be checked ("vector::_M_default_append", without the file's name).
    write(out / "rle_huge_height.bmp", struct.pack("<2sIHHI", b"BM", 90, 0, 0, 54)
          + struct.pack("<IiiHHIIiiII", 40, 4, 1023410179, 1, 24, 1, 0, 0, 0, 0, 0))


def main() -> None:
    regressions()
    # Assets named by the seed scenes (JSON and XML resolve relative names against this directory).
    write(ASSETS / "mesh.ply", PLY_ASCII)
    write(ASSETS / "mesh.obj", OBJ)
    oiio("--pattern", "checker:width=2:height=2", "4x4", "3", "-d", "uint8", "-o", str(ASSETS / "tex.png"))
    oiio("--pattern", "constant:color=0.5,0.6,0.7", "4x4", "3", "-d", "half", "-o", str(ASSETS / "env.exr"))
    for name in ["quad.png", "bump_height.png", "bump_normals.png", "pyramid.obj"]:
        shutil.copy(ROOT / "tests/data/mitsuba" / name, ASSETS / name)

    for name, scene in json_seeds().items():
        write(CORPUS / "json" / f"{name}.json", json.dumps(scene))
    # Mitsuba seeds: the test scenes, with $res defaults and films shrunk to 8x8.
    for xml in sorted((ROOT / "tests/data/mitsuba").glob("*.xml")):
        text = xml.read_text()
        text = re.sub(r'(<default name="res" value=")\d+', r"\g<1>8", text)
        text = re.sub(r'(name="(width|height)" value=")\d+', r"\g<1>8", text)
        write(CORPUS / "mitsuba_xml" / xml.name, text)
    write(CORPUS / "obj" / "mesh.obj", OBJ)
    shutil.copy(ROOT / "tests/data/mitsuba/pyramid.obj", CORPUS / "obj" / "pyramid.obj")
    write(CORPUS / "ply" / "ascii.ply", PLY_ASCII)
    write(CORPUS / "ply" / "binary_le.ply", ply_binary(False))
    write(CORPUS / "ply" / "binary_be.ply", ply_binary(True))
    # Image seeds: one selector byte (extension index in fuzz_image.cpp, colour space) + the file.
    tmp = HERE / "build-seeds"
    tmp.mkdir(exist_ok=True)
    formats = [(".png", "uint8", 0), (".exr", "half", 1), (".hdr", "float", 2), (".jpg", "uint8", 3),
               (".tif", "uint16", 4), (".tga", "uint8", 5), (".bmp", "uint8", 6)]
    # OpenImageIO reads PFM but does not write it: 4x3 RGB floats, little-endian (scale -1).
    pfm = b"PF\n4 3\n-1.0\n" + b"".join(struct.pack("<fff", x / 4, y / 3, 0.5) for y in range(3) for x in range(4))
    write(CORPUS / "image" / "seed.pfm", bytes([7]) + pfm)
    for ext, dtype, sel in formats:
        f = tmp / f"seed{ext}"
        oiio("--pattern", "checker:width=2:height=2", "4x3", "3", "-d", dtype, "-o", str(f))
        write(CORPUS / "image" / f"seed{ext}", bytes([sel]) + f.read_bytes())
    f = tmp / "mip.exr"
    oiio("--pattern", "fill:topleft=0,0,0:topright=1,0,0:bottomleft=0,1,0:bottomright=0,0,1", "8x8", "3",
         "-d", "half", "-otex", str(f))
    write(CORPUS / "image" / "mip.exr", bytes([1]) + f.read_bytes())
    shutil.rmtree(tmp)


if __name__ == "__main__":
    main()
