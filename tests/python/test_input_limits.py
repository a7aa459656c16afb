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
