"""pip install . says what it is doing (python/build_progress.py): pip hides a build's output unless -v, so the
stages and the compile percentage are written to /dev/tty, here to a stand-in stream, or without a terminal to
pip's own standard error."""

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
    progress = BuildProgress(stream=terminal, terminal=True)
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


def test_nothing_to_write_to_is_no_error():
    progress = BuildProgress(stream=None)
    progress.stream = None
    progress.run([sys.executable, "-c", "print('[1/2] x')"], "configuring")  # nothing to write to: no error


def test_without_a_terminal_whole_lines_reach_pips_standard_error(tmp_path):
    """pip's place is taken by a process whose standard error is a log file and which runs the build with its output
    in a pipe, as pip does; the whole chain runs in a new session, without a controlling terminal (no /dev/tty)."""
    build = (
        "import importlib.util, sys\n"
        "spec = importlib.util.spec_from_file_location('build_progress', %r)\n"
        "module = importlib.util.module_from_spec(spec)\n"
        "spec.loader.exec_module(module)\n"
        "script = \"for k in range(1, 101):\\n    print('[%%d/100] Building CXX object x.o' %% k, flush=True)\\n\"\n"
        "import time\n"
        "module.time.monotonic = iter(range(0, 10**6, 10)).__next__  # every line 10 s after the last\n"
        "progress = module.BuildProgress()\n"
        "progress.run([sys.executable, '-c', script], 'building the module with 2 jobs')\n"
        "progress.done('seqtopo._core')\n"
    ) % os.path.join(str(SOURCE_DIR), "python", "build_progress.py")
    pip = ("import subprocess, sys\n"
           "r = subprocess.run([sys.executable, '-c', sys.argv[1]], stdout=subprocess.PIPE, stderr=subprocess.STDOUT)\n"
           "sys.stdout.write('captured %d bytes' % len(r.stdout))\n"
           "sys.exit(r.returncode)\n")
    log = tmp_path / "pip-stderr.log"
    with open(log, "w") as stderr:
        done = subprocess.run([sys.executable, "-c", pip, build], stdout=subprocess.PIPE, stderr=stderr,
                              start_new_session=True, text=True)
    assert done.returncode == 0, log.read_text()
    text = log.read_text()
    lines = text.splitlines()
    assert lines[0] == "seqtopo build: building the module with 2 jobs", text
    compiling = [line for line in lines if line.startswith("seqtopo build: compiling")]
    # A line every 10 %, not one per file, and no terminal control characters.
    assert 9 <= len(compiling) <= 11, compiling
    assert "seqtopo build: compiling  91 % (91/100), 910 s" in text, text
    assert lines[-1].startswith("seqtopo build: done in") and lines[-1].endswith("seqtopo._core"), text
    assert "\r" not in text and "\x1b" not in text
