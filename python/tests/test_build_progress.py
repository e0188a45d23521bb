"""pip install . tells the terminal what it is doing (python/build_progress.py): pip hides a build's output
unless -v, so the stages and the compile percentage are written to /dev/tty, here to a stand-in stream."""

import importlib.util
import io
import os
import subprocess
import sys

import pytest

from conftest import SOURCE_DIR

# Loaded from its file: python/ on sys.path would also put the source tree's seqtopo (without _core) first.
_spec = importlib.util.spec_from_file_location("build_progress", os.path.join(str(SOURCE_DIR), "python",
                                                                              "build_progress.py"))
_module = importlib.util.module_from_spec(_spec)
_spec.loader.exec_module(_module)
BuildProgress = _module.BuildProgress


def test_stages_and_compile_percentage_reach_the_terminal(capfdbinary):
    terminal = io.StringIO()
    progress = BuildProgress(stream=terminal)
    # A build's output as ninja prints it, slowly enough for the 0.5 s refresh.
    script = "import time\nfor k in (1, 50, 100):\n    print('[%d/100] Building CXX object x.o' % k, flush=True)\n" \
             "    time.sleep(0.6)\n"
    progress.run([sys.executable, "-c", script], "building the module and the command with 2 jobs")
    progress.done("seqtopo._core and the seqtopo command")
    text = terminal.getvalue()
    assert "seqtopo build: building the module and the command with 2 jobs\n" in text
    assert "seqtopo build: compiling  50 % (50/100)" in text
    assert "seqtopo build: done in" in text and text.rstrip().endswith("seqtopo._core and the seqtopo command")
    # pip's log (our stdout) still gets the whole build output.
    assert b"[100/100] Building CXX object x.o" in capfdbinary.readouterr().out


def test_a_failed_step_says_how_to_see_the_output():
    terminal = io.StringIO()
    with pytest.raises(subprocess.CalledProcessError):
        BuildProgress(stream=terminal).run([sys.executable, "-c", "raise SystemExit(3)"], "configuring with CMake")
    assert "pip install -v ." in terminal.getvalue()


def test_no_terminal_no_output(monkeypatch):
    progress = BuildProgress(stream=None)
    progress.stream = None
    progress.run([sys.executable, "-c", "print('[1/2] x')"], "configuring")  # nothing to write to: no error
