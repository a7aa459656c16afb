"""Generate python/pellucid/_core.pyi, the type stubs of the compiled module, with pybind11-stubgen.

    python tools/gen_stubs.py            # rewrite python/pellucid/_core.pyi
    python tools/gen_stubs.py --check    # exit 1 and print a diff if the committed stub is stale

pybind11-stubgen (PyPI) imports pellucid._core in this interpreter and writes each function's
pybind11 signature and docstring as stub syntax. tests/python/test_stubs.py runs the check.
"""
from __future__ import annotations

import argparse
import difflib
import pathlib
import subprocess
import sys
import tempfile
from typing import List

ROOT = pathlib.Path(__file__).resolve().parents[1]
STUB = ROOT / "python" / "pellucid" / "_core.pyi"


def generate() -> str:
    """The stub text pybind11-stubgen writes for pellucid._core (exit status non-zero on any
    signature it cannot express)."""
    with tempfile.TemporaryDirectory() as out:
        r = subprocess.run([sys.executable, "-m", "pybind11_stubgen", "pellucid._core", "--exit-code", "-o", out],
                           capture_output=True, text=True)
        if r.returncode != 0:
            raise SystemExit(f"pybind11-stubgen failed (exit {r.returncode}):\n{r.stdout}{r.stderr}")
        return (pathlib.Path(out) / "pellucid" / "_core.pyi").read_text()


def main(argv: List[str]) -> int:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--check", action="store_true", help="compare with the committed stub; do not write")
    args = ap.parse_args(argv)
    text = generate()
    if args.check:
        old = STUB.read_text() if STUB.exists() else ""
        if old != text:
            sys.stdout.writelines(difflib.unified_diff(old.splitlines(True), text.splitlines(True),
                                                       str(STUB), "generated"))
            return 1
        return 0
    STUB.write_text(text)
    return 0


if __name__ == "__main__":
    sys.exit(main(sys.argv[1:]))
