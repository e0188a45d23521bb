"""The ``seqtopo`` command of a pip-installed package: runs the C++ command-line tool built with it.

``SEQTOPO_PIP_COMMAND=1 pip install .`` builds the tool beside the Python module and installs it as
``seqtopo/bin/seqtopo`` inside the package (a plain ``pip install .`` builds the module alone); this console entry
point (and ``python -m seqtopo``) hands it the arguments. In a CMake build tree
(``PYTHONPATH=build/release/python``) the tool is ``build/release/src/seqtopo``; ``SEQTOPO_CLI`` names another.
"""

import os
import sys


def _tool() -> str:
    here = os.path.dirname(os.path.abspath(__file__))
    candidates = [os.environ.get("SEQTOPO_CLI", ""), os.path.join(here, "bin", "seqtopo"),
                  os.path.join(here, "..", "..", "src", "seqtopo")]
    for path in candidates:
        if path and os.path.isfile(path) and os.access(path, os.X_OK):
            return path
    raise SystemExit("seqtopo: error: this install holds the Python module only: reinstall with "
                     "SEQTOPO_PIP_COMMAND=1 pip install . for the seqtopo command too (in a CMake build it is "
                     "<build>/src/seqtopo; scripts/run.sh builds it)")


def main() -> None:
    tool = _tool()
    os.execv(tool, ["seqtopo"] + sys.argv[1:])


if __name__ == "__main__":
    main()
