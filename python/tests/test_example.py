"""The Python example runs and writes its figure."""

import subprocess
import sys

import matplotlib.image

from conftest import SOURCE_DIR


def test_descriptors_to_map_example(tmp_path):
    out = tmp_path / "map.png"
    script = SOURCE_DIR / "examples" / "python" / "01_descriptors_to_map.py"
    result = subprocess.run([sys.executable, str(script), str(out)], capture_output=True, text=True, cwd=tmp_path)
    assert result.returncode == 0, result.stderr
    assert "places" in result.stdout
    image = matplotlib.image.imread(out)
    assert image.shape[0] > 100 and image.shape[1] > 100
