"""Shared fixtures: the command-line tool to compare with, and small synthetic sequences with revisits."""

import os
import pathlib
import shutil
import subprocess

import numpy as np
import pytest

SOURCE_DIR = pathlib.Path(os.environ.get("SEQTOPO_SOURCE_DIR", pathlib.Path(__file__).resolve().parents[2]))


@pytest.fixture(scope="session")
def cli() -> str:
    """Path of the `seqtopo` executable (CMake passes it as SEQTOPO_CLI)."""
    path = os.environ.get("SEQTOPO_CLI") or shutil.which("seqtopo")
    if not path or not os.path.exists(path):
        pytest.skip("the seqtopo command is not available (set SEQTOPO_CLI)")
    return path


def run_cli(cli: str, *args, check: bool = True) -> subprocess.CompletedProcess:
    result = subprocess.run([cli, *map(str, args)], capture_output=True, text=True)
    if check and result.returncode != 0:
        raise AssertionError(f"seqtopo {' '.join(map(str, args))} failed:\n{result.stderr}")
    return result


def cli_error(cli: str, *args) -> str:
    """The `<subject>: <message>` of the one error line a failing command prints."""
    result = run_cli(cli, *args, check=False)
    assert result.returncode != 0, result.stderr
    line = result.stderr.strip().splitlines()[-1]
    prefix = "seqtopo: error: "
    assert line.startswith(prefix), line
    return line[len(prefix):]


def route_descriptors(seed: int = 7, dim: int = 48, noise: float = 0.25) -> np.ndarray:
    """Descriptors of a walk that revisits places: places 0..59, then 15..44 again forward, then 55..30
    backwards. Each place has a random positive descriptor; each visit adds noise."""
    rng = np.random.default_rng(seed)
    places = rng.random((60, dim)) + 0.1
    route = list(range(60)) + list(range(15, 45)) + list(range(55, 29, -1))
    visits = places[route] + noise * rng.random((len(route), dim))
    return visits.astype(np.float32)


def localization_pair(seed: int = 11, dim: int = 32):
    """Map descriptors (80 frames) and a query (40 frames) driven through map frames 20..59 with noise,
    the last 10 query frames somewhere new."""
    rng = np.random.default_rng(seed)
    map_d = (rng.random((80, dim)) + 0.1).astype(np.float32)
    query = map_d[20:60] + 0.2 * rng.random((40, dim)).astype(np.float32)
    query[30:] = rng.random((10, dim)) + 0.1
    return map_d, query.astype(np.float32)
