"""Descriptors as numpy saves them in other dtypes and orders (float16, integers, big-endian, Fortran order) map
exactly as the same values in float32: numpy writes the files, the command reads them."""
import numpy as np
import pytest

from conftest import run_cli


def descriptors() -> np.ndarray:
    # Small integers, exact in every dtype below: a random walk whose frames 220-279 repeat 40-99 with noise.
    rng = np.random.default_rng(5)
    x = rng.integers(0, 100, (320, 24))
    x[220:280] = np.clip(x[40:100] + rng.integers(-4, 5, (60, 24)), 0, 100)
    return x


@pytest.mark.parametrize("dtype, fortran", [
    ("<f2", False), (">f4", False), ("<f8", False), ("<f4", True), ("|u1", False), ("|i1", False),
    (">i2", False), ("<i4", True), ("<u8", False),
])
def test_every_dtype_maps_as_float32(cli, tmp_path, dtype, fortran):
    x = descriptors()
    np.save(tmp_path / "f32.npy", x.astype("<f4"))
    other = x.astype(dtype)
    np.save(tmp_path / "other.npy", np.asfortranarray(other) if fortran else other)
    run_cli(cli, "map", tmp_path / "f32.npy", "--out", tmp_path / "a")
    run_cli(cli, "map", tmp_path / "other.npy", "--out", tmp_path / "b")
    closures = (tmp_path / "a" / "loop_closures.csv").read_text()
    assert closures.count("\n") > 20  # the planted revisit is found
    assert (tmp_path / "b" / "loop_closures.csv").read_text() == closures
    assert (tmp_path / "b" / "map.json").read_bytes() == (tmp_path / "a" / "map.json").read_bytes()
