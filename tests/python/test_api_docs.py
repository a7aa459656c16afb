"""The documentation site builds with no warning (every cross-reference resolves: docs/conf.py sets
Sphinx's nitpicky mode) and its API reference documents every name of ``pellucid.__all__``, and
every method and property that the compiled module's stub (python/pellucid/_core.pyi) gives the
classes among them. Skipped when the ``docs`` extra (Sphinx, sphinx-autoapi, myst-nb) is not
installed; `make` installs it."""
from __future__ import annotations

import ast
import pathlib
import re
import subprocess
import sys
from typing import Iterable, List, Set

import pytest

import pellucid

from conftest import ROOT

pytest.importorskip("sphinx", reason="the docs extra is not installed (pip install '.[docs]')")
pytest.importorskip("autoapi", reason="the docs extra is not installed (pip install '.[docs]')")
pytest.importorskip("myst_nb", reason="the docs extra is not installed (pip install '.[docs]')")


class Site:
    def __init__(self, out: pathlib.Path, warnings: str) -> None:
        self.out = out
        self.warnings = warnings
        self.ids: Set[str] = set()
        for page in (out / "api").rglob("*.html"):
            self.ids |= set(re.findall(r'id="([^"]+)"', page.read_text()))


@pytest.fixture(scope="module")
def site(tmp_path_factory: pytest.TempPathFactory) -> Site:
    tmp = tmp_path_factory.mktemp("docs")
    out, warnings = tmp / "html", tmp / "warnings.txt"
    r = subprocess.run([sys.executable, "-m", "sphinx", "-b", "html", "-q", "--keep-going", "-w", str(warnings),
                        "-d", str(tmp / "doctrees"), str(ROOT / "docs"), str(out)],
                       capture_output=True, text=True, timeout=600)
    assert r.returncode == 0, f"sphinx-build failed:\n{r.stdout}\n{r.stderr}"
    return Site(out, warnings.read_text())


def undocumented(ids: Set[str], names: Iterable[str]) -> List[str]:
    """The names (``pellucid.X`` or ``pellucid.X.y``) with neither an object nor a module anchor."""
    return [n for n in names if n not in ids and f"module-{n}" not in ids]


def _stub_members() -> List[str]:
    """``pellucid.Class.member`` for the public methods and properties of the stub's classes that
    the package exports."""
    tree = ast.parse((ROOT / "python" / "pellucid" / "_core.pyi").read_text())
    return [f"pellucid.{c.name}.{f.name}" for c in tree.body if isinstance(c, ast.ClassDef) and c.name in pellucid.__all__
            for f in c.body if isinstance(f, ast.FunctionDef) and not f.name.startswith("_")]


def test_site_builds_without_warnings(site: Site) -> None:
    assert site.warnings.strip() == "", "sphinx-build warned:\n" + site.warnings


def test_every_public_name_is_in_the_reference(site: Site) -> None:
    names = [f"pellucid.{n}" for n in pellucid.__all__]
    assert undocumented(site.ids, names) == []


def test_stub_members_are_in_the_reference(site: Site) -> None:
    members = _stub_members()
    assert "pellucid.FilmState.save" in members
    assert undocumented(site.ids, members) == []


def test_the_name_check_is_not_vacuous(site: Site) -> None:
    assert undocumented(site.ids, ["pellucid.render", "pellucid.materials", "pellucid.no_such_name"]) == [
        "pellucid.no_such_name"]


def test_pages_and_tutorials_are_in_the_site(site: Site) -> None:
    pages = [p.stem for p in (ROOT / "docs").glob("*.md")] + [f"tutorials/{p.stem}" for p in
                                                               (ROOT / "docs" / "tutorials").glob("*.ipynb")]
    assert [p for p in pages if not (site.out / f"{p}.html").is_file()] == []
