"""Interrupts and resume: SIGINT/SIGTERM stop pellucid.render() and both command lines within about a
second, keep the complete passes (the image, its spp in the file's metadata, the film state), and a
render resumed from that state is bit-identical to an uninterrupted one. Also the metadata every
render writes, -D / load_file(**params), and output checks before rendering."""
from __future__ import annotations

import os
import signal
import subprocess
import sys
import threading
import time

import numpy as np
import pytest

import pellucid

from conftest import ROOT

CLI = ROOT / "build" / "py" / "cpp" / "pellucid-render"
CORNELL = ROOT / "scenes" / "cornell_box.json"
PRINCIPLED = ROOT / "tests" / "data" / "mitsuba" / "principled.xml"
needs_cli = pytest.mark.skipif(not CLI.exists(), reason="pellucid-render is built by `make`")


def _py_cmd(*args: str) -> list:
    return [sys.executable, "-m", "pellucid", "render", *args]


def _cpp_cmd(*args: str) -> list:
    return [str(CLI), *args]


def _run(cmd: list) -> subprocess.CompletedProcess:
    return subprocess.run(cmd, capture_output=True, text=True, timeout=300)


def _kill_after(delay: float, sig: int) -> threading.Timer:
    t = threading.Timer(delay, lambda: os.kill(os.getpid(), sig))
    t.start()
    return t


def test_render_raises_keyboard_interrupt_and_keeps_the_passes() -> None:
    scene = pellucid.load_file(CORNELL)
    # Ctrl-C after 2 s: long enough for the first 8-spp pass on a slow, loaded 2-core machine (about
    # 1 s there), so that the partial film holds a completed pass.
    delay = 2.0
    timer = _kill_after(delay, signal.SIGINT)
    t0 = time.monotonic()
    with pytest.raises(KeyboardInterrupt) as info:
        pellucid.render(scene, spp=1 << 24)
    elapsed = time.monotonic() - t0
    timer.join()
    assert elapsed < delay + 1.0, f"stopped {elapsed - delay:.2f} s after Ctrl-C"
    partial = info.value.partial
    assert isinstance(partial, pellucid.RenderOutput)
    assert pellucid.last_interrupted() is partial
    stats = partial.stats
    assert stats["cancelled"] and stats["spp"] > 0 and stats["invalid_samples"] == 0
    assert partial.state.spp == stats["spp"] and partial.image.shape == (256, 256, 3)
    # The partial image is an ordinary render at that spp, and resuming it reaches the
    # uninterrupted image bit for bit.
    spp = stats["spp"]
    assert np.array_equal(partial.image, pellucid.render(scene, spp=spp))
    target = spp + 3
    assert np.array_equal(pellucid.render(scene, spp=target, resume=partial.state), pellucid.render(scene, spp=target))


def test_render_with_progress_bar_is_interruptible_too() -> None:
    pytest.importorskip("tqdm")
    scene = pellucid.load_file(ROOT / "scenes" / "tests" / "tiny_box.json")
    timer = _kill_after(0.5, signal.SIGINT)
    t0 = time.monotonic()
    with pytest.raises(KeyboardInterrupt) as info:
        pellucid.render(scene, spp=1 << 24, progress=True)
    timer.join()
    assert time.monotonic() - t0 < 1.5
    assert info.value.partial.stats["spp"] > 0


def test_resume_from_a_saved_state_file(tmp_path) -> None:
    scene = pellucid.load_file(ROOT / "scenes" / "tests" / "tiny_box.json")
    _, _, stats = pellucid.render_with_stats(scene, spp=5, seed=11, keep_state=True)
    state = stats["state"]
    assert (state.spp, state.seed, state.sampler, state.width, state.height) == (5, 11, "independent", 32, 24)
    path = tmp_path / "deep" / "film.state"
    state.save(str(path))
    loaded = pellucid.load_film_state(path)
    assert loaded.spp == 5 and loaded.integrator == state.integrator
    full = pellucid.render(scene, spp=9, seed=11)
    assert np.array_equal(pellucid.render(scene, spp=9, resume=loaded), full)
    assert np.array_equal(pellucid.render(scene, spp=9, resume=str(path)), full)
    with pytest.raises(pellucid.Error, match="used seed 11, this render asks for seed 2"):
        pellucid.render(scene, spp=9, seed=2, resume=loaded)
    with pytest.raises(pellucid.Error, match="spp: value 4 is below the 5 spp"):
        pellucid.render(scene, spp=4, resume=loaded)
    with pytest.raises(pellucid.Error, match="resume: expected a FilmState"):
        pellucid.render(scene, spp=9, resume=3)
    path.write_bytes(b"not a state")
    with pytest.raises(pellucid.Error, match="film.state: not a pellucid film state file"):
        pellucid.load_film_state(path)


def test_stats_report_dropped_samples_seed_and_sampler(tiny_scene_path) -> None:
    _, _, stats = pellucid.render_with_stats(pellucid.load_file(tiny_scene_path), spp=2, seed=4, sampler="sobol")
    assert stats["invalid_samples"] == 0 and stats["seed"] == 4 and stats["sampler"] == "sobol"
    assert "state" not in stats


@needs_cli
@pytest.mark.parametrize("cli", ["py", "cpp"])
@pytest.mark.parametrize("sig", [signal.SIGINT, signal.SIGTERM])
def test_cli_stops_on_signal_writes_partial_and_resumes(tmp_path, cli, sig) -> None:
    cmd = _py_cmd if cli == "py" else _cpp_cmd
    out = tmp_path / "out" / "img.exr"
    proc = subprocess.Popen(cmd(str(CORNELL), "-o", str(out), "--spp", str(1 << 24), "-q"),
                            stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True)
    time.sleep(3.0)  # past start-up and scene loading
    assert proc.poll() is None, proc.communicate()[1]
    t0 = time.monotonic()
    proc.send_signal(sig)
    _, err = proc.communicate(timeout=60)
    stopped = time.monotonic() - t0
    assert proc.returncode == 128 + sig, err
    assert stopped < 1.5, f"took {stopped:.2f} s to stop and write"
    meta = pellucid.read_image_attributes(out)
    spp = meta["pellucid:spp"]
    assert spp > 0 and meta["pellucid:interrupted"] == 1 and meta["pellucid:invalid_samples"] == 0
    state = out.with_name("img.exr.state")
    assert state.exists() and f"--resume {state}" in err
    assert pellucid.load_film_state(state).spp == spp
    # The partial image is the spp-sample render; resumed to spp + 3 it is the uninterrupted one.
    scene = pellucid.load_file(CORNELL)
    assert np.array_equal(pellucid.read_image(out), pellucid.render(scene, spp=spp))
    resumed = tmp_path / "resumed.exr"
    r = _run(cmd(str(CORNELL), "-o", str(resumed), "--spp", str(spp + 3), "--resume", str(state), "-q"))
    assert r.returncode == 0, r.stderr
    assert np.array_equal(pellucid.read_image(resumed), pellucid.render(scene, spp=spp + 3))
    assert pellucid.read_image_attributes(resumed)["pellucid:spp"] == spp + 3


@needs_cli
def test_both_clis_write_the_same_metadata(tmp_path, tiny_scene_path) -> None:
    a, b = tmp_path / "py.exr", tmp_path / "cpp.exr"
    for cmd, out in ((_py_cmd, a), (_cpp_cmd, b)):
        r = _run(cmd(str(tiny_scene_path), "-o", str(out), "--spp", "3", "--seed", "5"))
        assert r.returncode == 0, r.stderr
        assert "3 spp" in r.stderr and "0 invalid samples dropped" in r.stderr
    ma, mb = pellucid.read_image_attributes(a), pellucid.read_image_attributes(b)
    ours_a = {k: v for k, v in ma.items() if k.startswith("pellucid:") and k != "pellucid:seconds"}
    ours_b = {k: v for k, v in mb.items() if k.startswith("pellucid:") and k != "pellucid:seconds"}
    assert ours_a == ours_b == {
        "pellucid:spp": 3, "pellucid:invalid_samples": 0, "pellucid:interrupted": 0, "pellucid:seed": "5",
        "pellucid:sampler": "independent", "pellucid:version": pellucid.__version__}
    assert ma["pellucid:seconds"] > 0


@needs_cli
@pytest.mark.parametrize("cli", ["py", "cpp"])
def test_cli_state_option_and_resume_errors(tmp_path, tiny_scene_path, cli) -> None:
    cmd = _py_cmd if cli == "py" else _cpp_cmd
    st = tmp_path / "s" / "tiny.state"
    r = _run(cmd(str(tiny_scene_path), "-o", str(tmp_path / "a.exr"), "--spp", "2", "--state", str(st), "-q"))
    assert r.returncode == 0 and pellucid.load_film_state(st).spp == 2, r.stderr
    r = _run(cmd(str(tiny_scene_path), "-o", str(tmp_path / "b.exr"), "--spp", "5", "--resume", str(st),
                 "--sampler", "sobol"))
    assert r.returncode == 1 and "used the independent sampler, this render the sobol sampler" in r.stderr
    r = _run(cmd(str(CORNELL), "-o", str(tmp_path / "b.exr"), "--spp", "5", "--resume", str(st)))
    assert r.returncode == 1 and "resume:" in r.stderr
    assert not (tmp_path / "b.exr").exists()


@needs_cli
@pytest.mark.parametrize("cli", ["py", "cpp"])
def test_cli_defines_override_xml_defaults(tmp_path, cli) -> None:
    cmd = _py_cmd if cli == "py" else _cpp_cmd
    out = tmp_path / "p.exr"
    r = _run(cmd(str(PRINCIPLED), "-o", str(out), "-D", "spp=2", "-D", "width=20", "-Dheight=10", "-q"))
    assert r.returncode == 0, r.stderr
    assert pellucid.read_image(out).shape == (10, 20, 3)
    assert pellucid.read_image_attributes(out)["pellucid:spp"] == 2
    r = _run(cmd(str(PRINCIPLED), "-o", str(out), "-D", "spp"))
    assert r.returncode != 0 and "-D: expected NAME=VALUE, got" in r.stderr
    r = _run(cmd(str(CORNELL), "-o", str(out), "-D", "spp=2"))
    assert r.returncode == 1 and "JSON scenes have no $parameters" in r.stderr


def test_load_file_params_override_defaults() -> None:
    scene = pellucid.load_file(PRINCIPLED, spp=3, width=24, height=np.int64(12))
    assert (scene.spp, scene.width, scene.height) == (3, 24, 12)
    assert pellucid.load_file(PRINCIPLED).spp == 256
    with pytest.raises(pellucid.Error, match="JSON scenes have no"):
        pellucid.load_file(CORNELL, spp=4)


@needs_cli
@pytest.mark.parametrize("cli", ["py", "cpp"])
def test_outputs_are_checked_before_rendering(tmp_path, tiny_scene_path, cli) -> None:
    cmd = _py_cmd if cli == "py" else _cpp_cmd
    good = tmp_path / "good.exr"
    # A bad second output fails before the (long) render starts and before anything is written.
    t0 = time.monotonic()
    r = _run(cmd(str(CORNELL), "-o", str(good), "-o", str(tmp_path / "x.unknownfmt"), "--spp", str(1 << 20)))
    assert r.returncode == 1 and "unsupported image format '.unknownfmt'" in r.stderr
    assert time.monotonic() - t0 < 10 and not good.exists()
    # Missing folders are created.
    deep = tmp_path / "a" / "b" / "c.png"
    r = _run(cmd(str(tiny_scene_path), "-o", str(deep), "--spp", "1", "-q"))
    assert r.returncode == 0 and deep.exists(), r.stderr


@needs_cli
def test_help_lists_the_same_options() -> None:
    def options(text: str) -> list:
        lines = text.split("options:")[1].splitlines()
        return [ln.split()[0].rstrip(",") for ln in lines if ln.startswith("  -")]
    py = _run([sys.executable, "-m", "pellucid", "render", "--help"])
    cpp = _run([str(CLI), "--help"])
    assert py.returncode == cpp.returncode == 0
    assert [o for o in options(cpp.stdout) if o != "--version"] == options(py.stdout)
    # Errors in argparse's layout: a usage line, then "PROG: error: ...", exit status 2.
    for r in (_run(_py_cmd("x.json")), _run(_cpp_cmd("x.json"))):
        assert r.returncode == 2 and r.stderr.startswith("usage: ")
        assert "error: the following arguments are required: -o/--output" in r.stderr
