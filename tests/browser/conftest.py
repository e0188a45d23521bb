"""Fixtures of the browser tests: the seqtopo binary, real reports of `seqtopo map` and `seqtopo localize`
(made once per session), and one headless Chromium shared by every test."""

import os
import shutil
import subprocess
import tempfile

import pytest

import report_check

CLI = os.environ.get("SEQTOPO_CLI", "")
DATA = os.environ.get("SEQTOPO_DATA_DIR", os.path.join(os.path.dirname(__file__), "..", "..", "data"))
ARTIFACTS = os.environ.get("SEQTOPO_BROWSER_ARTIFACTS")


@pytest.fixture(scope="session")
def scratch():
    folder = tempfile.mkdtemp(prefix="seqtopo-browser-")
    yield folder
    shutil.rmtree(folder, ignore_errors=True)


@pytest.fixture(scope="session")
def browser():
    missing = report_check.missing_requirements()
    if missing:
        pytest.fail("missing: %s; %s" % (", ".join(missing), report_check.SETUP_HINT), pytrace=False)
    b = report_check.Browser()
    with b:
        yield b
    assert not b.leftover, "browser processes still running after quit (ended now): %s" % b.leftover


def run_seqtopo(args, cwd, env=None):
    """Runs seqtopo, requires exit status 0, returns the completed process (stdout, stderr)."""
    assert CLI and os.access(CLI, os.X_OK), "SEQTOPO_CLI=%r is not the seqtopo binary" % CLI
    r = subprocess.run([CLI] + args, cwd=cwd, stdin=subprocess.DEVNULL, capture_output=True, text=True, timeout=300,
                       env=None if env is None else dict(os.environ, **env))
    assert r.returncode == 0, "seqtopo %s exited with %d:\n%s" % (" ".join(args), r.returncode, r.stderr[-3000:])
    return r


@pytest.fixture(scope="session")
def map_report(scratch):
    """report.html of `seqtopo map` on the bundled corridor loop (no INPUT: the bundled data)."""
    out = os.path.join(scratch, "map")
    run_seqtopo(["map", "--out", out], cwd=scratch)
    return os.path.join(out, "report.html")


@pytest.fixture(scope="session")
def junction_report(scratch):
    """report.html of the bundled corridor without the graph clean-up: its unaligned first image leaves a
    junction (the default map is one cycle without any)."""
    out = os.path.join(scratch, "map-junction")
    run_seqtopo(["map", "--graph-cleanup", "false", "--out", out], cwd=scratch)
    return os.path.join(out, "report.html")


@pytest.fixture(scope="session")
def localize_report(scratch):
    """report.html of `seqtopo localize`: the corridor's second walk (images 41-84) in its first (1-40)."""
    corridor = os.path.join(DATA, "rtabmap-corridor")
    walks = {"first-walk": range(1, 41), "second-walk": range(41, 85)}
    for name, images in walks.items():
        os.makedirs(os.path.join(scratch, name))
        for k in images:
            os.symlink(os.path.join(os.path.abspath(corridor), "%d.jpg" % k), os.path.join(scratch, name, "%d.jpg" % k))
    # image 41+q revisits image 1+q (data/README.md): query q is map q for the 40 query frames the map holds
    with open(os.path.join(scratch, "truth.csv"), "w") as f:
        f.write("query,map\n" + "".join("%d,%d\n" % (q, q) for q in range(40)))
    out = os.path.join(scratch, "localize")
    run_seqtopo(["localize", "--map", "first-walk", "--query", "second-walk", "--gt", "truth.csv", "--out", out], cwd=scratch)
    return os.path.join(out, "report.html")


