"""`python -m pellucid bench ...` imports pellucid.bench lazily and hands it the arguments."""
from __future__ import annotations

import sys
import types

import pellucid.__main__ as cli


def test_bench_gets_the_remaining_arguments(monkeypatch) -> None:
    seen = []
    fake = types.ModuleType("pellucid.bench")
    fake.main = lambda argv: seen.append(argv) or 7
    monkeypatch.setitem(sys.modules, "pellucid.bench", fake)
    assert cli.main(["bench", "cornell", "--spp", "4", "-h"]) == 7
    assert seen == [["cornell", "--spp", "4", "-h"]]


def test_missing_bench_module_is_a_clear_error(monkeypatch, capsys) -> None:
    monkeypatch.setitem(sys.modules, "pellucid.bench", None)  # import fails
    assert cli.main(["bench"]) == 2
    err = capsys.readouterr().err
    assert "the bench subcommand is not available" in err and "pellucid.bench" in err


def test_render_is_not_affected_by_bench(tiny_scene_path, tmp_path) -> None:
    out = tmp_path / "x.exr"
    before = set(sys.modules)
    assert cli.main(["render", str(tiny_scene_path), "-o", str(out), "--spp", "1", "-q"]) == 0
    assert "pellucid.bench" not in set(sys.modules) - before
