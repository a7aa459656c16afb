"""Inputs the load_dict fuzzer (bench/fuzz/fuzz_load_dict.py) found raising something other than
pellucid.Error, and the raisable limits (each read once per process, so each case runs in a
subprocess with its environment variable set)."""
from __future__ import annotations

import os
import subprocess
import sys
from pathlib import Path

import numpy as np
import pytest

import pellucid

DATA = Path(__file__).resolve().parents[1] / "data" / "fuzz"


@pytest.mark.parametrize("value, message", [
    (10**400, r"materials\.m\.reflectance: value 100000000000\.\.\.\(401 digits\) overflows a double"),
    ("\udcff", r"materials\.m\.reflectance: the text cannot be encoded as UTF-8"),
])
def test_unconvertible_values_are_pellucid_errors(value, message) -> None:
    # Both raised RuntimeError "Unable to cast Python instance ..." before.
    with pytest.raises(pellucid.Error, match=message):
        pellucid.load_dict({"materials": {"m": {"type": "lambertian", "reflectance": value}}})


def test_surrogate_in_a_key_is_a_pellucid_error() -> None:
    with pytest.raises(pellucid.Error, match="materials: the text cannot be encoded as UTF-8"):
        pellucid.load_dict({"materials": {"\udcff": {"type": "lambertian"}}})


def test_directory_as_mesh_file_is_a_pellucid_error(tmp_path) -> None:
    # An empty filename resolves to the base directory; reading it raised std::ios_base::failure.
    with pytest.raises(pellucid.Error, match=r"shapes\[0\]\.filename: .*not a regular file \(a directory\?\)"):
        pellucid.load_dict({"shapes": [{"type": "ply", "filename": ""}]}, base_dir=tmp_path)


def test_checkerboard_colour_out_of_range_is_an_error() -> None:
    with pytest.raises(pellucid.Error, match=r"reflectance: the texture reaches -5 \(from "
                                             r"materials\.m\.reflectance\.color1\), out of range \[0, 1\]"):
        pellucid.load_dict({"materials": {"m": {"type": "lambertian",
                                                "reflectance": {"type": "checkerboard", "color1": -5}}}})


def _error_with_env(env: dict[str, str], code: str) -> str:
    r = subprocess.run([sys.executable, "-c", "import pellucid\ntry:\n" +
                        "".join("    " + line + "\n" for line in code.splitlines()) +
                        "except pellucid.Error as e:\n    print(e)\n"],
                       env={**os.environ, **env}, capture_output=True, text=True, timeout=120)
    assert r.returncode == 0, r.stderr
    return r.stdout.strip()


OBJ = "v 0 0 0\nv 1 0 0\nv 0 1 0\nv 1 1 0\nf 1 2 3\nf 2 4 3\n"


def test_mesh_element_limit_can_be_raised(tmp_path) -> None:
    (tmp_path / "m.obj").write_text(OBJ)
    load = f"pellucid.load_dict({{'shapes': [{{'type': 'obj', 'filename': 'm.obj'}}]}}, base_dir={str(tmp_path)!r})"
    e = _error_with_env({"PELLUCID_MAX_MESH_ELEMENTS": "3"}, load)
    assert "m.obj: more than 3 vertex positions (the mesh element limit; raise it with PELLUCID_MAX_MESH_ELEMENTS)" in e
    assert _error_with_env({"PELLUCID_MAX_MESH_ELEMENTS": "4"}, load) == ""


def test_film_limit_can_be_raised() -> None:
    load = "pellucid.load_dict({'film': {'width': 100, 'height': 50}})"
    e = _error_with_env({"PELLUCID_MAX_FILM_PIXELS": "4999"}, load)
    assert e == ("<dict>: film: resolution 100x50 is more than the limit of 4999 pixels "
                 "(raise it with PELLUCID_MAX_FILM_PIXELS)")
    assert _error_with_env({"PELLUCID_MAX_FILM_PIXELS": "5000"}, load) == ""
    # The default: 2^25 pixels.
    e = _error_with_env({}, "pellucid.load_dict({'film': {'width': 8192, 'height': 4097}})")
    assert "more than the limit of 33554432 pixels" in e


def test_texture_limit_can_be_raised() -> None:
    png = DATA.parent / "mitsuba" / "quad.png"
    load = ("pellucid.load_dict({'materials': {'m': {'type': 'lambertian', 'reflectance': "
            f"{{'type': 'image', 'filename': {str(png)!r}}}}}}}}})")
    e = _error_with_env({"PELLUCID_MAX_TEXTURE_PIXELS": "3"}, load)
    assert "materials.m.reflectance.filename: " in e and "more than the limit of 3 pixels" in e
    assert "PELLUCID_MAX_TEXTURE_PIXELS" in e
    assert _error_with_env({"PELLUCID_MAX_TEXTURE_PIXELS": "1000000"}, load) == ""


def test_bad_limit_value_is_an_error() -> None:
    e = _error_with_env({"PELLUCID_MAX_FILM_PIXELS": "lots"}, "pellucid.load_dict({'film': {'width': 8}})")
    assert e == "environment variable PELLUCID_MAX_FILM_PIXELS: expected an integer in [1, 268435456], got 'lots'"


def test_texture_cache_size_is_read_from_its_variable(tmp_path) -> None:
    png = tmp_path / "t.png"
    pellucid.write_image(png, np.full((4, 4, 3), 0.5, np.float32))
    load = ("pellucid.render(pellucid.load_dict({'film': {'width': 4, 'height': 4}, 'materials': {'m': {'type': 'lambertian', "
            f"'reflectance': {{'type': 'image', 'filename': {str(png)!r}}}}}}}, 'shapes': [{{'type': 'sphere', 'material': 'm'}}]}}), spp=1)")
    assert _error_with_env({"PELLUCID_TEXTURE_CACHE_MB": "10"}, load) == (
        "<dict>: materials.m.reflectance.filename: "
        "environment variable PELLUCID_TEXTURE_CACHE_MB: expected an integer in [64, 1048576], got '10'")
    assert _error_with_env({"PELLUCID_TEXTURE_CACHE_MB": "64"}, load) == ""


# OpenImageIO's BMP reader throws std::length_error from ImageInput::open for this header (see
# tests/data/fuzz/README.md); pellucid turns that into a pellucid.Error naming the file, in the
# image reader and in the texture path.
@pytest.mark.parametrize("path", ["read_image", "texture"])
def test_bmp_reader_exception_is_a_pellucid_error(path) -> None:
    bmp = DATA / "rle_huge_height.bmp"
    with pytest.raises(pellucid.Error, match=r"rle_huge_height\.bmp: cannot read"):
        if path == "read_image":
            pellucid.read_image(bmp)
        else:
            pellucid.load_dict({"materials": {"m": {"type": "lambertian", "reflectance": {
                "type": "image", "filename": str(bmp)}}}})


# A 1.4 KB EXR of 8 x 8 pixels whose header claims tiles of 2162883 x 64 pixels: the texture path
# makes OpenImageIO allocate and clear whole tiles (1.8 GB, 13 s) before the data fails to
# decompress. The header's tile size is limited like its image size.
def test_texture_with_huge_tiles_is_rejected_from_its_header() -> None:
    exr = DATA / "huge_tile.exr"
    e = _error_with_env({"PELLUCID_MAX_TEXTURE_PIXELS": "1048576"}, "pellucid.load_dict({'materials': {'m': {"
                        f"'type': 'lambertian', 'reflectance': {{'type': 'image', 'filename': {str(exr)!r}}}}}}}}})")
    assert "huge_tile.exr: tiles of 2162883x64 pixels" in e


# EXRs of 4 x 3 pixels whose headers claim a display window of 1501953 x 37377, or of 1 x 7601509
# (within the image size limit): the texture system sized its MIP levels by the display window and
# recursed through them for over 60 s (the image harness's timeout). A texture's display window must
# be its data window.
@pytest.mark.parametrize("name, window", [("huge_display_window.exr", "1501953x37377 at 0,25600"),
                                          ("tall_display_window.exr", "1x7601509 at 0,25600")])
def test_texture_whose_display_window_is_not_its_data_window_is_rejected(name, window) -> None:
    exr = DATA / name
    e = _error_with_env({}, "pellucid.load_dict({'materials': {'m': {"
                        f"'type': 'lambertian', 'reflectance': {{'type': 'image', 'filename': {str(exr)!r}}}}}}}}})")
    assert f"{name}: the display window ({window}) differs from the data window (4x3 at " in e


CLI = DATA.parents[2] / "build" / "py" / "cpp" / "pellucid-render"


def _cpu_flags() -> set:
    try:
        text = Path("/proc/cpuinfo").read_text()
    except OSError:
        return set()
    line = next((ln for ln in text.splitlines() if ln.startswith("flags")), "")
    return set(line.split(":", 1)[-1].split())


# Found by the Mitsuba XML harness: tiny films through the packet kernels. The Cornell-like test
# box at 3 x 3 pixels with the AVX-512 kernel, and the spheres scene at 1 x 4 pixels with the AVX2
# kernel (1 spp, one thread): pellucid-render hands rtcIntersect16 a valid lane whose ray Embree
# rejects, and Embree's assertion `all(valid, ray.valid())` aborts the process. Other kernels and
# the same renders in-process from Python did not abort: the bad lane was an idle lane's
# uninitialised ray. Idle lanes now pass no ray (path_services::trace_hits). Both scenes are small
# enough to be traced without Embree, so each also runs with PELLUCID_TRACE=embree.
@pytest.mark.skipif(not CLI.exists(), reason="pellucid-render is built by `make`")
@pytest.mark.parametrize("trace", ["default", "embree"])
@pytest.mark.parametrize("scene, simd, flag", [("packet_invalid_ray.xml", "avx512", "avx512bw"),
                                               ("packet_invalid_ray_1x4.xml", "avx2", "avx2")])
def test_packet_kernel_passes_only_valid_rays(tmp_path, scene, simd, flag, trace) -> None:
    if flag not in _cpu_flags():
        pytest.skip(f"reproduces with the {simd} kernel only")
    env = {**os.environ, "PELLUCID_SIMD": simd}
    env.pop("PELLUCID_TRACE", None)
    if trace == "embree":
        env["PELLUCID_TRACE"] = "embree"
    r = subprocess.run([str(CLI), str(DATA / scene), "-o", str(tmp_path / "out.exr"), "--spp", "1", "--threads", "1",
                        "-q"], capture_output=True, text=True, timeout=120, env=env)
    assert r.returncode == 0, r.stderr[-2000:]
