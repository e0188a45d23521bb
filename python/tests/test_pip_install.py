"""pip installs the package from the source tree, offline, into a venv that sees Debian's packages.

Slow (a CMake build of the module), so it runs only when SEQTOPO_TEST_PIP=1 (its own ctest entry).
SEQTOPO_CMAKE_BUILD_DIR, when set, keeps the CMake build folder between runs."""

import os
import random
import struct
import subprocess
import venv

import pytest

from conftest import SOURCE_DIR


def write_bmp(path, width, height, bgr):
    """A 24-bit BMP of width x height pixels, bgr row by row from the top (BMP stores rows bottom-up, padded to 4)."""
    row = width * 3
    pad = (4 - row % 4) % 4
    pixels = b"".join(bgr[y * row:(y + 1) * row] + b"\0" * pad for y in reversed(range(height)))
    header = struct.pack("<2sIHHI", b"BM", 54 + len(pixels), 0, 0, 54)
    info = struct.pack("<IiiHHIIiiII", 40, width, height, 1, 24, 0, len(pixels), 2835, 2835, 0, 0)
    path.write_bytes(header + info + pixels)


pytestmark = pytest.mark.skipif(os.environ.get("SEQTOPO_TEST_PIP") != "1", reason="set SEQTOPO_TEST_PIP=1")


def _venv(tmp_path):
    env_dir = tmp_path / "venv"
    venv.EnvBuilder(system_site_packages=True, with_pip=False).create(env_dir)
    env = {k: v for k, v in os.environ.items() if k not in ("PYTHONPATH", "SEQTOPO_CLI", "SEQTOPO_PIP_COMMAND")}
    env.setdefault("SEQTOPO_BUILD_JOBS", "2")
    env["PIP_NO_INDEX"] = "1"  # offline: nothing may come from a package index
    return env_dir, env_dir / "bin" / "python", env


def _pip_install(python, env, cwd):
    install = subprocess.run(
        [str(python), "-m", "pip", "install", "--no-build-isolation", "--no-deps", str(SOURCE_DIR)],
        capture_output=True, text=True, env=env, cwd=cwd)
    assert install.returncode == 0, install.stdout[-4000:] + install.stderr[-4000:]
    return install


def test_pip_install_builds_the_module_alone(tmp_path):
    env_dir, python, env = _venv(tmp_path)
    install = _pip_install(python, env, tmp_path)
    # Without a terminal the build's stages still reach pip's standard error (python/build_progress.py).
    assert "seqtopo build: building the module with 2 jobs" in install.stderr, install.stderr[-2000:]
    assert "seqtopo build: done in" in install.stderr
    check = "import seqtopo, os; print(os.path.dirname(seqtopo.__file__))"
    run = subprocess.run([str(python), "-c", check], capture_output=True, text=True, env=env, cwd=tmp_path)
    assert run.returncode == 0, run.stderr
    package = run.stdout.strip()
    assert package.startswith(str(env_dir)), package
    assert not os.path.exists(os.path.join(package, "bin")), os.listdir(package)  # no command-line tool built
    # The console entry point says how to get the command instead of failing obscurely.
    command = subprocess.run([str(env_dir / "bin" / "seqtopo"), "--help"], capture_output=True, text=True, env=env,
                             cwd=tmp_path)
    assert command.returncode != 0 and "SEQTOPO_PIP_COMMAND=1 pip install ." in command.stderr, command


def test_pip_install_from_source_tree(tmp_path):
    env_dir, python, env = _venv(tmp_path)
    env["SEQTOPO_PIP_COMMAND"] = "1"  # the command-line tool and its demo data too
    _pip_install(python, env, tmp_path)

    check = (
        "import numpy as np, seqtopo, os\n"
        "print(os.path.dirname(seqtopo.__file__))\n"
        "s = np.eye(12, dtype=np.float32) * 2 - 1\n"
        "a = seqtopo.align(s, gap=1.0, reverse=False)\n"
        "assert a[0].score == 12 and a[0].pairs.shape == (12, 2), a\n"
        "print(seqtopo.__version__)\n"
    )
    run = subprocess.run([str(python), "-c", check], capture_output=True, text=True, env=env, cwd=tmp_path)
    assert run.returncode == 0, run.stderr
    location = run.stdout.splitlines()[0]
    assert location.startswith(str(env_dir)), location  # the installed copy, not the source tree
    # The venv sees Debian's numpy but the installed package is its own.
    assert str(SOURCE_DIR) not in location
    # SEQTOPO_PIP_COMMAND=1 installed the seqtopo command too (a console entry point running the C++ tool).
    command = env_dir / "bin" / "seqtopo"
    assert command.exists(), sorted(p.name for p in (env_dir / "bin").iterdir())
    help_text = subprocess.run([str(command), "--help"], capture_output=True, text=True, env=env, cwd=tmp_path)
    assert help_text.returncode == 0 and "Usage: seqtopo [OPTIONS] SUBCOMMAND" in help_text.stdout, help_text
    module = subprocess.run([str(python), "-m", "seqtopo", "align", "--help"], capture_output=True, text=True, env=env,
                            cwd=tmp_path)
    assert module.returncode == 0 and "Usage: seqtopo align" in module.stdout, module
    # Images other than PNG and JPEG are decoded by the codecs plugin installed beside it (seqtopo/bin/), not the
    # one in the build folder: a folder of BMP frames (PNG and JPEG need no plugin).
    frames = tmp_path / "bmp"
    frames.mkdir()
    rng = random.Random(5)
    for k in range(30):
        write_bmp(frames / f"{k:02d}.bmp", 32, 24, bytes(rng.randrange(256) for _ in range(32 * 24 * 3)))
    mapped = subprocess.run([str(command), "map", str(frames), "--out", str(tmp_path / "bmp-map")],
                            capture_output=True, text=True, env=dict(env, LD_DEBUG="files"), cwd=tmp_path)
    assert mapped.returncode == 0, mapped.stderr[-3000:]
    opened = [line for line in mapped.stderr.splitlines() if "file=" in line and "libseqtopo_codecs.so" in line]
    assert opened and all(str(env_dir) in line for line in opened), opened
    # With no input it maps its own copy of the bundled corridor (seqtopo/data/ in the package), not the source's.
    demo = subprocess.run([str(command), "map", "--out", str(tmp_path / "demo")], capture_output=True, text=True,
                          env=env, cwd=tmp_path)
    assert demo.returncode == 0, demo.stderr[-3000:]
    report = (tmp_path / "demo" / "report.html").read_text()
    assert str(env_dir) in report and str(SOURCE_DIR / "data") not in report
