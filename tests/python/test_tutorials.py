"""Every notebook in docs/tutorials/ runs from the first cell to the last without an error, in a
fresh kernel of this interpreter (nbclient), and is stored with its outputs, so the documentation
site (which shows the stored outputs and never runs them) cannot show a tutorial that has rotted."""
from __future__ import annotations

import json
import pathlib
import sys
import time
from typing import Any, Dict, List

import pytest

from conftest import ROOT

TUTORIALS = ROOT / "docs" / "tutorials"
NOTEBOOKS = sorted(TUTORIALS.glob("*.ipynb"))


def _code_cells(nb: Dict[str, Any]) -> List[Dict[str, Any]]:
    return [c for c in nb["cells"] if c["cell_type"] == "code" and "".join(c["source"]).strip()]


def stored_output_problems(nb: Dict[str, Any]) -> List[str]:
    """What keeps a notebook from being one stored with its outputs: a code cell that was not run,
    cells not run once each from top to bottom, an error output, or no output at all."""
    cells = _code_cells(nb)
    counts = [c.get("execution_count") for c in cells]
    problems = []
    if None in counts:
        problems.append(f"code cells {[i for i, n in enumerate(counts) if n is None]} have no execution count")
    elif counts != list(range(1, len(cells) + 1)):
        problems.append(f"execution counts {counts} are not 1..{len(cells)} (run it top to bottom in a new kernel)")
    if any(o.get("output_type") == "error" for c in cells for o in c.get("outputs", [])):
        problems.append("a stored output is an error")
    if not any(c.get("outputs") for c in cells):
        problems.append("no cell has an output")
    return problems


def test_the_tutorials_are_there() -> None:
    assert (TUTORIALS / "materials.ipynb") in NOTEBOOKS


@pytest.mark.parametrize("path", NOTEBOOKS, ids=[p.stem for p in NOTEBOOKS])
def test_notebook_is_stored_with_outputs(path: pathlib.Path) -> None:
    problems = stored_output_problems(json.loads(path.read_text()))
    assert not problems, f"{path.name}: " + "; ".join(problems)


def test_the_stored_output_check_is_not_vacuous() -> None:
    nb = json.loads(NOTEBOOKS[0].read_text())
    assert not stored_output_problems(nb)
    for cell in _code_cells(nb):
        cell["execution_count"], cell["outputs"] = None, []
    assert stored_output_problems(nb)


@pytest.fixture()
def kernel_of_this_interpreter(tmp_path: pathlib.Path, monkeypatch: pytest.MonkeyPatch) -> str:
    """A kernelspec that runs ipykernel with sys.executable (this venv, where pellucid is installed),
    found first whatever kernels the machine has installed."""
    spec = tmp_path / "kernels" / "pellucid-test"
    spec.mkdir(parents=True)
    (spec / "kernel.json").write_text(json.dumps({
        "argv": [sys.executable, "-m", "ipykernel_launcher", "-f", "{connection_file}"],
        "display_name": "pellucid tests", "language": "python"}))
    monkeypatch.setenv("JUPYTER_PATH", str(tmp_path))
    monkeypatch.setenv("JUPYTER_PLATFORM_DIRS", "1")
    monkeypatch.setenv("MPLBACKEND", "module://matplotlib_inline.backend_inline")
    return "pellucid-test"


@pytest.mark.parametrize("path", NOTEBOOKS, ids=[p.stem for p in NOTEBOOKS])
def test_notebook_runs(path: pathlib.Path, kernel_of_this_interpreter: str) -> None:
    import nbformat
    from nbclient import NotebookClient

    nb = nbformat.read(path, as_version=4)
    client = NotebookClient(nb, kernel_name=kernel_of_this_interpreter, timeout=300,
                            resources={"metadata": {"path": str(path.parent)}})
    t0 = time.perf_counter()
    client.execute()  # raises CellExecutionError naming the cell on the first error
    print(f"{path.name}: {time.perf_counter() - t0:.1f} s")
    assert not stored_output_problems(nb)
