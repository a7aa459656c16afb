"""Inputs past a documented limit get a pellucid.Error naming the key path, never a crash that takes
the interpreter down (a self-referencing dict or a 100,000-deep list used to overflow the C++ stack)."""
from __future__ import annotations

import pytest

import pellucid


def test_self_referencing_dict_is_an_error() -> None:
    d: dict = {"film": {"width": 8, "height": 8}}
    d["film"]["self"] = d
    with pytest.raises(pellucid.Error, match=r"<dict>: film\.self(\.film\.self)*.*nested deeper than 256 levels"):
        pellucid.load_dict(d)


def test_deeply_nested_list_is_an_error() -> None:
    deep: list = []
    for _ in range(100_000):
        deep = [deep]
    with pytest.raises(pellucid.Error, match="nested deeper than 256 levels.*PELLUCID_MAX_SCENE_DEPTH"):
        pellucid.load_dict({"film": {"width": 8, "height": 8}, "extra": deep})


def test_depth_below_the_limit_reaches_the_key_check() -> None:
    deep: list = []
    for _ in range(200):
        deep = [deep]
    with pytest.raises(pellucid.Error, match=r"^<dict>: extra: unknown parameter"):
        pellucid.load_dict({"extra": deep})


def test_float_overflow_names_the_key() -> None:
    scene = {"film": {"width": 8, "height": 8},
             "lights": [{"type": "constant", "radiance": 1e39}]}
    with pytest.raises(pellucid.Error, match=r"lights\[0\]\.radiance: value 1e\+39 overflows a 32-bit float"):
        pellucid.load_dict(scene)


@pytest.fixture(scope="module")
def tiny_scene():
    return pellucid.load_dict(pellucid.scenes.furnace(film={"width": 4, "height": 4}))


@pytest.mark.parametrize("kwargs, message", [
    ({"spp": 10**12}, r"spp: value 1000000000000 is out of range \[1, 2147483647\]"),
    ({"spp": 0}, r"spp: value 0 is out of range"),
    ({"spp": 2.0}, r"spp: expected an integer, got 2\.0"),
    ({"seed": 2**64}, r"seed: value 18446744073709551616 is out of range \[0, 9223372036854775807\]"),
    ({"seed": -1}, r"seed: value -1 is out of range"),
    ({"threads": -2}, r"threads: value -2 is out of range"),
    ({"time_budget": float("nan")}, r"time_budget: value nan must be a finite number >= 0"),
    ({"target_rel_error": float("nan")}, r"target_rel_error: value nan must be a finite number >= 0"),
    ({"time_budget": -1.0}, r"time_budget: value -1\.0 must be"),
])
def test_render_arguments_are_checked(tiny_scene, kwargs, message) -> None:
    with pytest.raises(pellucid.Error, match=message):
        pellucid.render(tiny_scene, **kwargs)


def test_large_seed_in_range_renders(tiny_scene) -> None:
    img = pellucid.render(tiny_scene, spp=1, seed=2**53 + 1)
    assert img.shape == (4, 4, 3)
