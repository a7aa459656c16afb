"""The ``pellucid-render`` console script: runs the C++ executable that the package carries in
``pellucid/bin/`` (the same program as ``build/py/cpp/pellucid-render`` in a source build), passing
every argument through and returning its exit status."""
from __future__ import annotations

import os
import pathlib
import sys
from typing import List, Optional

import pellucid


def executable() -> Optional[pathlib.Path]:
    """Path of the packaged pellucid-render, or None when this installation has none."""
    for d in pellucid.__path__:  # more than one entry in an editable install
        exe = pathlib.Path(d) / "bin" / "pellucid-render"
        if exe.is_file() and os.access(exe, os.X_OK):
            return exe
    return None


def main(argv: Optional[List[str]] = None) -> int:
    exe = executable()
    if exe is None:
        print("pellucid-render: this installation carries no pellucid-render executable "
              "(it was built with PELLUCID_BUILD_APP=OFF); use `python -m pellucid render`", file=sys.stderr)
        return 2
    args = sys.argv[1:] if argv is None else argv
    os.execv(exe, ["pellucid-render", *args])
    return 0  # not reached: execv replaces this process


if __name__ == "__main__":
    sys.exit(main())
