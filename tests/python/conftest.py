"""Shared fixtures for the pytest suite."""
from __future__ import annotations

import json
import pathlib

import pytest

ROOT = pathlib.Path(__file__).resolve().parents[2]


@pytest.fixture()
def root() -> pathlib.Path:
    return ROOT


@pytest.fixture()
def tiny_scene_path() -> pathlib.Path:
    return ROOT / "scenes" / "tests" / "tiny_box.json"


@pytest.fixture()
def tiny_scene_dict(tiny_scene_path: pathlib.Path) -> dict:
    return json.loads(tiny_scene_path.read_text())
